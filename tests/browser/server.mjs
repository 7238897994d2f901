// Starts a real strata server process for a browser test and stops it afterwards.
import { spawn } from 'node:child_process';
import { once } from 'node:events';
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { createInterface } from 'node:readline';

export async function startServer(binary, args = [], { port = 0 } = {}) {
  // A state directory of its own: the IMU calibration one test's robot keeps is not where another starts.
  const stateHome = mkdtempSync(join(tmpdir(), 'strata-state-'));
  // Port 0 lets the server pick a free port; it prints the one it bound.
  const child = spawn(binary, ['serve', '--bind', '127.0.0.1', '--port', String(port), ...args], {
    stdio: ['ignore', 'pipe', 'inherit'],
    env: { ...process.env, XDG_STATE_HOME: stateHome },
  });
  child.on('exit', () => rmSync(stateHome, { recursive: true, force: true }));
  const lines = createInterface({ input: child.stdout });
  const exited = once(child, 'exit').then(([code]) => {
    throw new Error(`strata exited with code ${code} before serving`);
  });
  const url = new Promise((resolve) => {
    lines.on('line', (line) => {
      const match = line.match(/^strata: serving on (https?:\/\/\S+)$/);
      if (match) resolve(match[1]);
    });
  });
  const baseUrl = await Promise.race([url, exited]);
  exited.catch(() => {}); // after startup, exit is expected when we stop it
  return {
    url: baseUrl,
    async stop() {
      if (child.exitCode !== null) return child.exitCode;
      child.kill('SIGTERM');
      const [code] = await once(child, 'exit');
      return code;
    },
    /// SIGKILL: no chance to clean up, as a power cut or the OOM killer.
    async kill() {
      if (child.exitCode !== null || child.signalCode !== null) return;
      child.kill('SIGKILL');
      await once(child, 'exit');
    },
  };
}
