// What the map views draw, read back from the screen (issue 60): the other browser tests check the page's
// state, which a black canvas would pass. Here the server maps one scan and keeps that map (--max-scans 1),
// the robot is stopped, and screenshots are compared with what the server says the map is: the drivable
// view cell by cell with the server's occupancy image, the 3D view's pixels with the classes of the patches
// they show, in the map's documented colours; and the screen with the WebGL canvas's own frame.
// Usage: node --test map_pixels.test.mjs   (env STRATA_BINARY, STRATA_ARTIFACTS)
import assert from 'node:assert/strict';
import { mkdirSync, writeFileSync } from 'node:fs';
import path from 'node:path';
import { after, before, test } from 'node:test';

import { launchBrowser } from './browser.mjs';
import { openApp, TOKEN, until } from './page.mjs';
import { decodePng, rgbAt } from './png.mjs';
import { startServer } from './server.mjs';

const binary = process.env.STRATA_BINARY;
const artifacts = process.env.STRATA_ARTIFACTS || path.resolve('browser-artifacts');
assert.ok(binary, 'STRATA_BINARY must name the strata executable');
mkdirSync(artifacts, { recursive: true });

let server;
let browser;
let occupancy; // the map of the one scan, as the server states it (below)
let map; // the status's map: version, patches

const getJson = async (route) => (await fetch(`${server.url}${route}`)).json();

/** Polls `probe` (a REST question) until it answers something truthy; fails saying `what` after `timeout`. */
async function eventually(probe, what, timeout = 60000) {
  const deadline = Date.now() + timeout;
  for (;;) {
    const answer = await probe();
    if (answer) return answer;
    assert.ok(Date.now() < deadline, `timed out waiting until ${what}`);
    await new Promise((resolve) => setTimeout(resolve, 100));
  }
}

before(async () => {
  server = await startServer(binary, ['--time-scale', '4', '--max-scans', '1', '--operator-token', TOKEN]);
  browser = await launchBrowser();
  // The drivable map at the robot's level (free 254, occupied 0, unknown 205; row 0 the highest y) and
  // where it lies.
  occupancy = await eventually(async () => {
    const response = await fetch(`${server.url}/api/v1/occupancy`);
    if (response.status !== 200) return null;
    const header = (name) => Number(response.headers.get(name));
    const [originX, originY] = response.headers.get('X-Strata-Origin').split(',').map(Number);
    const image = decodePng(Buffer.from(await response.arrayBuffer()));
    return { image, originX, originY, resolution: header('X-Strata-Resolution'), level: header('X-Strata-Level'), version: header('X-Strata-Version') };
  }, 'the first scan is mapped');
  // The robot stops (an operator's cancel ends the demo drive), so nothing moves over the map between
  // finding where a cell is drawn and taking the screenshot.
  const cancel = await fetch(`${server.url}/api/v1/goal`, { method: 'DELETE', headers: { Authorization: `Bearer ${TOKEN}` } });
  assert.ok(cancel.ok, `the demo drive is stopped (${cancel.status})`);
  await eventually(async () => (await getJson('/api/v1/pose')).mode === 'standing', 'the robot stands');
  ({ map } = await getJson('/api/v1/status'));
  assert.equal(map.version, occupancy.version, 'the map stays as its one scan made it');
});

after(async () => {
  await browser?.close();
  assert.equal(await server?.stop(), 0, 'strata exits cleanly on SIGTERM');
});

// ---- reading the screen ------------------------------------------------------------------------------

/** Samples of the view: for each map point ([x, y, z]) or screen point ({ x, y }), where it is on the
 * page and whether the canvas shows it there (on screen, not under the bar, the panel or the joystick,
 * and not where the robot is drawn); for screen points also the map's patch there, as a tap picks it
 * (`pick`: 'wall', 'floor' or null). */
