// Issue 61: the fleet link over TLS with a login. Debian's mosquitto serves mqtts:// with a certificate made
// for the test (CA and server, openssl) and a password file (mosquitto_passwd) on one listener, plain MQTT
// on another for the test's own watcher; the real `strata serve` connects with --vda5050 mqtts://,
// --vda5050-ca-file, --vda5050-username and the password from STRATA_VDA5050_PASSWORD.
// Usage: node --test vda5050_tls.test.mjs   (env STRATA_BINARY, MOSQUITTO)
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { existsSync } from 'node:fs';
import path from 'node:path';
import { after, test } from 'node:test';

import mqtt from 'mqtt';

import { startServer } from '../browser/server.mjs';
import { freePort, startBroker } from './broker.mjs';
import { makeCertificates } from './certificates.mjs';

const binary = process.env.STRATA_BINARY;
const mosquitto = process.env.MOSQUITTO || '/usr/sbin/mosquitto';
const passwd = path.join(path.dirname(mosquitto), '..', 'bin', 'mosquitto_passwd');
const missing = !existsSync(mosquitto) ? `no mosquitto at ${mosquitto} (deploy/install-deps.sh installs it)` : false;
assert.ok(binary, 'STRATA_BINARY must name the strata executable');
if (missing) console.log(`fleet test skipped: ${missing}`);

const stops = [];
after(async () => {
  for (const stop of stops.reverse()) await stop();
});

test('over mqtts:// with a user and password the vehicle comes ONLINE and reports its state', { skip: missing }, async () => {
  const tlsPort = await freePort();
  let ca;
  const broker = await startBroker(mosquitto, {
    listeners: async (dir) => {
      const files = makeCertificates(dir);
      ca = files.ca;
      const passwords = path.join(dir, 'passwords');
      execFileSync(existsSync(passwd) ? passwd : 'mosquitto_passwd', ['-c', '-b', passwords, 'robot-7', 'fleet-secret-7'], { stdio: 'ignore' });
      return [`listener ${tlsPort} 127.0.0.1`, `cafile ${files.ca}`, `certfile ${files.cert}`, `keyfile ${files.key}`, 'allow_anonymous false', `password_file ${passwords}`];
    },
  });
  stops.push(() => broker.stop());

  const watcher = mqtt.connect(broker.url);
  stops.push(() => watcher.end(true));
  const prefix = 'uagv/v2/Strata/robot-7';
  const online = new Promise((resolve) => {
    watcher.on('message', (topic, payload) => {
      const body = JSON.parse(payload.toString());
      if (topic === `${prefix}/connection` && body.connectionState === 'ONLINE') resolve(body);
    });
  });
  const states = new Promise((resolve) => watcher.on('message', (topic) => topic === `${prefix}/state` && resolve()));
  await new Promise((resolve) => watcher.once('connect', resolve));
  await new Promise((resolve, reject) => watcher.subscribe(`${prefix}/+`, (e) => (e ? reject(e) : resolve())));

  process.env.STRATA_VDA5050_PASSWORD = 'fleet-secret-7';
  const server = await startServer(binary, [
    '--vda5050', `mqtts://127.0.0.1:${tlsPort}`, '--vda5050-ca-file', ca, '--vda5050-username', 'robot-7', '--vda5050-serial', 'robot-7', '--scanner', 'none',
  ]);
  stops.push(() => server.stop());
  const connection = await online;
  assert.equal(connection.serialNumber, 'robot-7');
  await states;
});
