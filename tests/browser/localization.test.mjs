// Map reuse from the page (issue 22): a saved map is loaded to localize in with the Load dialog, and the
// operator tells the robot where it is with the Set pose tool (press where it stands, drag the way it
// faces, on the robot's touch screen): the server searches around the estimate and the robot is placed
// where it really is, which the panel says in the server's words.
// Usage: node --test localization.test.mjs   (env STRATA_BINARY, STRATA_ARTIFACTS)
import assert from 'node:assert/strict';
import { mkdirSync, mkdtempSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { after, test } from 'node:test';

import { launchBrowser } from './browser.mjs';
import { openApp, TOKEN, until } from './page.mjs';
import { startServer } from './server.mjs';
import { touchSession } from './touch.mjs';

const binary = process.env.STRATA_BINARY;
const artifacts = process.env.STRATA_ARTIFACTS || path.resolve('browser-artifacts');
assert.ok(binary, 'STRATA_BINARY must name the strata executable');
mkdirSync(artifacts, { recursive: true });

const mapsDir = mkdtempSync(path.join(tmpdir(), 'strata-maps-'));
const server = await startServer(binary, ['--time-scale', '4', '--operator-token', TOKEN, '--maps-dir', mapsDir]);
const browser = await launchBrowser();

after(async () => {
  await browser.close();
  assert.equal(await server.stop(), 0, 'strata exits cleanly on SIGTERM');
});

const headers = { Authorization: `Bearer ${TOKEN}`, 'Content-Type': 'application/json' };
const getJson = async (route) => (await fetch(`${server.url}${route}`)).json();

/** The estimate to give by hand: a floor patch of the robot's storey `offset` m from where it truly is,
 * and the screen points to press there and drag to, pointing 2 m along `yaw`. */
async function poseGesture(page, truth, { offset, yaw }) {
  return page.evaluate(
    ({ truth, offset, yaw }) => {
      const rect = document.querySelector('.panel').getBoundingClientRect();
      const onScreen = (p) => p.visible && p.x > 10 && p.x < rect.left - 10 && p.y > 70 && p.y < 780;
      for (let turn = 0; turn < 16; turn += 1) {
        const bearing = (turn * Math.PI) / 8;
        const x = truth.x + offset * Math.cos(bearing);
        const y = truth.y + offset * Math.sin(bearing);
        const surface = window.strata.findSurface({ x, y, radius: 0.3, level: truth.z });
        if (!surface) continue;
        const press = window.strata.screenPoint([surface.x, surface.y, surface.z]);
        const towards = window.strata.screenPoint([surface.x + 2 * Math.cos(yaw), surface.y + 2 * Math.sin(yaw), surface.z]);
        if (!onScreen(press) || !onScreen(towards)) continue;
        const picked = window.strata.surfaceAt(press.x, press.y);
        if (!picked || Math.abs(picked.z - surface.z) > 0.1 || Math.hypot(picked.x - surface.x, picked.y - surface.y) > 0.3) continue;
        return { surface, press, towards };
      }
      return null;
    },
    { truth, offset, yaw },
  );
}

test('a saved map is loaded to localize in, and a pose set by press-and-drag places the robot where it is', async () => {
  const page = await openApp(browser, server.url, { touch: true, token: TOKEN });
  await page.locator('#role', { hasText: 'operator' }).waitFor({ timeout: 15000 });
  await until(page, () => window.strata.drawnPatches() > 1000 && window.strata.mapMode() === 'mapping', null, 90000);

  // While mapping, the map is where the scans put the robot: the tool says so and does not arm.
  await page.getByRole('button', { name: 'Set pose' }).click();
  assert.equal(await page.evaluate(() => window.strata.poseArmed()), false);
  assert.match((await page.evaluate(() => window.strata.notice()))?.text ?? '', /mapping: load a saved map/);

  // Stop the robot in the lab it started in, after its first scans (a touch on the joystick: it leaves
  // the demo route), as an operator would before telling it where it is, and let it come to rest there.
  for (let waited = 0; (await getJson('/api/v1/status')).registration.scans < 2; waited += 1) {
    assert.ok(waited < 600, 'the robot takes its first scans');
    await new Promise((resolve) => setTimeout(resolve, 200));
  }
  // A robot whose calibration no earlier run kept (the test's own state directory) is learning it.
  await page.locator('#loc-imu[data-kept="none"]', { hasText: 'learning it' }).waitFor({ timeout: 10000 });
  const stick = await page.locator('#joystick').boundingBox();
  const centre = [stick.x + stick.width / 2, stick.y + stick.height / 2];
  const touch = await touchSession(page);
  await touch.hold(centre);
  await touch.release();
  for (let rest = null, waited = 0; ; waited += 1) {
    await page.waitForTimeout(500);
    const now = (await getJson('/api/v1/pose')).truth;
    if (rest && Math.hypot(now.x - rest.x, now.y - rest.y) < 0.01) break;
    assert.ok(waited < 40, 'the robot comes to rest');
    rest = now;
  }
  // And the panel says so (issue 24: it said "driving" while the robot stood).
  await page.locator('#pose-mode', { hasText: 'standing' }).waitFor({ timeout: 10000 });
  const saved = await fetch(`${server.url}/api/v1/maps`, { method: 'POST', headers, body: JSON.stringify({ name: 'start.smls' }) });
  assert.equal(saved.status, 201, await saved.text());
  await page.getByRole('button', { name: 'Load', exact: true }).click();
  await page.locator('#load-name option[value="start.smls"]').waitFor();
  await page.locator('#load-name').selectOption('start.smls');
  await page.getByLabel(/localize in it/).check();
  await page.locator('#files-ok').click();
  await until(page, () => window.strata.mapMode() === 'localize', null, 30000);
  await page.locator('#map-mode', { hasText: 'localizing' }).waitFor();
  assert.match((await page.evaluate(() => window.strata.notice()))?.text ?? '', /Map loaded: localizing in the map/);

  // Hold the camera still and look down on the robot, then give an estimate 0.8 m from where the robot
  // truly is, facing 20 degrees off its true heading.
  await page.getByRole('button', { name: 'Follow robot' }).click();
  await page.getByRole('button', { name: 'Top', exact: true }).click();
  await page.waitForTimeout(500);
  // The loaded map streams in again: wait until a floor patch near the robot is drawn.
  let truth;
  let yaw;
  let gesture = null;
  for (let attempt = 0; attempt < 40 && !gesture; attempt += 1) {
    if (attempt) await page.waitForTimeout(500);
    truth = (await getJson('/api/v1/pose')).truth;
    yaw = truth.yaw + (20 * Math.PI) / 180;
    gesture = await poseGesture(page, truth, { offset: 0.8, yaw });
  }
  assert.ok(gesture, 'a floor patch 0.8 m from the robot is on screen');

  await page.getByRole('button', { name: 'Set pose' }).click();
  assert.equal(await page.evaluate(() => window.strata.poseArmed()), true);
  const before = await page.evaluate(() => window.strata.relocalization());
  await touch.hold([gesture.press.x, gesture.press.y], [gesture.towards.x, gesture.towards.y]);
  assert.equal(await page.evaluate(() => window.strata.poseArrow()), true, 'the heading arrow shows while dragging');
  await page.screenshot({ path: path.join(artifacts, 'pose_estimate_drag.png') });
  await touch.release();
  const sent = await until(page, () => window.strata.poseSent(), null, 10000);
  assert.ok(Math.hypot(sent.x - gesture.surface.x, sent.y - gesture.surface.y) < 0.3, `the estimate is where the press was: ${JSON.stringify({ sent, gesture })}`);
  assert.ok(Math.abs(sent.z - gesture.surface.z) < 0.3, 'on the level of the pressed surface');
  const headingError = Math.abs(Math.atan2(Math.sin(sent.yaw - yaw), Math.cos(sent.yaw - yaw)));
  assert.ok(headingError < (3 * Math.PI) / 180, `the heading is where the drag pointed (${sent.yaw} vs ${yaw})`);
  assert.equal(sent.dragged, true);
  assert.equal(await page.evaluate(() => window.strata.poseArmed()), false, 'the tool disarms after one estimate');

  // The server searched around it: found, the robot stands where it truly is, not where the tap was.
  const search = await until(
    page,
    (earlier) => {
      const now = window.strata.relocalization();
      return now && (!earlier || now.stamp !== earlier.stamp) && now;
    },
    before,
    90000, // a sanitized build takes seconds for the search
  );
  assert.equal(search.found, true, search.message);
  await page.locator('#loc-search', { hasText: 'found at' }).waitFor();
  assert.equal(await page.evaluate(() => window.strata.poseArrow()), false, 'the arrow goes once the server has answered');
  const placed = await getJson('/api/v1/pose');
  const error = Math.hypot(placed.x - placed.truth.x, placed.y - placed.truth.y);
  assert.ok(error < 0.25, `placed on the truth (${error.toFixed(2)} m off): ${JSON.stringify(placed)}`);
  await page.screenshot({ path: path.join(artifacts, 'pose_estimate_found.png') });
  // Standing, the stop-and-go scanner takes no scans: the panel says what is happening, not a rate of
  // "0.0 / min" (issue 63).
  await page.locator('#scan-rate', { hasText: 'standing, no scans' }).waitFor({ timeout: 30000 });
  assert.deepEqual(page.errors, []);
  await page.context().close();
});