function locate(page, { mapPoints = [], screenPoints = [] }) {
  return page.evaluate(
    ({ mapPoints, screenPoints }) => {
      const { strata } = window;
      const canvas = document.querySelector('#view canvas');
      // The robot's box on screen (it stands, so the box stays put), with a margin.
      const [rx, ry, rz] = strata.robotPosition();
      const corners = [];
      for (const dx of [-0.8, 0.8]) for (const dy of [-0.8, 0.8]) for (const dz of [-0.2, 1.4]) corners.push(strata.screenPoint([rx + dx, ry + dy, rz + dz]));
      const robot = {
        left: Math.min(...corners.map((c) => c.x)) - 4,
        right: Math.max(...corners.map((c) => c.x)) + 4,
        top: Math.min(...corners.map((c) => c.y)) - 4,
        bottom: Math.max(...corners.map((c) => c.y)) + 4,
      };
      const shown = (p) =>
        p.x >= 0 && p.y >= 0 && p.x < innerWidth && p.y < innerHeight &&
        document.elementFromPoint(p.x, p.y) === canvas &&
        !(p.x >= robot.left && p.x <= robot.right && p.y >= robot.top && p.y <= robot.bottom);
      const fromMap = mapPoints.map((point) => {
        const p = strata.screenPoint(point);
        return { x: p.x, y: p.y, shown: p.visible && shown(p) };
      });
      const fromScreen = screenPoints.map((p) => {
        const picked = shown(p) ? strata.patchAt(p.x, p.y) : undefined;
        return { ...p, shown: picked !== undefined, pick: picked ? (picked.vertical ? 'wall' : 'floor') : null };
      });
      return { fromMap, fromScreen };
    },
    { mapPoints, screenPoints },
  );
}

/** Points the held camera at `target` from `distance` m and waits for a frame drawn from there with every
 * tile in view at the detail it calls for (a few tiles are built per frame, the others drawn coarser
 * meanwhile). */
async function aimCamera(page, target, distance) {
  const frames = await page.evaluate(([target, distance]) => {
    window.strata.aimCamera(target, distance);
    return window.strata.frames();
  }, [target, distance]);
  await until(page, (n) => window.strata.frames() > n && window.strata.frameComplete(), frames, 30000);
}

/** The page as the user sees it, decoded (the WebGL canvas and everything over it). */
async function screenshot(page, name) {
  const png = await page.screenshot();
  writeFileSync(path.join(artifacts, name), png);
  return decodePng(png);
}

/** What the WebGL canvas holds, decoded: its last frame (the page keeps it, preserveDrawingBuffer). */
async function canvasBuffer(page) {
  const url = await page.evaluate(() => document.querySelector('#view canvas').toDataURL('image/png'));
  return decodePng(Buffer.from(url.slice(url.indexOf(',') + 1), 'base64'));
}

const BACKGROUND = [0x11, 0x15, 0x1c]; // the scene's background (scene_view.js), where nothing is drawn

/** The nearest of `palette` ({ name: [r, g, b] }) within `tolerance` in every channel, else 'other'. */
function nearest(rgb, palette, tolerance) {
  let best = 'other';
  let bestDistance = tolerance + 1;
  for (const [name, colour] of Object.entries(palette)) {
    const distance = Math.max(...colour.map((c, i) => Math.abs(c - rgb[i])));
    if (distance < bestDistance) [best, bestDistance] = [name, distance];
  }
  return best;
}

/** Per expected class: how many samples, how many showed it, and what they showed instead. */
function tally(samples) {
  const classes = {};
  for (const { expected, seen } of samples) {
    const entry = (classes[expected] ??= { samples: 0, matched: 0, seen: {} });
    entry.samples += 1;
    if (seen === expected) entry.matched += 1;
    entry.seen[seen] = (entry.seen[seen] ?? 0) + 1;
  }
  return classes;
}

// ---- the tests ---------------------------------------------------------------------------------------

