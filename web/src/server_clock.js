// The server's clock as this page can tell it. Teleop commands carry it as `t`, so that the server refuses
// those a link outage held back (proto/PROTOCOL.md, "Teleoperation"). hello and every pong carry the
// server's clock_ms: when one arrives, the server's clock reads at least that (the message spent some time
// in transit), so the best estimate is the largest such bound. Only recent samples count, so a client clock
// that runs a little fast or slow is followed.
const SAMPLES = 8; // pongs come every 2 s: the last 16 s

export class ServerClock {
  constructor() {
    this.offsets = []; // clock_ms - performance.now() at arrival, newest last
  }

  /** A message carrying the server's clock_ms arrived now (or at `arrivedMs`, performance.now()). */
  observe(clockMs, arrivedMs = performance.now()) {
    if (typeof clockMs !== 'number' || !Number.isFinite(clockMs)) return;
    this.offsets.push(clockMs - arrivedMs);
    if (this.offsets.length > SAMPLES) this.offsets.shift();
  }

  /** A new connection: its server may be another process, with another clock. */
  reset() {
    this.offsets = [];
  }

  /** The server's clock now, ms; null before any sample (a server older than protocol 1.1). */
  now(atMs = performance.now()) {
    return this.offsets.length === 0 ? null : atMs + Math.max(...this.offsets);
  }
}
