// The MLS map in the 3D view: per tile one mesh, its geometry the tile's patches merged (tile_geometry.js)
// at the level of detail its distance calls for (tile_lod.js), built when first needed and kept. A vertical
// patch (wall, step) is a column reaching `depth` below its top; a horizontal patch the top of a slab at
// its height. Tiles are replaced in place when a newer version arrives, and removed when an empty one does.
// Far away, whole regions of tiles are drawn as one mesh (tile_regions.js). Picking works on the
// full-detail patches (tile_pick.js), whatever level is drawn.
import * as THREE from 'three';
import { createMapMaterials } from './map_material.js';
import { CLASS_VERTICAL } from './tile_decoder.js';
import { buildTileGeometry } from './tile_geometry.js';
import {
  CELL,
  concatBoxes,
  joinBoxList,
  levelBoxes,
  levelFor,
  LOD_CELL_SIZES,
  patchBottom,
  pixelsPerMetre,
  SLAB,
} from './tile_lod.js';
import { pickPatch } from './tile_pick.js';
import { Region, regionKey } from './tile_regions.js';

// Which patches a view draws, relative to the ground the robot stands on (`level`, m). The 3D view hides
// what hangs above the robot's head so the robot stays in sight (thesis 3.3.1); the top view shows only
// the surfaces at the robot's level (a floor, and the walls around it), not the storey below or above.
export const PATCH_FILTERS = {
  all: () => true,
  belowHead: (top, bottom, level) => bottom <= level + 2.0,
  atLevel: (top, bottom, level, vertical) =>
    vertical ? bottom <= level + 2.0 && top >= level - 0.3 : Math.abs(top - level) <= 0.5,
};

// Geometry built per frame at most this long (ms): zooming in on a big map needs the full detail of many
// tiles at once, and they come in over a few frames (drawn coarser meanwhile) rather than in one long one.
const BUILD_BUDGET_MS = 12;

// Frames slower than SLOW_FRAME_MS make the map coarser (coarse levels chosen up to MAX_DETAIL_SCALE times
// nearer), faster than FAST_FRAME_MS finer again: on a slow (software) GPU a zoomed-in view of full-detail
// tiles costs seconds per frame otherwise, while a fast one keeps full detail. Tiles whose 0.1 m cells
// cover LOD_CELL_PIXELS * MAX_DETAIL_SCALE / 4 or more pixels keep full detail whatever the GPU.
const SLOW_FRAME_MS = 40;
const FAST_FRAME_MS = 25;
const MAX_DETAIL_SCALE = 4;

const emptyGeometry = new THREE.BufferGeometry();
const frustum = new THREE.Frustum();
const viewProjection = new THREE.Matrix4();
const bufferSize = new THREE.Vector2();

export class TileLayer {
  constructor(scene) {
    this.group = new THREE.Group();
    this.group.name = 'map';
    scene.add(this.group);
    this.materials = createMapMaterials(); // [floors, walls]: unlit, the lighting is in the vertex colours
    // "x,y" -> { version, patches, shown, box, sphere, levels (geometries), boxes (coarse), mesh, region }
    this.tiles = new Map();
    this.regions = new Map(); // "rx,ry" -> Region
    this.colorMode = 'height';
    this.filter = PATCH_FILTERS.belowHead;
    this.level = 0;
    this.patchCount = 0;
    this.tilesPerLevel = LOD_CELL_SIZES.map(() => 0); // drawn in the last frame, by level of detail
    this.detailScale = 1; // 1: the coarse levels where LOD_CELL_PIXELS puts them; more: nearer (adaptDetail)
  }

  /** A frame took `frameMs` (until the GPU had drawn it): coarser if that is slow, finer if fast. */
  adaptDetail(frameMs) {
    if (frameMs > SLOW_FRAME_MS) this.detailScale = Math.min(this.detailScale * 1.25, MAX_DETAIL_SCALE);
    else if (frameMs < FAST_FRAME_MS) this.detailScale = Math.max(this.detailScale / 1.1, 1);
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
    if (old) this.removeTile(old);
    if (!patches || patches.count === 0) {
      this.tiles.delete(key);
      return;
    }
    const mesh = new THREE.Mesh(emptyGeometry, this.materials);
    mesh.matrixAutoUpdate = false; // the map frame: never moves
    mesh.visible = false; // until update() gives it a geometry
    const region = this.regionOf(tileX, tileY);
    const tile = { version, patches, shown: null, box: new THREE.Box3(), sphere: new THREE.Sphere(), levels: [], boxes: [], mesh, region };
    this.tiles.set(key, tile);
    region.tiles.add(tile);
    this.patchCount += patches.count;
    this.select(tile);
    this.group.add(mesh);
  }

  regionOf(tileX, tileY) {
    const key = regionKey(tileX, tileY);
    let region = this.regions.get(key);
    if (!region) {
      region = new Region(this.materials, emptyGeometry);
      region.key = key;
      this.regions.set(key, region);
      this.group.add(region.mesh);
    }
    return region;
  }

  removeTile(tile) {
    this.patchCount -= tile.patches.count;
    this.dropGeometry(tile);
    tile.mesh.removeFromParent();
    const { region } = tile;
    region.tiles.delete(tile);
    if (region.tiles.size > 0) {
      region.changed();
    } else {
      region.dispose();
      this.regions.delete(region.key);
    }
  }

  clear() {
    for (const tile of this.tiles.values()) this.removeTile(tile);
    this.tiles.clear();
  }

