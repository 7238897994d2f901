// The 3D scene: the MLS map, the drivable map, the simulated world's ground truth (faint), the robot and
// its ground-truth ghost, the goal and path. Everything is in the map frame: x east, y north, z up.
// The camera follows the robot (thesis 3.3.1: the robot stays in the centre of the screen) unless the user
// switches to the free camera.
import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
import { createLights } from './lights.js';
import { OccupancyLayer } from './occupancy_layer.js';
import { PathLayer } from './path_layer.js';
import { applyPose, createRobotModel } from './robot_model.js';
import { TileLayer } from './tile_layer.js';
import { enableTouchTwist } from './touch_twist.js';
import { applyView } from './views.js';
import { buildWorld, fadeAbove } from './world_view.js';

export class SceneView {
  constructor(container) {
    // No MSAA: the map is tens of thousands of small boxes, and on a robot's integrated (or software)
    // GPU multisampling them costs more than the smoother edges are worth.
    this.renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
    container.appendChild(this.renderer.domElement);

    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0x11151c);
    this.scene.add(...createLights());

    this.camera = new THREE.PerspectiveCamera(50, 1, 0.1, 500);
    this.camera.up.set(0, 0, 1);
    this.camera.position.set(-6, -10, 9);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.enableDamping = true;
    this.controls.minDistance = 2;
    this.controls.maxDistance = 200;
    enableTouchTwist(this.renderer.domElement, this.camera, this.controls);

    this.worldGroup = new THREE.Group();
    this.scene.add(this.worldGroup);
    this.tiles = new TileLayer(this.scene);
    this.occupancy = new OccupancyLayer(this.scene);
    this.paths = new PathLayer(this.scene);

    this.robot = createRobotModel();
    this.truth = createRobotModel({ color: 0xffffff, opacity: 0.25 });
    this.robot.visible = false;
    this.truth.visible = false;
    this.scene.add(this.robot, this.truth);

    this.follow = true;
    this.worldShown = true;
    this.level = 0; // m: the height of the ground the robot stands on
    this.view = null;
    this.frames = 0;
    this.complete = false;
    this.onFrame = null;
    this.uncoveredArea = null; // client px: where the bar and the panel leave the map in sight
    applyView(this, '3d');

