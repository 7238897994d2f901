// Benchmark (issue 61, "Done when"): the fleet link's own figures, on loopback, with Debian's mosquitto and
// one real `strata serve --vda5050` (the simulated robot driving its demo route), every vehicle message
// checked against the 2.1.0 schemas (VehicleWatcher):
//   1. state latency from a change to the broker: an instantAction published by the bench at t0, the first
//      `state` showing it (the action FINISHED; for startPause / stopPause also `paused` toggled) received
//      at t1, both on the bench's clock. startPause / stopPause is a state change the vehicle notices at its
//      next poll (at the pose rate); stateRequest is answered at once. Also t0 to the state's header
//      timestamp (the vehicle's system clock, ms; the same machine).
//   2. visualization rate: messages per second on `visualization` over DURATION s against --pose-rate,
//      and the gaps between them.
//   3. reconnect after a broker restart: mosquitto stopped, started on the same port DOWN_S later; from the
//      broker running again to the vehicle's `connection` ONLINE and its first state at the bench.
// Prints one JSON line per part; a benchmark, not a test (nothing here depends on time).
// Usage: STRATA_BINARY=../../build/release/strata node bench_fleet_link.mjs
//   env MOSQUITTO, STRATA_VDA5050_DIR; SAMPLES (200), DURATION (30 s), POSE_RATE (25), RESTARTS (5), DOWN_S ("1,5"),
//   BROKER_NODELAY=1 (mosquitto's set_tcp_nodelay: without it the broker's sends to the bench wait on Nagle)
import { mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';

import { startServer } from '../browser/server.mjs';
import { startBroker } from './broker.mjs';
import { fleetSetup, VehicleWatcher } from './master.mjs';

const { binary, mosquitto, schemaDir, missing } = fleetSetup();
if (missing) process.exit(0);
const samples = Number(process.env.SAMPLES || 200);
const duration = Number(process.env.DURATION || 30);
const poseRate = Number(process.env.POSE_RATE || 25);
const restarts = Number(process.env.RESTARTS || 5);
const downSeconds = (process.env.DOWN_S || '1,5').split(',').map(Number);

const agv = { manufacturer: 'StrataBench', serialNumber: 'robot-1' };
const prefix = `uagv/v2/${agv.manufacturer}/${agv.serialNumber}`;
const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));
const wallClock = (at) => performance.timeOrigin + at; // performance.now() as ms since the epoch
const round = (value) => Math.round(value * 10) / 10;

/** p50, p99 and max of `values` (ms), nearest rank. */
function percentiles(values) {
  const sorted = [...values].sort((a, b) => a - b);
  const rank = (p) => sorted[Math.min(sorted.length - 1, Math.ceil((p / 100) * sorted.length) - 1)];
  return { p50: round(rank(50)), p99: round(rank(99)), max: round(sorted[sorted.length - 1]), n: sorted.length };
}

const scratch = mkdtempSync(path.join(tmpdir(), 'strata-fleet-bench-'));
const brokerNoDelay = process.env.BROKER_NODELAY === '1';
const broker = await startBroker(mosquitto, { tcpNoDelay: brokerNoDelay });
const watch = new VehicleWatcher();
let server;
let headerId = 0;

/** Publishes one instant action; resolves with t0 (performance.now() just before publishing). */
async function publishAction(actionType) {
  const actionId = `bench-${++headerId}`;
  const message = { headerId, timestamp: new Date().toISOString(), version: '2.1.0', ...agv, actions: [{ actionId, actionType, blockingType: 'NONE', actionParameters: [] }] };
  const t0 = performance.now();
  await watch.publish(`${prefix}/instantActions`, JSON.stringify(message));
  return { actionId, t0 };
}

/** `samples` actions of the kinds `types` (in turn); the latency of each to the first state showing it. */
async function stateLatency(types, showsIt) {
  const bench = [];
  const header = [];
  for (let i = 0; i < samples; i++) {
    const type = types[i % types.length];
    await sleep(Math.random() * 50); // a random phase against the vehicle's poll timer
    const from = watch.received.length;
    const { actionId, t0 } = await publishAction(type);
    await watch.waitFor((m) => m.kind === 'state' && m.body.actionStates.some((a) => a.actionId === actionId && a.actionStatus === 'FINISHED') && showsIt(type, m.body), `state after ${type}`, { from, timeout: 10000 });
    const message = watch.received.slice(from).find((m) => m.kind === 'state' && m.body.actionStates.some((a) => a.actionId === actionId));
    bench.push(message.at - t0);
    header.push(Date.parse(message.body.timestamp) - wallClock(t0));
  }
  return { to_bench_ms: percentiles(bench), to_header_timestamp_ms: percentiles(header) };
}

