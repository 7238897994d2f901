// The teleop joystick with a deadman: while a finger (or the mouse button) holds the knob, teleop commands
// go out at 10 Hz (the server lets each one drive for 0.5 s), and a changed command at once from the pointer
// event (at most every MIN_SEND_GAP_MS), never waiting for the map to be drawn; letting go, losing the
// pointer, hiding the page or losing the connection stops sending and sends v = 0, w = 0 at once. Each
// command carries a sequence number and when it was sent on the server's clock, so that commands a link
// outage held back never move the robot when they arrive (proto/PROTOCOL.md, "Teleoperation").
const SEND_INTERVAL_MS = 100;
const MIN_SEND_GAP_MS = 40;
const MAX_SPEED = 0.6; // m/s forward at full deflection
const MAX_TURN = 1.0; // rad/s counter-clockwise at full deflection

export class Joystick {
  /**
   * send(message) returns whether it went out; onChange(state) reports { held, v, w }; serverNow() is the
   * server's clock in ms (ServerClock.now), or null when the server does not give it.
   */
  constructor(element, { send, serverNow = () => null, onChange = () => {} }) {
    this.element = element;
    this.knob = element.querySelector('.knob');
    this.send = send;
    this.serverNow = serverNow;
    this.seq = 0;
    this.onChange = onChange;
    this.held = false;
    this.pointerId = null;
    this.v = 0;
    this.w = 0;
    this.sent = 0;
    this.sentAt = -Infinity;
    this.timer = null;

    element.addEventListener('pointerdown', (event) => this.grab(event));
    element.addEventListener('pointermove', (event) => {
      if (event.pointerId === this.pointerId) this.move(event);
    });
    for (const type of ['pointerup', 'pointercancel', 'lostpointercapture']) {
      element.addEventListener(type, (event) => {
        if (event.pointerId === this.pointerId) this.release();
      });
    }
    window.addEventListener('blur', () => this.release());
    document.addEventListener('visibilitychange', () => {
      if (document.hidden) this.release();
    });
  }

  grab(event) {
    if (this.held) return;
    event.preventDefault();
    this.held = true;
    this.pointerId = event.pointerId;
    this.element.setPointerCapture(event.pointerId);
    this.element.classList.add('held');
    this.move(event);
    this.tick();
    this.timer = setInterval(() => this.tick(), SEND_INTERVAL_MS);
  }

  move(event) {
    const rect = this.element.getBoundingClientRect();
    const radius = rect.width / 2;
    let dx = (event.clientX - (rect.left + radius)) / radius;
    let dy = (event.clientY - (rect.top + radius)) / radius;
    const length = Math.hypot(dx, dy);
    if (length > 1) {
      dx /= length;
      dy /= length;
    }
    this.knob.style.transform = `translate(${dx * radius * 0.6}px, ${dy * radius * 0.6}px)`;
    // Up is forward; right turns clockwise (negative w). A small dead zone so a resting thumb sends 0.
    const shape = (t) => (Math.abs(t) < 0.08 ? 0 : t);
    const v = Number((-shape(dy) * MAX_SPEED).toFixed(3));
    const w = Number((-shape(dx) * MAX_TURN).toFixed(3));
    const changed = v !== this.v || w !== this.w;
    this.v = v;
    this.w = w;
    this.onChange(this.state);
    if (changed && this.timer !== null && performance.now() - this.sentAt >= MIN_SEND_GAP_MS) this.tick();
  }

  tick() {
    if (this.send(this.command(this.v, this.w))) this.sent += 1;
    this.sentAt = performance.now();
  }

  /** The deadman: stop sending, and stop the robot now rather than when the last command expires. */
  release() {
    if (!this.held) return;
    this.held = false;
    clearInterval(this.timer);
    this.timer = null;
    this.pointerId = null;
    this.v = 0;
    this.w = 0;
    this.element.classList.remove('held');
    this.knob.style.transform = '';
    this.send(this.command(0, 0));
    this.onChange(this.state);
  }

  command(v, w) {
    const t = this.serverNow();
    this.seq += 1;
    return t === null ? { op: 'teleop', v, w } : { op: 'teleop', v, w, seq: this.seq, t: Math.round(t) };
  }

  get state() {
    return { held: this.held, v: this.v, w: this.w, sent: this.sent };
  }
}