    this.resize(container);
    window.addEventListener('resize', () => this.resize(container));
    // Draw on demand: only when something changed (a pose, a tile, the camera), not 60 times a second,
    // so a robot standing still costs no GPU time and the page stays responsive on slow GPUs.
    // Updates that only move things along (poses at 25 Hz, tiles) wait for at least twice what the last
    // frame cost, so a slow (or software) GPU never keeps the page too busy to answer a touch; the user
    // moving the camera is drawn at once.
    this.dirty = true;
    this.frameCostMs = 16;
    this.renderedAt = -Infinity;
    this.interactingUntil = -Infinity; // while the user moves the camera, and its damped glide after
    this.sightCheckedAt = -Infinity; // when keepRobotInSight last looked along the line to the robot
    this.controls.addEventListener('start', () => {
      this.interactingUntil = Infinity;
    });
    this.controls.addEventListener('end', () => {
      this.interactingUntil = performance.now() + 1000;
    });
    // Every camera change the user makes is drawn at once: a mouse-wheel zoom moves the camera inside the
    // event handler, and the loop's controls.update() then reports nothing new (issue 24). The loop's own
    // updates (the damped glide, following the robot) are drawn as it paces them.
    this.updatingControls = false;
    this.controls.addEventListener('change', () => {
      if (!this.updatingControls) this.requestRender({ now: true });
    });
    this.renderer.setAnimationLoop((now) => {
      if (this.justRendered) {
        // The first tick after a frame arrives when the GPU has taken it: that gap is the frame's cost.
        this.frameCostMs = 0.7 * this.frameCostMs + 0.3 * (now - this.renderedAt);
        this.justRendered = false;
        this.tiles.adaptDetail(this.frameCostMs);
      }
      // The camera moves when the user moves it (and glides on, damped), or when it follows the robot.
      this.updatingControls = true;
      if (this.controls.update()) this.dirty = true;
      this.updatingControls = false;
      const interacting = now < this.interactingUntil;
      const due = now - this.renderedAt >= Math.min(2 * this.frameCostMs, 1000);
      if (this.dirty && (interacting || this.urgent || due)) {
        this.render();
        this.renderedAt = now;
        this.justRendered = true;
      }
    });
  }

  /** Draw again: at once for what the user did (`now`), when due for what streamed in. */
  requestRender({ now = false } = {}) {
    this.dirty = true;
    if (now) this.urgent = true;
  }

  resize(container) {
    const { clientWidth: width, clientHeight: height } = container;
    this.renderer.setSize(width, height);
    this.requestRender();
    this.camera.aspect = width / Math.max(height, 1);
    this.centreOnUncoveredArea();
  }

  /** The part of the view the page's bar and panel leave uncovered ({ left, top, right, bottom }, px). */
  setUncoveredArea(area) {
    this.uncoveredArea = area;
    this.centreOnUncoveredArea();
    this.requestRender({ now: true });
  }

  /**
   * What the camera looks at (the robot, when following it) is drawn in the centre of the uncovered area
   * rather than of the whole canvas, half hidden behind the panel: the projection's centre is shifted there.
   */
  centreOnUncoveredArea() {
    const { width, height } = this.renderer.domElement.getBoundingClientRect();
    const area = this.uncoveredArea;
    if (!area || width === 0 || height === 0) {
      this.camera.clearViewOffset();
      return;
    }
    const shiftX = width / 2 - (area.left + area.right) / 2;
    const shiftY = height / 2 - (area.top + area.bottom) / 2;
    this.camera.setViewOffset(width, height, shiftX, shiftY, width, height);
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
    plane.position.z = -0.03; // under the map's floor slabs
    const grid = new THREE.GridHelper(size, size, 0x4a5565, 0x38414f);
    grid.rotation.x = Math.PI / 2; // GridHelper lies in x-z; our ground is x-y
    grid.position.z = -0.028;
    this.ground.add(plane, grid);
    this.worldGroup.add(this.ground);
  }

  /** The simulator's ground-truth geometry, drawn faintly for orientation. */
  setWorld(world) {
    this.worldGroup.clear();
    if (!world.terrain) {
      const size = Math.max(world.bounds.max[0] - world.bounds.min[0], world.bounds.max[1] - world.bounds.min[1]);
      this.setGround(Math.ceil(size / 2));
    }
    const shapes = buildWorld(world);
    shapes.name = 'shapes';
    this.worldGroup.add(shapes);
  }

  /**
   * Whether the simulator's ground truth is drawn. It is for orientation until the map arrives, then the
   * map replaces it (and it is costly: its large transparent shapes make a software-rendered frame ten
   * times slower). The top-down views never draw it.
   */
  setWorldShown(shown) {
    this.worldShown = shown;
    this.worldGroup.visible = shown && !VIEW_IS_TOP_DOWN(this.view);
    this.requestRender({ now: true });
  }

  get worldShapes() {
    return this.worldGroup.getObjectByName('shapes');
  }

  setView(name) {
    applyView(this, name);
    this.requestRender({ now: true });
  }

  setFollow(follow) {
    this.follow = follow;
    if (follow && this.robot.visible) this.centreOn(this.robot.position);
    this.requestRender({ now: true });
  }

  centreOn(position) {
    const delta = position.clone().sub(this.controls.target);
    this.camera.position.add(delta);
    this.controls.target.add(delta);
  }

  setPose(pose) {
    this.requestRender();
    const wasVisible = this.robot.visible;
    applyPose(this.robot, pose);
    this.robot.visible = true;
    if (!wasVisible) {
      this.controls.target.copy(this.robot.position);
      this.camera.position.copy(this.robot.position).add(new THREE.Vector3(-4, -6, 9)); // behind, above
      if (VIEW_IS_TOP_DOWN(this.view)) applyView(this, this.view);
    } else if (this.follow) {
      // Keep the robot centred: move the camera with it, keeping the user's angle and zoom.
      this.centreOn(this.robot.position);
      this.keepRobotInSight();
    }
    if (pose.truth) {
      applyPose(this.truth, pose.truth);
      this.truth.visible = true;
    }
    if (this.worldShapes) fadeAbove(this.worldShapes, (pose.truth ?? pose).z + 1.6);
    // Which storey the robot is on decides what the top and 3D views draw.
    if (Math.abs(pose.z - this.level) >= 0.25) {
      this.level = pose.z;
      this.tiles.setFilter(this.tiles.filter, this.level);
    }
  }

  /**
   * Whether the map hides the robot from the camera at `eye`: a shown patch on the line of sight, nearer
   * than the robot by more than half a metre (the floor it stands on is not in the way).
   */
  robotHiddenFrom(eye) {
    const body = this.robot.position.clone().add(ROBOT_BODY);
    const hit = this.tiles.pick(new THREE.Ray(eye, body.clone().sub(eye).normalize()));
    return Boolean(hit) && Math.hypot(hit.x - eye.x, hit.y - eye.y) < Math.hypot(body.x - eye.x, body.y - eye.y) - 0.5;
  }

  /**
   * A followed robot stays in sight (issue 63: in the campus hallway a low camera beside it looked at the
   * near wall): when the map stands between the camera and the robot, the camera rises over it in steps,
   * keeping its distance and the direction it looks from, as far as looking straight down. Not while the
   * user moves the camera; at most five times a second (a pick walks the patches along the line).
   */
  keepRobotInSight() {
    const now = performance.now();
    if (VIEW_IS_TOP_DOWN(this.view) || now < this.interactingUntil || now - this.sightCheckedAt < 200) return;
    this.sightCheckedAt = now;
    if (!this.robotHiddenFrom(this.camera.position)) return;
    const offset = this.camera.position.clone().sub(this.controls.target);
    const distance = offset.length();
    const across = Math.hypot(offset.x, offset.y);
    const [dx, dy] = across > 1e-6 ? [offset.x / across, offset.y / across] : [0, -1];
    const eye = new THREE.Vector3();
    for (let elevation = Math.atan2(offset.z, across) + STEP_UP; elevation < MAX_ELEVATION + 1e-9; elevation += STEP_UP) {
      const e = Math.min(elevation, MAX_ELEVATION);
      eye.set(dx * distance * Math.cos(e), dy * distance * Math.cos(e), distance * Math.sin(e)).add(this.controls.target);
      if (!this.robotHiddenFrom(eye)) break;
    }
    this.camera.position.copy(eye);
    this.controls.update();
  }

  render() {
    const start = performance.now();
    this.dirty = false;
    this.urgent = false;
    // Tiles whose detail is still being built are drawn again when due, finer.
    const pending = this.tiles.group.visible && this.tiles.update(this.camera, this.renderer);
    if (pending) this.dirty = true;
    this.renderer.render(this.scene, this.camera);
    this.complete = !pending; // every shown tile drawn at the detail it calls for (tests wait for it)
    this.frames += 1;
    this.onFrame?.(performance.now() - start);
  }
}

const VIEW_IS_TOP_DOWN = (name) => name === 'top' || name === 'occupancy';
const ROBOT_BODY = new THREE.Vector3(0, 0, 0.6); // m above the robot's origin: what must stay in sight
const STEP_UP = (10 * Math.PI) / 180;
const MAX_ELEVATION = (85 * Math.PI) / 180; // OrbitControls keeps the camera off the vertical itself
