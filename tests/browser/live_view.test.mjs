// The page loads from the real server, connects over WebSocket and shows the simulated robot moving.
// Usage: node --test live_view.test.mjs   (env STRATA_BINARY, STRATA_ARTIFACTS)
import assert from 'node:assert/strict';
import { mkdirSync } from 'node:fs';
import path from 'node:path';
import { after, before, test } from 'node:test';

import { launchBrowser } from './browser.mjs';
import { openApp, TOKEN, until } from './page.mjs';
import { touchSession } from './touch.mjs';
import { startServer } from './server.mjs';

const binary = process.env.STRATA_BINARY;
const artifacts = process.env.STRATA_ARTIFACTS || path.resolve('browser-artifacts');
assert.ok(binary, 'STRATA_BINARY must name the strata executable');
mkdirSync(artifacts, { recursive: true });

let server;
let browser;

before(async () => {
  server = await startServer(binary, ['--time-scale', '4', '--operator-token', TOKEN]);
  browser = await launchBrowser();
});

after(async () => {
  await browser?.close();
  assert.equal(await server?.stop(), 0, 'strata exits cleanly on SIGTERM');
});

test('page shows the robot moving with a live connection', async () => {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  const errors = [];
  page.on('pageerror', (error) => errors.push(error.message));
  await page.goto(server.url);

  await page.locator('#connection[data-state="connected"]').waitFor({ timeout: 15000 });
  await page.waitForFunction(() => window.strata?.robotVisible(), null, { timeout: 15000 });
  assert.ok((await page.evaluate(() => window.strata.worldShapes())) > 0, 'the world geometry is drawn');

  const first = await page.evaluate(() => window.strata.robotPosition());
  const firstReadout = await page.locator('#pose-x').textContent();
  // The robot drives its loop: wait until the drawn robot has moved 0.5 m, and the readout with it.
  await page.waitForFunction(
    ([x0, y0]) => {
      const [x, y] = window.strata.robotPosition();
      return Math.hypot(x - x0, y - y0) > 0.5;
    },
    first,
    { timeout: 60000 },
  );
  const readout = await page.locator('#pose-x').textContent();
  assert.notEqual(readout, firstReadout, 'the pose readout changes');
  assert.match(readout, /^-?\d+\.\d\d m$/);

  // The first stop-and-go scan registers: the pose now rests on scan matching, and the panel says so.
  await page.locator('#loc-source', { hasText: 'scan matching' }).waitFor({ timeout: 30000 });
  await page.locator('#loc-last').filter({ hasNotText: '–' }).waitFor({ timeout: 60000 });
  assert.equal(await page.locator('#driver').textContent(), 'simulator', 'the panel names the data source');

  // The localization state with its colour and the reason in words, as the status stream sent them.
  await page.locator('#loc-state[data-state]').waitFor({ timeout: 30000 });
  const state = await page.locator('#loc-state').getAttribute('data-state');
  assert.ok(['ok', 'degraded', 'lost'].includes(state), `state ${state}`);
  assert.equal(await page.locator('#loc-state').textContent(), state);
  const colours = await page.evaluate(() => {
    const style = getComputedStyle(document.documentElement);
    const colour = (name) => style.getPropertyValue(name);
    return { ok: colour('--ok'), degraded: colour('--warn'), lost: colour('--bad') };
  });
  const rgb = (hex) => `rgb(${[1, 3, 5].map((i) => parseInt(hex.trim().slice(i, i + 2), 16)).join(', ')})`;
  assert.equal(await page.locator('#loc-state').evaluate((el) => getComputedStyle(el).color), rgb(colours[state]));
  assert.ok((await page.locator('#loc-reason').textContent()).length > 0, 'the reason is shown');
  // A long reason wraps onto more lines inside the panel: nothing clipped, no ellipsis.
  const wrapped = await page.locator('#loc-reason').evaluate((el) => {
    const shown = el.textContent;
    el.textContent = 'x';
    const oneLine = el.getBoundingClientRect().height;
    el.textContent = 'open ground: position along x,y and heading from odometry for 25 m; '.repeat(3) + 'the end';
    const box = el.getBoundingClientRect();
    const panel = el.closest('.panel').getBoundingClientRect();
    const measured = {
      lines: box.height / oneLine,
      clipped: el.scrollHeight > el.clientHeight + 1 || el.scrollWidth > el.clientWidth + 1,
      inside: box.left >= panel.left && box.right <= panel.right,
      ellipsis: getComputedStyle(el).textOverflow === 'ellipsis',
    };
    el.textContent = shown;
    return measured;
  });
  assert.ok(wrapped.lines >= 3, `the long reason wraps (${wrapped.lines} lines)`);
  assert.equal(wrapped.clipped, false, 'the reason is not clipped');
  assert.equal(wrapped.inside, true, 'the reason stays inside the panel');
  assert.equal(wrapped.ellipsis, false, 'no ellipsis');

  await page.screenshot({ path: path.join(artifacts, 'live_view.png') });
  assert.deepEqual(errors, [], 'no uncaught errors in the page');
  await page.close();
});

