// Merging a coarse level's boxes: neighbouring coarse cells floored at nearly one height become one rectangle,
// and wall boxes in a row along a wall one long box. A software GPU pays per triangle (measured: 1.5 to 2.5
// microseconds each on this project's CI machine, more than the pixels they cover at a distance), and a
// level of detail that is an approximation anyway loses nothing visible by it: MERGE_TOLERANCE is a hue
// shift of under 0.5 % in the height colours.
export const MERGE_TOLERANCE = 0.03; // m

/**
 * `floors`: whole-cell floors of one height band, { gx, gy (coarse cell indices), z, bits }. Calls
 * emit(gx0, gx1, gy0, gy1, z, bits) per rectangle (cells gx0..gx1-1 by gy0..gy1-1): runs along x, then
 * runs of equal extent stacked along y, each within MERGE_TOLERANCE of its first cell and of one class.
 */
export function mergeFloors(floors, emit, tolerance = MERGE_TOLERANCE) {
  if (floors.length === 0) return;
  floors.sort((a, b) => a.gy - b.gy || a.gx - b.gx);
  // Runs along x within each row.
  const runs = [];
  let run = null;
  for (const f of floors) {
    const continues = run && f.gy === run.gy && f.gx === run.gx1 && f.bits === run.bits && Math.abs(f.z - run.z0) <= tolerance;
    if (continues) {
      run.gx1 += 1;
      run.sum += f.z;
      run.n += 1;
    } else {
      run = { gy: f.gy, gx0: f.gx, gx1: f.gx + 1, z0: f.z, sum: f.z, n: 1, bits: f.bits };
      runs.push(run);
    }
  }
  // Runs with the same extent in consecutive rows, stacked.
  const open = new Map(); // "gx0,gx1,bits" -> rectangle still growing along y
  const flush = (rect) => emit(rect.gx0, rect.gx1, rect.gy0, rect.gy1, rect.sum / rect.n, rect.bits);
  for (const r of runs) {
    const key = `${r.gx0},${r.gx1},${r.bits}`;
    const rect = open.get(key);
    const z = r.sum / r.n;
    if (rect && rect.gy1 === r.gy && Math.abs(z - rect.z0) <= tolerance) {
      rect.gy1 += 1;
      rect.sum += r.sum;
      rect.n += r.n;
    } else {
      if (rect) flush(rect);
      open.set(key, { gx0: r.gx0, gx1: r.gx1, gy0: r.gy, gy1: r.gy + 1, z0: z, sum: r.sum, n: r.n, bits: r.bits });
    }
  }
  for (const rect of open.values()) flush(rect);
}

const EDGE = 1e-4; // m: boxes closer than this touch

/**
 * `walls`: boxes { x0, x1, y0, y1, z0, z1 }. Returns them with the ones that touch end to end along x (same
 * y extent, heights within `tolerance`) joined, then likewise along y: a straight wall is one box.
 */
export function mergeWalls(walls, tolerance = MERGE_TOLERANCE) {
  return joinBoxes(walls, tolerance);
}

/** Boxes { x0, x1, y0, y1, z0, z1, bits? } joined as mergeWalls joins walls, only boxes of equal `bits`. */
export function joinBoxes(boxes, tolerance = MERGE_TOLERANCE) {
  const alongX = joinRuns(boxes, 'x', 'y', tolerance);
  return joinRuns(alongX, 'y', 'x', tolerance);
}

function joinRuns(boxes, along, across, tolerance) {
  const [a0, a1, c0, c1] = [`${along}0`, `${along}1`, `${across}0`, `${across}1`];
  const sorted = [...boxes].sort((p, q) => p[c0] - q[c0] || p[c1] - q[c1] || p[a0] - q[a0] || (p.bits ?? 0) - (q.bits ?? 0));
  const joined = [];
  let last = null;
  for (const box of sorted) {
    const touches =
      last &&
      box.bits === last.bits &&
      Math.abs(box[c0] - last[c0]) < EDGE &&
      Math.abs(box[c1] - last[c1]) < EDGE &&
      Math.abs(box[a0] - last[a1]) < EDGE &&
      Math.abs(box.z0 - last.z0) <= tolerance &&
      Math.abs(box.z1 - last.z1) <= tolerance;
    if (touches) {
      last[a1] = box[a1];
      last.z0 = Math.min(last.z0, box.z0);
      last.z1 = Math.max(last.z1, box.z1);
    } else {
      last = { ...box };
      joined.push(last);
    }
  }
  return joined;
}
