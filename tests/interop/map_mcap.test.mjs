// The map as MCAP (issue 62), read by the MCAP project's own reader and decoded by Foxglove's ROS 2
// deserializer, as Foxglove and Lichtblick read it: a real `strata serve` (the simulator's default world)
// maps a few scans, then GET /api/v1/map?format=mcap (zstd and plain) is opened with @mcap/core's indexed
// reader (footer, summary, chunk indexes, summary and chunk CRCs), every message is decoded with
// @foxglove/rosmsg2-serialization from the file's own ros2msg schemas, and the fields are checked against
// the server's other exports: the OccupancyGrid is the PGM/YAML of the same map version cell for cell.
// A file cut short is refused. `strata map export --mcap` of the map saved by the same server reads alike.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { execFile } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { promisify } from 'node:util';
import { crc32 } from 'node:zlib';
import { startServer } from '../browser/server.mjs';
import { openMcap as open, decodeAll as decodeAllOf, rosMap as rosMapOf, checkGridIsTheExport } from './mcap_files.mjs';

const token = 'map-mcap-test-operator-token';
let server;
let maps;

before(async () => {
  maps = mkdtempSync(join(tmpdir(), 'strata-mcap-maps-'));
  server = await startServer(process.env.STRATA_BINARY, [
    '--time-scale', '5', '--operator-token', token, '--maps-dir', maps,
  ]);
  // A map with a drivable level and keyframes to make a path of.
  for (let i = 0; ; i++) {
    const status = await (await fetch(`${server.url}/api/v1/status`)).json();
    if (status.map?.tiles > 0 && status.pose !== null && status.pose_graph?.keyframes >= 2) break;
    if (i === 600) throw new Error(`no map with keyframes after 60 s: ${JSON.stringify(status)}`);
    await new Promise((resolve) => setTimeout(resolve, 100));
  }
});

after(async () => {
  await server?.stop();
  rmSync(maps, { recursive: true, force: true });
});

async function download(query) {
  const response = await fetch(`${server.url}/api/v1/map?${query}`);
  assert.equal(response.status, 200, `${query}: ${response.status} ${await response.clone().text()}`);
  return { response, bytes: new Uint8Array(await response.arrayBuffer()) };
}

/// Every message decoded, by topic; each channel offers rosbag2's QoS.
const decodeAll = (reader) => decodeAllOf(reader, (channel) => {
  assert.ok(channel.metadata.get('offered_qos_profiles'), 'the ros2 profile asks for the QoS');
});

const rosMap = () => rosMapOf(server.url);

/// Checks the decoded messages against the ROS export `ros`; returns what they held, for the log.
function checkMessages(messages, ros) {
  assert.deepEqual(Object.keys(messages).sort(), ['/map', '/map_patches', '/tf', '/trajectory']);
  for (const list of Object.values(messages)) assert.equal(list.length, 1);

  // The drivable map: the PGM/YAML of the same version, cell for cell.
  const grid = messages['/map'][0];
  const free = checkGridIsTheExport(grid, ros);
  assert.ok(free > 100, `${free} free cells`);

  // The patches: x, y, z, height, class, level, every point inside the map's extent.
  const cloud = messages['/map_patches'][0];
  assert.equal(cloud.type, 'sensor_msgs/msg/PointCloud2');
  assert.deepEqual(cloud.fields.map((field) => field.name), ['x', 'y', 'z', 'height', 'class', 'level']);
  assert.ok(cloud.width > 1000, `${cloud.width} patches`);
  assert.equal(cloud.data.length, cloud.width * cloud.point_step);
  const view = new DataView(cloud.data.buffer, cloud.data.byteOffset, cloud.data.byteLength);
  const classes = new Set();
  const cells = new Map();  // "x,y" -> the levels of its patches, in the cloud's order
  for (let i = 0; i < cloud.width; i++) {
    const at = i * cloud.point_step;
    const [x, y, z, height] = [0, 4, 8, 12].map((offset) => view.getFloat32(at + offset, true));
    assert.ok([x, y, z, height].every(Number.isFinite) && height >= 0);
    classes.add(view.getUint8(at + 16));
    const key = `${x},${y}`;
    cells.set(key, [...(cells.get(key) ?? []), view.getUint8(at + 17)]);
  }
  assert.ok(classes.has(0) && classes.has(1), `classes ${[...classes]}: floors and walls`);
  // Each cell's patches are numbered 0, 1, ... from the lowest.
  for (const [key, levels] of cells) assert.deepEqual(levels, levels.map((_, i) => i), key);
  assert.ok([...cells.values()].some((levels) => levels.length > 1), 'cells with more than one patch');

  // The keyframes' path, and tf: every frame a message names reaches the root, map.
  const path = messages['/trajectory'][0];
  assert.equal(path.type, 'nav_msgs/msg/Path');
  assert.ok(path.poses.length >= 2, `${path.poses.length} poses`);
  const tf = messages['/tf'][0].transforms;
  const parents = new Map(tf.map((transform) => [transform.child_frame_id, transform.header.frame_id]));
  assert.deepEqual([...parents], [['base_link', 'map']]);
  const last = path.poses.at(-1).pose.position;
  assert.deepEqual(tf[0].transform.translation, { x: last.x, y: last.y, z: last.z });
  for (const frame of ['map', 'base_link', grid.header.frame_id, cloud.header.frame_id, path.header.frame_id]) {
    let at = frame;
    for (let hops = 0; at !== 'map'; hops++) {
      assert.ok(parents.has(at) && hops < 10, `frame ${frame} does not reach map`);
      at = parents.get(at);
    }
  }
  return `${ros.width}x${ros.height} cells (${free} free), ${cloud.width} patches, ${path.poses.length} keyframes`;
}

