// Measurements bench_render.mjs takes inside the page on a big map: the frame rate while the view is redrawn
// continuously, and how long the joystick's commands take from the pointer event to the WebSocket while it
// is. Each function runs in the page (page.evaluate) or installs what does.

/** Before the app loads: note when pointer events happened and when teleop commands went out. */
export async function installSendProbe(page) {
  await page.addInitScript(() => {
    window.benchProbe = { pointer: [], teleop: [] };
    window.addEventListener(
      'pointerdown',
      (event) => window.benchProbe.pointer.push({ type: event.type, t: event.timeStamp }),
      { capture: true },
    );
    window.addEventListener(
      'pointermove',
      (event) => event.buttons && window.benchProbe.pointer.push({ type: event.type, t: event.timeStamp }),
      { capture: true },
    );
    const send = WebSocket.prototype.send;
    WebSocket.prototype.send = function sendNoted(data) {
      if (typeof data === 'string' && data.includes('"teleop"')) {
        const { v, w } = JSON.parse(data);
        window.benchProbe.teleop.push({ t: performance.now(), v, w });
      }
      return send.call(this, data);
    };
  });
}

/** Keeps the page drawing a frame on every animation frame (as while the user orbits) until stopped. */
export function startRedrawing(page) {
  return page.evaluate(() => {
    window.benchRedraw = true;
    const spin = () => {
      if (!window.benchRedraw) return;
      window.strata.redraw();
      requestAnimationFrame(spin);
    };
    spin();
  });
}

export function stopRedrawing(page) {
  return page.evaluate(() => {
    window.benchRedraw = false;
  });
}

/**
 * Frames per second while redrawing continuously for at least `ms` and `minFrames` frames, and the
 * main-thread time of render() (median), draw calls and triangles of the last frame.
 */
export function measureFrames(page, { ms = 3000, minFrames = 5 } = {}) {
  return page.evaluate(
    async ({ ms, minFrames }) => {
      const { strata } = window;
      const nextFrame = () => new Promise((resolve) => requestAnimationFrame(resolve));
      // Warm up: whatever the new camera needs built is built, and the frames queued before it are drawn
      // (the GPU may lag the page by a frame or two), before the clock starts.
      const warmUp = performance.now();
      for (let i = 0; i < 3 || performance.now() - warmUp < 1500; i++) {
        strata.redraw();
        const before = strata.frames();
        while (strata.frames() === before) await nextFrame();
      }
      const firstFrame = strata.frames();
      const start = performance.now();
      while (performance.now() - start < ms || strata.frames() - firstFrame < minFrames) {
        strata.redraw();
        await nextFrame();
      }
      const seconds = (performance.now() - start) / 1000;
      const frames = strata.frames() - firstFrame;
      const renderMs = strata.perf().renderMs.slice(-Math.min(frames, 120)); // the probe keeps 120
      const sorted = [...renderMs].sort((a, b) => a - b);
      return {
        fps: Math.round((frames / seconds) * 100) / 100,
        frames,
        medianRenderCallMs: sorted[Math.floor(sorted.length / 2)],
        drawnPatches: strata.drawnPatches(),
        tilesByLevel: strata.lodLevels?.(), // tiles drawn at each level of detail (0: full), where there are levels
        ...strata.renderInfo(),
      };
    },
    { ms, minFrames },
  );
}

/**
 * Drags the joystick (grab, push forward in steps, hold `holdMs`, let go) while the page redraws
 * continuously: the delay from the grab's pointer event to the first teleop send, from the last move to
 * the first send carrying its command, and the send rate while held (the joystick sends at 10 Hz).
 */
export async function measureJoystick(page, { holdMs = 3000 } = {}) {
  const box = await page.locator('#joystick').boundingBox();
  const x = box.x + box.width / 2;
  const y = box.y + box.height / 2;
  await page.evaluate(() => {
    window.benchProbe.pointer.length = 0;
    window.benchProbe.teleop.length = 0;
  });
  await startRedrawing(page);
  await page.mouse.move(x, y);
  await page.mouse.down();
  await page.mouse.move(x, y - box.height * 0.4, { steps: 5 });
  await page.waitForTimeout(holdMs);
  await page.mouse.up();
  await page.waitForTimeout(500);
  await stopRedrawing(page);
  const { pointer, teleop, final } = await page.evaluate(() => ({ ...window.benchProbe, final: window.strata.joystick() }));
  const down = pointer.find((p) => p.type === 'pointerdown');
  const lastMove = pointer.filter((p) => p.type === 'pointermove').at(-1);
  const held = teleop.filter((s) => s.v !== 0 || s.w !== 0);
  const firstSend = teleop.find((s) => s.t >= down.t);
  const movedSend = held.find((s) => s.t >= lastMove.t);
  const gaps = held.slice(1).map((s, i) => s.t - held[i].t);
  const heldSeconds = held.length > 1 ? (held.at(-1).t - held[0].t) / 1000 : 0;
  const round = (ms) => (ms === undefined ? null : Math.round(ms));
  return {
    grabToSendMs: round(firstSend && firstSend.t - down.t),
    lastMoveToSendMs: round(movedSend && movedSend.t - lastMove.t),
    sendsPerSecondHeld: heldSeconds > 0 ? Math.round(((held.length - 1) / heldSeconds) * 10) / 10 : 0,
    maxGapBetweenSendsMs: round(gaps.length ? Math.max(...gaps) : undefined),
    stoppedAtRelease: teleop.at(-1)?.v === 0 && !final.held,
  };
}
