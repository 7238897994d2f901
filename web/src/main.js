// Strata's browser client: connects to the server, draws the robot live, shows connection state.
import { Connection, websocketUrl } from './connection.js';
import { SceneView } from './scene_view.js';

const view = new SceneView(document.getElementById('view'));
const badge = document.getElementById('connection');
const sourceLabel = document.getElementById('source');
const fields = Object.fromEntries(
  ['x', 'y', 'z', 'yaw', 'stamp', 'mode'].map((name) => [name, document.getElementById(`pose-${name}`)]),
);

const localization = Object.fromEntries(
  ['source', 'scans', 'last', 'fit', 'message'].map((name) => [name, document.getElementById(`loc-${name}`)]),
);

const stateText = { connecting: 'connecting…', connected: 'live', disconnected: 'disconnected: retrying' };
const degrees = (radians) => (radians * 180) / Math.PI;

function showPose(pose) {
  fields.x.textContent = `${pose.x.toFixed(2)} m`;
  fields.y.textContent = `${pose.y.toFixed(2)} m`;
  fields.z.textContent = `${pose.z.toFixed(2)} m`;
  fields.yaw.textContent = `${degrees(pose.yaw).toFixed(1)}°`;
  fields.stamp.textContent = `${pose.stamp.toFixed(1)} s`;
  fields.mode.textContent = pose.mode ?? '–';
  localization.source.textContent = pose.source === 'registration' ? 'scan matching' : 'odometry only';
  view.setPose(pose);
}

function showStatus(status) {
  const r = status.registration;
  localization.scans.textContent = `${r.scans} (${r.accepted} ok, ${r.rejected} rejected)`;
  if (!r.last) return;
  const correction = { full: 'corrected', partial: 'partly corrected', none: 'kept odometry' };
  localization.last.textContent = correction[r.last.correction] ?? r.last.correction;
  localization.fit.textContent = `${(r.last.rmse * 100).toFixed(1)} cm, ${(r.last.seconds * 1000).toFixed(0)} ms`;
  localization.message.textContent = r.last.verdict === 'rejected' ? r.last.message : '';
}

const handlers = {
  hello: (m) => {
    sourceLabel.textContent = `server ${m.version} · ${m.protocol}`;
  },
  sim_world: (m) => view.setWorld(m),
  pose: showPose,
  status: showStatus,
  error: (m) => console.warn(`strata: server error ${m.code}: ${m.message}`),
};

const connection = new Connection(websocketUrl(), {
  onMessage: (message) => handlers[message.op]?.(message),
  onState: (state) => {
    badge.dataset.state = state;
    badge.textContent = stateText[state];
  },
});
connection.open();

// A read-only handle for tests and for poking around in the console.
window.strata = {
  robotPosition: () => view.robot.position.toArray(),
  robotVisible: () => view.robot.visible,
  worldShapes: () => view.worldGroup.children[0]?.children.length ?? 0,
};
