// What the fleet tests share about the master's side: the VDA 5050 2.1.0 schemas every vehicle message is
// checked against (ajv), and instant actions carried out through vda-5050-lib's MasterController.
import assert from 'node:assert/strict';
import { existsSync, readFileSync } from 'node:fs';
import path from 'node:path';

import Ajv2020 from 'ajv/dist/2020.js';
import mqtt from 'mqtt';

/**
 * The strata binary, mosquitto and the 2.1.0 schemas' directory from the environment (STRATA_BINARY,
 * MOSQUITTO, STRATA_VDA5050_DIR), and `missing`: why the fleet tests must skip, or false.
 */
export function fleetSetup() {
  const binary = process.env.STRATA_BINARY;
  const mosquitto = process.env.MOSQUITTO || '/usr/sbin/mosquitto';
  const schemaDir = path.join(process.env.STRATA_VDA5050_DIR || path.resolve('../../../shared/vda5050'), '2.1.0');
  const missing = !existsSync(schemaDir) ? `the VDA 5050 2.1.0 schemas are not at ${schemaDir} (STRATA_VDA5050_DIR)` : !existsSync(mosquitto) ? `no mosquitto at ${mosquitto} (deploy/install-deps.sh installs it)` : false;
  assert.ok(binary, 'STRATA_BINARY must name the strata executable');
  // ctest reports the test as skipped on this line (SKIP_REGULAR_EXPRESSION in tests/CMakeLists.txt).
  if (missing) console.log(`fleet test skipped: ${missing}`);
  return { binary, mosquitto, schemaDir, missing };
}

export const vehicleTopics = ['connection', 'state', 'visualization', 'factsheet'];

/** A validator per vehicle topic, from the specification's own 2.1.0 schemas in `schemaDir`. */
export function validators(schemaDir) {
  const ajv = new Ajv2020({ strict: false, allErrors: true });
  ajv.addFormat('date-time', /^\d{4}-\d{2}-\d{2}T\d{2}:\d{2}:\d{2}(\.\d+)?(Z|[+-]\d{2}:\d{2})$/);
  return Object.fromEntries(
    vehicleTopics.map((kind) => [kind, ajv.compile(JSON.parse(readFileSync(path.join(schemaDir, `${kind}.schema`), 'utf8')))]),
  );
}

/**
 * The test's own MQTT client on the broker: every vehicle message under a topic filter is checked against
 * the 2.1.0 schemas (the failures in `invalid`) and kept in `received` as { serial, kind, body, at, retained }
 * (`at`: performance.now() on arrival; `retained`: from the broker's store when subscribing).
 */
export class VehicleWatcher {
  received = [];
  invalid = [];
  client = null;
  #waiters = [];

  /** Connects (reconnecting every `reconnectPeriod` ms after a broker outage) and subscribes to `filter`. */
  async connect(brokerUrl, schemaDir, filter, { reconnectPeriod = 200 } = {}) {
    const validate = validators(schemaDir);
    this.client = mqtt.connect(brokerUrl, { reconnectPeriod });
    this.client.on('message', (topic, payload, packet) => {
      const at = performance.now();
      const [, , , serial, kind] = topic.split('/');
      if (!vehicleTopics.includes(kind)) return;
      const body = JSON.parse(payload.toString());
      if (!validate[kind](body)) this.invalid.push({ serial, kind, body, errors: validate[kind].errors });
      const message = { serial, kind, body, at, retained: packet.retain };
      this.received.push(message);
      this.#waiters = this.#waiters.filter((waiter) => !waiter(message));
    });
    await new Promise((resolve) => this.client.once('connect', resolve));
    await new Promise((resolve, reject) => this.client.subscribe(filter, { qos: 1 }, (e) => (e ? reject(e) : resolve())));
  }

  /** The body of the first message from index `from` on that `match` accepts; `what` names it in the timeout's error. */
  waitFor(match, what, { from = 0, timeout = 30000 } = {}) {
    const found = this.received.slice(from).find(match);
    if (found) return Promise.resolve(found.body);
    return new Promise((resolve, reject) => {
      const timer = setTimeout(() => reject(new Error(`no ${what} as expected within ${timeout} ms`)), timeout);
      this.#waiters.push((m) => {
        if (!match(m)) return false;
        clearTimeout(timer);
        resolve(m.body);
        return true;
      });
    });
  }

  /** Publishes `payload` (a string) raw on `topic`, as a faulty master would. */
  publish(topic, payload) {
    return new Promise((resolve, reject) => this.client.publish(topic, payload, { qos: 0 }, (e) => (e ? reject(e) : resolve())));
  }

  end() {
    this.client?.end(true);
  }
}

/** Carries out one instant action on `agv` through `master`; resolves with its final (FINISHED or FAILED) state. */
export function instantAction(master, agv, actionType, actionParameters = []) {
  return new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`${actionType}: no final action state`)), 60000);
    master
      .initiateInstantActions(agv, { instantActions: [{ actionId: master.createUuid(), actionType, blockingType: 'NONE', actionParameters }] }, {
        onActionStateChanged: (actionState) => {
          if (actionState.actionStatus === 'FINISHED' || actionState.actionStatus === 'FAILED') {
            clearTimeout(timer);
            resolve(actionState);
          }
        },
        onActionError: (error) => {
          clearTimeout(timer);
          reject(new Error(`${actionType} refused: ${JSON.stringify(error)}`));
        },
      })
      .catch(reject);
  });
}