test('the drivable view shows the server\'s occupancy image, cell by cell, where the map lies', async (t) => {
  const { image, originX, originY, resolution: r, level } = occupancy;
  const page = await openApp(browser, server.url);
  await until(page, (version) => window.strata.occupancy()?.version === version, occupancy.version);
  await page.getByRole('button', { name: 'Drivable' }).click();
  await page.getByRole('button', { name: 'Follow robot' }).click(); // the camera holds still over the map
  const width = image.width * r;
  const height = image.height * r;
  const centre = [originX + width / 2, originY + height / 2, level];
  await until(page, () => window.strata.occupancy().visible);
  // From straight above, near enough that a cell covers several pixels, far enough to see most of it.
  await aimCamera(page, centre, 1.3 * Math.max(width, height));

  // Every cell's centre on the plane the image is drawn on, and a ring of points 0.3 to 1.5 m outside the
  // image, where nothing is drawn.
  const cells = [];
  const points = [];
  for (let row = 0; row < image.height; row++) {
    for (let column = 0; column < image.width; column++) {
      const value = rgbAt(image, column, row)[0];
      cells.push(value === 254 ? 'free' : value === 0 ? 'occupied' : value === 205 ? 'unknown' : `grey ${value}`);
      points.push([originX + (column + 0.5) * r, originY + height - (row + 0.5) * r, level + 0.02]);
    }
  }
  for (let k = 0; k < 400; k++) {
    const side = k % 4;
    const margin = 0.3 + 0.4 * (Math.floor(k / 4) % 4);
    const f = k / 400;
    const along = side < 2 ? originX - margin + f * (width + 2 * margin) : originY - margin + f * (height + 2 * margin);
    const point = [
      [along, originY - margin], [along, originY + height + margin],
      [originX - margin, along], [originX + width + margin, along],
    ][side];
    cells.push('background');
    points.push([...point, level + 0.02]);
  }
  const { fromMap } = await locate(page, { mapPoints: points });
  const shot = await screenshot(page, 'pixels_drivable.png');
  // A cell must cover a few pixels for its centre pixel to be its own, whatever rounds.
  const cellPixels = Math.hypot(fromMap[1].x - fromMap[0].x, fromMap[1].y - fromMap[0].y);
  assert.ok(cellPixels >= 3, `a cell covers ${cellPixels.toFixed(1)} px`);

  const palette = { free: [254, 254, 254], unknown: [205, 205, 205], occupied: [0, 0, 0], background: BACKGROUND };
  const samples = [];
  fromMap.forEach((p, i) => {
    if (p.shown) samples.push({ expected: cells[i], seen: nearest(rgbAt(shot, p.x, p.y), palette, 10) });
  });
  const classes = tally(samples);
  const detail = JSON.stringify(classes);
  t.diagnostic(detail);
  for (const [name, least] of [['free', 1000], ['unknown', 1000], ['occupied', 100], ['background', 100]]) {
    const entry = classes[name];
    assert.ok(entry?.samples >= least, `at least ${least} ${name} cells in sight: ${detail}`);
    assert.ok(entry.matched >= 0.95 * entry.samples, `${name} cells are drawn ${name}: ${detail}`);
  }
  assert.deepEqual(page.errors, []);
  await page.context().close();
});

// The map's colours by traversability as the user guide gives them: green where the planner may drive,
// amber on other floors, grey-red for walls and steps. The scene's lights are near white: a face's shading
// makes its colour darker or lighter, hardly another hue (worked out for each face: within 20 degrees), so a
// pixel is told by its hue.
const CLASS_COLOURS = { floor: [0x3fb950, 0xd29922], wall: [0x9a6a6a] };

function hsl([r, g, b]) {
  const [R, G, B] = [r / 255, g / 255, b / 255];
  const max = Math.max(R, G, B);
  const min = Math.min(R, G, B);
  const l = (max + min) / 2;
  const d = max - min;
  if (d === 0) return { h: 0, s: 0, l };
  const s = d / (1 - Math.abs(2 * l - 1));
  let h = max === R ? ((G - B) / d) % 6 : max === G ? (B - R) / d + 2 : (R - G) / d + 4;
  h = (h * 60 + 360) % 360;
  return { h, s, l };
}

const hexRgb = (hex) => [(hex >> 16) & 0xff, (hex >> 8) & 0xff, hex & 0xff];
const CLASS_HUES = Object.entries(CLASS_COLOURS).flatMap(([name, colours]) => colours.map((hex) => ({ name, ...hsl(hexRgb(hex)) })));

/** 'background', a class of CLASS_COLOURS (the nearest hue, within 30 degrees), or 'other'. */
function mapClass(rgb) {
  if (Math.max(...rgb.map((c, i) => Math.abs(c - BACKGROUND[i]))) <= 10) return 'background';
  const { h, s, l } = hsl(rgb);
  if (s < 0.08 || l < 0.1) return 'other'; // grey or black: no class colour
  let best = { name: 'other', distance: 30 };
  for (const colour of CLASS_HUES) {
    const distance = Math.min(Math.abs(h - colour.h), 360 - Math.abs(h - colour.h));
    if (distance <= best.distance) best = { name: colour.name, distance };
  }
  return best.name;
}

