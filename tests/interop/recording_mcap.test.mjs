// A run recorded as MCAP (issue 62, `strata serve --record-mcap`), read by the MCAP project's own reader and
// decoded by Foxglove's ROS 2 deserializer: a real `strata serve` drives the yard and records three scans
// into both Strata's own layout (--record) and MCAP; every message of the MCAP file decodes from its own
// schema, and its fields are checked against the other exports: each /scan's points are the bytes of the
// own layout's PCD of that scan, the exact rows are the own layout's CSV rows, the tf tree reaches map from
// the sensor, the last /map is the PGM/YAML of the final map cell for cell. A file cut short is refused by
// the indexed reader and reads up to the cut with the streaming one.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { copyFileSync, existsSync, mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { execFile } from 'node:child_process';
import { promisify } from 'node:util';
import { startServer } from '../browser/server.mjs';
import { openMcap, decodeAll, streamRecords, rosMap, checkGridIsTheExport } from './mcap_files.mjs';

const scans = 3;
const token = 'recording-mcap-test-operator-token';
let work;
let ros;
let bytes;
let goal;  // the goal sent after the scans, as GET /api/v1/goal last reported it

before(async () => {
  work = mkdtempSync(join(tmpdir(), 'strata-recording-mcap-'));
  const server = await startServer(process.env.STRATA_BINARY, [
    '--world', 'yard', '--scanner', 'tilting', '--seed', '7', '--time-scale', '4', '--max-scans', String(scans),
    '--record', join(work, 'own'), '--record-mcap', join(work, 'run.mcap'), '--maps-dir', join(work, 'maps'),
    '--operator-token', token,
  ]);
  try {
    // Every scan mapped: the map's version counts them.
    for (let i = 0; ; i++) {
      const status = await (await fetch(`${server.url}/api/v1/status`)).json();
      if (status.registration.scans >= scans && status.map.version >= scans) break;
      if (i === 1200) throw new Error(`${scans} scans not mapped after 120 s: ${JSON.stringify(status)}`);
      await new Promise((resolve) => setTimeout(resolve, 100));
    }
    assert.ok(existsSync(join(work, 'run.mcap.part')), 'written as FILE.part while it runs');
    ros = await rosMap(server.url);
    // A goal 1.5 m ahead on the mapped ground: its events and its path go into the recording.
    const pose = await (await fetch(`${server.url}/api/v1/pose`)).json();
    const sent = await fetch(`${server.url}/api/v1/goal`, {
      method: 'POST',
      headers: { Authorization: `Bearer ${token}`, 'Content-Type': 'application/json' },
      body: JSON.stringify({ x: pose.x + 1.5 * Math.cos(pose.yaw), y: pose.y + 1.5 * Math.sin(pose.yaw) }),
    });
    assert.ok(sent.ok, await sent.text());
    for (let i = 0; ; i++) {
      goal = await (await fetch(`${server.url}/api/v1/goal`)).json();
      if (['reached', 'failed'].includes(goal.phase)) break;
      if (i === 600) throw new Error(`the goal is still ${goal.phase} after 60 s`);
      await new Promise((resolve) => setTimeout(resolve, 100));
    }
  } finally {
    assert.equal(await server.stop(), 0);
  }
  bytes = new Uint8Array(readFileSync(join(work, 'run.mcap')));
});

after(() => rmSync(work, { recursive: true, force: true }));

/// The lines of a CSV file of the own layout, without its header.
function rows(file) {
  return readFileSync(file, 'utf8').split('\n').slice(1).filter((line) => line !== '');
}

