// The page's estimate of the server's clock (web/src/server_clock.js), which stamps teleop commands so that
// the server can refuse those a link outage held back. Pure, run by node's test runner without a browser.
import assert from 'node:assert/strict';
import { test } from 'node:test';

import { ServerClock } from '../../web/src/server_clock.js';

test('unknown until the server gives its clock', () => {
  const clock = new ServerClock();
  assert.equal(clock.now(1000), null);
  clock.observe(undefined, 1000); // a server before protocol 1.1
  assert.equal(clock.now(1000), null);
});

test('the clock from hello, carried forward by the time elapsed here', () => {
  const clock = new ServerClock();
  clock.observe(5_000_000, 100); // hello arrived at performance.now() = 100
  assert.equal(clock.now(350), 5_000_250);
});

test('the quickest message gives the best estimate: transit only makes a sample late', () => {
  const clock = new ServerClock();
  clock.observe(5_000_000, 100); // spent 40 ms in transit
  clock.observe(5_002_000, 2_060); // spent 0 ms: offset 4_999_940 (the largest)
  clock.observe(5_004_000, 4_300); // held back 200 ms
  assert.equal(clock.now(5_000), 5_004_940);
});

test('only recent samples count, and a new connection starts over', () => {
  const clock = new ServerClock();
  clock.observe(9_000_000, 0); // an offset far above the rest, soon out of the window
  for (let i = 1; i <= 8; i += 1) clock.observe(1_000 * i, 1_000 * i);
  assert.equal(clock.now(10_000), 10_000);
  clock.reset();
  assert.equal(clock.now(10_000), null);
});