test('the map as MCAP, zstd and plain, reads with its index and CRCs and decodes to the ROS map export', async (t) => {
  const ros = await rosMap();
  const sizes = {};
  for (const compression of ['zstd', 'none']) {
    const { response, bytes } = await download(`format=mcap&compression=${compression}&version=${ros.version}`);
    assert.equal(response.headers.get('x-strata-version'), ros.version);
    assert.match(response.headers.get('content-disposition'), /filename="map\.mcap"/);
    sizes[compression] = bytes.length;
    const reader = await open(bytes);  // checks the summary's CRC
    assert.equal(reader.header.profile, 'ros2');
    assert.ok(reader.chunkIndexes.length >= 1);
    for (const chunk of reader.chunkIndexes) assert.equal(chunk.compression, compression === 'zstd' ? 'zstd' : '');
    assert.equal(reader.statistics.messageCount, 4n);
    // The data section's CRC (the reader keeps it, it does not check it): everything before Data End.
    const dataEnd = Number(reader.footer.summaryStart) - 13;
    assert.equal(bytes[dataEnd], 0x0f);
    assert.equal(reader.dataSectionCrc, crc32(bytes.subarray(0, dataEnd)));
    t.diagnostic(`${compression}: ${bytes.length} bytes, ${checkMessages(await decodeAll(reader), ros)}`);
  }
  assert.ok(sizes.zstd < sizes.none / 2, `zstd ${sizes.zstd} bytes, plain ${sizes.none}`);
});

test('a map MCAP cut short or corrupted is refused by the reader', async () => {
  const { bytes } = await download('format=mcap&compression=none');
  for (const length of [bytes.length - 1, bytes.length - 40, Math.floor(bytes.length / 2), 20]) {
    await assert.rejects(open(bytes.subarray(0, length)), undefined, `cut at ${length} of ${bytes.length}`);
  }
  // A flipped byte inside the chunk: the chunk's CRC refuses it.
  const corrupt = bytes.slice();
  const reader = await open(corrupt);
  const chunk = reader.chunkIndexes[0];
  corrupt[Number(chunk.chunkStartOffset + chunk.chunkLength) - 100] ^= 0xff;
  await assert.rejects(decodeAll(await open(corrupt)), /CRC/);
});

test('format=mcap takes compression zstd or none only', async () => {
  for (const query of ['format=mcap&compression=lz4', 'format=ply&compression=none']) {
    const response = await fetch(`${server.url}/api/v1/map?${query}`);
    assert.equal(response.status, 400, query);
    assert.equal((await response.json()).error.code, 'bad_params');
  }
});

test('strata map export --mcap writes the saved map, its keyframes and its drivable map', async (t) => {
  const saved = await fetch(`${server.url}/api/v1/maps`, {
    method: 'POST',
    headers: { Authorization: `Bearer ${token}`, 'Content-Type': 'application/json' },
    body: JSON.stringify({ name: 'yard' }),
  });
  assert.equal(saved.status, 201, await saved.text());
  const pose = await (await fetch(`${server.url}/api/v1/pose`)).json();
  const output = join(maps, 'yard.mcap');
  const { stdout } = await promisify(execFile)(process.env.STRATA_BINARY, [
    'map', 'export', join(maps, 'yard'), '--mcap', output, '--robot', `${pose.x},${pose.y},${pose.z}`,
  ]);
  const summary = JSON.parse(stdout);
  assert.equal(summary.mcap, output);
  assert.ok(summary.keyframes >= 2, stdout);
  const bytes = new Uint8Array(readFileSync(output));
  assert.equal(summary.mcap_bytes, bytes.length);
  const messages = await decodeAll(await open(bytes));
  assert.deepEqual(Object.keys(messages).sort(), ['/map', '/map_patches', '/tf', '/trajectory']);
  assert.equal(messages['/map_patches'][0].width, summary.patches);
  assert.equal(messages['/trajectory'][0].poses.length, summary.keyframes);
  const grid = messages['/map'][0];
  assert.ok(grid.data.some((cell) => cell === 0), 'free cells around the robot');
  t.diagnostic(`${bytes.length} bytes, ${summary.patches} patches, ${summary.keyframes} keyframes, ` +
    `${grid.info.width}x${grid.info.height} cells`);
});
