// A real MQTT broker for the fleet tests: Debian's mosquitto on a free loopback port, with its config in
// the test's own temporary directory (nothing of the machine's /etc/mosquitto is read).
import { spawn } from 'node:child_process';
import { once } from 'node:events';
import { mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { createServer } from 'node:net';
import { tmpdir, userInfo } from 'node:os';
import { join } from 'node:path';
import { createInterface } from 'node:readline';

export async function freePort() {
  const server = createServer();
  server.listen(0, '127.0.0.1');
  await once(server, 'listening');
  const { port } = server.address();
  server.close();
  await once(server, 'close');
  return port;
}

/**
 * Starts mosquitto with an anonymous listener on a free loopback port; `listeners(dir)` may return the
 * config lines of more (each with its own settings), files in `dir`. `restart(downMs)` stops it and starts
 * it again on the same ports after `downMs` (a broker outage); it resolves once the broker runs again.
 * `tcpNoDelay`: mosquitto's set_tcp_nodelay (no Nagle on what it sends to clients; its default is off).
 */
export async function startBroker(binary, { listeners = async () => [], tcpNoDelay = false } = {}) {
  const dir = mkdtempSync(join(tmpdir(), 'strata-mosquitto-'));
  const port = await freePort();
  const config = join(dir, 'mosquitto.conf');
  // `user`: started by root, mosquitto would become the user "mosquitto", who cannot read the test's files.
  const lines = [`user ${userInfo().username}`, 'per_listener_settings true', 'persistence false', 'log_dest stderr', `listener ${port} 127.0.0.1`, 'allow_anonymous true', ...(tcpNoDelay ? ['set_tcp_nodelay true'] : [])];
  writeFileSync(config, [...lines, ...(await listeners(dir)), ''].join('\n'));
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
    async restart(downMs = 0) {
      await stop();
      if (downMs > 0) await new Promise((resolve) => setTimeout(resolve, downMs));
      await launch();
    },
    async stop() {
      await stop();
      rmSync(dir, { recursive: true, force: true });
    },
  };
}
