// The MLS map in the 3D view: per tile, instanced boxes, one per patch. A vertical patch (wall, step) is a
// column reaching `depth` below its top; a horizontal patch the top of a slab at its height.
// Tiles are replaced in place when a newer version arrives, and removed when an empty one does.
import * as THREE from 'three';
import { patchColor } from './patch_colors.js';
import { CLASS_VERTICAL } from './tile_decoder.js';

const CELL = 0.1; // m: the map's resolution (proto/TILE_ENCODING.md); one box per cell
const SLAB = 0.04; // m: the least height drawn for a vertical patch

// Which patches a view draws, relative to the ground the robot stands on (`level`, m). The 3D view hides
// what hangs above the robot's head so the robot stays in sight (thesis 3.3.1); the top view shows only
// the surfaces at the robot's level (a floor, and the walls around it), not the storey below or above.
export const PATCH_FILTERS = {
  all: () => true,
  belowHead: (top, bottom, level) => bottom <= level + 2.0,
  atLevel: (top, bottom, level, vertical) =>
    vertical ? bottom <= level + 2.0 && top >= level - 0.3 : Math.abs(top - level) <= 0.5,
};

// Walls and steps are boxes. A floor is drawn as the top face of its slab only: seen from above (or from
// below, double-sided) that is all one sees of a 4 cm slab, and it is 2 triangles instead of 12, which is
// what keeps a 100 000-patch map smooth on a robot's modest GPU.
const unitBox = new THREE.BoxGeometry(1, 1, 1);
const floorSquare = new THREE.PlaneGeometry(1, 1);

/** A sphere around the listed patches' boxes (x, y of cell centres; z from bottoms to tops). */
function tileBounds({ position, depth }, shown, vertical) {
  let minX = Infinity, minY = Infinity, minZ = Infinity;
  let maxX = -Infinity, maxY = -Infinity, maxZ = -Infinity;
  for (let k = 0; k < shown.length; k++) {
    const i = shown[k];
    const x = position[3 * i];
    const y = position[3 * i + 1];
    const z = position[3 * i + 2];
    if (x < minX) minX = x;
    if (x > maxX) maxX = x;
    if (y < minY) minY = y;
    if (y > maxY) maxY = y;
    if (z > maxZ) maxZ = z;
    const bottom = vertical ? z - depth[i] : z;
    if (bottom < minZ) minZ = bottom;
  }
  const box = new THREE.Box3(
    new THREE.Vector3(minX - CELL, minY - CELL, minZ - SLAB),
    new THREE.Vector3(maxX + CELL, maxY + CELL, maxZ + SLAB),
  );
  return box.getBoundingSphere(new THREE.Sphere());
}

export class TileLayer {
  constructor(scene) {
    this.group = new THREE.Group();
    this.group.name = 'map';
    scene.add(this.group);
    this.material = new THREE.MeshLambertMaterial({ color: 0xffffff });
    this.floorMaterial = new THREE.MeshLambertMaterial({ color: 0xffffff, side: THREE.DoubleSide });
    this.tiles = new Map(); // "x,y" -> { version, patches, meshes (userData.shown: patch per instance) }
    this.colorMode = 'height';
    this.filter = PATCH_FILTERS.belowHead;
    this.level = 0;
    this.patchCount = 0;
  }

  static key(tileX, tileY) {
    return `${tileX},${tileY}`;
  }

  /** Whether a frame of this version for this tile would be news (the stream never goes backwards). */
  isNewer(tileX, tileY, version) {
    const tile = this.tiles.get(TileLayer.key(tileX, tileY));
    return !tile || version > tile.version;
  }

  /** Puts decoded patches in place of the tile's old ones; null or zero patches removes the tile. */
  setTile(tileX, tileY, version, patches) {
    const key = TileLayer.key(tileX, tileY);
    const old = this.tiles.get(key);
    if (old && version <= old.version) return; // a decode that finished after a newer one
    if (old) this.removeMesh(old);
    if (!patches || patches.count === 0) {
      this.tiles.delete(key);
      return;
    }
    const tile = { version, patches, meshes: [], shownCount: 0 };
    this.tiles.set(key, tile);
    this.patchCount += patches.count;
    this.buildMesh(tile);
  }

  removeMesh(tile) {
    this.patchCount -= tile.patches.count;
    this.disposeMeshes(tile);
  }

