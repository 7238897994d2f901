// Levels of detail of a tile: the patches themselves (0.1 m cells), or coarse cells of 0.4 m and 0.8 m, each
// holding one floor per height band (0.5 m) and one box round its walls. A tile is drawn at the coarsest
// level whose cells stay small on screen (LOD_CELL_PIXELS): far away a 0.1 m cell is under a pixel, and its
// patch's 2 to 10 triangles are work a software GPU cannot afford a million times a frame.
import * as THREE from 'three';
import { joinBoxes, mergeFloors, mergeWalls } from './box_merge.js';
import { patchColor } from './patch_colors.js';
import { CLASS_TRAVERSABLE, CLASS_VERTICAL } from './tile_decoder.js';

export const CELL = 0.1; // m: the map's resolution (proto/TILE_ENCODING.md)
export const SLAB = 0.04; // m: the least height drawn for a vertical patch
const TILE_CELLS = 32;
export const LOD_CELL_SIZES = [CELL, 0.4, 0.8]; // m: level 0 is full detail; each divides a tile's 3.2 m
export const LOD_CELL_PIXELS = 8; // the most a coarse cell may cover on screen (drawing buffer pixels)
// m: floors of a coarse cell within one band of height are one surface. The bands are centred on multiples
// of BAND, so a (rough) floor at 0 m stays in one band rather than straddling two.
const BAND = 0.5;
// A coarse cell this much floored (in one band) is drawn wholly floored: a wall through a cell takes a row
// of its patches, and the floor under the wall is hidden by it.
const WHOLE_FLOOR = 0.7;

/** A list of axis-aligned boxes, with room for `capacity` (a floor's box is flat: z0 = z1). */
function boxList(capacity) {
  return {
    count: 0,
    x0: new Float32Array(capacity),
    x1: new Float32Array(capacity),
    y0: new Float32Array(capacity),
    y1: new Float32Array(capacity),
    z0: new Float32Array(capacity),
    z1: new Float32Array(capacity),
    bits: new Uint8Array(capacity), // class bits (tile_decoder.js): vertical, traversable
    color: new Float32Array(3 * capacity),
  };
}

const scratchColor = new THREE.Color();

function pushBox(boxes, x0, x1, y0, y1, z0, z1, classBits, colorMode, colorZ) {
  const b = boxes.count++;
  boxes.x0[b] = x0;
  boxes.x1[b] = x1;
  boxes.y0[b] = y0;
  boxes.y1[b] = y1;
  boxes.z0[b] = z0;
  boxes.z1[b] = z1;
  boxes.bits[b] = classBits;
  patchColor(colorMode, colorZ, classBits, scratchColor).toArray(boxes.color, 3 * b);
}

/** The bottom of a patch's box: a wall reaches `depth` below its top (at least SLAB), a floor is its top. */
export function patchBottom(patches, i) {
  const top = patches.position[3 * i + 2];
  return patches.classBits[i] & CLASS_VERTICAL ? top - Math.max(patches.depth[i], SLAB) : top;
}

/** The boxes of level `level` for a tile's `shown` patches (indices into `patches`). */
export function levelBoxes(patches, shown, level, colorMode) {
  return level === 0 ? patchBoxes(patches, shown, colorMode) : coarseBoxes(patches, shown, LOD_CELL_SIZES[level], colorMode);
}

/**
 * Full detail: a box per wall patch, and the floor patches' squares, neighbours within box_merge.js's
 * tolerance (3 cm) merged into rectangles. Near the camera a floor is thousands of cells, 2 triangles
 * each, and what a software GPU spends its frame on (zoomed in at 250 k patches: 41 k triangles, 17
 * frames/s); a rectangle at their mean height shows the same floor (picking reads the patches themselves).
 */
function patchBoxes(patches, shown, colorMode) {
  const { position, classBits } = patches;
  const boxes = boxList(shown.length);
  const floors = [];
  for (const i of shown) {
    // The cell's edges from its index, so that neighbours' edges are the very same numbers: no cracks.
    const cx = Math.floor(position[3 * i] / CELL);
    const cy = Math.floor(position[3 * i + 1] / CELL);
    const top = position[3 * i + 2];
    if (classBits[i] & CLASS_VERTICAL) {
      pushBox(boxes, cx * CELL, (cx + 1) * CELL, cy * CELL, (cy + 1) * CELL, patchBottom(patches, i), top, classBits[i], colorMode, top);
    } else {
      floors.push({ gx: cx, gy: cy, z: top, bits: classBits[i] });
    }
  }
  mergeFloors(floors, (gx0, gx1, gy0, gy1, z, bits) =>
    pushBox(boxes, gx0 * CELL, gx1 * CELL, gy0 * CELL, gy1 * CELL, z, z, bits, colorMode, z));
  return boxes;
}

/**
 * Coarse cells of `size` m: per cell one box round its walls (their extent: a wall stays a thin line along
 * its side of the cell) and per band of height one floor at the floors' mean height over their extent,
 * traversable when most of its patches are. Floors that cover their whole cell merge with their
 * neighbours', and walls in a row join (box_merge.js).
 */