test('every message of the recorded run decodes, and matches the own layout and the map export', async (t) => {
  const reader = await openMcap(bytes);  // the footer, the summary and its CRC
  assert.equal(reader.header.profile, 'ros2');
  for (const chunk of reader.chunkIndexes) assert.equal(chunk.compression, 'zstd');
  const messages = await decodeAll(reader, (channel) => {  // every chunk's CRC
    // /map is latched for ros2 bag play, as map_server publishes it (transient local); the rest the default.
    const qos = channel.metadata.get('offered_qos_profiles');
    if (channel.topic === '/map') assert.match(qos, /durability: 1/);
    else assert.equal(qos, undefined, channel.topic);
  });
  const types = Object.fromEntries(Object.entries(messages).map(([topic, list]) => [topic, list[0].type]));
  for (const topic of ['/strata/recording', '/strata/odometry', '/strata/scans', '/odom', '/tf', '/imu', '/scan',
    '/pose', '/map']) {
    assert.ok(messages[topic]?.length > 0, `${topic} recorded`);
  }
  assert.deepEqual(types, {
    '/strata/recording': 'std_msgs/msg/String', '/strata/odometry': 'std_msgs/msg/String',
    '/strata/scans': 'std_msgs/msg/String', '/odom': 'nav_msgs/msg/Odometry', '/tf': 'tf2_msgs/msg/TFMessage',
    '/imu': 'sensor_msgs/msg/Imu', '/scan': 'sensor_msgs/msg/PointCloud2',
    '/pose': 'geometry_msgs/msg/PoseWithCovarianceStamped', '/map': 'nav_msgs/msg/OccupancyGrid',
    '/goal_events': 'std_msgs/msg/String',
    ...(goal.phase === 'reached' ? { '/plan': 'nav_msgs/msg/Path' } : {}),
  });

  // The scans: the points of the own layout's PCD files, byte for byte, in the sensor frame.
  const own = join(work, 'own');
  assert.equal(messages['/scan'].length, scans);
  messages['/scan'].forEach((cloud, i) => {
    assert.equal(cloud.header.frame_id, 'sensor');
    assert.deepEqual(cloud.fields.map((field) => field.name), ['x', 'y', 'z', 'time'].slice(0, cloud.point_step / 4));
    const pcd = readFileSync(join(own, 'scans', `${String(i).padStart(6, '0')}.pcd`));
    const data = pcd.subarray(pcd.indexOf('DATA binary\n') + 'DATA binary\n'.length);
    assert.ok(cloud.width > 1000, `${cloud.width} points`);
    assert.ok(Buffer.from(cloud.data).equals(data), `scan ${i}: the /scan points differ from the PCD's`);
  });
  // The exact rows a replay reads are the own layout's rows.
  const odometryRows = rows(join(own, 'odometry.csv'));
  assert.deepEqual(messages['/strata/odometry'].map((m) => m.data), odometryRows);
  assert.equal(messages['/odom'].length, odometryRows.length);
  assert.deepEqual(messages['/strata/scans'].map((m) => m.data.split(',').slice(1)),
    rows(join(own, 'scans.csv')).map((row) => row.split(',').slice(1)));
  const recording = JSON.parse(messages['/strata/recording'][0].data);
  assert.equal(recording.format, 'strata-recording-mcap');
  assert.equal(recording.seed, 7);

  // The odometry and the IMU: base_link in odom; gravity, about 9.8 m/s^2, up in the base frame.
  const odom = messages['/odom'].at(-1);
  assert.equal(odom.header.frame_id, 'odom');
  assert.equal(odom.child_frame_id, 'base_link');
  const imu = messages['/imu'][0];
  const { x, y, z } = imu.linear_acceleration;
  assert.ok(Math.abs(Math.hypot(x, y, z) - 9.80665) < 1e-6 && z > 9, `${x} ${y} ${z}`);
  assert.equal(imu.orientation_covariance[0], -1, 'no orientation');

  // tf: sensor -> base_link -> odom -> map, each frame a message names reaches map.
  const parents = new Map();
  for (const message of messages['/tf']) {
    for (const transform of message.transforms) parents.set(transform.child_frame_id, transform.header.frame_id);
  }
  assert.deepEqual(Object.fromEntries(parents), { base_link: 'odom', sensor: 'base_link', odom: 'map' });
  assert.equal(messages['/pose'].length, scans);
  assert.equal(messages['/pose'][0].header.frame_id, 'map');

  // The goal's phases as JSON, the last the one the API reports; the path it drove, in map.
  const events = messages['/goal_events'].map((m) => JSON.parse(m.data));
  assert.ok(events.every((event) => event.id === goal.id));
  assert.equal(events.at(-1).phase, goal.phase, JSON.stringify(events));
  if (goal.phase === 'reached') {
    const plan = messages['/plan'].at(-1);
    assert.equal(plan.header.frame_id, 'map');
    assert.ok(plan.poses.length >= 2, `${plan.poses.length} poses`);
  }

  // The drivable map as it changed; the last one is the map's PGM/YAML export.
  const free = checkGridIsTheExport(messages['/map'].at(-1), ros);
  assert.ok(free > 100, `${free} free cells`);
  t.diagnostic(`${bytes.length} bytes: ${Object.entries(messages).map(([topic, list]) => `${topic} ${list.length}`).join(', ')}`);
});

