// Benchmark (not a test): how fast the web client shows the map, and how long a tile update holds the
// page's main thread. Prints JSON. Runs the real server (simulator sped up, lidar: it maps while driving)
// until the map has at least --tiles tiles, then loads the page --runs times in headless chromium.
// Usage: STRATA_BINARY=… node bench_render.mjs [--tiles 100] [--runs 3] [--watch 15]
import { parseArgs } from 'node:util';
import { mkdtempSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';

import { launchBrowser } from './browser.mjs';
import { startServer } from './server.mjs';

const { values: options } = parseArgs({
  options: {
    tiles: { type: 'string', default: '100' },
    runs: { type: 'string', default: '3' },
    watch: { type: 'string', default: '15' }, // s of live updates to watch per run
  },
});
const wantTiles = Number(options.tiles);
const binary = process.env.STRATA_BINARY;
if (!binary) throw new Error('STRATA_BINARY must name the strata executable');

const mapsDir = mkdtempSync(path.join(tmpdir(), 'strata-bench-maps-'));
const server = await startServer(binary, ['--time-scale', '8', '--scanner', 'lidar', '--maps-dir', mapsDir]);
const status = async () => (await (await fetch(`${server.url}/api/v1/status`)).json()).map;
const grownBy = Date.now() + 600_000;
while ((await status()).tiles < wantTiles) {
  if (Date.now() > grownBy) throw new Error(`the map did not reach ${wantTiles} tiles`);
  await new Promise((resolve) => setTimeout(resolve, 1000));
}

const browser = await launchBrowser();
const runs = [];
const median = (xs) => [...xs].sort((a, b) => a - b)[Math.floor(xs.length / 2)];
for (let run = 0; run < Number(options.runs); run++) {
  const map = await status();
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  await page.goto(server.url);
  // Milliseconds since navigation started until every tile the server held at load time is on screen.
  const allTilesMs = await page.waitForFunction(
    (n) => window.strata?.tileCount() >= n && window.strata.perf().firstMapRenderMs !== null && performance.now(),
    map.tiles,
    { polling: 'raf', timeout: 60000 },
  ).then((handle) => handle.jsonValue());
  const start = await page.evaluate(() => window.strata.perf());
  await page.waitForTimeout(Number(options.watch) * 1000); // live tile updates while the robot maps on
  const end = await page.evaluate(() => window.strata.perf());
  runs.push({
    tilesAtLoad: map.tiles,
    patchesAtLoad: map.patches,
    helloMs: Math.round(start.helloMs),
    firstTileFrameMs: Math.round(start.firstTileFrameMs),
    firstTileDecodedMs: Math.round(start.firstTileDecodedMs),
    firstMapRenderMs: Math.round(start.firstMapRenderMs),
    allTilesOnScreenMs: Math.round(allTilesMs),
    tileUpdates: end.tileUpdates,
    maxTileMainThreadMs: Math.round(end.maxTileMainThreadMs * 10) / 10,
    longTasksMs: end.longTasks, // any main-thread task over 50 ms, whatever caused it (rendering included)
    medianRenderCallMs: median(end.renderMs),
    drawnPatches: await page.evaluate(() => window.strata.drawnPatches()),
  });
  await page.close();
}
await browser.close();
await server.stop();

console.log(JSON.stringify({
  target: { firstMapRenderMs: 2000, tileMainThreadMs: 16 },
  median: {
    firstMapRenderMs: median(runs.map((r) => r.firstMapRenderMs)),
    allTilesOnScreenMs: median(runs.map((r) => r.allTilesOnScreenMs)),
    maxTileMainThreadMs: median(runs.map((r) => r.maxTileMainThreadMs)),
  },
  runs,
}, null, 2));
