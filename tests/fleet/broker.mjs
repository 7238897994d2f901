// A real MQTT broker for the fleet tests: Debian's mosquitto on a free loopback port, with its config in
// the test's own temporary directory (nothing of the machine's /etc/mosquitto is read).
import { spawn } from 'node:child_process';
import { once } from 'node:events';
import { mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { createServer } from 'node:net';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { createInterface } from 'node:readline';

async function freePort() {
  const server = createServer();
  server.listen(0, '127.0.0.1');
  await once(server, 'listening');
  const { port } = server.address();
  server.close();
  await once(server, 'close');
  return port;
}

/** Starts mosquitto; `restart()` stops it and starts it again on the same port (a broker outage). */
export async function startBroker(binary) {
  const dir = mkdtempSync(join(tmpdir(), 'strata-mosquitto-'));
  const port = await freePort();
  const config = join(dir, 'mosquitto.conf');
  writeFileSync(config, [`listener ${port} 127.0.0.1`, 'allow_anonymous true', 'persistence false', 'log_dest stderr', ''].join('\n'));
  let child = null;
  const launch = async () => {
    child = spawn(binary, ['-c', config], { stdio: ['ignore', 'ignore', 'pipe'] });
    const lines = createInterface({ input: child.stderr });
    const exited = once(child, 'exit').then(([code]) => {
      throw new Error(`mosquitto exited with code ${code} before listening`);
    });
    const running = new Promise((resolve) => {
      lines.on('line', (line) => {
        if (/ running$/.test(line)) resolve();
      });
    });
    await Promise.race([running, exited]);
    exited.catch(() => {});
  };
  const stop = async () => {
    if (!child || child.exitCode !== null) return;
    child.kill('SIGTERM');
    await once(child, 'exit');
  };
  await launch();
  return {
    url: `mqtt://127.0.0.1:${port}`,
    async restart() {
      await stop();
      await launch();
    },
    async stop() {
      await stop();
      rmSync(dir, { recursive: true, force: true });
    },
  };
}
