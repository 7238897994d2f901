// Strata's browser client: connects to the server and wires the map view, the status panel and the
// operator's tools (goal, joystick, map files, token) to the WebSocket.
import * as THREE from 'three';
import { Connection, websocketUrl } from './connection.js';
import { FRAME_OCCUPANCY, FRAME_TILE, parseFrame } from './frames.js';
import { GoalTool } from './goal_tool.js';
import { Joystick } from './joystick.js';
import { defaultMapName, downloadUrl, listMaps, NAME_PATTERN, tokenRefused } from './map_files.js';
import { Notices } from './notices.js';
import { COLOR_MODES } from './patch_colors.js';
import { SceneView } from './scene_view.js';
import { StatusPanel } from './status_panel.js';
import { CLASS_TRAVERSABLE, CLASS_VERTICAL, TileDecoder } from './tile_decoder.js';
import { isValidToken, loadToken, storeToken } from './token.js';

const $ = (id) => document.getElementById(id);
const view = new SceneView($('view'));
const panel = new StatusPanel();
const notices = new Notices($('notice'));
const decoder = new TileDecoder();

let role = null;
let lastGoal = { phase: 'none', id: 0 };
let nextRequestId = 1;
const requestId = () => nextRequestId++;

// Performance, read by tests and bench_render.mjs: when the map first appeared on screen, and the longest
// main-thread part of a tile update (decoding itself runs in DRACOLoader's workers).
const perf = {
  helloMs: null, // when the server's hello arrived (ms since the page started loading)
  firstTileFrameMs: null, // when the first tile frame arrived
  firstTileDecodedMs: null, // when the first tile came back from the decoder
  firstMapRenderMs: null, // when the first frame with map patches in it was drawn
  maxTileMainThreadMs: 0, // the longest main-thread part of one tile update
  tileUpdates: 0,
  slowTileUpdates: [], // tile updates whose main-thread part took over 16 ms: { n (which update), ms, patches }
  longTasks: [], // durations of main-thread tasks over 50 ms (PerformanceObserver 'longtask')
  renderMs: [], // the last 120 frames' render() durations on the main thread
};
try {
  new PerformanceObserver((list) => {
    for (const entry of list.getEntries()) perf.longTasks.push(Math.round(entry.duration));
  }).observe({ type: 'longtask', buffered: true });
} catch {
  // longtask is a Chromium feature; other browsers just do without the measurement
}
view.onFrame = (ms) => {
  perf.renderMs.push(Math.round(ms * 10) / 10);
  if (perf.renderMs.length > 120) perf.renderMs.shift();
  if (perf.firstMapRenderMs === null && view.tiles.drawnCount > 0) perf.firstMapRenderMs = performance.now();
};

// ---- map tiles and the drivable map, from binary frames --------------------------------------------
const newestTileVersion = new Map(); // "x,y" -> newest version announced, so late decodes never win

async function receiveTile(frame) {
  const key = `${frame.tileX},${frame.tileY}`;
  perf.firstTileFrameMs ??= performance.now();
  if ((newestTileVersion.get(key) ?? -1) >= frame.version) return;
  newestTileVersion.set(key, frame.version);
  let patches = null;
  if (frame.payload.byteLength > 0) {
    try {
      patches = await decoder.decode(frame.payload);
    } catch (error) {
      console.warn(`strata: tile ${key} did not decode`, error);
      return;
    }
  }
  if (newestTileVersion.get(key) !== frame.version) return; // a newer version arrived meanwhile
  perf.firstTileDecodedMs ??= performance.now();
  const start = performance.now();
  view.tiles.setTile(frame.tileX, frame.tileY, frame.version, patches);
  view.requestRender();
  const took = performance.now() - start;
  perf.maxTileMainThreadMs = Math.max(perf.maxTileMainThreadMs, took);
  if (took > 16) perf.slowTileUpdates.push({ n: perf.tileUpdates, ms: Math.round(took * 10) / 10, patches: patches?.count ?? 0 });
  perf.tileUpdates += 1;
}

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

function receiveBinary(buffer) {
  const frame = parseFrame(buffer);
  if (frame?.kind === FRAME_TILE) {
    mapArrived();
    receiveTile(frame);
  }
  else if (frame?.kind === FRAME_OCCUPANCY) view.occupancy.add(frame).then(() => view.requestRender());
}

// ---- server messages ------------------------------------------------------------------------------
const phaseText = {
  none: 'no goal',
  accepted: 'goal accepted',
  planning: 'planning a path…',
  driving: 'driving to the goal',
  reached: 'goal reached',
  failed: 'no way to the goal',
  cancelled: 'goal cancelled',
};

