// The three views of thesis 3.3.1: the 3D map; the top view, looking straight down and showing only the
// surfaces at the robot's level; and the drivable map (occupancy) at the robot's level, from above.
import { PATCH_FILTERS } from './tile_layer.js';

export const VIEWS = {
  '3d': { label: '3D', filter: PATCH_FILTERS.belowHead, tiles: true, occupancy: false, topDown: false },
  top: { label: 'Top', filter: PATCH_FILTERS.atLevel, tiles: true, occupancy: false, topDown: true },
  occupancy: { label: 'Drivable', filter: PATCH_FILTERS.atLevel, tiles: false, occupancy: true, topDown: true },
};

const FREE_POLAR = { min: 0, max: Math.PI / 2 - 0.05 }; // orbit freely, but stay above the ground

/** Applies a view to the scene: what is drawn, and how the camera may move. */
export function applyView(scene, name) {
  const view = VIEWS[name];
  scene.tiles.group.visible = view.tiles;
  scene.occupancy.setVisible(view.occupancy);
  scene.worldGroup.visible = scene.worldShown && !view.topDown; // from above it would only clutter the map
  scene.tiles.setFilter(view.filter, scene.level);
  const { controls, camera } = scene;
  if (view.topDown) {
    // Straight down, north up; the user may still zoom, pan and turn about the vertical.
    const distance = Math.max(controls.getDistance(), 20);
    camera.position.copy(controls.target).add({ x: 0, y: -0.001, z: distance });
    controls.minPolarAngle = 0;
    controls.maxPolarAngle = 0;
  } else {
    controls.minPolarAngle = FREE_POLAR.min;
    controls.maxPolarAngle = FREE_POLAR.max;
    if (scene.view && VIEWS[scene.view].topDown) {
      // Back to the 3D view from above: the usual viewpoint above and behind the robot.
      const distance = controls.getDistance();
      camera.position.copy(controls.target).add({ x: -0.45 * distance, y: -0.65 * distance, z: 0.6 * distance });
    }
  }
  controls.update();
  scene.view = name;
}