try {
  await watch.connect(broker.url, schemaDir, `${prefix}/+`, { reconnectPeriod: 20 });
  const config = path.join(scratch, 'strata.ini');
  writeFileSync(config, ['[serve]', `vda5050 = "${broker.url}"`, `vda5050-manufacturer = "${agv.manufacturer}"`, `vda5050-serial = "${agv.serialNumber}"`, ''].join('\n'));
  server = await startServer(binary, ['--config', config, '--time-scale', '1', '--pose-rate', String(poseRate), '--maps-dir', path.join(scratch, 'maps')]);
  await watch.waitFor((m) => m.kind === 'connection' && m.body.connectionState === 'ONLINE', 'connection ONLINE');
  await watch.waitFor((m) => m.kind === 'visualization', 'visualization');
  await sleep(2000); // the robot under way on its demo route

  // 2. The visualization rate, while the robot drives.
  const from = watch.received.length;
  const started = performance.now();
  await sleep(duration * 1000);
  const ended = performance.now();
  const shown = watch.received.slice(from).filter((m) => m.kind === 'visualization' && m.at <= ended);
  const gaps = shown.slice(1).map((m, i) => m.at - shown[i].at);
  const positions = shown.map((m) => m.body.agvPosition).filter(Boolean);
  const travelled = positions.slice(1).reduce((sum, p, i) => sum + Math.hypot(p.x - positions[i].x, p.y - positions[i].y), 0);
  const statesMeanwhile = watch.received.slice(from).filter((m) => m.kind === 'state' && m.at <= ended).map((m) => m.body.driving);
  console.log(JSON.stringify({
    part: 'visualization rate',
    broker_tcp_nodelay: brokerNoDelay,
    pose_rate_hz: poseRate,
    seconds: round((ended - started) / 1000),
    messages: shown.length,
    per_second: round(shown.length / ((ended - started) / 1000)),
    travelled_m: round(travelled),
    states_driving_true_false: [statesMeanwhile.filter(Boolean).length, statesMeanwhile.filter((d) => !d).length],
    gap_ms: { ...percentiles(gaps), expected: round(1000 / poseRate) },
    gaps_over_2_periods: gaps.filter((g) => g > 2000 / poseRate).length,
  }));

  // 1. State latency: a change (startPause / stopPause toggles `paused`) and a stateRequest.
  const pause = await stateLatency(['startPause', 'stopPause'], (type, state) => state.paused === (type === 'startPause'));
  console.log(JSON.stringify({ part: 'state latency, startPause/stopPause (a change, noticed at the next poll)', poll_period_ms: round(1000 / poseRate), ...pause }));
  const request = await stateLatency(['stateRequest'], () => true);
  console.log(JSON.stringify({ part: 'state latency, stateRequest (answered at once)', ...request }));

  // 3. Reconnect after a broker restart, the broker down for each of DOWN_S.
  for (const down of downSeconds) {
    const online = [];
    const firstState = [];
    const onlineByHeader = [];
    let retainedOnline = 0;
    for (let run = 0; run < restarts; run++) {
      const mark = watch.received.length;
      await broker.restart(down * 1000);
      const up = performance.now();
      const connection = await watch.waitFor((m) => m.kind === 'connection' && m.body.connectionState === 'ONLINE', 'connection ONLINE', { from: mark, timeout: 60000 });
      await watch.waitFor((m) => m.kind === 'state', 'state', { from: mark, timeout: 60000 });
      const after = watch.received.slice(mark);
      const onlineMessage = after.find((m) => m.kind === 'connection' && m.body === connection);
      const stateMessage = after.find((m) => m.kind === 'state');
      online.push(onlineMessage.at - up);
      firstState.push(stateMessage.at - up);
      onlineByHeader.push(Date.parse(connection.timestamp) - wallClock(up));
      if (onlineMessage.retained) retainedOnline++;
      await sleep(1000);
    }
    console.log(JSON.stringify({
      part: 'reconnect after a broker restart',
      broker_down_s: down,
      restarts,
      online_ms: online.map(Math.round),
      online_by_header_ms: onlineByHeader.map(Math.round),
      first_state_ms: firstState.map(Math.round),
      online_ms_median: Math.round([...online].sort((a, b) => a - b)[Math.floor(online.length / 2)]),
      online_received_retained: retainedOnline,
    }));
  }
  console.log(JSON.stringify({ part: 'schemas', messages: watch.received.length, invalid: watch.invalid.length }));
} finally {
  await server?.stop();
  watch.end();
  await broker.stop();
  rmSync(scratch, { recursive: true, force: true });
}
