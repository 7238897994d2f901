// Issue 61 item 3: Strata as the fleet's map server, and the VDA 5050 2.1 map actions, with real parts only:
// Debian's mosquitto, two real `strata serve` processes, npm's vda-5050-lib MasterController as the master,
// every message both vehicles send checked against the specification's 2.1.0 schemas. Robot A maps the
// yard and saves: an immutable map version at a stable URL. The master tells robot B (no map) to
// downloadMap it from A, enableMap, initPosition: B localizes in A's map under A's mapId and mapVersion.
// Faults: a link that 404s, a wrong mapHash, a corrupt file (FAILED with the reason, B's maps unchanged).
// The map server's HTTP: ETag, If-None-Match -> 304, Range -> 206, a range past the end -> 416.
// Usage: node --test map_server.test.mjs   (env STRATA_BINARY, MOSQUITTO, STRATA_VDA5050_DIR)
import assert from 'node:assert/strict';
import { createHash } from 'node:crypto';
import { mkdirSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { createServer } from 'node:http';
import { createServer as createHttpsServer } from 'node:https';
import { once } from 'node:events';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { after, before, test } from 'node:test';

import { MasterController } from 'vda-5050-lib';

import { startServer } from '../browser/server.mjs';
import { startBroker } from './broker.mjs';
import { makeCertificates } from './certificates.mjs';
import { fleetSetup, instantAction as runInstantAction, VehicleWatcher } from './master.mjs';

const { binary, mosquitto, schemaDir, missing } = fleetSetup();

const TOKEN = 'fleet-test-operator-token-0123456789';
const robotA = { manufacturer: 'StrataTest', serialNumber: 'robot-a' };
const robotB = { manufacturer: 'StrataTest', serialNumber: 'robot-b' };

let broker;
let serverA;
let serverB;
let corruptServer; // a plain HTTP server handing out a damaged copy of the map
let trusted; // certificates signed by the CA the servers trust (SSL_CERT_FILE)
const fileServers = []; // node's HTTPS servers of the map's file
let master;
let scratch;
let version; // A's saved map version: { name, version, bytes, sha256, url }
const watch = new VehicleWatcher(); // every message of both vehicles, checked against 2.1.0
const { received, invalid } = watch;

/** The first `kind` message of vehicle `serial` from index `from` on that `predicate` accepts. */
const waitFor = (serial, kind, predicate = () => true, options = {}) =>
  watch.waitFor((m) => m.serial === serial && m.kind === kind && predicate(m.body), `${kind} message of ${serial}`, options);

const headers = { Authorization: `Bearer ${TOKEN}`, 'Content-Type': 'application/json' };
const getJson = async (server, route) => (await fetch(`${server.url}${route}`)).json();
const sha256 = (bytes) => createHash('sha256').update(bytes).digest('hex');
const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

/** One instant action through the MasterController, its parameters as an object; its final state. */
const instantAction = (agv, actionType, parameters = {}) =>
  runInstantAction(master, agv, actionType, Object.entries(parameters).map(([key, value]) => ({ key, value })));

async function serve(agv, extra = []) {
  const config = path.join(scratch, `${agv.serialNumber}.ini`);
  writeFileSync(config, ['[serve]', `vda5050 = "${broker.url}"`, `vda5050-manufacturer = "${agv.manufacturer}"`, `vda5050-serial = "${agv.serialNumber}"`, ''].join('\n'));
  return startServer(binary, ['--config', config, '--time-scale', '4', '--operator-token', TOKEN, '--maps-dir', path.join(scratch, agv.serialNumber), ...extra]);
}

before(async () => {
  if (missing) return;
  broker = await startBroker(mosquitto);
  await watch.connect(broker.url, schemaDir, 'uagv/v2/StrataTest/+/+');

  scratch = mkdtempSync(path.join(tmpdir(), 'strata-fleet-maps-'));
  // The CA the servers' https client trusts: OpenSSL's default verify paths read SSL_CERT_FILE.
  mkdirSync(path.join(scratch, 'trusted'));
  trusted = makeCertificates(path.join(scratch, 'trusted'));
  process.env.SSL_CERT_FILE = trusted.ca;
  [serverA, serverB] = await Promise.all([serve(robotA), serve(robotB)]);
  // B stands where it starts (a command ends the simulator's demo route): it localizes there in A's map and
  // drives only the master's orders.
  const stopped = await fetch(`${serverB.url}/api/v1/goal`, { method: 'DELETE', headers });
  assert.equal(stopped.status, 200, await stopped.text());
  master = new MasterController(
    { interfaceName: 'uagv', transport: { brokerUrl: broker.url }, vdaVersion: '2.0.0', topicObjectValidation: { inbound: false } },
    { targetAgvs: {} },
  );
  await master.start();
});

after(async () => {
  await Promise.all([serverA?.stop(), serverB?.stop()]);
  await master?.stop();
  watch.end();
  await broker?.stop();
  corruptServer?.close();
  for (const server of fileServers) server.close();
  if (scratch) rmSync(scratch, { recursive: true, force: true });
});

test('robot A saves the yard: an immutable version with its SHA-256 at a stable URL', { skip: missing }, async () => {
  for (let waited = 0; (await getJson(serverA, '/api/v1/status')).registration.scans < 3; waited += 1) {
    assert.ok(waited < 600, 'robot A takes its first scans');
    await sleep(200);
  }
  const saved = await fetch(`${serverA.url}/api/v1/maps`, { method: 'POST', headers, body: JSON.stringify({ name: 'yard.smls' }) });
  assert.equal(saved.status, 201, await saved.text());
  const { versions } = await getJson(serverA, '/api/v1/map-versions');
  assert.equal(versions.length, 1, JSON.stringify(versions));
  version = versions[0];
  assert.equal(version.name, 'yard.smls');
  assert.equal(version.version, '1');
  assert.equal(version.url, '/api/v1/maps/yard.smls/versions/1');
  // A's state lists it (ENABLED while A's live map is that version, DISABLED once a scan changes the map).
  const state = await waitFor(robotA.serialNumber, 'state', (s) => s.maps.some((m) => m.mapId.startsWith('yard.smls@') && m.mapVersion === '1'));
  assert.ok(state.maps.length >= 1);
});

test('the map server: ETag, If-None-Match -> 304, ranges -> 206, past the end -> 416 (plain HTTP)', { skip: missing }, async () => {
  const url = `${serverA.url}${version.url}`;
  const whole = await fetch(url);
  assert.equal(whole.status, 200);
  const bytes = Buffer.from(await whole.arrayBuffer());
  assert.equal(bytes.length, version.bytes);
  assert.equal(sha256(bytes), version.sha256, 'the listed hash is the file\'s');
  assert.equal(whole.headers.get('etag'), `"${version.sha256}"`);
  assert.equal(whole.headers.get('cache-control'), 'public, max-age=31536000, immutable');
  assert.equal(whole.headers.get('accept-ranges'), 'bytes');

  const cached = await fetch(url, { headers: { 'If-None-Match': `"${version.sha256}"` } });
  assert.equal(cached.status, 304);
  assert.equal((await cached.arrayBuffer()).byteLength, 0);
  const other = await fetch(url, { headers: { 'If-None-Match': '"0000"' } });
  assert.equal(other.status, 200);
  await other.arrayBuffer();

  const part = await fetch(url, { headers: { Range: 'bytes=8-107' } });
  assert.equal(part.status, 206);
  assert.equal(part.headers.get('content-range'), `bytes 8-107/${bytes.length}`);
  assert.deepEqual(Buffer.from(await part.arrayBuffer()), bytes.subarray(8, 108));
  const tail = await fetch(url, { headers: { Range: 'bytes=-16' } });
  assert.equal(tail.status, 206);
  assert.deepEqual(Buffer.from(await tail.arrayBuffer()), bytes.subarray(bytes.length - 16));
  const past = await fetch(url, { headers: { Range: `bytes=${bytes.length}-` } });
  assert.equal(past.status, 416);
  assert.equal(past.headers.get('content-range'), `bytes */${bytes.length}`);
  await past.arrayBuffer();

  const absent = await fetch(`${serverA.url}/api/v1/maps/yard.smls/versions/99`);
  assert.equal(absent.status, 404);
  await absent.arrayBuffer();
  const traversal = await fetch(`${serverA.url}/api/v1/maps/..%2F..%2Fetc/versions/passwd`);
  assert.equal(traversal.status, 404);
  await traversal.arrayBuffer();
});

test('downloadMap faults: a 404 link, a wrong hash, a corrupt file: FAILED with the reason, maps unchanged', { skip: missing }, async () => {
  const mapsBefore = (await waitFor(robotB.serialNumber, 'state')).maps;
  const link = `${serverA.url}${version.url}`;
  const notFound = await instantAction(robotB, 'downloadMap', { mapId: 'yard.smls@0', mapVersion: '1', mapDownloadLink: `${serverA.url}/api/v1/maps/yard.smls/versions/99`, mapHash: version.sha256 });
  assert.equal(notFound.actionStatus, 'FAILED');
  assert.match(notFound.resultDescription, /404/);

  const wrongHash = await instantAction(robotB, 'downloadMap', { mapId: 'yard.smls@0', mapVersion: '1', mapDownloadLink: link, mapHash: 'ab'.repeat(32) });
  assert.equal(wrongHash.actionStatus, 'FAILED');
  assert.match(wrongHash.resultDescription, /SHA-256/);

  // The map with one byte changed in its middle, with the damaged file's own hash: the hash passes, the
  // file's checks do not.
  const damaged = Buffer.from(await (await fetch(link)).arrayBuffer());
  damaged[Math.floor(damaged.length / 2)] ^= 0x5a;
  corruptServer = createServer((request, response) => response.writeHead(200, { 'Content-Type': 'application/octet-stream' }).end(damaged));
  corruptServer.listen(0, '127.0.0.1');
  await once(corruptServer, 'listening');
  const corrupt = await instantAction(robotB, 'downloadMap', { mapId: 'yard.smls@0', mapVersion: '1', mapDownloadLink: `http://127.0.0.1:${corruptServer.address().port}/yard`, mapHash: sha256(damaged) });
  assert.equal(corrupt.actionStatus, 'FAILED');
  assert.match(corrupt.resultDescription, /checksum|corrupt|truncated|invalid/i);

  const after = await waitFor(robotB.serialNumber, 'state', (s) => s.actionStates.some((a) => a.actionId === corrupt.actionId && a.actionStatus === 'FAILED'));
  assert.deepEqual(after.maps, mapsBefore, 'nothing was stored');
  assert.deepEqual((await getJson(serverB, '/api/v1/map-versions')).versions, []);
  assert.deepEqual(invalid, []);
});

test('robot B downloads A\'s map through the master, enables it, is placed and localizes under A\'s mapId', { skip: missing }, async () => {
  const link = `${serverA.url}${version.url}`;
  const started = performance.now();
  const downloaded = await instantAction(robotB, 'downloadMap', { mapId: 'yard.smls@0', mapVersion: version.version, mapDownloadLink: link, mapHash: version.sha256 });
  assert.equal(downloaded.actionStatus, 'FINISHED', downloaded.resultDescription);
  const stored = await waitFor(robotB.serialNumber, 'state', (s) => s.maps.some((m) => m.mapId === 'yard.smls@0'));
  const entry = stored.maps.find((m) => m.mapId === 'yard.smls@0');
  assert.deepEqual([entry.mapVersion, entry.mapStatus], ['1', 'DISABLED'], 'stored, not in use');
  assert.equal(stored.agvPosition.mapId, '~live@0', 'B goes on in its own live map');
  const listed = (await getJson(serverB, '/api/v1/map-versions')).versions;
  assert.deepEqual(listed.map((v) => [v.name, v.version, v.sha256]), [['yard.smls', '1', version.sha256]], 'the same name, version and bytes');
  // The same version again is refused (VDA 5050 2.1, 6.7.3), and nothing changes.
  const again = await instantAction(robotB, 'downloadMap', { mapId: 'yard.smls@0', mapVersion: version.version, mapDownloadLink: link });
  assert.equal(again.actionStatus, 'FAILED');
  assert.match(again.resultDescription, /there already/);

  const enabled = await instantAction(robotB, 'enableMap', { mapId: 'yard.smls@0', mapVersion: version.version });
  assert.equal(enabled.actionStatus, 'FINISHED', enabled.resultDescription);
  console.log(`download and enable of a ${version.bytes}-byte map: ${(performance.now() - started).toFixed(0)} ms (through the broker)`);
  const inUse = await waitFor(robotB.serialNumber, 'state', (s) => s.agvPosition?.mapId === 'yard.smls@0');
  assert.ok(inUse.maps.some((m) => m.mapId === 'yard.smls@0' && m.mapVersion === '1' && m.mapStatus === 'ENABLED'), JSON.stringify(inUse.maps));
  const deleteInUse = await instantAction(robotB, 'deleteMap', { mapId: 'yard.smls@0', mapVersion: '1' });
  assert.equal(deleteInUse.actionStatus, 'FAILED');
  assert.match(deleteInUse.resultDescription, /in use/);

  // Both robots start at the yard's same spot: B's true pose is where A's map has it.
  const truth = (await getJson(serverB, '/api/v1/pose')).truth;
  const mark = received.length;
  const placed = await instantAction(robotB, 'initPosition', { x: truth.x + 0.3, y: truth.y, theta: truth.yaw, mapId: 'yard.smls@0', lastNodeId: '' });
  assert.equal(placed.actionStatus, 'FINISHED', placed.resultDescription);
  const localized = await waitFor(robotB.serialNumber, 'state', (s) => s.agvPosition?.positionInitialized === true && s.agvPosition.mapId === 'yard.smls@0', { from: mark, timeout: 60000 });
  const pose = (await getJson(serverB, '/api/v1/pose')).truth;
  const position = (await waitFor(robotB.serialNumber, 'visualization', (v) => v.agvPosition?.mapId === 'yard.smls@0', { from: received.length - 1 })).agvPosition;
  assert.ok(Math.hypot(position.x - pose.x, position.y - pose.y) < 0.5, `B is where A's map has it: ${JSON.stringify(position)} vs ${JSON.stringify(pose)}`);
  assert.equal(localized.maps.find((m) => m.mapStatus === 'ENABLED' && m.mapId === 'yard.smls@0').mapVersion, '1');
  assert.deepEqual(invalid, []);
});

/** A VDA 5050 order of `nodes` ({ id, x, y }) on the yard's level 0, sequenceIds from `first`, the first `released` in the base. */
function yardOrder(orderId, orderUpdateId, nodes, released, first = 0) {
  const node = (n, i) => ({ nodeId: n.id, sequenceId: first + 2 * i, released: i < released, nodePosition: { x: n.x, y: n.y, mapId: 'yard.smls@0' }, actions: [] });
  const edge = (n, i) => ({ edgeId: `${nodes[i].id}-${n.id}`, sequenceId: first + 2 * i + 1, released: i + 1 < released, startNodeId: nodes[i].id, endNodeId: n.id, actions: [] });
  return { orderId, orderUpdateId, nodes: nodes.map(node), edges: nodes.slice(1).map(edge) };
}

/** Assigns `order` to `agv` through the master: the nodes it reports traversed, and when it is processed. */
function assignOrder(agv, order) {
  const traversed = [];
  const processed = new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`order ${order.orderId}/${order.orderUpdateId}: not processed`)), 60000);
    master
      .assignOrder(agv, order, {
        onNodeTraversed: (node) => traversed.push(node.nodeId),
        onOrderProcessed: (error, byCancelation, active, { state }) => {
          clearTimeout(timer);
          resolve({ error, byCancelation, active, state });
        },
      })
      .catch(reject);
  });
  return { traversed, processed };
}