// While the simulator drives its demo route (nobody has commanded the robot): out of the lab and down the hallway.
test('a followed robot in the hallway stays in sight when the camera is put low beside it', async () => {
  // Issue 63: following the robot down the campus hallway, a low camera beside it looked at the near wall.
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  const errors = [];
  page.on('pageerror', (error) => errors.push(error.message));
  await page.goto(server.url);
  await until(page, () => window.strata?.robotVisible());
  if (!(await page.evaluate(() => window.strata.follow()))) await page.getByRole('button', { name: 'Follow robot' }).click();
  // The demo route leaves the lab into the hallway (y 4.0-6.5, walls 3 m high) and down it.
  await until(page, () => {
    const [x, y] = window.strata.robotPosition();
    return x > 12 && Math.abs(y - 5.25) < 0.8;
  }, null, 90000);
  // From 8 m south of the robot, 8 degrees above the horizon: the hallway's south wall is in between.
  const low = (8 * Math.PI) / 180;
  await page.evaluate((elevation) => window.strata.placeCamera(-Math.PI / 2, elevation, 8), low);
  // The robot in sight: no patch of the map drawn at the robot's body nearer the camera than the robot.
  // The camera follows the next poses and rises over the wall; before issue 63 it stayed behind it.
  const seen = await until(
    page,
    (elevation) => {
      const [x, y, z] = window.strata.robotPosition();
      const [cx, cy] = window.strata.cameraPosition();
      const screen = window.strata.screenPoint([x, y, z + 0.6]);
      const patch = window.strata.patchAt(screen.x, screen.y);
      const hidden = Boolean(patch) && Math.hypot(patch.x - cx, patch.y - cy) < Math.hypot(x - cx, y - cy) - 0.5;
      return !hidden && window.strata.cameraElevation() > elevation + 0.01 && { elevation: window.strata.cameraElevation() };
    },
    low,
    20000,
  );
  assert.ok(seen.elevation < (86 * Math.PI) / 180, 'risen no further than needed: not past straight down');
  assert.equal(await page.evaluate(() => window.strata.follow()), true, 'still following');
  await page.screenshot({ path: path.join(artifacts, 'follow_hallway.png') });
  assert.deepEqual(errors, []);
  await page.close();
});

// Then, still in the hallway (it runs 35 m on east), the operator takes over with the joystick.
test('held forward, the joystick drives on without a stop to scan; the scan comes when it is let go', async () => {
  // Issue 63: under a held joystick the stop-and-go robot stood about 1 s in every 2 m to scan.
  const page = await openApp(browser, server.url, { touch: true, token: TOKEN });
  await page.locator('#role', { hasText: 'operator' }).waitFor({ timeout: 15000 });
  await until(page, () => window.strata.robotVisible());
  const box = await page.locator('#joystick').boundingBox();
  const centre = [box.x + box.width / 2, box.y + box.height / 2];
  const touch = await touchSession(page);
  await touch.hold(centre, [centre[0], centre[1] - box.height * 0.45]); // push forward
  // Once it rolls, every motion state the panel shows is kept until the joystick is let go.
  const start = await until(page, () => window.strata.joystick().held && window.strata.robotPosition());
  await until(page, (p0) => {
    const [x, y] = window.strata.robotPosition();
    return Math.hypot(x - p0[0], y - p0[1]) > 0.3;
  }, start, 30000);
  await page.evaluate(() => {
    const mode = document.getElementById('pose-mode');
    window.modesSeen = new Set([mode.textContent]);
    new MutationObserver(() => window.modesSeen.add(mode.textContent)).observe(mode, { childList: true, characterData: true, subtree: true });
  });
  await until(page, (p0) => {
    const [x, y] = window.strata.robotPosition();
    return Math.hypot(x - p0[0], y - p0[1]) > 3.0; // past a scan's spacing (2 m) and then some
  }, start, 60000);
  const held = await page.evaluate(() => [...window.modesSeen]);
  await touch.release();
  assert.ok(!held.includes('scanning'), `no stop to scan while held: ${held}`);
  // Let go, the robot stops and takes the scan it owes.
  await page.locator('#pose-mode', { hasText: 'scanning' }).waitFor({ timeout: 30000 });
  assert.deepEqual(page.errors, []);
  await page.context().close();
});

test('the page shows a lost server and reconnects when it is back', async () => {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  await page.goto(server.url);
  await page.locator('#connection[data-state="connected"]').waitFor({ timeout: 15000 });

  const port = new URL(server.url).port;
  assert.equal(await server.stop(), 0);
  await page.locator('#connection[data-state="disconnected"]').waitFor({ timeout: 15000 });
  await page.screenshot({ path: path.join(artifacts, 'disconnected.png') });

  server = await startServer(binary, [], { port });
  await page.locator('#connection[data-state="connected"]').waitFor({ timeout: 30000 });
  await page.close();
});