test('the 3D view draws the tiles\' floors and walls in their colours, where the tiles are', async (t) => {
  const page = await openApp(browser, server.url);
  // Every patch of the map has arrived (the server's count) and is drawn.
  await until(page, (patches) => window.strata.patchCount() === patches && window.strata.drawnPatches() > 0, map.patches);
  await page.getByRole('button', { name: /^Colour/ }).click();
  await page.locator('#color-mode', { hasText: 'traversability' }).waitFor();
  await page.getByRole('button', { name: 'Follow robot' }).click();
  // Look at the middle of the free floor the scan saw, from the 3D view's usual slant.
  const { image, originX, originY, resolution: r, level } = occupancy;
  let [sx, sy, n] = [0, 0, 0];
  for (let row = 0; row < image.height; row++) {
    for (let column = 0; column < image.width; column++) {
      if (rgbAt(image, column, row)[0] !== 254) continue;
      sx += originX + (column + 0.5) * r;
      sy += originY + (image.height - row - 0.5) * r;
      n += 1;
    }
  }
  await aimCamera(page, [sx / n, sy / n, level], 12);

  const area = await page.evaluate(() => window.strata.uncoveredArea());
  const grid = [];
  for (let y = area.top + 4; y < area.bottom; y += 8) for (let x = area.left + 4; x < area.right; x += 8) grid.push({ x, y });
  const { fromScreen } = await locate(page, { screenPoints: grid });
  const shot = await screenshot(page, 'pixels_3d.png');
  const samples = fromScreen
    .filter((p) => p.shown)
    .map((p) => ({ expected: p.pick ?? 'background', seen: mapClass(rgbAt(shot, p.x, p.y)) }));
  const classes = tally(samples);
  const seen = tally(samples.map(({ seen }) => ({ expected: seen, seen })));
  const detail = `${JSON.stringify(classes)}; seen ${JSON.stringify(Object.fromEntries(Object.entries(seen).map(([k, v]) => [k, v.samples])))}`;
  t.diagnostic(`${detail}; tiles by level of detail ${await page.evaluate(() => window.strata.lodLevels())}`);
  // The view is not one colour: the map covers much of it, in both classes' colours.
  const share = (name) => (seen[name]?.samples ?? 0) / samples.length;
  assert.ok(share('floor') + share('wall') >= 0.2, `the map covers the view: ${detail}`);
  assert.ok(share('floor') >= 0.05, `floors in floor colours: ${detail}`);
  assert.ok(share('wall') >= 0.02, `walls in wall colours: ${detail}`);
  // Where the patch under a pixel (picked as a tap picks) is a wall the pixel has a wall's colour, where a
  // floor a floor's, where there is none the background's.
  for (const [name, least] of [['floor', 0.9], ['wall', 0.9], ['background', 0.95]]) {
    const entry = classes[name];
    assert.ok(entry?.samples >= 50, `at least 50 samples show ${name}: ${detail}`);
    assert.ok(entry.matched >= least * entry.samples, `where the map has ${name}, the view shows it: ${detail}`);
  }
  assert.deepEqual(page.errors, []);
  await page.context().close();
});

// Where no GPU is usable Chromium composites in software, as in these tests: there an opaque bar over the
// top of the WebGL canvas made it leave out the canvas's bottom strip, as tall as the bar (as if what the bar
// hides were worked out from the wrong end of the upside-down WebGL image). Wherever nothing covers the
// canvas, the screen shows the canvas's last frame.
test('the screen shows all of the map that nothing covers', async (t) => {
  const { image, originX, originY, resolution: r, level } = occupancy;
  const page = await openApp(browser, server.url); // the robot's 1280 x 800 screen
  await until(page, (version) => window.strata.occupancy()?.version === version, occupancy.version);
  // The drivable map from near by fills the screen: no part of it the background colour.
  await page.getByRole('button', { name: 'Drivable' }).click();
  await page.getByRole('button', { name: 'Follow robot' }).click();
  await until(page, () => window.strata.occupancy().visible);
  await aimCamera(page, [originX + (image.width * r) / 2, originY + (image.height * r) / 2, level], 5);
  const grid = [];
  for (let y = 2; y < 800; y += 6) for (let x = 2; x < 1280; x += 6) grid.push({ x, y });
  const { fromScreen } = await locate(page, { screenPoints: grid });
  const shot = await screenshot(page, 'pixels_canvas.png');
  const buffer = await canvasBuffer(page);
  const rows = new Set(); // where the screen is not the canvas
  let samples = 0;
  for (const p of fromScreen.filter((q) => q.shown)) {
    samples += 1;
    const [a, b] = [rgbAt(shot, p.x, p.y), rgbAt(buffer, p.x, p.y)];
    if (Math.max(...a.map((c, i) => Math.abs(c - b[i]))) > 2) rows.add(p.y);
  }
  const differ = [...rows].sort((a, b) => a - b);
  t.diagnostic(`${samples} samples; rows where the screen differs: ${differ.length ? `${differ[0]} to ${differ.at(-1)}` : 'none'}`);
  assert.ok(samples > grid.length / 2, `the canvas is in sight: ${samples} of ${grid.length} samples`);
  assert.deepEqual(differ, [], 'the screen shows the canvas wherever nothing covers it');
  assert.deepEqual(page.errors, []);
  await page.context().close();
});
