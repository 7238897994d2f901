// The operator's map UI against the real server and simulator: the map arrives and grows, the views
// switch (the drivable map shows its image), pinch zooms, viewers are refused control with a visible
// message, and the operator token (kept for the session) makes the page an operator that saves and loads.
// Usage: node --test map_view.test.mjs   (env STRATA_BINARY, STRATA_ARTIFACTS)
import assert from 'node:assert/strict';
import { mkdirSync, mkdtempSync } from 'node:fs';
import { readFile } from 'node:fs/promises';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { after, before, test } from 'node:test';

import { launchBrowser } from './browser.mjs';
import { floorPointNearRobot, nextFrame, openApp, TOKEN, until } from './page.mjs';
import { startServer } from './server.mjs';
import { touchSession } from './touch.mjs';

const binary = process.env.STRATA_BINARY;
const artifacts = process.env.STRATA_ARTIFACTS || path.resolve('browser-artifacts');
assert.ok(binary, 'STRATA_BINARY must name the strata executable');
mkdirSync(artifacts, { recursive: true });

let server;
let browser;

before(async () => {
  const mapsDir = mkdtempSync(path.join(tmpdir(), 'strata-maps-'));
  server = await startServer(binary, ['--time-scale', '4', '--operator-token', TOKEN, '--maps-dir', mapsDir]);
  browser = await launchBrowser();
});

after(async () => {
  await browser?.close();
  assert.equal(await server?.stop(), 0, 'strata exits cleanly on SIGTERM');
});

test('the map appears and grows as the robot scans', async () => {
  const page = await openApp(browser, server.url);
  const first = await until(page, () => window.strata.drawnPatches() > 0 && window.strata.patchCount());
  assert.ok((await page.evaluate(() => window.strata.tileCount())) > 0);
  // The robot drives on and scans again: the map takes in more patches, tile by tile.
  await until(page, (n) => window.strata.patchCount() > n * 1.05, first, 120000);
  await page.locator('#map-size').filter({ hasText: 'tiles' }).waitFor();
  await nextFrame(page);
  await page.screenshot({ path: path.join(artifacts, 'view_3d.png') });
  assert.equal(await page.evaluate(() => window.strata.view()), '3d');
  assert.deepEqual(page.errors, [], 'no uncaught errors in the page');
  await page.context().close();
});

test('switching views: top view, the drivable map image, colours by traversability', async () => {
  const page = await openApp(browser, server.url);
  await until(page, () => window.strata.drawnPatches() > 0 && window.strata.occupancy());

  await page.getByRole('button', { name: 'Top', exact: true }).click();
  assert.equal(await page.evaluate(() => window.strata.view()), 'top');
  assert.equal(await page.locator('#views [data-view="top"]').getAttribute('aria-pressed'), 'true');
  // The top view draws only the surfaces at the robot's level: never more than the 3D view.
  await until(page, () => window.strata.drawnPatches() > 0);
  await nextFrame(page);
  await page.screenshot({ path: path.join(artifacts, 'view_top.png') });

  await page.getByRole('button', { name: 'Drivable' }).click();
  const occupancy = await until(page, () => {
    const o = window.strata.occupancy();
    return window.strata.view() === 'occupancy' && o?.visible && o;
  });
  assert.ok(occupancy.free > 0, 'the drivable map shows free cells');
  assert.ok(occupancy.occupied + occupancy.unknown > 0, 'and cells that are not drivable');
  await nextFrame(page);
  await page.screenshot({ path: path.join(artifacts, 'view_drivable.png') });

  await page.getByRole('button', { name: '3D' }).click();
  await page.getByRole('button', { name: /^Colour/ }).click();
  assert.equal(await page.evaluate(() => window.strata.colorMode()), 'traversability');
  await page.locator('#color-mode', { hasText: 'traversability' }).waitFor();
  await nextFrame(page);
  await page.screenshot({ path: path.join(artifacts, 'view_3d_traversability.png') });

  await page.getByRole('button', { name: 'Follow robot' }).click();
  assert.equal(await page.evaluate(() => window.strata.follow()), false, 'free camera');
  assert.deepEqual(page.errors, []);
  await page.context().close();
});