function coarseBoxes(patches, shown, size, colorMode) {
  const { position, classBits } = patches;
  // key -> [x0, x1, y0, y1, z0, z1, sum of tops, count, traversable count, vertical, gx, gy, band]
  const groups = new Map();
  const half = CELL / 2;
  for (const i of shown) {
    const x = position[3 * i];
    const y = position[3 * i + 1];
    const top = position[3 * i + 2];
    const vertical = classBits[i] & CLASS_VERTICAL;
    // A number for (coarse cell, band), walls in band 0: a string key per patch costs more than the rest.
    const band = vertical ? 0 : Math.min(Math.max(Math.floor(top / BAND + 0.5) + 512, 1), 1023);
    const gx = Math.floor(x / size);
    const gy = Math.floor(y / size);
    const key = ((gx + 32768) * 65536 + gy + 32768) * 1024 + band;
    let g = groups.get(key);
    if (!g) {
      g = [Infinity, -Infinity, Infinity, -Infinity, Infinity, -Infinity, 0, 0, 0, vertical, gx, gy, band];
      groups.set(key, g);
    }
    g[0] = Math.min(g[0], x - half);
    g[1] = Math.max(g[1], x + half);
    g[2] = Math.min(g[2], y - half);
    g[3] = Math.max(g[3], y + half);
    g[4] = Math.min(g[4], patchBottom(patches, i));
    g[5] = Math.max(g[5], top);
    g[6] += top;
    g[7] += 1;
    if (classBits[i] & CLASS_TRAVERSABLE) g[8] += 1;
  }
  const boxes = boxList(groups.size);
  const cellsPerCoarse = Math.round(size / CELL) ** 2;
  const wholeFloors = new Map(); // band -> [{ gx, gy, z, bits }]: floors drawn over their whole coarse cell
  const walls = [];
  for (const g of groups.values()) {
    if (g[9]) {
      walls.push({ x0: g[0], x1: g[1], y0: g[2], y1: g[3], z0: g[4], z1: g[5] });
      continue;
    }
    const mean = g[6] / g[7];
    const bits = 2 * g[8] >= g[7] ? CLASS_TRAVERSABLE : 0;
    if (g[7] >= WHOLE_FLOOR * cellsPerCoarse) {
      if (!wholeFloors.has(g[12])) wholeFloors.set(g[12], []);
      wholeFloors.get(g[12]).push({ gx: g[10], gy: g[11], z: mean, bits });
    } else {
      pushBox(boxes, g[0], g[1], g[2], g[3], mean, mean, bits, colorMode, mean);
    }
  }
  for (const w of mergeWalls(walls)) pushBox(boxes, w.x0, w.x1, w.y0, w.y1, w.z0, w.z1, CLASS_VERTICAL, colorMode, w.z1);
  for (const floors of wholeFloors.values()) {
    mergeFloors(floors, (gx0, gx1, gy0, gy1, z, bits) =>
      pushBox(boxes, gx0 * size, gx1 * size, gy0 * size, gy1 * size, z, z, bits, colorMode, z));
  }
  return boxes;
}

/** One box list holding all of `lists`. */
export function concatBoxes(lists) {
  const count = lists.reduce((n, list) => n + list.count, 0);
  const out = boxList(count);
  out.count = count;
  for (const name of ['x0', 'x1', 'y0', 'y1', 'z0', 'z1', 'bits', 'color']) {
    const width = name === 'color' ? 3 : 1;
    let at = 0;
    for (const list of lists) {
      out[name].set(list[name].subarray(0, width * list.count), at);
      at += width * list.count;
    }
  }
  return out;
}

/**
 * `boxes` with the ones that touch end to end and match (class, heights within box_merge.js's tolerance)
 * joined, recoloured: a region's tiles' coarse boxes, whose floors and walls run on across tile borders.
 */
export function joinBoxList(boxes, colorMode) {
  const list = [];
  for (let b = 0; b < boxes.count; b++) {
    list.push({ x0: boxes.x0[b], x1: boxes.x1[b], y0: boxes.y0[b], y1: boxes.y1[b], z0: boxes.z0[b], z1: boxes.z1[b], bits: boxes.bits[b] });
  }
  const joined = joinBoxes(list);
  const out = boxList(joined.length);
  for (const j of joined) {
    // A floor is drawn at its top: joined floors at the highest of theirs, within the tolerance.
    const z0 = j.bits & CLASS_VERTICAL ? j.z0 : j.z1;
    pushBox(out, j.x0, j.x1, j.y0, j.y1, z0, j.z1, j.bits, colorMode, j.z1);
  }
  return out;
}

/** How many drawing-buffer pixels a metre at `box` covers, seen by `camera` on a buffer `height` px tall. */
export function pixelsPerMetre(box, camera, height) {
  if (camera.isOrthographicCamera) return (height * camera.zoom) / (camera.top - camera.bottom);
  const distance = Math.max(box.distanceToPoint(camera.position), 0.01);
  return (height * camera.zoom) / (2 * distance * Math.tan(THREE.MathUtils.degToRad(camera.fov) / 2));
}

/**
 * The coarsest level whose cells cover at most LOD_CELL_PIXELS at `pixelsPerMetre`, or `detailScale` times
 * that when the GPU cannot keep up (TileLayer.adaptDetail).
 */
export function levelFor(pixelsPerMetre, detailScale = 1) {
  for (let level = LOD_CELL_SIZES.length - 1; level > 0; level--) {
    if (LOD_CELL_SIZES[level] * pixelsPerMetre <= LOD_CELL_PIXELS * detailScale) return level;
  }
  return 0;
}

export const TILE_SIZE = TILE_CELLS * CELL; // m
