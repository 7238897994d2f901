// The robot as drawn in the 3D view: a wheelchair-sized base with its scanner on top. Its pose applies
// roll, pitch and yaw (thesis 3.3.1) in the robot's z-up frame.
import * as THREE from 'three';

function box(size, material, position) {
  const mesh = new THREE.Mesh(new THREE.BoxGeometry(...size), material);
  mesh.position.set(...position);
  return mesh;
}

export function createRobotModel({ color = 0x58a6ff, opacity = 1 } = {}) {
  const transparent = opacity < 1;
  const body = new THREE.MeshStandardMaterial({ color, transparent, opacity, roughness: 0.6 });
  const dark = new THREE.MeshStandardMaterial({ color: 0x222831, transparent, opacity, roughness: 0.9 });
  const robot = new THREE.Group();
  robot.add(box([0.9, 0.6, 0.25], body, [0, 0, 0.3]));    // base
  robot.add(box([0.15, 0.6, 0.6], body, [-0.38, 0, 0.7])); // backrest
  robot.add(box([0.25, 0.12, 0.04], dark, [0.5, 0, 0.3])); // nose: shows the heading
  const wheelGeometry = new THREE.CylinderGeometry(0.22, 0.22, 0.08, 24);
  for (const side of [-1, 1]) {
    const wheel = new THREE.Mesh(wheelGeometry, dark);
    wheel.position.set(-0.1, side * 0.34, 0.22);
    robot.add(wheel); // CylinderGeometry's axis is y: the wheel's axle
  }
  const scanner = new THREE.Mesh(new THREE.CylinderGeometry(0.08, 0.08, 0.18, 16), dark);
  scanner.rotation.x = Math.PI / 2;
  scanner.position.set(0.2, 0, 1.1);
  robot.add(scanner);
  robot.rotation.order = 'ZYX'; // R = Rz(yaw) Ry(pitch) Rx(roll), as the server's poses
  return robot;
}

export function applyPose(object, pose) {
  object.position.set(pose.x, pose.y, pose.z);
  object.rotation.set(pose.roll, pose.pitch, pose.yaw, 'ZYX');
}