test('touch: pinching zooms the view, two fingers turn it', async () => {
  const page = await openApp(browser, server.url, { touch: true });
  await until(page, () => window.strata.robotVisible());
  await page.getByRole('button', { name: 'Follow robot' }).click(); // hold the camera still for the test
  const before = await page.evaluate(() => window.strata.cameraDistance());
  const touch = await touchSession(page);
  await touch.pinch([480, 420], 100, 400); // fingers apart: zoom in
  const zoomedIn = await until(page, (d) => {
    const now = window.strata.cameraDistance();
    return now < d * 0.9 && now;
  }, before, 15000);
  await touch.pinch([480, 420], 400, 100); // together: zoom out
  await until(page, (d) => window.strata.cameraDistance() > d * 1.1, zoomedIn, 15000);
  // Two fingers turning a quarter turn about their midpoint turn the view about the vertical.
  const azimuth = await page.evaluate(() => window.strata.cameraAzimuth());
  await touch.twoFingers([[380, 420], [580, 420]], [[480, 320], [480, 520]]);
  await until(page, (a) => {
    const turn = Math.abs(Math.atan2(Math.sin(window.strata.cameraAzimuth() - a), Math.cos(window.strata.cameraAzimuth() - a)));
    return turn > 0.5;
  }, azimuth, 15000);
  await nextFrame(page);
  await page.screenshot({ path: path.join(artifacts, 'touch_pinch.png') });
  assert.deepEqual(page.errors, []);
  await page.context().close();
});

test('far tiles are drawn coarse, near ones in full detail, and a tap picks the exact patch', async () => {
  const page = await openApp(browser, server.url);
  await until(page, () => window.strata.drawnPatches() > 1000 && window.strata.robotVisible());
  await page.getByRole('button', { name: 'Follow robot' }).click(); // the camera holds still
  const robot = await page.evaluate(() => window.strata.robotPosition());
  const aim = (distance) => page.evaluate(([r, d]) => window.strata.aimCamera(r, d), [robot, distance]);
  const levels = () => page.evaluate(() => window.strata.lodLevels());

  await aim(4);
  await until(page, () => window.strata.lodLevels()[0] > 0); // full detail near the camera

  await aim(150);
  await nextFrame(page);
  const far = await levels();
  assert.equal(far[0], 0, 'nothing in full detail from 150 m away');
  assert.ok(far[1] + far[2] > 0, 'the map is drawn at a coarse level');

  // While coarse cells are drawn, a tap on a patch's centre picks that very patch. From 150 m the camera
  // looks down at a slant: in the hallway its walls hide most of the floor near the robot (the tap then
  // picks the wall), so floor patches up to 15 m away are tried, a few hundred at most; and again over a
  // few frames, as the tiles change under the test while the robot maps.
  const exact = await until(page, ([x, y, level]) => {
    const surfaces = window.strata.findSurfaces({ x, y, radius: 15, level });
    const step = Math.max(1, Math.floor(surfaces.length / 300));
    for (let k = 0; k < surfaces.length; k += step) {
      const surface = surfaces[k];
      const point = window.strata.screenPoint([surface.x, surface.y, surface.z]);
      const picked = window.strata.surfaceAt(point.x, point.y);
      if (picked && picked.x === surface.x && picked.y === surface.y && picked.z === surface.z) return true;
    }
    return false;
  }, robot, 20000).catch(() => false);
  assert.ok(exact, 'a tap picks the exact patch under a coarse level');
  assert.deepEqual(page.errors, []);
  await page.context().close();
});

test('without the token, control actions are refused with a visible message', async () => {
  const page = await openApp(browser, server.url, { touch: true });
  await page.locator('#role', { hasText: 'viewer' }).waitFor();
  await until(page, () => window.strata.drawnPatches() > 0 && window.strata.robotVisible());
  // The tiles around the robot have arrived and the camera shows them (a busy machine decodes slowly), before
  // the camera is held still.
  assert.ok(await floorPointNearRobot(page), 'a floor patch near the robot comes on screen');

  // A goal tapped on the map (the camera held still, so the tapped patch stays where it was found).
  await page.getByRole('button', { name: 'Follow robot' }).click();
  await page.getByRole('button', { name: 'Set goal' }).click();
  // The map streams in while the test taps: a tile replaced between finding the patch and the tap makes
  // the tap miss (the tool stays armed), so find and tap again, a few times.
  const touch = await touchSession(page);
  const refusal = page.locator('#notice', { hasText: 'needs the operator token' });
  for (let attempt = 0; attempt < 6; attempt += 1) {
    const target = await floorPointNearRobot(page);
    assert.ok(target, 'a floor patch near the robot is on screen');
    await touch.tap([target.point.x, target.point.y]);
    try {
      await refusal.waitFor({ timeout: 5000 });
      break;
    } catch {
      // missed: try again
    }
  }
  await refusal.waitFor({ timeout: 15000 });
  assert.match(await page.locator('#notice').textContent(), /goal/i);
  await page.screenshot({ path: path.join(artifacts, 'refused_without_token.png') });

  // Saving the map.
  await page.getByRole('button', { name: 'Save' }).click();
  await page.locator('#files-ok').click();
  await page.locator('#notice', { hasText: /Saving the map failed: needs the operator token/ }).waitFor({ timeout: 15000 });
  assert.deepEqual(page.errors, []);
  await page.context().close();
});

