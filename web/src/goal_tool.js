// Setting a goal by pointing at the map (thesis 3.3.1: "just pointing within the scene"). Armed by its
// button so a tap meant to rotate the view never sends the robot off; then a tap (or click) on a surface
// sends set_goal with the x, y and z of that surface, z picking its level (a bridge deck or the road
// below). In the drivable-map view the tap lands on the map image, at the robot's level.
import * as THREE from 'three';

const TAP_SLOP_PX = 10; // a press that moves further is a drag (rotate, pan), not a tap

export class GoalTool {
  /** onPick({ x, y, z }) is called with the surface point the user tapped. */
  constructor(sceneView, { onPick, onMiss, onArmed }) {
    this.sceneView = sceneView;
    this.onPick = onPick;
    this.onMiss = onMiss;
    this.onArmed = onArmed;
    this.armed = false;
    this.raycaster = new THREE.Raycaster();
    this.press = null;
    const element = sceneView.renderer.domElement;
    element.addEventListener('pointerdown', (event) => {
      this.press = event.isPrimary ? { x: event.clientX, y: event.clientY, id: event.pointerId } : null;
    });
    element.addEventListener('pointerup', (event) => {
      const press = this.press;
      this.press = null;
      if (!this.armed || !press || press.id !== event.pointerId) return;
      if (Math.hypot(event.clientX - press.x, event.clientY - press.y) > TAP_SLOP_PX) return;
      this.tap(event.clientX, event.clientY);
    });
  }

  setArmed(armed) {
    this.armed = armed;
    this.onArmed?.(armed);
  }

  /** The surface point under a screen position (client pixels), or null. */
  surfaceAt(clientX, clientY) {
    const { renderer, camera, tiles, occupancy, view } = this.sceneView;
    const rect = renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2(((clientX - rect.left) / rect.width) * 2 - 1, -((clientY - rect.top) / rect.height) * 2 + 1);
    this.raycaster.setFromCamera(ndc, camera);
    if (view === 'occupancy') {
      const [hit] = occupancy.plane.visible ? this.raycaster.intersectObject(occupancy.plane) : [];
      if (!hit) return null;
      return { x: hit.point.x, y: hit.point.y, z: occupancy.mosaic.levelZ };
    }
    const [hit] = this.raycaster.intersectObjects(tiles.group.children, false);
    if (!hit) return null;
    const patch = tiles.patchAt(hit);
    // A wall or a step is no place to stand, and guessing which floor was meant could send the robot to
    // the wrong storey: ask for another tap instead.
    if (patch.vertical) return null;
    return { x: patch.x, y: patch.y, z: patch.z };
  }

  tap(clientX, clientY) {
    const point = this.surfaceAt(clientX, clientY);
    if (!point) {
      this.onMiss?.();
      return;
    }
    this.setArmed(false);
    this.onPick(point);
  }
}
