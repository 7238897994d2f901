// Benchmark (not a test): how fast the web client shows the map, and how long a tile update holds the
// page's main thread. Prints JSON.
//  1. Live: the real server maps while driving (lidar, simulator sped up) until the map has --tiles
//     tiles, with a page watching: the longest main-thread part of a tile update (decoding itself runs
//     in DRACOLoader's workers) and the long tasks, whatever caused them.
//  2. First render: that map saved, a server without a scanner loads it (so it holds still), and the page
//     is loaded --runs times: when the first map patches and all the tiles are on screen.
// Usage: STRATA_BINARY=… node bench_render.mjs [--tiles 100] [--runs 3]
import { mkdtempSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { parseArgs } from 'node:util';

import { launchBrowser } from './browser.mjs';
import { TOKEN } from './page.mjs';
import { startServer } from './server.mjs';

const { values: options } = parseArgs({
  options: { tiles: { type: 'string', default: '100' }, runs: { type: 'string', default: '3' } },
});
const wantTiles = Number(options.tiles);
const binary = process.env.STRATA_BINARY;
if (!binary) throw new Error('STRATA_BINARY must name the strata executable');
const mapsDir = mkdtempSync(path.join(tmpdir(), 'strata-bench-maps-'));
const auth = { Authorization: `Bearer ${TOKEN}`, 'Content-Type': 'application/json' };
const median = (xs) => [...xs].sort((a, b) => a - b)[Math.floor(xs.length / 2)];
const browser = await launchBrowser();

// 1. Live updates while the map grows to the wanted size.
let server = await startServer(binary, ['--time-scale', '8', '--scanner', 'lidar', '--maps-dir', mapsDir, '--operator-token', TOKEN]);
const mapStatus = async () => (await (await fetch(`${server.url}/api/v1/status`)).json()).map;
const watcher = await browser.newPage({ viewport: { width: 1280, height: 800 } });
await watcher.goto(server.url);
const grownBy = Date.now() + 600_000;
while ((await mapStatus()).tiles < wantTiles) {
  if (Date.now() > grownBy) throw new Error(`the map did not reach ${wantTiles} tiles`);
  await new Promise((resolve) => setTimeout(resolve, 1000));
}
const live = await watcher.evaluate(() => window.strata.perf());
await watcher.close();
const saved = await fetch(`${server.url}/api/v1/maps`, { method: 'POST', headers: auth, body: JSON.stringify({ name: 'bench.strata' }) });
if (!saved.ok) throw new Error(`saving the map: HTTP ${saved.status}`);
await server.stop();

// 2. First render of a map that holds still.
server = await startServer(binary, ['--scanner', 'none', '--maps-dir', mapsDir, '--operator-token', TOKEN]);
const loaded = await fetch(`${server.url}/api/v1/maps/bench.strata/load`, { method: 'POST', headers: auth });
if (!loaded.ok) throw new Error(`loading the map: HTTP ${loaded.status}`);
const map = await mapStatus();
const runs = [];
for (let run = 0; run < Number(options.runs); run++) {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  await page.goto(server.url);
  // Milliseconds since navigation started until every tile is on screen.
  const allTilesMs = await page
    .waitForFunction(
      (n) => window.strata?.tileCount() >= n && window.strata.perf().firstMapRenderMs !== null && performance.now(),
      map.tiles,
      { polling: 'raf', timeout: 60000 },
    )
    .then((handle) => handle.jsonValue());
  await page.waitForTimeout(1000);
  const perf = await page.evaluate(() => window.strata.perf());
  runs.push({
    helloMs: Math.round(perf.helloMs),
    firstTileFrameMs: Math.round(perf.firstTileFrameMs),
    firstTileDecodedMs: Math.round(perf.firstTileDecodedMs),
    firstMapRenderMs: Math.round(perf.firstMapRenderMs),
    allTilesOnScreenMs: Math.round(allTilesMs),
    maxTileMainThreadMs: Math.round(perf.maxTileMainThreadMs * 10) / 10,
    slowTileUpdates: perf.slowTileUpdates,
    longTasksMs: perf.longTasks,
  });
  await page.close();
}
await browser.close();
await server.stop();

console.log(JSON.stringify({
  target: { firstMapRenderMs: 2000, tileMainThreadMs: 16 },
  map: { tiles: map.tiles, patches: map.patches },
  firstRender: {
    medianFirstMapRenderMs: median(runs.map((r) => r.firstMapRenderMs)),
    medianAllTilesOnScreenMs: median(runs.map((r) => r.allTilesOnScreenMs)),
    runs,
  },
  liveUpdates: {
    tileUpdates: live.tileUpdates,
    maxTileMainThreadMs: Math.round(live.maxTileMainThreadMs * 10) / 10,
    slowTileUpdates: live.slowTileUpdates,
    longTasksMs: live.longTasks,
    medianRenderCallMs: median(live.renderMs),
  },
}, null, 2));
