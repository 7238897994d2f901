// The 3D view: ground, the simulated world's geometry, the robot and its ground-truth ghost.
// Everything is in the robot's map frame: x east, y north, z up.
import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
import { applyPose, createRobotModel } from './robot_model.js';
import { buildWorld, fadeAbove } from './world_view.js';

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

  /** A flat ground with a 1 m grid, for worlds without terrain. */
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
    this.ground?.removeFromParent();
    if (!world.terrain) {
      const size = Math.max(world.bounds.max[0] - world.bounds.min[0], world.bounds.max[1] - world.bounds.min[1]);
      this.setGround(Math.ceil(size / 2));
    }
    this.worldGroup.add(buildWorld(world));
  }

  setPose(pose) {
    // Keep the robot centred (thesis 3.3.1): move the camera with it, keeping the user's angle and zoom.
    const previous = this.robot.position.clone();
    applyPose(this.robot, pose);
    if (this.robot.visible) {
      const delta = this.robot.position.clone().sub(previous);
      this.camera.position.add(delta);
    } else {
      this.camera.position.copy(this.robot.position).add(new THREE.Vector3(-4, -6, 9)); // behind, above
    }
    this.controls.target.copy(this.robot.position);
    this.robot.visible = true;
    if (pose.truth) {
      applyPose(this.truth, pose.truth);
      this.truth.visible = true;
    }
    const world = this.worldGroup.children[0];
    if (world) fadeAbove(world, (pose.truth ?? pose).z + 1.6);
  }

  render() {
    this.controls.update();
    this.renderer.render(this.scene, this.camera);
  }
}
