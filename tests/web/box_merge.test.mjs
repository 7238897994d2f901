// The map renderer's merging of coarse boxes (web/src/box_merge.js): what decides how many triangles a far
// tile costs. Pure functions, run by node's test runner without a browser.
import assert from 'node:assert/strict';
import { test } from 'node:test';

import { MERGE_TOLERANCE, joinBoxes, mergeFloors, mergeWalls } from '../../web/src/box_merge.js';

function rectangles(floors, tolerance) {
  const out = [];
  mergeFloors(floors, (gx0, gx1, gy0, gy1, z, bits) => out.push({ gx0, gx1, gy0, gy1, z, bits }), tolerance);
  return out;
}

function grid(width, height, z = 0.0, bits = 1) {
  const cells = [];
  for (let gy = 0; gy < height; ++gy) for (let gx = 0; gx < width; ++gx) cells.push({ gx, gy, z, bits });
  return cells;
}

test('a level floor of 4 x 3 cells is one rectangle at its height', () => {
  const out = rectangles(grid(4, 3, 1.25));
  assert.deepEqual(out, [{ gx0: 0, gx1: 4, gy0: 0, gy1: 3, z: 1.25, bits: 1 }]);
});

test('floors within the tolerance merge at their mean height; a step beyond it, another class or a gap split', () => {
  const gentle = grid(2, 1).map((c, i) => ({ ...c, z: i * 0.02 }));
  assert.equal(rectangles(gentle).length, 1);
  assert.ok(Math.abs(rectangles(gentle)[0].z - 0.01) < 1e-12);

  const step = grid(2, 1).map((c, i) => ({ ...c, z: i * (MERGE_TOLERANCE + 0.01) }));
  assert.equal(rectangles(step).length, 2);

  const classes = grid(2, 1).map((c, i) => ({ ...c, bits: i + 1 }));
  assert.equal(rectangles(classes).length, 2);

  const gap = [{ gx: 0, gy: 0, z: 0, bits: 1 }, { gx: 2, gy: 0, z: 0, bits: 1 }];
  assert.equal(rectangles(gap).length, 2);
});

test('rows stack only where their runs have the same extent', () => {
  // An L: a row of 3 under a row of 1: two rectangles, every cell covered once.
  const l = [...grid(3, 1), { gx: 0, gy: 1, z: 0, bits: 1 }];
  const out = rectangles(l);
  assert.equal(out.length, 2);
  const area = out.reduce((sum, r) => sum + (r.gx1 - r.gx0) * (r.gy1 - r.gy0), 0);
  assert.equal(area, 4);
});

test('wall boxes in a row along a wall join into one; across a gap or at another height they do not', () => {
  const wall = [0, 1, 2].map((i) => ({ x0: i * 0.4, x1: (i + 1) * 0.4, y0: 0, y1: 0.1, z0: 0, z1: 2 }));
  const joined = mergeWalls(wall);
  assert.equal(joined.length, 1);
  assert.ok(Math.abs(joined[0].x1 - 1.2) < 1e-9 && joined[0].x0 === 0 && joined[0].z1 === 2);

  const gapped = [wall[0], wall[2]];
  assert.equal(mergeWalls(gapped).length, 2);

  const taller = [wall[0], { ...wall[1], z1: 2 + MERGE_TOLERANCE + 0.01 }];
  assert.equal(mergeWalls(taller).length, 2);

  // Along y too, and only boxes of one class.
  const column = [0, 1].map((i) => ({ x0: 0, x1: 0.1, y0: i * 0.4, y1: (i + 1) * 0.4, z0: 0, z1: 1, bits: 2 }));
  assert.equal(joinBoxes(column).length, 1);
  assert.equal(joinBoxes([column[0], { ...column[1], bits: 3 }]).length, 2);
});
