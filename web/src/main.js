// Strata's browser client: connects to the server and wires the map view, the status panel and the
// operator's tools (goal, joystick, map files, token) to the WebSocket. Wiring only: each part lives in
// its own module.
import { Connection, websocketUrl } from './connection.js';
import { setUpFilesDialog } from './files_dialog.js';
import { GoalPanel } from './goal_panel.js';
import { Joystick } from './joystick.js';
import { ServerClock } from './server_clock.js';
import { setUpToggles, trackUncoveredArea } from './layout.js';
import { tokenRefused } from './map_files.js';
import { MapFeed } from './map_feed.js';
import { Notices } from './notices.js';
import { COLOR_MODES } from './patch_colors.js';
import { createPerfProbe } from './perf_probe.js';
import { PosePanel } from './pose_panel.js';
import { SceneView } from './scene_view.js';
import { StatusPanel } from './status_panel.js';
import { installTestHandle } from './test_handle.js';
import { setUpTokenDialog } from './token_dialog.js';
import { loadToken, storeToken } from './token.js';

const $ = (id) => document.getElementById(id);
const view = new SceneView($('view'));
const panel = new StatusPanel();
const notices = new Notices($('notice'));
const perf = createPerfProbe(view);
setUpToggles();
trackUncoveredArea(view, document.querySelector('.bar'), document.querySelector('.panel'));

let role = null;
let nextRequestId = 1;
const requestId = () => nextRequestId++;

// The ground truth is for orientation until there is a map; then the map replaces it, unless the user
// asked for it with the World button.
let worldChosen = false;
function mapArrived() {
  if (!worldChosen && view.worldShown) showWorld(false);
}

function showWorld(shown) {
  view.setWorldShown(shown);
  $('world-toggle').setAttribute('aria-pressed', String(shown));
}

const mapFeed = new MapFeed(view, perf, { onMapArrived: mapArrived });

/** Sends a command; says so when the link is down instead of failing silently. */
function command(message) {
  const sent = connection.send({ ...message, id: requestId() });
  if (!sent) notices.show('Not connected to the robot: the command was not sent', 'error');
  return sent;
}

const goals = new GoalPanel(view, { command, notices });
let lastPose = null;
const poses = new PosePanel(view, { command, notices, currentYaw: () => lastPose?.yaw ?? 0 });
// One picking tool at a time: arming one disarms the other.
$('goal-arm').addEventListener('click', () => poses.tool.armed && poses.tool.setArmed(false));
$('pose-arm').addEventListener('click', () => goals.tool.armed && goals.tool.setArmed(false));

// ---- server messages ------------------------------------------------------------------------------
const ackText = {
  save_map: 'Map saved',
  load_map: 'Map loaded',
  set_goal: 'Goal sent',
  cancel_goal: 'Stopped',
  set_pose: 'Pose estimate sent: the robot is searched for around it',
};

function showRole(newRole) {
  role = newRole;
  const badge = $('role');
  badge.dataset.role = role;
  badge.textContent = role === 'operator' ? 'operator' : 'viewer';
}

const pings = new Map(); // id -> performance.now() when sent
const serverClock = new ServerClock(); // teleop's t

const handlers = {
  hello: (m) => {
    perf.helloMs ??= performance.now();
    serverClock.reset();
    serverClock.observe(m.clock_ms);
    $('source').textContent = `server ${m.version} · ${m.protocol}`;
    showRole(m.role);
    mapFeed.clear();
  },
  sim_world: (m) => {
    view.setWorld(m);
    view.requestRender();
  },
  pose: (m) => {
    lastPose = m;
    panel.showPose(m);
    view.setPose(m);
  },
  status: (m) => {
    panel.showStatus(m);
    poses.showStatus(m);
    if (m.map?.tiles > 0) mapArrived();
  },
  goal: (m) => goals.show(m),
  path: (m) => {
    view.paths.showPath(m);
    view.requestRender();
  },
  ack: (m) => {
    if (!ackText[m.request]) return;
    // A load's note says what the server does with the map now (maps on in it, localizes in it, why not).
    const note = m.request === 'load_map' && m.message;
    notices.show(note ? `${ackText[m.request]}: ${note}` : ackText[m.request], 'ok', note ? 6 : 3);
  },
  pong: (m) => {
    serverClock.observe(m.clock_ms);
    const sent = pings.get(m.id);
    pings.delete(m.id);
    if (sent !== undefined) panel.showRoundTrip(performance.now() - sent);
  },
  error: (m) => {
    console.warn(`strata: server error ${m.code}: ${m.message}`);
    if (m.request === 'set_pose') poses.refused();
    notices.serverError(m);
  },
};

// ---- the joystick (before the connection, whose state changes release it) -------------------------
const joystick = new Joystick($('joystick'), {
  send: (message) => connection.send(message),
  serverNow: () => serverClock.now(),
});

// ---- the connection ---------------------------------------------------------------------------------
const stateText = { connecting: 'connecting…', connected: 'live', disconnected: 'disconnected: retrying' };
let connectionState = 'connecting';

const connection = new Connection(websocketUrl(), {
  onMessage: (message) => handlers[message.op]?.(message),
  onBinary: (buffer) => mapFeed.receive(buffer),
  onState: (state) => {
    connectionState = state;
    $('connection').dataset.state = state;
    $('connection').textContent = stateText[state];
    if (state !== 'connected') joystick.release();
  },
  onRefused: async () => {
    // The socket never opened: the server is down, or it refused our token (401). Only REST can tell.
    const token = connection.token;
    if (token && (await tokenRefused(token)) && connection.token === token) {
      storeToken(null);
      notices.show('The operator token was refused: watching as a viewer. Enter the right token to drive.', 'auth', 10);
      connection.useToken(null);
    }
  },
});
connection.token = loadToken();
connection.open();

setInterval(() => {
  if (!connection.isOpen) return;
  const id = requestId();
  pings.set(id, performance.now());
  connection.send({ op: 'ping', id });
}, 2000);

// ---- the view controls ------------------------------------------------------------------------------
for (const button of document.querySelectorAll('#views button')) {
  button.addEventListener('click', () => {
    view.setView(button.dataset.view);
    for (const other of document.querySelectorAll('#views button')) {
      other.setAttribute('aria-pressed', String(other === button));
    }
  });
}

$('color-mode').addEventListener('click', () => {
  const next = COLOR_MODES[(COLOR_MODES.indexOf(view.tiles.colorMode) + 1) % COLOR_MODES.length];
  view.tiles.setColorMode(next);
  view.requestRender({ now: true });
  $('color-mode').textContent = `Colour: ${next}`;
});

$('world-toggle').addEventListener('click', () => {
  worldChosen = true;
  showWorld(!view.worldShown);
});

$('follow').addEventListener('click', () => {
  view.setFollow(!view.follow);
  $('follow').setAttribute('aria-pressed', String(view.follow));
  // A toggle: its label stays, its pressed state (lit) says whether the camera follows.
});

// ---- dialogs and the test handle --------------------------------------------------------------------
setUpTokenDialog(connection, notices);
setUpFilesDialog({ command, notices });
installTestHandle({ view, goals, poses, joystick, notices, perf, state: () => ({ connection: connectionState, role }) });
