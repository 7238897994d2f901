// The goal and the planned path in the 3D view: a pin at the goal (its colour says the phase) and a line
// along the path, lifted a little above the surfaces so it is not hidden in them.
import * as THREE from 'three';

const LIFT = 0.12; // m above the surface
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
    this.line = new THREE.Line(new THREE.BufferGeometry(), new THREE.LineBasicMaterial({ color: 0xf0f6fc }));
    this.line.visible = false;
    this.line.frustumCulled = false;
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
    const positions = new Float32Array(points.length * 3);
    points.forEach(([x, y, z], i) => positions.set([x, y, z + LIFT], 3 * i));
    this.line.geometry.dispose();
    this.line.geometry = new THREE.BufferGeometry();
    this.line.geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  }
}