test('the operator token, entered once, makes the page an operator for the session: save and load a map', async () => {
  const page = await openApp(browser, server.url);
  await page.locator('#role', { hasText: 'viewer' }).waitFor();

  // A wrong token is refused by the server; the page says so and keeps watching.
  await page.getByRole('button', { name: 'Token' }).click();
  await page.locator('#token-input').fill('not-the-right-token-0000');
  await page.getByRole('button', { name: 'Use token' }).click();
  await page.locator('#notice', { hasText: 'token was refused' }).waitFor({ timeout: 30000 });
  await page.locator('#connection[data-state="connected"]').waitFor({ timeout: 30000 });
  await page.locator('#role', { hasText: 'viewer' }).waitFor();

  await page.getByRole('button', { name: 'Token' }).click();
  await page.locator('#token-input').fill(TOKEN);
  await page.getByRole('button', { name: 'Use token' }).click();
  await page.locator('#role', { hasText: 'operator' }).waitFor({ timeout: 15000 });

  // Kept while the page is open: a reload connects as the operator again without asking.
  await page.reload();
  await page.locator('#role', { hasText: 'operator' }).waitFor({ timeout: 15000 });
  await until(page, () => window.strata.patchCount() > 0);

  await page.getByRole('button', { name: 'Save' }).click();
  await page.locator('#save-name').fill('browser-test.strata');
  await page.locator('#files-ok').click();
  await page.locator('#notice', { hasText: 'Map saved' }).waitFor({ timeout: 30000 });

  // The list of saved maps is a REST call with the Bearer token.
  await page.getByRole('button', { name: 'Load', exact: true }).click();
  await page.locator('#load-name option', { hasText: 'browser-test.strata' }).waitFor({ timeout: 15000 });
  await page.screenshot({ path: path.join(artifacts, 'load_map_dialog.png') });
  await page.locator('#files-ok').click();
  await page.locator('#notice', { hasText: 'Map loaded' }).waitFor({ timeout: 30000 });
  await until(page, () => window.strata.patchCount() > 0);

  // Download: a plain link to the map in the chosen format.
  await page.getByRole('button', { name: 'Download' }).click();
  await page.locator('#download-format').selectOption('ply');
  const download = page.waitForEvent('download', { timeout: 30000 });
  await page.locator('#files-ok').click();
  assert.match((await download).suggestedFilename(), /\.ply$/);

  // The drivable map for ROS map_server: the YAML and the image it names, of one map version while the
  // robot maps on (issue 63: two links fetched the two at different versions).
  await page.getByRole('button', { name: 'Download' }).click();
  await page.locator('#download-format').selectOption('ros');
  const files = {};
  const both = new Promise((resolve) => {
    page.on('download', async (file) => {
      files[file.suggestedFilename()] = await readFile(await file.path());
      if (Object.keys(files).length === 2) resolve();
    });
  });
  await page.locator('#files-ok').click();
  await Promise.race([both, page.waitForTimeout(30000)]);
  assert.deepEqual(Object.keys(files).sort(), ['map.pgm', 'map.yaml']);
  const yaml = files['map.yaml'].toString();
  assert.match(yaml, /^image: map\.pgm$/m);
  const version = yaml.match(/^# strata map version (\d+);/)?.[1];
  assert.ok(version, yaml);
  const named = await fetch(`${server.url}/api/v1/map?format=pgm&version=${version}`);
  if (named.status === 200) assert.ok(Buffer.from(await named.arrayBuffer()).equals(files['map.pgm']), 'the image of the YAML\'s version');
  else assert.equal(named.status, 410, 'the map moved on since: that version is gone');
  assert.match(files['map.pgm'].subarray(0, 2).toString(), /P5/);
  assert.deepEqual(page.errors, []);
  await page.context().close();
});
