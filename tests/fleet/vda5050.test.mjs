// Issue 61, first slice: the robot as a VDA 5050 2.1 vehicle over MQTT, with real parts only: Debian's
// mosquitto as the broker, the real `strata serve` (its vda5050 options from a config file), npm's
// vda-5050-lib MasterController as the master, and every message the vehicle sends checked against the
// specification's own 2.1.0 JSON schemas (../shared/vda5050/2.1.0, found through STRATA_VDA5050_DIR).
// Usage: node --test vda5050.test.mjs   (env STRATA_BINARY, MOSQUITTO, STRATA_VDA5050_DIR)
import assert from 'node:assert/strict';
import { mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { after, before, test } from 'node:test';

import { MasterController } from 'vda-5050-lib';

import { startServer } from '../browser/server.mjs';
import { startBroker } from './broker.mjs';
import { fleetSetup, instantAction as runInstantAction, VehicleWatcher } from './master.mjs';

const { binary, mosquitto, schemaDir, missing } = fleetSetup();

const TOKEN = 'fleet-test-operator-token-0123456789';
const agv = { manufacturer: 'StrataTest', serialNumber: 'robot-1' };
const prefix = `uagv/v2/${agv.manufacturer}/${agv.serialNumber}`;

let broker;
let server;
let master;
let scratch;
const watch = new VehicleWatcher(); // every message on the vehicle's topics, checked against 2.1.0
const { received, invalid } = watch;

/** The first message of `kind` from index `from` on that `predicate` accepts; waits up to `timeout` ms. */
const waitFor = (kind, predicate = () => true, options = {}) => watch.waitFor((m) => m.kind === kind && predicate(m.body), `${kind} message`, options);

const getJson = async (route) => (await fetch(`${server.url}${route}`)).json();
const headers = { Authorization: `Bearer ${TOKEN}`, 'Content-Type': 'application/json' };

/** Carries out an instant action on this test's vehicle through the MasterController. */
const instantAction = (actionType, actionParameters = []) => runInstantAction(master, agv, actionType, actionParameters);

/** Publishes `payload` raw on the vehicle's instantActions topic, as a faulty master would. */
const publishRaw = (payload) => watch.publish(`${prefix}/instantActions`, payload);

const header = (headerId) => ({ headerId, timestamp: new Date().toISOString(), version: '2.1.0', ...agv });

before(async () => {
  if (missing) return;
  broker = await startBroker(mosquitto);
  await watch.connect(broker.url, schemaDir, `${prefix}/+`);

  scratch = mkdtempSync(path.join(tmpdir(), 'strata-fleet-'));
  const config = path.join(scratch, 'strata.ini');
  writeFileSync(config, ['[serve]', `vda5050 = "${broker.url}"`, `vda5050-manufacturer = "${agv.manufacturer}"`, `vda5050-serial = "${agv.serialNumber}"`, ''].join('\n'));
  server = await startServer(binary, ['--config', config, '--time-scale', '4', '--operator-token', TOKEN, '--maps-dir', path.join(scratch, 'maps')]);

  // The lib validates against VDA 5050 2.0 and wants that version in every header; this vehicle speaks 2.1,
  // which the test checks against the 2.1.0 schemas itself.
  master = new MasterController(
    { interfaceName: 'uagv', transport: { brokerUrl: broker.url }, vdaVersion: '2.0.0', topicObjectValidation: { inbound: false } },
    { targetAgvs: agv },
  );
  await master.start();
});

after(async () => {
  await server?.stop();
  await master?.stop();
  watch.end();
  await broker?.stop();
  if (scratch) rmSync(scratch, { recursive: true, force: true });
});

test('the vehicle comes ONLINE and its state, visualization and factsheet follow the 2.1.0 schemas', { skip: missing }, async () => {
  const connection = await waitFor('connection', (c) => c.connectionState === 'ONLINE');
  assert.equal(connection.serialNumber, agv.serialNumber);
  const state = await waitFor('state', (s) => s.agvPosition !== undefined);
  assert.equal(state.version, '2.1.0');
  assert.equal(state.agvPosition.mapId, '~live@0', 'the live map, never saved, on level 0');
  assert.equal(state.operatingMode, 'AUTOMATIC');
  assert.deepEqual(state.safetyState, { eStop: 'NONE', fieldViolation: false });
  const visualization = await waitFor('visualization', (v) => v.agvPosition !== undefined);
  assert.ok(Number.isFinite(visualization.agvPosition.x));
  const factsheet = await waitFor('factsheet');
  const actions = factsheet.protocolFeatures.agvActions.map((a) => a.actionType);
  for (const type of ['initPosition', 'stateRequest', 'factsheetRequest', 'cancelOrder', 'startPause', 'stopPause']) assert.ok(actions.includes(type), type);
  assert.ok(factsheet.typeSpecification.localizationTypes.includes('NATURAL'));
  // Header ids count up per topic.
  const states = received.filter((m) => m.kind === 'state').map((m) => m.body.headerId);
  assert.deepEqual(states, [...states].sort((a, b) => a - b));
  assert.deepEqual(invalid, []);
});

test('initPosition goes the Set pose way: refused while mapping, a search once localizing; stateRequest answers', { skip: missing }, async () => {
  const whileMapping = await instantAction('initPosition', [
    { key: 'x', value: 0 }, { key: 'y', value: 0 }, { key: 'theta', value: 0 }, { key: 'mapId', value: '~live@0' }, { key: 'lastNodeId', value: '' },
  ]);
  assert.equal(whileMapping.actionStatus, 'FAILED');
  assert.match(whileMapping.resultDescription, /mapping|saved map|localiz/i);

  for (let waited = 0; (await getJson('/api/v1/status')).registration.scans < 2; waited += 1) {
    assert.ok(waited < 600, 'the robot takes its first scans');
    await new Promise((resolve) => setTimeout(resolve, 200));
  }
  const saved = await fetch(`${server.url}/api/v1/maps`, { method: 'POST', headers, body: JSON.stringify({ name: 'yard.smls' }) });
  assert.equal(saved.status, 201, await saved.text());
  const loaded = await fetch(`${server.url}/api/v1/maps/yard.smls/load`, { method: 'POST', headers, body: JSON.stringify({ mode: 'localize' }) });
  assert.equal(loaded.status, 200, await loaded.text());
  const state = await waitFor('state', (s) => s.agvPosition?.mapId === 'yard.smls@0');
  assert.ok(state.maps.some((m) => m.mapId === 'yard.smls@0' && m.mapStatus === 'ENABLED'), JSON.stringify(state.maps));

  const before = (await getJson('/api/v1/status')).relocalization;
  const truth = (await getJson('/api/v1/pose')).truth;
  const placed = await instantAction('initPosition', [
    { key: 'x', value: truth.x + 0.3 }, { key: 'y', value: truth.y }, { key: 'theta', value: truth.yaw }, { key: 'mapId', value: 'yard.smls@0' }, { key: 'lastNodeId', value: '' },
  ]);
  assert.equal(placed.actionStatus, 'FINISHED', placed.resultDescription);
  // The server searched around the estimate, as after the web app's Set pose.
  for (let waited = 0; ; waited += 1) {
    const now = (await getJson('/api/v1/status')).relocalization;
    if (now && (!before || now.stamp !== before.stamp)) break;
    assert.ok(waited < 600, 'a search for the robot follows the initPosition');
    await new Promise((resolve) => setTimeout(resolve, 200));
  }

  const mark = received.length;
  const answered = await instantAction('stateRequest');
  assert.equal(answered.actionStatus, 'FINISHED');
  await waitFor('state', (s) => s.actionStates.some((a) => a.actionId === answered.actionId && a.actionStatus === 'FINISHED'), { from: mark });
  assert.deepEqual(invalid, []);
});

test('malformed, unknown and huge instantActions are refused with an error in state, and nothing is done', { skip: missing }, async () => {
  const refused = async (payload, expect) => {
    const mark = received.length;
    await publishRaw(payload);
    const state = await waitFor('state', (s) => s.errors.some((e) => e.errorType === 'validationError' && expect.test(e.errorDescription)), { from: mark });
    return state;
  };
  const valid = (id) => ({ actionId: id, actionType: 'stateRequest', blockingType: 'NONE' });
  // Wrong types: x as a string.
  let state = await refused(
    JSON.stringify({ ...header(900), actions: [valid('ok-1'), { actionId: 'bad-1', actionType: 'initPosition', blockingType: 'HARD', actionParameters: [{ key: 'x', value: '1' }, { key: 'y', value: 0 }, { key: 'theta', value: 0 }, { key: 'mapId', value: 'yard.smls@0' }] }] }),
    /"x"/,
  );
  const error = state.errors.find((e) => e.errorType === 'validationError');
  assert.ok(error.errorReferences.some((r) => r.referenceKey === 'actionId' && r.referenceValue === 'bad-1'), JSON.stringify(error));
  assert.ok(!state.actionStates.some((a) => a.actionId === 'ok-1'), 'no action of a refused message is carried out');
  // An action this vehicle does not know.
  state = await refused(JSON.stringify({ ...header(901), actions: [valid('ok-2'), { actionId: 'lift-1', actionType: 'lift', blockingType: 'HARD' }] }), /lift/);
  assert.ok(!state.actionStates.some((a) => a.actionId === 'ok-2'));
  // Not JSON, and a huge message (1 MB).
  await refused('{"headerId": 1, "actions": [', /not JSON/);
  await refused(JSON.stringify({ ...header(902), actions: [valid('ok-3')], padding: 'x'.repeat(1 << 20) }), /bytes/);
  // An order without nodes: refused as malformed (VDA 5050 2.1, 6.6.4.1), nothing taken.
  const mark = received.length;
  await watch.publish(`${prefix}/order`, JSON.stringify({ ...header(903), orderId: 'o-1', orderUpdateId: 0, nodes: [], edges: [] }));
  const refusedOrder = await waitFor('state', (s) => s.errors.some((e) => e.errorType === 'validationError' && /at least one node/.test(e.errorDescription)), { from: mark });
  assert.deepEqual([refusedOrder.orderId, refusedOrder.nodeStates], ['', []]);
  // Still at work afterwards: a good message is carried out, and the refusal's error goes.
  const answered = await instantAction('stateRequest');
  assert.equal(answered.actionStatus, 'FINISHED');
  const after = await waitFor('state', (s) => s.actionStates.some((a) => a.actionId === answered.actionId));
  assert.ok(!after.errors.some((e) => e.errorType === 'validationError'), JSON.stringify(after.errors));
  assert.ok(!after.actionStates.some((a) => ['ok-1', 'ok-2', 'ok-3'].includes(a.actionId)));
  assert.deepEqual(invalid, []);
});

test('the broker restarted: the vehicle reconnects and is ONLINE again with its state; SIGTERM says OFFLINE', { skip: missing }, async () => {
  const mark = received.length;
  await broker.restart();
  await waitFor('connection', (c) => c.connectionState === 'ONLINE', { from: mark, timeout: 30000 });
  await waitFor('state', () => true, { from: mark });
  // The robot's own work went on meanwhile: the server answers.
  assert.ok((await getJson('/api/v1/status')).registration.scans >= 2);

  const beforeStop = received.length;
  assert.equal(await server.stop(), 0, 'strata exits cleanly on SIGTERM');
  await waitFor('connection', (c) => c.connectionState === 'OFFLINE', { from: beforeStop, timeout: 10000 });
  assert.deepEqual(invalid, []);
});
