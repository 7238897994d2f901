// Decodes a tile's Draco point set (proto/TILE_ENCODING.md) in DRACOLoader's web workers, so the page
// itself only copies the decoded arrays. The decoder (draco_wasm_wrapper.js, draco_decoder.wasm, and the
// asm.js draco_decoder.js for browsers without WebAssembly) comes from three's npm package: DRACOLoader
// names those files with `new URL(..., import.meta.url)`, so Vite copies them into the bundle's assets/
// and strata serves them with the app. Nothing is fetched from the internet (the robot may have none).
import { LinearSRGBColorSpace } from 'three';
import { DRACOLoader } from 'three/examples/jsm/loaders/DRACOLoader.js';

// Attributes by their Draco unique id, not their order (TILE_ENCODING.md).
const ATTRIBUTE_IDS = { position: 0, depth: 1, variance: 2, classBits: 3 };
const ATTRIBUTE_TYPES = {
  position: 'Float32Array',
  depth: 'Float32Array',
  variance: 'Uint8Array',
  classBits: 'Uint8Array',
};

export const CLASS_VERTICAL = 1;
export const CLASS_TRAVERSABLE = 2;

/**
 * An attribute's values as one packed array (itemSize values per point). DRACOLoader pads each point's
 * values to 4 bytes (WebGL's alignment) and returns an interleaved attribute then: a uint8 attribute holds
 * its point i at [4 i], not [i].
 */
function perPoint(attribute) {
  if (!attribute.isInterleavedBufferAttribute) return attribute.array;
  const { count, itemSize } = attribute;
  const { array, stride } = attribute.data;
  const packed = new array.constructor(count * itemSize);
  for (let i = 0; i < count; i++) {
    for (let c = 0; c < itemSize; c++) packed[i * itemSize + c] = array[i * stride + attribute.offset + c];
  }
  return packed;
}

export class TileDecoder {
  constructor() {
    // Two workers: the robot's computer has few cores, and the map server needs them more than we do.
    this.loader = new DRACOLoader().setWorkerLimit(2);
    this.loader.preload(); // fetch and compile the decoder now, while the WebSocket is still connecting
  }

  /** Resolves to { count, position (xyz), depth, classBits }: one entry per patch. */
  async decode(payload) {
    // The worker takes the buffer over (transfer): hand it a copy of exactly the payload's bytes.
    const buffer = payload.slice().buffer;
    const rethrow = (error) => {
      throw error;
    };
    const geometry = await this.loader.decodeDracoFile(
      buffer, (g) => g, ATTRIBUTE_IDS, ATTRIBUTE_TYPES, LinearSRGBColorSpace, rethrow);
    const patches = {
      count: geometry.getAttribute('position').count,
      position: perPoint(geometry.getAttribute('position')),
      depth: perPoint(geometry.getAttribute('depth')),
      classBits: perPoint(geometry.getAttribute('classBits')),
    };
    geometry.dispose();
    return patches;
  }

  dispose() {
    this.loader.dispose();
  }
}
