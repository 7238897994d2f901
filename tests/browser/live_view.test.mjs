// The page loads from the real server, connects over WebSocket and shows the simulated robot moving.
// Usage: node --test live_view.test.mjs   (env STRATA_BINARY, STRATA_ARTIFACTS)
import assert from 'node:assert/strict';
import { mkdirSync } from 'node:fs';
import path from 'node:path';
import { after, before, test } from 'node:test';

import { launchBrowser } from './browser.mjs';
import { startServer } from './server.mjs';

const binary = process.env.STRATA_BINARY;
const artifacts = process.env.STRATA_ARTIFACTS || path.resolve('browser-artifacts');
assert.ok(binary, 'STRATA_BINARY must name the strata executable');
mkdirSync(artifacts, { recursive: true });

let server;
let browser;

before(async () => {
  server = await startServer(binary, ['--time-scale', '4']);
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

  await page.screenshot({ path: path.join(artifacts, 'live_view.png') });
  assert.deepEqual(errors, [], 'no uncaught errors in the page');
  await page.close();
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
