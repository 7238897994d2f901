// What the interop tests share: an MCAP file opened with @mcap/core's indexed reader (zstd from fzstd), its
// messages decoded with @foxglove/rosmsg2-serialization from the file's own ros2msg schemas, and the ROS
// map_server export (PGM/YAML) of a server's current map to compare a /map with.
import assert from 'node:assert/strict';
import { McapIndexedReader, McapStreamReader } from '@mcap/core';
import { parse } from '@foxglove/rosmsg';
import { MessageReader } from '@foxglove/rosmsg2-serialization';
import { decompress } from 'fzstd';

export const decompressHandlers = { zstd: (buffer, size) => decompress(buffer, new Uint8Array(Number(size))) };

/// The reader over bytes in memory (@mcap/core leaves decompression to its user): footer, summary, chunk
/// indexes, the summary's CRC.
export function openMcap(bytes) {
  const readable = {
    size: async () => BigInt(bytes.length),
    read: async (offset, length) => bytes.subarray(Number(offset), Number(offset + length)),
  };
  return McapIndexedReader.Initialize({ readable, decompressHandlers });
}

/// Every message of the file decoded by its channel's schema (chunk CRCs checked), by topic; `checkChannel`
/// sees each channel first.
export async function decodeAll(reader, checkChannel = () => {}) {
  const decoders = new Map();
  for (const [id, channel] of reader.channelsById) {
    const schema = reader.schemasById.get(channel.schemaId);
    assert.equal(schema.encoding, 'ros2msg');
    assert.equal(channel.messageEncoding, 'cdr');
    checkChannel(channel);
    decoders.set(id, {
      topic: channel.topic,
      type: schema.name,
      reader: new MessageReader(parse(new TextDecoder().decode(schema.data), { ros2: true })),
    });
  }
  const messages = {};
  for await (const message of reader.readMessages({ validateCrcs: true })) {
    const decoder = decoders.get(message.channelId);
    (messages[decoder.topic] ??= []).push({ type: decoder.type, logTime: message.logTime, ...decoder.reader.readMessage(message.data) });
  }
  return messages;
}

/// The records the streaming reader gets from `bytes` (a file cut short: up to the cut), and whether it
/// reached a valid end.
export function streamRecords(bytes) {
  const reader = new McapStreamReader({ decompressHandlers, validateCrcs: true });
  reader.append(bytes);
  const records = [];
  for (let record; (record = reader.nextRecord()); ) records.push(record);
  return { records, done: reader.done() };
}

/// The ROS map_server pair of the server's current map: its version, YAML fields and PGM cells.
export async function rosMap(url) {
  const get = async (query) => {
    const response = await fetch(`${url}/api/v1/map?${query}`);
    assert.equal(response.status, 200, `${query}: ${response.status} ${await response.clone().text()}`);
    return { response, bytes: new Uint8Array(await response.arrayBuffer()) };
  };
  const { response, bytes: yamlBytes } = await get('format=yaml');
  const version = response.headers.get('x-strata-version');
  const yaml = new TextDecoder().decode(yamlBytes);
  const origin = yaml.match(/^origin: \[([^,]+), ([^,]+), /m).slice(1).map(Number);
  const resolution = Number(yaml.match(/^resolution: (\S+)$/m)[1]);
  const { bytes: pgm } = await get(`format=pgm&version=${version}`);
  const header = new TextDecoder('latin1').decode(pgm.subarray(0, 64)).match(/^P5\n(?:#[^\n]*\n)*(\d+) (\d+)\n255\n/);
  const [width, height] = [Number(header[1]), Number(header[2])];
  return { version, origin, resolution, width, height, cells: pgm.subarray(header[0].length) };
}

/// Checks a decoded OccupancyGrid against the ROS export `ros` cell for cell (the PGM's first row is the
/// highest y); returns its free cells.
export function checkGridIsTheExport(grid, ros) {
  assert.equal(grid.type, 'nav_msgs/msg/OccupancyGrid');
  assert.equal(grid.header.frame_id, 'map');
  assert.equal(grid.info.width, ros.width);
  assert.equal(grid.info.height, ros.height);
  assert.ok(Math.abs(grid.info.resolution - ros.resolution) < 1e-6);
  assert.ok(Math.abs(grid.info.origin.position.x - ros.origin[0]) < 1e-6, `${grid.info.origin.position.x} ${ros.origin[0]}`);
  assert.ok(Math.abs(grid.info.origin.position.y - ros.origin[1]) < 1e-6);
  assert.equal(grid.info.origin.orientation.w, 1);
  assert.equal(grid.data.length, ros.width * ros.height);
  const pgmValue = { 0: 254, 100: 0, [-1]: 205 };
  let free = 0;
  for (let row = 0; row < ros.height; row++) {
    for (let col = 0; col < ros.width; col++) {
      const cell = grid.data[row * ros.width + col];
      if (cell === 0) free++;
      const pixel = ros.cells[(ros.height - 1 - row) * ros.width + col];
      if (pgmValue[cell] !== pixel) assert.fail(`cell ${col},${row}: ${cell} in the grid, ${pixel} in the PGM`);
    }
  }
  return free;
}
