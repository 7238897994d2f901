// Regions of REGION_TILES x REGION_TILES tiles, drawn as one mesh when the whole region is far enough for a
// coarse level: a zoomed-out million-patch map is some 800 tiles, and a software GPU pays for every draw
// call (measured: 784 calls cost more than their 38 000 triangles), so far away it draws some 50 regions
// instead. Near regions leave their tiles to be drawn one by one, each at its own level of detail.
import * as THREE from 'three';
import { buildTileGeometry } from './tile_geometry.js';

export const REGION_TILES = 4;

/** The key of the region holding tile (tileX, tileY). */
export function regionKey(tileX, tileY) {
  return `${Math.floor(tileX / REGION_TILES)},${Math.floor(tileY / REGION_TILES)}`;
}

export class Region {
  constructor(materials, emptyGeometry) {
    this.tiles = new Set();
    this.box = new THREE.Box3();
    this.sphere = new THREE.Sphere();
    this.levels = []; // merged geometry per coarse level, built when first drawn
    this.emptyGeometry = emptyGeometry;
    this.mesh = new THREE.Mesh(emptyGeometry, materials);
    this.mesh.matrixAutoUpdate = false;
    this.mesh.visible = false;
  }

  /** A member tile changed (added, replaced, removed, filtered, recoloured): bounds anew, geometry dropped. */
  changed() {
    this.box.makeEmpty();
    for (const tile of this.tiles) if (tile.shown.length > 0) this.box.union(tile.box);
    this.box.getBoundingSphere(this.sphere);
    for (const geometry of this.levels) geometry?.dispose();
    this.levels = [];
    this.mesh.geometry = this.emptyGeometry;
  }

  /** The region's geometry at coarse `level`, built from `boxes(tiles, level)` (a box list) when first asked. */
  geometry(level, boxes) {
    this.levels[level] ??= buildTileGeometry(boxes([...this.tiles], level), this.sphere);
    return this.levels[level];
  }

  dispose() {
    for (const geometry of this.levels) geometry?.dispose();
    this.levels = [];
    this.mesh.removeFromParent();
  }
}
