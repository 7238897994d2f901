// The map from the server's binary frames: Draco tiles into the tile layer (newest version wins, however
// the decodes finish) and the drivable map's PNGs into the occupancy layer.
import { FRAME_OCCUPANCY, FRAME_TILE, parseFrame } from './frames.js';
import { TileDecoder } from './tile_decoder.js';

export class MapFeed {
  /** `onMapArrived`: called with every tile frame (the ground truth may give way to the map). */
  constructor(view, perf, { onMapArrived }) {
    this.view = view;
    this.perf = perf;
    this.onMapArrived = onMapArrived;
    this.decoder = new TileDecoder();
    this.newestTileVersion = new Map(); // "x,y" -> newest version announced, so late decodes never win
  }

  /** A fresh connection resends every tile; tiles deleted while we were away would otherwise linger. */
  clear() {
    this.view.tiles.clear();
    this.newestTileVersion.clear();
  }

  receive(buffer) {
    const frame = parseFrame(buffer);
    if (frame?.kind === FRAME_TILE) {
      this.onMapArrived();
      this.receiveTile(frame);
    } else if (frame?.kind === FRAME_OCCUPANCY) {
      this.view.occupancy.add(frame).then(() => this.view.requestRender());
    }
  }

  async receiveTile(frame) {
    const { view, perf } = this;
    const key = `${frame.tileX},${frame.tileY}`;
    perf.firstTileFrameMs ??= performance.now();
    if ((this.newestTileVersion.get(key) ?? -1) >= frame.version) return;
    this.newestTileVersion.set(key, frame.version);
    let patches = null;
    if (frame.payload.byteLength > 0) {
      try {
        patches = await this.decoder.decode(frame.payload);
      } catch (error) {
        console.warn(`strata: tile ${key} did not decode`, error);
        return;
      }
    }
    if (this.newestTileVersion.get(key) !== frame.version) return; // a newer version arrived meanwhile
    perf.firstTileDecodedMs ??= performance.now();
    const start = performance.now();
    view.tiles.setTile(frame.tileX, frame.tileY, frame.version, patches);
    view.requestRender();
    const took = performance.now() - start;
    perf.maxTileMainThreadMs = Math.max(perf.maxTileMainThreadMs, took);
    if (took > 16) perf.slowTileUpdates.push({ n: perf.tileUpdates, ms: Math.round(took * 10) / 10, patches: patches?.count ?? 0 });
    perf.tileUpdates += 1;
  }
}
