// The 3D view: ground, the simulated world's geometry, the robot and its ground-truth ghost.
// Everything is in the robot's map frame: x east, y north, z up.
import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
import { applyPose, createRobotModel } from './robot_model.js';

export class SceneView {
  constructor(container) {
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
    container.appendChild(this.renderer.domElement);

    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0x11151c);
    this.scene.add(new THREE.HemisphereLight(0xdde6ff, 0x202020, 1.6));
    const sun = new THREE.DirectionalLight(0xffffff, 1.5);
    sun.position.set(6, -8, 12);
    this.scene.add(sun);

    this.camera = new THREE.PerspectiveCamera(50, 1, 0.1, 500);
    this.camera.up.set(0, 0, 1);
    this.camera.position.set(-6, -10, 9);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.enableDamping = true;
    this.controls.maxPolarAngle = Math.PI / 2 - 0.05; // stay above the ground

    this.worldGroup = new THREE.Group();
    this.scene.add(this.worldGroup);
    this.setGround(12);

    this.robot = createRobotModel();
    this.truth = createRobotModel({ color: 0xffffff, opacity: 0.25 });
    this.robot.visible = false;
    this.truth.visible = false;
    this.scene.add(this.robot, this.truth);

    this.resize(container);
    window.addEventListener('resize', () => this.resize(container));
    this.renderer.setAnimationLoop(() => this.render());
  }

  resize(container) {
    const { clientWidth: width, clientHeight: height } = container;
    this.renderer.setSize(width, height);
    this.camera.aspect = width / Math.max(height, 1);
    this.camera.updateProjectionMatrix();
  }

  setGround(halfExtent) {
    this.ground?.removeFromParent();
    const size = 2 * halfExtent;
    this.ground = new THREE.Group();
    const plane = new THREE.Mesh(
      new THREE.PlaneGeometry(size, size),
      new THREE.MeshStandardMaterial({ color: 0x2b3340, roughness: 1 }),
    );
    const grid = new THREE.GridHelper(size, size, 0x4a5565, 0x38414f);
    grid.rotation.x = Math.PI / 2; // GridHelper lies in x-z; our ground is x-y
    grid.position.z = 0.002;
    this.ground.add(plane, grid);
    this.scene.add(this.ground);
  }

  /** The simulator's ground-truth geometry, drawn faintly for orientation. */
  setWorld(world) {
    this.worldGroup.clear();
    this.setGround(world.half_extent);
    const material = new THREE.MeshStandardMaterial({ color: 0xb08d57, transparent: true, opacity: 0.55 });
    for (const b of world.boxes) {
      const size = [0, 1, 2].map((i) => b.max[i] - b.min[i]);
      const mesh = new THREE.Mesh(new THREE.BoxGeometry(...size), material);
      mesh.position.set(...[0, 1, 2].map((i) => (b.max[i] + b.min[i]) / 2));
      mesh.name = b.name;
      this.worldGroup.add(mesh);
    }
  }

  setPose(pose) {
    // Keep the robot centred (thesis 3.3.1): move the camera with it, keeping the user's angle and zoom.
    const previous = this.robot.position.clone();
    applyPose(this.robot, pose);
    if (this.robot.visible) {
      const delta = this.robot.position.clone().sub(previous);
      this.camera.position.add(delta);
    }
    this.controls.target.copy(this.robot.position);
    this.robot.visible = true;
    if (pose.truth) {
      applyPose(this.truth, pose.truth);
      this.truth.visible = true;
    }
  }

  render() {
    this.controls.update();
    this.renderer.render(this.scene, this.camera);
  }
}
