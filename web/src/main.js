// Strata's browser client: connects to the server, draws the robot live, shows connection state.
import { Connection, websocketUrl } from './connection.js';
import { SceneView } from './scene_view.js';

const view = new SceneView(document.getElementById('view'));
const badge = document.getElementById('connection');
const sourceLabel = document.getElementById('source');
const fields = Object.fromEntries(
  ['x', 'y', 'z', 'yaw', 'stamp', 'mode'].map((name) => [name, document.getElementById(`pose-${name}`)]),
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
  view.setPose(pose);
}

const handlers = {
  hello: (m) => {
    sourceLabel.textContent = `server ${m.version} · ${m.protocol}`;
  },
  sim_world: (m) => view.setWorld(m),
  pose: showPose,
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
