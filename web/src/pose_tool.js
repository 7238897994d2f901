// The operator's pose estimate (ROS's "2D Pose Estimate", for a multi-level map): armed by its button, a
// press on a surface picks where the robot stands and on which level (the surface pressed: a bridge deck
// or the road below), a drag from there points its heading, and letting go sends it. The server searches
// around it (2 m, 30 degrees), so an estimate by eye is enough. While the tool is armed the camera holds
// still: the drag draws the heading instead of turning the view.
import * as THREE from 'three';
import { pointAtHeight, surfaceAt } from './surface_pick.js';

const HEADING_DRAG_PX = 12; // a shorter drag points no heading: the robot's current heading is kept
const MARKER_LIFT = 0.15; // m above the surface, so the surface does not hide it

/** A ring where the robot stands and a thick arrow the way it faces (+x): a line would be one pixel wide. */
function createPoseMarker() {
  const material = new THREE.MeshBasicMaterial({ color: 0xd29922 });
  const marker = new THREE.Group();
  const shaft = new THREE.Mesh(new THREE.CylinderGeometry(0.06, 0.06, 1.1, 12), material);
  shaft.rotation.z = -Math.PI / 2; // the cylinder's axis is y: turn it onto x
  shaft.position.x = 0.55;
  const head = new THREE.Mesh(new THREE.ConeGeometry(0.22, 0.5, 16), material);
  head.rotation.z = -Math.PI / 2;
  head.position.x = 1.35;
  const ring = new THREE.Mesh(new THREE.RingGeometry(0.3, 0.42, 32), material);
  marker.add(shaft, head, ring);
  return marker;
}

export class PoseTool {
  /**
   * onPose({ x, y, z, yaw, dragged }) gets the estimate when the finger lifts; currentYaw() is the robot's
   * heading now (radians), the estimate's heading until a drag points another.
   */
  constructor(sceneView, { onPose, onMiss, onArmed, currentYaw }) {
    this.sceneView = sceneView;
    this.onPose = onPose;
    this.onMiss = onMiss;
    this.onArmed = onArmed;
    this.currentYaw = currentYaw;
    this.armed = false;
    this.press = null;
    this.arrow = createPoseMarker();
    this.arrow.visible = false;
    sceneView.scene.add(this.arrow);
    const element = sceneView.renderer.domElement;
    element.addEventListener('pointerdown', (event) => this.down(event));
    element.addEventListener('pointermove', (event) => this.move(event));
    element.addEventListener('pointerup', (event) => this.up(event));
    element.addEventListener('pointercancel', (event) => {
      if (this.press?.id === event.pointerId) this.cancelPress();
    });
  }

  setArmed(armed) {
    this.armed = armed;
    if (!armed) this.press = null;
    this.sceneView.controls.enabled = !armed;
    this.onArmed?.(armed);
  }

  /** The arrow of the last estimate stays until the server has said how its search went. */
  clearMarker() {
    if (this.press) return;
    this.arrow.visible = false;
    this.sceneView.requestRender();
  }

  down(event) {
    if (!this.armed || !event.isPrimary) return;
    const place = surfaceAt(this.sceneView, event.clientX, event.clientY);
    if (!place) {
      this.onMiss?.();
      return;
    }
    this.press = { id: event.pointerId, clientX: event.clientX, clientY: event.clientY, place, yaw: this.currentYaw(), dragged: false };
    this.showArrow();
  }

  move(event) {
    const press = this.press;
    if (!press || event.pointerId !== press.id) return;
    if (Math.hypot(event.clientX - press.clientX, event.clientY - press.clientY) < HEADING_DRAG_PX) return;
    const towards = pointAtHeight(this.sceneView, event.clientX, event.clientY, press.place.z);
    if (!towards) return; // above the horizon: keep the heading drawn last
    press.yaw = Math.atan2(towards.y - press.place.y, towards.x - press.place.x);
    press.dragged = true;
    this.showArrow();
  }

  up(event) {
    const press = this.press;
    if (!press || event.pointerId !== press.id) return;
    this.move(event);
    this.setArmed(false);
    this.onPose({ ...press.place, yaw: press.yaw, dragged: press.dragged });
  }

  cancelPress() {
    this.press = null;
    this.arrow.visible = false;
    this.sceneView.requestRender();
  }

  showArrow() {
    const { place, yaw } = this.press;
    this.arrow.position.set(place.x, place.y, place.z + MARKER_LIFT);
    this.arrow.rotation.set(0, 0, yaw);
    this.arrow.visible = true;
    this.sceneView.requestRender({ now: true });
  }
}
