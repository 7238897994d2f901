// The drivable map at the robot's level (occupancy frames, proto/PROTOCOL.md). Each frame covers only the
// region the last scan changed, so the frames are pasted into one mosaic on the map's pixel grid and drawn
// as a texture on a plane at the level's height. A frame from another level (the robot climbed to the
// bridge) starts a new mosaic: the thesis's occupancy view is the map at the robot's current level.
import * as THREE from 'three';

const LEVEL_TOLERANCE = 0.5; // m: frames whose levels differ by less belong to the same storey
const MAX_SIDE = 4096; // px: a canvas (and texture) side the page can always allocate

export class OccupancyLayer {
  constructor(scene) {
    this.canvas = document.createElement('canvas');
    this.context = this.canvas.getContext('2d');
    this.texture = new THREE.CanvasTexture(this.canvas);
    this.texture.magFilter = THREE.NearestFilter; // crisp cells, as the planner sees them
    this.texture.colorSpace = THREE.SRGBColorSpace;
    this.plane = new THREE.Mesh(
      new THREE.PlaneGeometry(1, 1),
      new THREE.MeshBasicMaterial({ map: this.texture, transparent: true, depthWrite: false }),
    );
    this.plane.name = 'occupancy';
    this.plane.visible = false;
    scene.add(this.plane);
    this.mosaic = null; // { minX, maxY (m, the canvas's top-left corner), resolution, levelZ }
    this.frames = 0;
    this.latest = null;
    this.pending = Promise.resolve();
  }

  /** Adds an occupancy frame (parsed by frames.js); frames are pasted in arrival order. */
  add(frame) {
    this.pending = this.pending.then(() => this.paste(frame)).catch((error) => {
      console.warn('strata: an occupancy image did not decode', error);
    });
    return this.pending;
  }

  async paste(frame) {
    const image = await createImageBitmap(new Blob([frame.payload], { type: 'image/png' }));
    const { resolution: r } = frame;
    const frameMinX = frame.originX;
    const frameMaxY = frame.originY + frame.height * r;
    let m = this.mosaic;
    if (!m || Math.abs(m.resolution - r) > 1e-9 || Math.abs(m.levelZ - frame.levelZ) > LEVEL_TOLERANCE) {
      m = this.mosaic = { minX: frameMinX, maxY: frameMaxY, resolution: r, levelZ: frame.levelZ };
      this.canvas.width = frame.width;
      this.canvas.height = frame.height;
    }
    // Grow the canvas (keeping what it holds) to cover the frame, on the same pixel grid.
    const left = Math.min(m.minX, frameMinX);
    const top = Math.max(m.maxY, frameMaxY);
    const right = Math.max(m.minX + this.canvas.width * r, frameMinX + frame.width * r);
    const bottom = Math.min(m.maxY - this.canvas.height * r, frame.originY);
    const width = Math.round((right - left) / r);
    const height = Math.round((top - bottom) / r);
    if (width > MAX_SIDE || height > MAX_SIDE) {
      // Too large to keep: start over from this frame.
      this.mosaic = null;
      return this.paste(frame);
    }
    if (width !== this.canvas.width || height !== this.canvas.height || left !== m.minX || top !== m.maxY) {
      const old = await createImageBitmap(this.canvas);
      const dx = Math.round((m.minX - left) / r);
      const dy = Math.round((top - m.maxY) / r);
      this.canvas.width = width;
      this.canvas.height = height;
      this.context.drawImage(old, dx, dy);
      m.minX = left;
      m.maxY = top;
      // A resized canvas needs a new texture: the old one's storage has the old size.
      this.texture.dispose();
      this.texture = new THREE.CanvasTexture(this.canvas);
      this.texture.magFilter = THREE.NearestFilter;
      this.texture.colorSpace = THREE.SRGBColorSpace;
      this.plane.material.map = this.texture;
    }
    m.levelZ = frame.levelZ;
    this.context.drawImage(image, Math.round((frameMinX - m.minX) / r), Math.round((m.maxY - frameMaxY) / r));
    image.close();
    this.texture.needsUpdate = true;
    this.plane.scale.set(this.canvas.width * r, this.canvas.height * r, 1);
    this.plane.position.set(m.minX + (this.canvas.width * r) / 2, m.maxY - (this.canvas.height * r) / 2, m.levelZ + 0.02);
    this.frames += 1;
    this.plane.visible = Boolean(this.wanted);
    this.latest = { ...frame, payload: undefined };
  }

  setVisible(visible) {
    this.plane.visible = visible && this.frames > 0;
    this.wanted = visible;
  }

  clear() {
    this.mosaic = null;
    this.frames = 0;
    this.canvas.width = this.canvas.height = 1;
    this.plane.visible = false;
  }

  /** Pixel statistics of the mosaic, for tests: how much of it is free, occupied or unknown. */
  census() {
    const { width, height } = this.canvas;
    const data = this.context.getImageData(0, 0, width, height).data;
    const counts = { free: 0, occupied: 0, unknown: 0, empty: 0 };
    for (let i = 0; i < data.length; i += 4) {
      if (data[i + 3] === 0) counts.empty++;
      else if (data[i] >= 250) counts.free++;
      else if (data[i] <= 5) counts.occupied++;
      else counts.unknown++;
    }
    return { width, height, ...counts };
  }
}