  /** The tile's boxes at a coarse level (kept: regions are merged from them). */
  boxesOf(tile, level) {
    tile.boxes[level] ??= levelBoxes(tile.patches, tile.shown, level, this.colorMode);
    return tile.boxes[level];
  }

  /** The tile's patches the filter lets through, and their bounds (for culling, picking, detail). */
  select(tile) {
    const { count, position, classBits } = tile.patches;
    const shown = new Uint32Array(count);
    let n = 0;
    const { min, max } = tile.box.makeEmpty();
    for (let i = 0; i < count; i++) {
      const top = position[3 * i + 2];
      const bottom = patchBottom(tile.patches, i);
      if (!this.filter(top, bottom, this.level, (classBits[i] & CLASS_VERTICAL) !== 0)) continue;
      shown[n++] = i;
      min.set(Math.min(min.x, position[3 * i]), Math.min(min.y, position[3 * i + 1]), Math.min(min.z, bottom));
      max.set(Math.max(max.x, position[3 * i]), Math.max(max.y, position[3 * i + 1]), Math.max(max.z, top));
    }
    tile.shown = shown.subarray(0, n);
    if (n > 0) tile.box.expandByVector(new THREE.Vector3(CELL / 2, CELL / 2, SLAB));
    tile.box.getBoundingSphere(tile.sphere);
    this.dropGeometry(tile);
  }

  /** Forgets what was built from the tile's patches (its region's merged geometry too). */
  dropGeometry(tile) {
    for (const geometry of tile.levels) geometry?.dispose();
    tile.levels = [];
    tile.boxes = [];
    tile.mesh.geometry = emptyGeometry;
    tile.mesh.visible = false;
    tile.region.changed();
  }

  /**
   * Before a frame: hides the tiles outside the camera's view and gives the others the geometry of the
   * level of detail their distance calls for. Returns whether some tile was drawn coarser than it should
   * be (its geometry is still to be built: draw again soon).
   */
  update(camera, renderer) {
    const height = renderer.getDrawingBufferSize(bufferSize).y;
    camera.updateMatrixWorld();
    frustum.setFromProjectionMatrix(viewProjection.multiplyMatrices(camera.projectionMatrix, camera.matrixWorldInverse));
    this.tilesPerLevel.fill(0);
    const start = performance.now();
    const overBudget = () => performance.now() - start > BUILD_BUDGET_MS;
    let pending = false;
    for (const region of this.regions.values()) {
      const inView = !region.box.isEmpty() && frustum.intersectsBox(region.box);
      // The level its nearest point calls for: its tiles all call for this one or a coarser one.
      const regionLevel = inView ? levelFor(pixelsPerMetre(region.box, camera, height), this.detailScale) : 0;
      region.mesh.visible = regionLevel > 0;
      if (region.mesh.visible) {
        let level = regionLevel;
        if (!region.levels[level] && overBudget()) {
          level = nearestBuilt(region.levels, level, 1) ?? level;
          pending = true;
        }
        region.mesh.geometry = region.geometry(level, (tiles, l) =>
          joinBoxList(concatBoxes(tiles.map((tile) => this.boxesOf(tile, l))), this.colorMode));
        for (const tile of region.tiles) if (tile.shown.length > 0) this.tilesPerLevel[level] += 1;
      }
      for (const tile of region.tiles) {
        const { mesh } = tile;
        mesh.visible = inView && regionLevel === 0 && tile.shown.length > 0 && frustum.intersectsBox(tile.box);
        if (!mesh.visible) continue;
        const wanted = levelFor(pixelsPerMetre(tile.box, camera, height), this.detailScale);
        let level = wanted;
        if (!tile.levels[wanted] && overBudget()) {
          // Out of time this frame: the nearest level already built, else the coarsest (cheap to build).
          level = nearestBuilt(tile.levels, wanted, 0) ?? LOD_CELL_SIZES.length - 1;
          pending = true;
        }
        tile.levels[level] ??= buildTileGeometry(level === 0 ? levelBoxes(tile.patches, tile.shown, 0, this.colorMode) : this.boxesOf(tile, level), tile.sphere);
        mesh.geometry = tile.levels[level];
        this.tilesPerLevel[level] += 1;
      }
    }
    return pending;
  }

  setColorMode(mode) {
    if (mode === this.colorMode) return;
    this.colorMode = mode;
    for (const tile of this.tiles.values()) this.dropGeometry(tile);
  }

  /** Which patches to draw (PATCH_FILTERS) around the robot's ground height `level`. */
  setFilter(filter, level = this.level) {
    if (filter === this.filter && Math.abs(level - this.level) < 0.25) return;
    this.filter = filter;
    this.level = level;
    for (const tile of this.tiles.values()) this.select(tile);
  }

  /** The shown patch a ray (THREE.Ray) hits first: its top centre in the map frame, and whether it is a
   * wall; or null. */
  pick(ray) {
    return this.group.visible ? pickPatch(this.tiles.values(), ray) : null;
  }

  get tileCount() {
    return this.tiles.size;
  }

  get drawnCount() {
    let n = 0;
    for (const tile of this.tiles.values()) n += tile.shown.length;
    return n;
  }
}

/** The built level (from `lowest` up) nearest to `wanted`, or undefined. */
function nearestBuilt(levels, wanted, lowest) {
  let best;
  levels.forEach((geometry, level) => {
    if (geometry && level >= lowest && (best === undefined || Math.abs(level - wanted) < Math.abs(best - wanted))) best = level;
  });
  return best;
}
