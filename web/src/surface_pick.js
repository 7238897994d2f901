// What a tap on the map points at, for the tools that pick a place on it (goal, pose estimate): the map
// surface under a screen position, and the point at a given height under it (where a drag points).
import * as THREE from 'three';

const raycaster = new THREE.Raycaster();

function rayThrough(sceneView, clientX, clientY) {
  const rect = sceneView.renderer.domElement.getBoundingClientRect();
  const ndc = new THREE.Vector2(((clientX - rect.left) / rect.width) * 2 - 1, -((clientY - rect.top) / rect.height) * 2 + 1);
  raycaster.setFromCamera(ndc, sceneView.camera);
  return raycaster;
}

/**
 * The surface point under a screen position (client pixels), or null. Its z picks the level (a bridge deck
 * or the road below); in the drivable-map view the tap lands on the map image, at the robot's level.
 */
export function surfaceAt(sceneView, clientX, clientY) {
  const { tiles, occupancy, view } = sceneView;
  const ray = rayThrough(sceneView, clientX, clientY);
  if (view === 'occupancy') {
    const [hit] = occupancy.plane.visible ? ray.intersectObject(occupancy.plane) : [];
    if (!hit) return null;
    return { x: hit.point.x, y: hit.point.y, z: occupancy.mosaic.levelZ };
  }
  const patch = tiles.pick(ray.ray);
  if (!patch) return null;
  // A wall or a step is no place to stand, and guessing which floor was meant could put the robot on the
  // wrong storey: the caller asks for another tap instead.
  if (patch.vertical) return null;
  return { x: patch.x, y: patch.y, z: patch.z };
}

/** The map's patch under a screen position, wall or floor: { x, y, z (its top), vertical }, or null. */
export function patchAt(sceneView, clientX, clientY) {
  return sceneView.tiles.pick(rayThrough(sceneView, clientX, clientY).ray);
}

/** Where the line of sight through a screen position meets the horizontal plane at height z, or null. */
export function pointAtHeight(sceneView, clientX, clientY, z) {
  const ray = rayThrough(sceneView, clientX, clientY).ray;
  const point = ray.intersectPlane(new THREE.Plane(new THREE.Vector3(0, 0, 1), -z), new THREE.Vector3());
  return point && { x: point.x, y: point.y };
}