function showGoal(goal) {
  lastGoal = goal;
  const element = $('goal-state');
  element.dataset.phase = goal.phase;
  let text = phaseText[goal.phase] ?? goal.phase;
  if ((goal.phase === 'failed' || goal.phase === 'cancelled') && goal.reason) text += ` (${goal.reason.replaceAll('_', ' ')})`;
  if (goal.x !== undefined && goal.phase !== 'none') text += ` · ${goal.x.toFixed(1)}, ${goal.y.toFixed(1)}`;
  element.textContent = text;
  view.paths.showGoal(goal);
  view.requestRender();
}

const ackText = {
  save_map: 'Map saved',
  load_map: 'Map loaded',
  set_goal: 'Goal sent',
  cancel_goal: 'Stopped',
};

function showRole(newRole) {
  role = newRole;
  const badge = $('role');
  badge.dataset.role = role;
  badge.textContent = role === 'operator' ? 'operator' : 'viewer';
}

const pings = new Map(); // id -> performance.now() when sent

const handlers = {
  hello: (m) => {
    perf.helloMs ??= performance.now();
    $('source').textContent = `server ${m.version} · ${m.protocol}`;
    showRole(m.role);
    // A fresh connection resends every tile; tiles deleted while we were away would otherwise linger.
    view.tiles.clear();
    newestTileVersion.clear();
  },
  sim_world: (m) => {
    view.setWorld(m);
    view.requestRender();
  },
  pose: (m) => {
    panel.showPose(m);
    view.setPose(m);
  },
  status: (m) => {
    panel.showStatus(m);
    if (m.map?.tiles > 0) mapArrived();
  },
  goal: showGoal,
  path: (m) => {
    view.paths.showPath(m);
    view.requestRender();
  },
  ack: (m) => {
    if (ackText[m.request]) notices.show(ackText[m.request], 'ok', 3);
  },
  pong: (m) => {
    const sent = pings.get(m.id);
    pings.delete(m.id);
    if (sent !== undefined) panel.showRoundTrip(performance.now() - sent);
  },
  error: (m) => {
    console.warn(`strata: server error ${m.code}: ${m.message}`);
    notices.serverError(m);
  },
};

// ---- the joystick (before the connection, whose state changes release it) -------------------------
const joystick = new Joystick($('joystick'), { send: (message) => connection.send(message) });

// ---- the connection ---------------------------------------------------------------------------------
const stateText = { connecting: 'connecting…', connected: 'live', disconnected: 'disconnected: retrying' };
let connectionState = 'connecting';

const connection = new Connection(websocketUrl(), {
  onMessage: (message) => handlers[message.op]?.(message),
  onBinary: receiveBinary,
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

/** Sends a command; says so when the link is down instead of failing silently. */
function command(message) {
  const sent = connection.send({ ...message, id: requestId() });
  if (!sent) notices.show('Not connected to the robot: the command was not sent', 'error');
  return sent;
}

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
  $('follow').textContent = view.follow ? 'Follow robot' : 'Free camera';
});

// ---- goals --------------------------------------------------------------------------------------------
let lastGoalSent = null;
const goalTool = new GoalTool(view, {
  onPick: (point) => {
    lastGoalSent = point;
    command({ op: 'set_goal', x: round(point.x), y: round(point.y), z: round(point.z) });
  },
  onMiss: () => notices.show('Tap a floor or ground surface of the map to set the goal there', 'info', 4),
  onArmed: (armed) => {
    $('goal-arm').setAttribute('aria-pressed', String(armed));
    $('goal-arm').textContent = armed ? 'Tap the map…' : 'Set goal';
    $('view').classList.toggle('picking', armed);
  },
});
const round = (value) => Math.round(value * 1000) / 1000;
$('goal-arm').addEventListener('click', () => goalTool.setArmed(!goalTool.armed));
$('goal-cancel').addEventListener('click', () => {
  goalTool.setArmed(false);
  command({ op: 'cancel_goal' });
});

// ---- the operator token -------------------------------------------------------------------------------
const tokenDialog = $('token-dialog');
$('token-button').addEventListener('click', () => {
  $('token-input').value = '';
  tokenDialog.showModal();
});
tokenDialog.addEventListener('close', () => {
  if (tokenDialog.returnValue === 'use') {
    const token = $('token-input').value.trim();
    if (!isValidToken(token)) {
      notices.show('That is not a token: 16-128 letters, digits, - or _', 'error');
      return;
    }
    storeToken(token);
    connection.useToken(token);
  } else if (tokenDialog.returnValue === 'forget') {
    storeToken(null);
    connection.useToken(null);
    notices.show('Token forgotten: watching as a viewer', 'info', 4);
  }
});

// ---- map files ----------------------------------------------------------------------------------------
const filesDialog = $('files-dialog');
let filesMode = null;

