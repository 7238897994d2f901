// A PNG decoder for the tests that look at pixels: 8-bit greyscale, grey + alpha, RGB and RGBA images,
// not interlaced, which is what Chromium's screenshots and the server's occupancy images are. Node's zlib
// inflates; the rest is the PNG specification's scanline filters. Written here rather than taken from npm:
// the test's reading of a pixel then owes nothing to the browser under test, and tests/node_modules needs
// no package the machine's npm cache lacks.
import { inflateSync } from 'node:zlib';

const SIGNATURE = Buffer.from([0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a]);
const CHANNELS = { 0: 1, 2: 3, 4: 2, 6: 4 }; // colour type -> samples per pixel

/** { width, height, channels, data }: data holds `channels` bytes per pixel, rows top to bottom. */
export function decodePng(buffer) {
  if (!buffer.subarray(0, 8).equals(SIGNATURE)) throw new Error('not a PNG');
  let header = null;
  const compressed = [];
  for (let at = 8; at < buffer.length; ) {
    const length = buffer.readUInt32BE(at);
    const type = buffer.toString('latin1', at + 4, at + 8);
    const body = buffer.subarray(at + 8, at + 8 + length);
    if (type === 'IHDR') {
      header = {
        width: body.readUInt32BE(0),
        height: body.readUInt32BE(4),
        depth: body[8],
        colourType: body[9],
        interlace: body[12],
      };
    } else if (type === 'IDAT') {
      compressed.push(body);
    } else if (type === 'IEND') {
      break;
    }
    at += 12 + length;
  }
  const channels = CHANNELS[header?.colourType];
  if (!channels || header.depth !== 8 || header.interlace !== 0) {
    throw new Error(`unsupported PNG: ${JSON.stringify(header)}`);
  }
  const { width, height } = header;
  const raw = inflateSync(Buffer.concat(compressed));
  const stride = width * channels;
  const data = Buffer.alloc(stride * height);
  for (let y = 0; y < height; y++) {
    const filter = raw[y * (stride + 1)];
    const source = y * (stride + 1) + 1;
    const row = y * stride;
    for (let i = 0; i < stride; i++) {
      const a = i >= channels ? data[row + i - channels] : 0; // left
      const b = y > 0 ? data[row - stride + i] : 0; // up
      const c = i >= channels && y > 0 ? data[row - stride + i - channels] : 0; // up left
      let predicted;
      if (filter === 0) predicted = 0;
      else if (filter === 1) predicted = a;
      else if (filter === 2) predicted = b;
      else if (filter === 3) predicted = (a + b) >> 1;
      else if (filter === 4) predicted = paeth(a, b, c);
      else throw new Error(`PNG row ${y}: filter ${filter}`);
      data[row + i] = (raw[source + i] + predicted) & 0xff;
    }
  }
  return { width, height, channels, data };
}

function paeth(a, b, c) {
  const p = a + b - c;
  const pa = Math.abs(p - a);
  const pb = Math.abs(p - b);
  const pc = Math.abs(p - c);
  if (pa <= pb && pa <= pc) return a;
  return pb <= pc ? b : c;
}

/** [r, g, b] of the pixel at (x, y) (greyscale repeated). */
export function rgbAt({ width, channels, data }, x, y) {
  const at = (Math.floor(y) * width + Math.floor(x)) * channels;
  return channels < 3 ? [data[at], data[at], data[at]] : [data[at], data[at + 1], data[at + 2]];
}
