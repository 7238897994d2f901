// Binary frames from the server (proto/PROTOCOL.md, "Binary frames"): a common little-endian header, then
// the payload at header_bytes, so later layouts that add header fields still parse here.
export const FRAME_TILE = 1;
export const FRAME_OCCUPANCY = 2;

/** The frame's fields and its payload (a view, not a copy), or null for kinds this client does not know. */
export function parseFrame(buffer) {
  if (buffer.byteLength < 24) return null;
  const view = new DataView(buffer);
  const kind = view.getUint8(0);
  const headerBytes = view.getUint16(2, true);
  const common = {
    kind,
    version: Number(view.getBigUint64(8, true)),
    stamp: view.getFloat64(16, true),
    payload: new Uint8Array(buffer, headerBytes),
  };
  if (kind === FRAME_TILE && headerBytes >= 40) {
    return {
      ...common,
      tileX: view.getInt32(24, true),
      tileY: view.getInt32(28, true),
      patches: view.getUint32(32, true),
    };
  }
  if (kind === FRAME_OCCUPANCY && headerBytes >= 64) {
    return {
      ...common,
      originX: view.getFloat64(24, true),
      originY: view.getFloat64(32, true),
      resolution: view.getFloat64(40, true),
      levelZ: view.getFloat64(48, true),
      width: view.getUint32(56, true),
      height: view.getUint32(60, true),
    };
  }
  return null;
}
