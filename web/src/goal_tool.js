// Setting a goal by pointing at the map (thesis 3.3.1: "just pointing within the scene"). Armed by its
// button so a tap meant to rotate the view never sends the robot off; then a tap (or click) on a surface
// sends set_goal with the x, y and z of that surface, z picking its level (a bridge deck or the road
// below). In the drivable-map view the tap lands on the map image, at the robot's level.
import { patchAt, surfaceAt } from './surface_pick.js';

const TAP_SLOP_PX = 10; // a press that moves further is a drag (rotate, pan), not a tap

export class GoalTool {
  /** onPick({ x, y, z }) is called with the surface point the user tapped; onPick({ x, y }) for a wall. */
  constructor(sceneView, { onPick, onMiss, onArmed }) {
    this.sceneView = sceneView;
    this.onPick = onPick;
    this.onMiss = onMiss;
    this.onArmed = onArmed;
    this.armed = false;
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
    return surfaceAt(this.sceneView, clientX, clientY);
  }

  tap(clientX, clientY) {
    // A wall is sent as it is, without a level (the robot's own), for the server to say why it is no place
    // for the robot and where the nearest one is, as it does over REST (issue 63).
    const wall = this.sceneView.view === 'occupancy' ? null : patchAt(this.sceneView, clientX, clientY);
    const point = this.surfaceAt(clientX, clientY) ?? (wall?.vertical ? { x: wall.x, y: wall.y } : null);
    if (!point) {
      this.onMiss?.();
      return;
    }
    this.setArmed(false);
    this.onPick(point);
  }
}