test('a recording cut short is refused by the indexed reader and reads up to the cut with the streaming one', async () => {
  const whole = streamRecords(bytes);
  assert.ok(whole.done);
  const messagesOf = (records) => records.filter((record) => record.type === 'Message');
  const all = messagesOf(whole.records);
  for (const cut of [bytes.length - 1, Math.floor(bytes.length * 0.75), Math.floor(bytes.length / 2), 4000]) {
    const part = bytes.subarray(0, cut);
    await assert.rejects(openMcap(part), undefined, `cut at ${cut} of ${bytes.length}`);
    const { records, done } = streamRecords(part);
    assert.ok(!done, `cut at ${cut}`);
    const read = messagesOf(records);
    // What was read is the file's beginning: the same messages, in order.
    assert.ok(read.length < all.length || cut > bytes.length - 1000, `cut at ${cut}: ${read.length} of ${all.length}`);
    read.forEach((message, i) => assert.equal(message.sequence, all[i].sequence));
    if (cut > 4000) assert.ok(read.length > 0, `cut at ${cut}: messages before the cut`);
  }
});

test('a killed recorder leaves FILE.part, which reads to its last chunk and which --replay refuses', async () => {
  const part = join(work, 'killed.mcap.part');
  const server = await startServer(process.env.STRATA_BINARY, [
    '--world', 'yard', '--scanner', 'tilting', '--seed', '7', '--time-scale', '4', '--max-scans', '2',
    '--record-mcap', join(work, 'killed.mcap'), '--maps-dir', join(work, 'killed-maps'),
  ]);
  let scansRead = 0;
  try {
    // Each scan closes its chunk: wait until both are in the file, as any reader reads it.
    for (let i = 0; scansRead < 2; i++) {
      if (i === 1200) throw new Error(`${scansRead} scans in ${part} after 120 s`);
      await new Promise((resolve) => setTimeout(resolve, 100));
      const { records } = streamRecords(new Uint8Array(readFileSync(part)));
      const channels = new Map(records.filter((r) => r.type === 'Channel').map((r) => [r.id, r.topic]));
      scansRead = records.filter((r) => r.type === 'Message' && channels.get(r.channelId) === '/scan').length;
    }
  } finally {
    await server.kill();
  }
  assert.ok(!existsSync(join(work, 'killed.mcap')), 'not renamed: the run did not stop cleanly');
  const bytes = new Uint8Array(readFileSync(part));
  const { records, done } = streamRecords(bytes);
  assert.ok(!done, 'no footer');
  assert.ok(records.filter((r) => r.type === 'Message').length > 2);
  await assert.rejects(openMcap(bytes));
  // Under its final name, --replay refuses it: nothing starts.
  const named = join(work, 'killed.mcap');
  copyFileSync(part, named);
  const replay = await promisify(execFile)(process.env.STRATA_BINARY, ['serve', '--port', '0', '--replay', named])
    .then(() => assert.fail('the replay started'), (error) => error);
  assert.notEqual(replay.code, 0);
  assert.match(replay.stderr + replay.stdout, /killed\.mcap: cut short/);
  assert.doesNotMatch(replay.stdout, /serving on/);
});
