// Picking a patch with a ray, on the full-detail patches whatever level of detail a tile is drawn at: the
// goal and pose tools put the robot on the exact patch's top. Tiles are tried nearest first by where the
// ray enters their bounds, each patch as its box (tile_lod.js's patch boxes), with no geometry built.
import * as THREE from 'three';
import { CELL, patchBottom } from './tile_lod.js';
import { CLASS_VERTICAL } from './tile_decoder.js';

const entry = new THREE.Vector3();

// The ray's parameter interval inside the box being tested (module state: no allocation per patch).
let near = 0;
let far = Infinity;

/** Narrows [near, far] to where the ray (origin o, direction d along one axis) is within [lo, hi]. */
function clip(o, d, lo, hi) {
  if (Math.abs(d) < 1e-12) return o >= lo && o <= hi;
  const t1 = (lo - o) / d;
  const t2 = (hi - o) / d;
  near = Math.max(near, Math.min(t1, t2));
  far = Math.min(far, Math.max(t1, t2));
  return near <= far;
}

/** Where along the ray (unit direction d) it enters the box, or Infinity; only before `limit`. */
function enterBox(o, d, x0, x1, y0, y1, z0, z1, limit) {
  near = 0;
  far = limit;
  if (clip(o[0], d[0], x0, x1) && clip(o[1], d[1], y0, y1) && clip(o[2], d[2], z0, z1)) return near;
  return Infinity;
}

/**
 * The nearest shown patch `ray` (a THREE.Ray) hits among `tiles` (TileLayer's: patches, shown, box):
 * { x, y, z (its top), vertical }, or null.
 */
export function pickPatch(tiles, ray) {
  const candidates = [];
  for (const tile of tiles) {
    if (tile.shown.length === 0) continue;
    if (ray.intersectBox(tile.box, entry)) candidates.push({ tile, distance: entry.distanceTo(ray.origin) });
  }
  candidates.sort((a, b) => a.distance - b.distance);
  const o = ray.origin.toArray();
  const d = ray.direction.toArray();
  const half = CELL / 2;
  let best = null;
  let bestDistance = Infinity;
  for (const { tile, distance } of candidates) {
    if (distance > bestDistance) break; // this tile and the rest start beyond the nearest hit
    const { position } = tile.patches;
    for (const i of tile.shown) {
      const x = position[3 * i];
      const y = position[3 * i + 1];
      const top = position[3 * i + 2];
      const t = enterBox(o, d, x - half, x + half, y - half, y + half, patchBottom(tile.patches, i), top, bestDistance);
      if (t < bestDistance) {
        bestDistance = t;
        best = { tile, i };
      }
    }
  }
  if (!best) return null;
  const { position, classBits } = best.tile.patches;
  const i = best.i;
  return { x: position[3 * i], y: position[3 * i + 1], z: position[3 * i + 2], vertical: (classBits[i] & CLASS_VERTICAL) !== 0 };
}