/** Publishes `order` raw on `agv`'s order topic with a header, as a master that resends or is behind would. */
const publishOrder = (agv, order, headerId) =>
  watch.publish(`uagv/v2/${agv.manufacturer}/${agv.serialNumber}/order`, JSON.stringify({ headerId, timestamp: new Date().toISOString(), version: '2.1.0', ...agv, ...order }));

const near = (position, node, within = 0.6) => Math.hypot(position.x - node.x, position.y - node.y) < within;

test('robot B drives an order of three nodes on the yard\'s mapId: node by node, the horizon after an update, through a broker restart', { skip: missing }, async () => {
  const at = (await waitFor(robotB.serialNumber, 'visualization', (v) => v.agvPosition?.mapId === 'yard.smls@0', { from: received.length - 1 })).agvPosition;
  // Along the campus's first street, which A drove while it mapped: B starts where A started.
  const nodes = [{ id: 'start', x: at.x, y: at.y }, { id: 'east', x: 6.5, y: 10 }, { id: 'corner', x: 8.7, y: 9 }];
  // The base: start and east; corner is the horizon until the update releases it.
  const mark = received.length;
  const first = assignOrder(robotB, yardOrder('yard-round', 0, nodes, 2));
  const waiting = await first.processed;
  assert.equal(waiting.error, undefined, JSON.stringify(waiting.error));
  assert.equal(waiting.active, true, 'the base is done, the horizon waits');
  assert.deepEqual(first.traversed, ['start', 'east']);
  assert.deepEqual([waiting.state.lastNodeId, waiting.state.lastNodeSequenceId], ['east', 2]);
  assert.deepEqual(waiting.state.nodeStates.map((n) => [n.nodeId, n.released]), [['corner', false]]);
  assert.deepEqual(waiting.state.edgeStates.map((e) => [e.edgeId, e.released]), [['east-corner', false]]);
  assert.ok(near((await getJson(serverB, '/api/v1/pose')).truth, nodes[1]), 'B stands at east');
  // The states on the way: the node states shrink as nodes are passed, and B drove.
  const states = received.slice(mark).filter((m) => m.serial === robotB.serialNumber && m.kind === 'state' && m.body.orderId === 'yard-round');
  const counts = states.map((m) => m.body.nodeStates.length).filter((count, i, all) => i === 0 || count !== all[i - 1]);
  assert.deepEqual(counts, [2, 1], 'east and corner left, then corner');
  assert.ok(states.some((m) => m.body.driving), 'driving on the way to east');

  // The broker restarted mid-order: B comes back ONLINE with its state, the order still there.
  const beforeRestart = received.length;
  const masterOnline = new Promise((resolve) => master.registerConnectionStateChange((now, before) => now === 'online' && before !== 'online' && resolve()));
  await broker.restart();
  await waitFor(robotB.serialNumber, 'connection', (c) => c.connectionState === 'ONLINE', { from: beforeRestart });
  const resent = await waitFor(robotB.serialNumber, 'state', () => true, { from: beforeRestart });
  assert.deepEqual([resent.orderId, resent.lastNodeId, resent.nodeStates.length], ['yard-round', 'east', 1]);
  await masterOnline;

  // The update stitches on at east and releases corner: B drives there and the order is done.
  const update = assignOrder(robotB, yardOrder('yard-round', 1, nodes.slice(1), 2, 2));
  const done = await update.processed;
  assert.equal(done.error, undefined, JSON.stringify(done.error));
  assert.equal(done.active, false, 'finished');
  assert.deepEqual([done.state.lastNodeId, done.state.lastNodeSequenceId, done.state.orderUpdateId], ['corner', 4, 1]);
  assert.deepEqual([done.state.nodeStates, done.state.edgeStates], [[], []]);
  assert.ok(near((await getJson(serverB, '/api/v1/pose')).truth, nodes[2]), 'B stands at corner');

  // A stale update (orderUpdateId 0 after 1) is refused and changes nothing.
  const beforeStale = received.length;
  await publishOrder(robotB, yardOrder('yard-round', 0, nodes.slice(1), 2, 2), 9001);
  const stale = await waitFor(robotB.serialNumber, 'state', (s) => s.errors.some((e) => e.errorType === 'orderUpdateError'), { from: beforeStale });
  assert.match(stale.errors.find((e) => e.errorType === 'orderUpdateError').errorDescription, /older than the current 1/);
  assert.deepEqual([stale.orderUpdateId, stale.lastNodeId, stale.nodeStates.length], [1, 'corner', 0]);
  assert.deepEqual(invalid, []);
});

