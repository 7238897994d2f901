// Colours of MLS patches: by height (a ramp over the map's usual range of levels) or by traversability
// (what the planner may drive on: green; other horizontal surfaces: amber; walls and steps: grey-red).
import * as THREE from 'three';
import { CLASS_TRAVERSABLE, CLASS_VERTICAL } from './tile_decoder.js';

export const COLOR_MODES = ['height', 'traversability'];

// A fixed range, so a colour means the same height everywhere and tiles never need recolouring when the
// map grows taller: -1 m (blue) to 7 m (red), about two storeys of the campus.
const HEIGHT_LOW = -1;
const HEIGHT_HIGH = 7;

const traversable = new THREE.Color(0x3fb950);
const blockedFloor = new THREE.Color(0xd29922);
const wall = new THREE.Color(0x9a6a6a);

/** Writes patch i's colour into `out` (a THREE.Color). */
export function patchColor(mode, z, classBits, out) {
  if (mode === 'traversability') {
    if (classBits & CLASS_VERTICAL) return out.copy(wall);
    return out.copy(classBits & CLASS_TRAVERSABLE ? traversable : blockedFloor);
  }
  const t = THREE.MathUtils.clamp((z - HEIGHT_LOW) / (HEIGHT_HIGH - HEIGHT_LOW), 0, 1);
  const lightness = classBits & CLASS_VERTICAL ? 0.42 : 0.55; // walls a shade darker than floors
  return out.setHSL(0.66 * (1 - t), 0.7, lightness);
}
