// window.strata: a read-only handle for the browser tests and benchmarks, and for poking around in the
// console. Its names are what tests/browser/ reads: keep them.
import * as THREE from 'three';
import { patchAt } from './surface_pick.js';
import { CLASS_TRAVERSABLE, CLASS_VERTICAL } from './tile_decoder.js';

/** The nearest drawn, traversable, horizontal patch to (x, y) within `radius` m (and within 0.5 m of
 * height `level`, when given), or null. */
function findSurfaces(view, { x, y, radius = 3, minDistance = 0, level = null }) {
  const found = [];
  for (const tile of view.tiles.tiles.values()) {
    const { position, classBits } = tile.patches;
    for (const i of tile.shown) {
      if (classBits[i] & CLASS_VERTICAL || !(classBits[i] & CLASS_TRAVERSABLE)) continue;
      if (level !== null && Math.abs(position[3 * i + 2] - level) > 0.5) continue;
      const d = Math.hypot(position[3 * i] - x, position[3 * i + 1] - y);
      if (d > radius || d < minDistance) continue;
      found.push({ x: position[3 * i], y: position[3 * i + 1], z: position[3 * i + 2], d });
    }
  }
  return found.sort((a, b) => a.d - b.d);
}

/** Where a map-frame point appears on the page, in client pixels. */
function screenPoint(view, [x, y, z]) {
  const p = new THREE.Vector3(x, y, z).project(view.camera);
  const rect = view.renderer.domElement.getBoundingClientRect();
  return { x: rect.left + ((p.x + 1) / 2) * rect.width, y: rect.top + ((1 - p.y) / 2) * rect.height, visible: Math.abs(p.z) <= 1 };
}

/** Looks at `target` ([x, y, z], map frame) from `distance` m, keeping the view's direction. */
function aimCamera(view, target, distance) {
  const { camera, controls } = view;
  const direction = camera.position.clone().sub(controls.target).normalize();
  controls.target.set(...target);
  camera.position.copy(controls.target).addScaledVector(direction, distance);
  controls.update();
  view.requestRender({ now: true });
}

/** `state()` gives the page's own state: { connection, role }. */
export function installTestHandle({ view, goals, poses, joystick, notices, perf, state }) {
  window.strata = {
    robotPosition: () => view.robot.position.toArray(),
    robotVisible: () => view.robot.visible,
    worldShapes: () => view.worldShapes?.children.length ?? 0,
    worldShown: () => view.worldShown,
    connection: () => state().connection,
    role: () => state().role,
    tileCount: () => view.tiles.tileCount,
    patchCount: () => view.tiles.patchCount,
    drawnPatches: () => view.tiles.drawnCount,
    view: () => view.view,
    colorMode: () => view.tiles.colorMode,
    follow: () => view.follow,
    uncoveredArea: () => view.uncoveredArea && { ...view.uncoveredArea }, // the bar and the panel cover the rest
    cameraDistance: () => view.controls.getDistance(),
    cameraAzimuth: () => view.controls.getAzimuthalAngle(),
    frames: () => view.frames,
    frameComplete: () => view.complete, // the last frame drew no tile coarser than it should
    // The drivable map's mosaic: how many frames, the map version of the newest, and its pixel census.
    occupancy: () => {
      const { frames, plane, latest } = view.occupancy;
      return frames ? { frames, version: latest.version, visible: plane.visible, ...view.occupancy.census() } : null;
    },
    goal: () => ({ ...goals.lastGoal }),
    goalSent: () => goals.lastGoalSent && { ...goals.lastGoalSent },
    goalArmed: () => goals.tool.armed,
    poseSent: () => poses.lastSent && { ...poses.lastSent },
    poseArmed: () => poses.tool.armed,
    poseArrow: () => poses.tool.arrow.visible,
    relocalization: () => poses.lastSearch && { ...poses.lastSearch },
    mapMode: () => poses.mapMode,
    pathPoints: () => view.paths.pointCount,
    joystick: () => joystick.state,
    notice: () => (document.getElementById('notice').hidden ? null : notices.last),
    perf: () => structuredClone(perf),
    // Traversable floor patches near (x, y) on `level`: the nearest, or all of them nearest first.
    findSurface: (query) => findSurfaces(view, query)[0] ?? null,
    findSurfaces: (query) => findSurfaces(view, query),
    screenPoint: (point) => screenPoint(view, point),
    surfaceAt: (clientX, clientY) => goals.tool.surfaceAt(clientX, clientY), // what a tap there would pick
    patchAt: (clientX, clientY) => patchAt(view, clientX, clientY), // the patch drawn there, wall or floor
    // For bench_render.mjs: draw again now (to measure frame rates), aim the camera, what a frame cost.
    redraw: () => view.requestRender({ now: true }),
    aimCamera: (target, distance) => aimCamera(view, target, distance),
    /** Puts the camera `distance` m from what it looks at, seen from the compass `bearing` (radians, 0: east)
     * at `elevation` (radians above the horizon). */
    placeCamera: (bearing, elevation, distance) => {
      const { camera, controls } = view;
      camera.position.set(Math.cos(bearing) * Math.cos(elevation), Math.sin(bearing) * Math.cos(elevation), Math.sin(elevation));
      camera.position.multiplyScalar(distance).add(controls.target);
      controls.update();
      view.requestRender({ now: true });
    },
    cameraElevation: () => {
      const offset = view.camera.position.clone().sub(view.controls.target);
      return Math.atan2(offset.z, Math.hypot(offset.x, offset.y));
    },
    cameraPosition: () => view.camera.position.toArray(),
    lodLevels: () => [...view.tiles.tilesPerLevel], // tiles drawn in the last frame, by level of detail
    renderInfo: () => ({ calls: view.renderer.info.render.calls, triangles: view.renderer.info.render.triangles }),
  };
}
