// One tile's boxes merged into one BufferGeometry: a floor is the top face of its box (2 triangles: from
// above, or from below, that is all one sees of a 4 cm slab), a wall or step its four sides and top (10).
// One geometry per tile rather than an instance per box: a tile is one draw call whatever it holds, and a
// coarse level of detail (tile_lod.js) is just a geometry with fewer boxes. Colours carry the lighting
// (lights.js), in sRGB, so map_material.js's unlit materials draw them as they are: floors first (group 0,
// double-sided), then walls (group 1, front faces only).
import * as THREE from 'three';
import { lambertShade } from './lights.js';
import { CLASS_VERTICAL } from './tile_decoder.js';

// The faces of a wall box: outward normal, and its four corners as (x: 0 = x0, 1 = x1; y; z) choices,
// counter-clockwise seen from outside.
const WALL_FACES = [
  { normal: [1, 0, 0], corners: [[1, 0, 0], [1, 1, 0], [1, 1, 1], [1, 0, 1]] },
  { normal: [-1, 0, 0], corners: [[0, 1, 0], [0, 0, 0], [0, 0, 1], [0, 1, 1]] },
  { normal: [0, 1, 0], corners: [[1, 1, 0], [0, 1, 0], [0, 1, 1], [1, 1, 1]] },
  { normal: [0, -1, 0], corners: [[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 0, 1]] },
  { normal: [0, 0, 1], corners: [[0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]] },
];
const FACE_SHADES = WALL_FACES.map((face) => lambertShade(new THREE.Vector3(...face.normal)));
const TOP_SHADE = FACE_SHADES[4];

/** A linear RGB channel in sRGB (what the canvas shows). */
function toSRGB(c) {
  return c <= 0.0031308 ? 12.92 * c : 1.055 * Math.min(c, 1) ** (1 / 2.4) - 0.055;
}

/**
 * A BufferGeometry for `boxes` (tile_lod.js's box list: extents x0..x1, y0..y1, z0..z1, class bits and
 * linear RGB colours), its bounds set to `sphere` (the tile's, for culling) rather than computed.
 */
export function buildTileGeometry(boxes, sphere) {
  const { count, x0, x1, y0, y1, z0, z1, bits, color } = boxes;
  let walls = 0;
  for (let b = 0; b < count; b++) walls += bits[b] & CLASS_VERTICAL;
  const vertexCount = 4 * (count - walls) + 4 * WALL_FACES.length * walls;
  const positions = new Float32Array(3 * vertexCount);
  const colors = new Float32Array(3 * vertexCount);
  const index = vertexCount > 65535 ? new Uint32Array((vertexCount / 4) * 6) : new Uint16Array((vertexCount / 4) * 6);
  let v = 0;
  let i = 0;
  const xs = [0, 0];
  const ys = [0, 0];
  const zs = [0, 0];
  const quad = (corners, b, shade) => {
    const r = toSRGB(color[3 * b] * shade.r);
    const g = toSRGB(color[3 * b + 1] * shade.g);
    const bl = toSRGB(color[3 * b + 2] * shade.b);
    for (const [cx, cy, cz] of corners) {
      positions[3 * v] = xs[cx];
      positions[3 * v + 1] = ys[cy];
      positions[3 * v + 2] = zs[cz];
      colors[3 * v] = r;
      colors[3 * v + 1] = g;
      colors[3 * v + 2] = bl;
      v++;
    }
    const first = v - 4;
    index[i++] = first;
    index[i++] = first + 1;
    index[i++] = first + 2;
    index[i++] = first;
    index[i++] = first + 2;
    index[i++] = first + 3;
  };
  const corners = (b) => {
    xs[0] = x0[b];
    xs[1] = x1[b];
    ys[0] = y0[b];
    ys[1] = y1[b];
    zs[0] = z0[b];
    zs[1] = z1[b];
  };
  for (let b = 0; b < count; b++) {
    if (bits[b] & CLASS_VERTICAL) continue;
    corners(b);
    quad(WALL_FACES[4].corners, b, TOP_SHADE); // the top face, at z1 (= z0 for a floor)
  }
  const floorIndices = i;
  for (let b = 0; b < count; b++) {
    if (!(bits[b] & CLASS_VERTICAL)) continue;
    corners(b);
    for (let f = 0; f < WALL_FACES.length; f++) quad(WALL_FACES[f].corners, b, FACE_SHADES[f]);
  }
  const geometry = new THREE.BufferGeometry();
  geometry.addGroup(0, floorIndices, 0);
  geometry.addGroup(floorIndices, i - floorIndices, 1);
  geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  geometry.setAttribute('color', new THREE.BufferAttribute(colors, 3));
  geometry.setIndex(new THREE.BufferAttribute(index, 1));
  geometry.boundingSphere = sphere;
  return geometry;
}