function openFiles(mode, title) {
  filesMode = mode;
  $('files-title').textContent = title;
  $('files-save').hidden = mode !== 'save';
  $('files-load').hidden = mode !== 'load';
  $('files-download').hidden = mode !== 'download';
  filesDialog.showModal();
}

$('map-save').addEventListener('click', () => {
  $('save-name').value = defaultMapName();
  openFiles('save', 'Save the map');
});
$('map-load').addEventListener('click', async () => {
  let maps;
  try {
    maps = await listMaps();
  } catch (error) {
    notices.serverError({ ...error, request: 'load_map' });
    return;
  }
  const select = $('load-name');
  select.replaceChildren(
    ...maps.map((map) => {
      const option = new Option(`${map.name} · ${(map.bytes / 1024).toFixed(0)} KiB · ${new Date(map.modified * 1000).toLocaleString()}`, map.name);
      return option;
    }),
  );
  if (maps.length) select.selectedIndex = 0;
  else notices.show('No saved maps yet', 'info', 4);
  openFiles('load', 'Load a saved map');
});
$('map-download').addEventListener('click', () => openFiles('download', 'Download the map'));

filesDialog.addEventListener('close', () => {
  if (filesDialog.returnValue !== 'ok') return;
  if (filesMode === 'save') {
    const name = $('save-name').value.trim();
    if (!NAME_PATTERN.test(name)) {
      notices.show('A map name is a plain file name: letters, digits, . - _ (up to 64)', 'error');
      return;
    }
    command({ op: 'save_map', name });
  } else if (filesMode === 'load') {
    const name = $('load-name').value;
    if (name) command({ op: 'load_map', name });
  } else if (filesMode === 'download') {
    const link = document.createElement('a');
    link.href = downloadUrl($('download-format').value);
    link.download = '';
    link.click();
  }
});

// ---- the test handle ----------------------------------------------------------------------------------
/** The nearest drawn, traversable, horizontal patch to (x, y) within `radius` m (and within 0.5 m of
 * height `level`, when given), or null. */
function findSurface({ x, y, radius = 3, minDistance = 0, level = null }) {
  let best = null;
  for (const tile of view.tiles.tiles.values()) {
    const { position, classBits } = tile.patches;
    for (const i of tile.meshes.flatMap((mesh) => [...mesh.userData.shown])) {
      if (classBits[i] & CLASS_VERTICAL || !(classBits[i] & CLASS_TRAVERSABLE)) continue;
      if (level !== null && Math.abs(position[3 * i + 2] - level) > 0.5) continue;
      const d = Math.hypot(position[3 * i] - x, position[3 * i + 1] - y);
      if (d > radius || d < minDistance) continue;
      if (!best || d < best.d) best = { x: position[3 * i], y: position[3 * i + 1], z: position[3 * i + 2], d };
    }
  }
  return best;
}

/** Where a map-frame point appears on the page, in client pixels. */
function screenPoint([x, y, z]) {
  const p = new THREE.Vector3(x, y, z).project(view.camera);
  const rect = view.renderer.domElement.getBoundingClientRect();
  return { x: rect.left + ((p.x + 1) / 2) * rect.width, y: rect.top + ((1 - p.y) / 2) * rect.height, visible: Math.abs(p.z) <= 1 };
}

// A read-only handle for tests and for poking around in the console.
window.strata = {
  robotPosition: () => view.robot.position.toArray(),
  robotVisible: () => view.robot.visible,
  worldShapes: () => view.worldShapes?.children.length ?? 0,
  worldShown: () => view.worldShown,
  connection: () => connectionState,
  role: () => role,
  tileCount: () => view.tiles.tileCount,
  patchCount: () => view.tiles.patchCount,
  drawnPatches: () => view.tiles.drawnCount,
  view: () => view.view,
  colorMode: () => view.tiles.colorMode,
  follow: () => view.follow,
  cameraDistance: () => view.controls.getDistance(),
  cameraAzimuth: () => view.controls.getAzimuthalAngle(),
  frames: () => view.frames,
  occupancy: () => (view.occupancy.frames ? { frames: view.occupancy.frames, visible: view.occupancy.plane.visible, ...view.occupancy.census() } : null),
  goal: () => ({ ...lastGoal }),
  goalSent: () => lastGoalSent && { ...lastGoalSent },
  goalArmed: () => goalTool.armed,
  pathPoints: () => view.paths.pointCount,
  joystick: () => joystick.state,
  notice: () => (document.getElementById('notice').hidden ? null : notices.last),
  perf: () => structuredClone(perf),
  findSurface,
  screenPoint,
  surfaceAt: (clientX, clientY) => goalTool.surfaceAt(clientX, clientY), // what a tap there would pick
};