test('an order to a node B cannot reach stops with NODE_UNREACHABLE and the planner\'s reason; cancelOrder clears it', { skip: missing }, async () => {
  const at = (await waitFor(robotB.serialNumber, 'visualization', (v) => v.agvPosition?.mapId === 'yard.smls@0', { from: received.length - 1 })).agvPosition;
  // Far beyond anything A's map has seen: no way there.
  const order = assignOrder(robotB, yardOrder('beyond-the-map', 0, [{ id: 'here', x: at.x, y: at.y }, { id: 'outside', x: -60, y: 9.5 }], 2));
  const stopped = await order.processed;
  assert.equal(stopped.error?.errorType, 'NODE_UNREACHABLE', JSON.stringify(stopped.error));
  assert.match(stopped.error.errorDescription, /"outside" cannot be reached: .+ \((off_map|no_connection|goal_not_drivable)\)/);
  assert.ok(stopped.error.errorReferences.some((r) => r.referenceKey === 'nodeId' && r.referenceValue === 'outside'));
  assert.deepEqual(stopped.state.nodeStates.map((n) => n.nodeId), ['outside'], 'the node not reached is still to do');
  // A new order is refused while this one is not finished; cancelOrder ends it.
  const beforeBusy = received.length;
  await publishOrder(robotB, yardOrder('another', 0, [{ id: 'here', x: at.x, y: at.y }], 1), 9002);
  await waitFor(robotB.serialNumber, 'state', (s) => s.errors.some((e) => e.errorType === 'orderError' && /not finished/.test(e.errorDescription)), { from: beforeBusy });
  const cancelled = await instantAction(robotB, 'cancelOrder');
  assert.equal(cancelled.actionStatus, 'FINISHED', cancelled.resultDescription);
  const after = await waitFor(robotB.serialNumber, 'state', (s) => s.actionStates.some((a) => a.actionId === cancelled.actionId));
  assert.deepEqual([after.orderId, after.nodeStates, after.edgeStates], ['beyond-the-map', [], []]);
  assert.deepEqual(invalid, []);
});

