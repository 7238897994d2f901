// The goal and the planned path in the 3D view: a pin at the goal (its colour says the phase) and a tube
// along the path, lifted a little above the surfaces so it is not hidden in them.
import * as THREE from 'three';

const LIFT = 0.12; // m above the surface
const TUBE_RADIUS = 0.05; // m
const PHASE_COLORS = {
  accepted: 0xd29922, planning: 0xd29922, driving: 0x58a6ff, reached: 0x3fb950, failed: 0xf85149,
  cancelled: 0x8b98a9,
};

export class PathLayer {
  constructor(scene) {
    this.pinMaterial = new THREE.MeshStandardMaterial({ color: 0xd29922, emissive: 0x222222 });
    this.pin = new THREE.Group();
    const head = new THREE.Mesh(new THREE.SphereGeometry(0.18, 16, 12), this.pinMaterial);
    head.position.z = 1.0;
    const stem = new THREE.Mesh(new THREE.CylinderGeometry(0.03, 0.03, 1.0, 8), this.pinMaterial);
    stem.rotation.x = Math.PI / 2;
    stem.position.z = 0.5;
    const ring = new THREE.Mesh(new THREE.RingGeometry(0.25, 0.35, 32), new THREE.MeshBasicMaterial({ color: 0xffffff }));
    ring.position.z = 0.03;
    this.pin.add(head, stem, ring);
    this.pin.visible = false;
    // A tube, not a THREE.Line: WebGL draws lines one pixel wide, too thin to see on a touch screen.
    this.line = new THREE.Mesh(new THREE.BufferGeometry(), new THREE.MeshBasicMaterial({ color: 0xf0f6fc }));
    this.line.visible = false;
    scene.add(this.pin, this.line);
    this.pointCount = 0;
  }

  showGoal(goal) {
    const active = goal.phase !== 'none' && goal.x !== undefined;
    this.pin.visible = active && goal.phase !== 'cancelled';
    if (!active) return;
    this.pin.position.set(goal.x, goal.y, goal.z ?? 0);
    this.pinMaterial.color.setHex(PHASE_COLORS[goal.phase] ?? 0xd29922);
  }

  showPath(path) {
    const points = path.points ?? [];
    this.pointCount = points.length;
    this.line.visible = points.length >= 2;
    this.line.geometry.dispose();
    if (points.length < 2) {
      this.line.geometry = new THREE.BufferGeometry();
      return;
    }
    const vertices = points.map(([x, y, z]) => new THREE.Vector3(x, y, z + LIFT));
    // Tension 0: the tube follows the planned polyline instead of rounding its corners off.
    const curve = new THREE.CatmullRomCurve3(vertices, false, 'catmullrom', 0);
    this.line.geometry = new THREE.TubeGeometry(curve, Math.min(4 * points.length, 2000), TUBE_RADIUS, 6, false);
  }
}