  clear() {
    for (const tile of this.tiles.values()) this.removeMesh(tile);
    this.tiles.clear();
  }

  buildMesh(tile) {
    const { count, position, depth, classBits } = tile.patches;
    const floors = new Uint32Array(count);
    const walls = new Uint32Array(count);
    let nFloors = 0;
    let nWalls = 0;
    for (let i = 0; i < count; i++) {
      const top = position[3 * i + 2];
      const vertical = (classBits[i] & CLASS_VERTICAL) !== 0;
      const bottom = vertical ? top - depth[i] : top;
      if (!this.filter(top, bottom, this.level, vertical)) continue;
      if (vertical) walls[nWalls++] = i;
      else floors[nFloors++] = i;
    }
    this.disposeMeshes(tile);
    tile.shownCount = nFloors + nWalls;
    tile.meshes = [
      this.instances(tile, floorSquare, this.floorMaterial, floors.subarray(0, nFloors), false),
      this.instances(tile, unitBox, this.material, walls.subarray(0, nWalls), true),
    ].filter(Boolean);
    for (const mesh of tile.meshes) this.group.add(mesh);
  }

  /** One InstancedMesh for the listed patches of a tile, or null when there are none. */
  instances(tile, geometry, material, shown, vertical) {
    const n = shown.length;
    if (n === 0) return null;
    const { position, depth } = tile.patches;
    const mesh = new THREE.InstancedMesh(geometry, material, n);
    const matrices = mesh.instanceMatrix.array;
    for (let k = 0; k < n; k++) {
      const i = shown[k];
      const height = vertical ? Math.max(depth[i], SLAB) : 1;
      // A scale-and-translate matrix, written directly (column-major) rather than composed per box.
      const m = 16 * k;
      matrices[m] = CELL;
      matrices[m + 5] = CELL;
      matrices[m + 10] = height;
      matrices[m + 12] = position[3 * i];
      matrices[m + 13] = position[3 * i + 1];
      matrices[m + 14] = vertical ? position[3 * i + 2] - height / 2 : position[3 * i + 2];
      matrices[m + 15] = 1;
    }
    mesh.instanceMatrix.needsUpdate = true;
    mesh.instanceColor = new THREE.InstancedBufferAttribute(new Float32Array(3 * n), 3);
    mesh.userData = { tile, shown };
    this.colorMesh(mesh);
    // The bounds for culling and picking from the tile's extent, rather than InstancedMesh's per-instance
    // pass over every matrix: this runs on the main thread for each tile update.
    mesh.boundingSphere = tileBounds(tile.patches, shown, vertical);
    return mesh;
  }

  disposeMeshes(tile) {
    for (const mesh of tile.meshes ?? []) {
      mesh.removeFromParent();
      mesh.dispose();
    }
    tile.meshes = [];
  }

  colorMesh(mesh) {
    const { tile, shown } = mesh.userData;
    const color = new THREE.Color();
    const colors = mesh.instanceColor.array;
    const { position, classBits } = tile.patches;
    for (let k = 0; k < shown.length; k++) {
      const i = shown[k];
      patchColor(this.colorMode, position[3 * i + 2], classBits[i], color).toArray(colors, 3 * k);
    }
    mesh.instanceColor.needsUpdate = true;
  }

  setColorMode(mode) {
    if (mode === this.colorMode) return;
    this.colorMode = mode;
    for (const tile of this.tiles.values()) for (const mesh of tile.meshes) this.colorMesh(mesh);
  }

  /** Which patches to draw (PATCH_FILTERS) around the robot's ground height `level`. */
  setFilter(filter, level = this.level) {
    if (filter === this.filter && Math.abs(level - this.level) < 0.25) return;
    this.filter = filter;
    this.level = level;
    for (const tile of this.tiles.values()) this.buildMesh(tile);
  }

  /** The patch a ray hit: its top centre in the map frame. */
  patchAt(intersection) {
    const { tile, shown } = intersection.object.userData;
    const i = shown[intersection.instanceId];
    const p = tile.patches.position;
    const vertical = (tile.patches.classBits[i] & CLASS_VERTICAL) !== 0;
    return { x: p[3 * i], y: p[3 * i + 1], z: p[3 * i + 2], vertical };
  }

  get tileCount() {
    return this.tiles.size;
  }

  get drawnCount() {
    let n = 0;
    for (const tile of this.tiles.values()) n += tile.shownCount;
    return n;
  }
}