/** An HTTPS server of `bytes` with `certificates`; its URL. */
async function httpsFile(certificates, bytes) {
  const server = createHttpsServer({ cert: readFileSync(certificates.cert), key: readFileSync(certificates.key) }, (request, response) =>
    response.writeHead(200, { 'Content-Type': 'application/octet-stream' }).end(bytes),
  );
  fileServers.push(server);
  server.listen(0, '127.0.0.1');
  await once(server, 'listening');
  return `https://127.0.0.1:${server.address().port}/yard.smls`;
}

test('downloadMap over https: a server with a trusted certificate is taken, another is refused', { skip: missing }, async () => {
  const bytes = Buffer.from(await (await fetch(`${serverA.url}${version.url}`)).arrayBuffer());
  const taken = await instantAction(robotB, 'downloadMap', { mapId: 'yard.smls@0', mapVersion: 'tls-1', mapDownloadLink: await httpsFile(trusted, bytes), mapHash: version.sha256 });
  assert.equal(taken.actionStatus, 'FINISHED', taken.resultDescription);
  mkdirSync(path.join(scratch, 'stranger'));
  const stranger = makeCertificates(path.join(scratch, 'stranger')); // signed by a CA nobody trusts
  const refused = await instantAction(robotB, 'downloadMap', { mapId: 'yard.smls@0', mapVersion: 'tls-2', mapDownloadLink: await httpsFile(stranger, bytes), mapHash: version.sha256 });
  assert.equal(refused.actionStatus, 'FAILED');
  assert.match(refused.resultDescription, /certificate/);
  const versions = (await getJson(serverB, '/api/v1/map-versions')).versions.map((v) => v.version);
  assert.deepEqual(versions, ['1', 'tls-1']);
  assert.deepEqual(invalid, []);
});

