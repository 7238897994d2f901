// Benchmark (not a test): how fast the web client shows the map, and how long a tile update holds the
// page's main thread. Prints JSON.
//  1. Live: the real server maps while driving (lidar, simulator sped up) until the map has --tiles
//     tiles, with a page watching: the longest main-thread part of a tile update (decoding itself runs
//     in DRACOLoader's workers) and the long tasks, whatever caused them.
//  2. First render: that map saved, a server without a scanner loads it (so it holds still), and the page
//     is loaded --runs times: when the first map patches and all the tiles are on screen.
//  3. Big maps: for each of --patches (default 250000 and 1000000), strata_synthetic_map writes a map file
//     of that many patches (a campus: ground, buildings of one and two storeys, ramps), a server without a
//     scanner loads it, and the page, redrawing continuously, reports frames per second with the whole map
//     in view (3D, zoomed out), zoomed in (3D, 10 m away) and from the top, with draw calls and triangles;
//     then the joystick's input-to-send latency and send rate while the page redraws zoomed out.
// Usage: STRATA_BINARY=… [STRATA_SYNTHETIC_MAP=…] node bench_render.mjs [--tiles 100] [--runs 3]
//        [--parts live,big] [--patches 250000,1000000]
// STRATA_SYNTHETIC_MAP defaults to build/release/tests/strata_synthetic_map of this checkout.
import { execFileSync } from 'node:child_process';
import { mkdtempSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { parseArgs } from 'node:util';

import { launchBrowser } from './browser.mjs';
import { openApp, TOKEN } from './page.mjs';
import { installSendProbe, measureFrames, measureJoystick } from './render_probe.mjs';
import { startServer } from './server.mjs';

const { values: options } = parseArgs({
  options: {
    tiles: { type: 'string', default: '100' },
    runs: { type: 'string', default: '3' },
    parts: { type: 'string', default: 'live,big' },
    patches: { type: 'string', default: '250000,1000000' },
  },
});
const parts = new Set(options.parts.split(','));
const wantTiles = Number(options.tiles);
const binary = process.env.STRATA_BINARY;
if (!binary) throw new Error('STRATA_BINARY must name the strata executable');
const mapsDir = mkdtempSync(path.join(tmpdir(), 'strata-bench-maps-'));
const auth = { Authorization: `Bearer ${TOKEN}`, 'Content-Type': 'application/json' };
const median = (xs) => [...xs].sort((a, b) => a - b)[Math.floor(xs.length / 2)];
const browser = await launchBrowser();

const result = {};
if (parts.has('live')) Object.assign(result, await liveAndFirstRender());
if (parts.has('big')) result.bigMaps = await bigMaps();
await browser.close();
console.log(JSON.stringify(result, null, 2));

/** Parts 1 and 2: the live map and its first render. */
async function liveAndFirstRender() {
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
  await server.stop();

  return {
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
  };
}

// 3. Big maps, drawn from a real map file through the real server.
async function bigMaps() {
  const tool = process.env.STRATA_SYNTHETIC_MAP ?? new URL('../../build/release/tests/strata_synthetic_map', import.meta.url).pathname;
  const results = [];
  for (const wanted of options.patches.split(',').map(Number)) {
    const file = path.join(mapsDir, `synthetic-${wanted}.strata`);
    const written = JSON.parse(execFileSync(tool, ['--patches', String(wanted), '--out', file], { encoding: 'utf8' }));
    const server = await startServer(binary, ['--scanner', 'none', '--maps-dir', mapsDir, '--operator-token', TOKEN]);
    try {
      results.push(await measureBigMap(server, file, written));
    } finally {
      await server.stop();
    }
  }
  return { target: { fpsAt250k: 30, fpsAt1M: 15 }, maps: results };
}

/** Part 3 on one map file, `written` what strata_synthetic_map said of it. */
async function measureBigMap(server, file, written) {
  const loaded = await fetch(`${server.url}/api/v1/maps/${path.basename(file)}/load`, { method: 'POST', headers: auth });
  if (!loaded.ok) throw new Error(`loading the map: HTTP ${loaded.status}`);
  const { tiles, patches } = (await (await fetch(`${server.url}/api/v1/status`)).json()).map;
  const page = await openApp(browser, server.url, { token: TOKEN, beforeLoad: installSendProbe });
  const loadStart = Date.now();
  await page.waitForFunction((n) => window.strata.tileCount() >= n, tiles, { timeout: 600_000, polling: 500 });
  const allTilesMs = Date.now() - loadStart;
  if (await page.evaluate(() => window.strata.follow())) await page.evaluate(() => document.getElementById('follow').click());
  // The campus lies in [0, size x] x [0, size y]; the whole of it is in view from about 1.3 sizes away.
  const [sizeX, sizeY] = written.size_m;
  const centre = [sizeX / 2, sizeY / 2, 0];
  const whole = 1.3 * Math.max(sizeX, sizeY);
  const aim = (distance) => page.evaluate(([c, d]) => window.strata.aimCamera(c, d), [centre, distance]);
  // Views are switched by a click in the page: a page that takes seconds per frame would make
  // playwright's click, which waits for animation frames, time out.
  const showView = (name) => page.evaluate((n) => document.querySelector(`#views [data-view="${n}"]`).click(), name);
  const result = { map: { patches, tiles, sizeM: written.size_m }, allTilesMs };
  const note = (name, value) => {
    result[name] = value;
    console.error(`${patches} patches, ${name}: ${JSON.stringify(value)}`); // progress, on stderr
  };
  // What a frame costs with nothing of the map in view (the camera looking away from it): the
  // browser's own share of every frame on this machine, a ceiling for the others.
  await page.evaluate((d) => window.strata.aimCamera([-1000, -1000, 0], d), whole);
  note('nothingInView', await measureFrames(page));
  await aim(whole);
  note('zoomedOut', await measureFrames(page));
  await aim(10);
  note('zoomedIn', await measureFrames(page));
  await showView('top');
  await aim(whole);
  note('top', await measureFrames(page));
  await showView('3d');
  await aim(whole);
  note('joystickWhileRedrawing', await measureJoystick(page));
  await page.context().close();
  return result;
}
