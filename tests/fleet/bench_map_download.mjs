// Benchmark (issue 61, "Done when"): a ~10 MB map's download-and-enable time on loopback, through the
// fleet: Debian's mosquitto, two real `strata serve`, npm's vda-5050-lib MasterController. Robot A serves
// a synthetic campus with localization data (strata_synthetic_map --localizable 1) as map version 1;
// the master tells robot B to downloadMap it from A's URL (mapHash checked) and enableMap it, each timed
// from the instantActions message to the action's FINISHED in B's state. Prints one JSON line; a
// benchmark, not a test (nothing here depends on time).
// Usage: node bench_map_download.mjs   (env STRATA_BINARY, STRATA_SYNTHETIC_MAP, MOSQUITTO; PATCHES, RUNS)
import { execFileSync } from 'node:child_process';
import { copyFileSync, mkdirSync, mkdtempSync, rmSync, statSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';

import { MasterController } from 'vda-5050-lib';

import { startServer } from '../browser/server.mjs';
import { startBroker } from './broker.mjs';

const binary = process.env.STRATA_BINARY;
const synthetic = process.env.STRATA_SYNTHETIC_MAP;
const mosquitto = process.env.MOSQUITTO || '/usr/sbin/mosquitto';
const patches = Number(process.env.PATCHES || 600000);
const runs = Number(process.env.RUNS || 3);
if (!binary || !synthetic) throw new Error('STRATA_BINARY and STRATA_SYNTHETIC_MAP must name the executables');

const TOKEN = 'fleet-bench-operator-token-0123456789';
const robotB = { manufacturer: 'StrataBench', serialNumber: 'robot-b' };
const scratch = mkdtempSync(path.join(tmpdir(), 'strata-map-bench-'));
const median = (values) => [...values].sort((a, b) => a - b)[Math.floor(values.length / 2)];

function instantAction(master, actionType, parameters) {
  const actionParameters = Object.entries(parameters).map(([key, value]) => ({ key, value }));
  const started = performance.now();
  return new Promise((resolve, reject) => {
    master
      .initiateInstantActions(robotB, { instantActions: [{ actionId: master.createUuid(), actionType, blockingType: 'NONE', actionParameters }] }, {
        onActionStateChanged: (state) => {
          if (state.actionStatus === 'FINISHED') resolve(performance.now() - started);
          if (state.actionStatus === 'FAILED') reject(new Error(`${actionType} FAILED: ${state.resultDescription}`));
        },
        onActionError: (error) => reject(new Error(`${actionType} refused: ${JSON.stringify(error)}`)),
      })
      .catch(reject);
  });
}

const broker = await startBroker(mosquitto);
const servers = [];
let master;
try {
  const mapsA = path.join(scratch, 'a');
  mkdirSync(mapsA);
  const generated = path.join(scratch, 'campus.smls');
  execFileSync(synthetic, ['--patches', String(patches), '--out', generated, '--localizable', '1']);
  copyFileSync(generated, path.join(mapsA, 'campus.smls'));
  const serverA = await startServer(binary, ['--time-scale', '1', '--operator-token', TOKEN, '--maps-dir', mapsA]);
  servers.push(serverA);
  const headers = { Authorization: `Bearer ${TOKEN}`, 'Content-Type': 'application/json' };
  // Loaded and saved: the save makes version 1 (the same bytes as the file).
  let response = await fetch(`${serverA.url}/api/v1/maps/campus.smls/load`, { method: 'POST', headers, body: '{"mode":"localize"}' });
  if (!response.ok) throw new Error(await response.text());
  response = await fetch(`${serverA.url}/api/v1/maps`, { method: 'POST', headers, body: '{"name":"campus.smls"}' });
  if (!response.ok) throw new Error(await response.text());
  const version = (await (await fetch(`${serverA.url}/api/v1/map-versions`)).json()).versions[0];

  const config = path.join(scratch, 'b.ini');
  writeFileSync(config, ['[serve]', `vda5050 = "${broker.url}"`, `vda5050-manufacturer = "${robotB.manufacturer}"`, `vda5050-serial = "${robotB.serialNumber}"`, ''].join('\n'));
  const serverB = await startServer(binary, ['--config', config, '--time-scale', '1', '--operator-token', TOKEN, '--maps-dir', path.join(scratch, 'b')]);
  servers.push(serverB);
  master = new MasterController(
    { interfaceName: 'uagv', transport: { brokerUrl: broker.url }, vdaVersion: '2.0.0', topicObjectValidation: { inbound: false } },
    { targetAgvs: robotB },
  );
  await master.start();

  const download = [];
  const enable = [];
  for (let run = 1; run <= runs; run++) {
    // Each run its own version name on B: a version is stored once (VDA 5050 6.7.3).
    const mapVersion = `run${run}`;
    download.push(await instantAction(master, 'downloadMap', { mapId: 'campus.smls@0', mapVersion, mapDownloadLink: `${serverA.url}${version.url}`, mapHash: version.sha256 }));
    enable.push(await instantAction(master, 'enableMap', { mapId: 'campus.smls@0', mapVersion }));
  }
  const total = download.map((d, i) => d + enable[i]);
  console.log(JSON.stringify({
    bytes: version.bytes,
    file_mb: +(statSync(generated).size / 1e6).toFixed(2),
    patches,
    runs,
    download_ms: download.map((v) => Math.round(v)),
    enable_ms: enable.map((v) => Math.round(v)),
    download_and_enable_ms_median: Math.round(median(total)),
  }));
} finally {
  await master?.stop();
  for (const server of servers) await server.stop();
  await broker.stop();
  rmSync(scratch, { recursive: true, force: true });
}