test('deleteMap removes a version not in use', { skip: missing }, async () => {
  // A saves its map under another name: yard.smls's version is not in use any more.
  const saved = await fetch(`${serverA.url}/api/v1/maps`, { method: 'POST', headers, body: JSON.stringify({ name: 'yard-copy.smls' }) });
  assert.equal(saved.status, 201, await saved.text());
  const deleted = await instantAction(robotA, 'deleteMap', { mapId: 'yard.smls@0', mapVersion: '1' });
  assert.equal(deleted.actionStatus, 'FINISHED', deleted.resultDescription);
  const state = await waitFor(robotA.serialNumber, 'state', (s) => s.actionStates.some((a) => a.actionId === deleted.actionId && a.actionStatus === 'FINISHED'));
  assert.ok(!state.maps.some((m) => m.mapId.startsWith('yard.smls@')), JSON.stringify(state.maps));
  assert.deepEqual((await getJson(serverA, '/api/v1/map-versions')).versions.map((v) => v.name), ['yard-copy.smls']);
  assert.deepEqual(invalid, []);
});

test('both servers stop cleanly on SIGTERM (exit status 0: no sanitizer report, no crash)', { skip: missing }, async () => {
  assert.deepEqual(await Promise.all([serverA.stop(), serverB.stop()]), [0, 0]);
});
