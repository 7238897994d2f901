// Touch gestures for browser tests, sent through the DevTools protocol so the page sees real touch
// input (touch events and pointer events of type "touch"), as on the robot's touch screen.
export async function touchSession(page) {
  const cdp = await page.context().newCDPSession(page);
  const send = (type, points) =>
    cdp.send('Input.dispatchTouchEvent', {
      type,
      touchPoints: points.map(([x, y], id) => ({ x, y, id, radiusX: 4, radiusY: 4, force: 1 })),
    });
  return {
    /** Two fingers from `from` to `to` ([[x, y], [x, y]] each), in `steps` moves. */
    async twoFingers(from, to, steps = 8) {
      await send('touchStart', from);
      for (let i = 1; i <= steps; i++) {
        const t = i / steps;
        await send('touchMove', from.map(([x, y], k) => [x + (to[k][0] - x) * t, y + (to[k][1] - y) * t]));
        await page.waitForTimeout(16);
      }
      await send('touchEnd', []);
    },
    /** Pinch about a centre: fingers from `startGap` to `endGap` pixels apart (apart: zoom in). */
    async pinch([cx, cy], startGap, endGap) {
      const pair = (gap) => [[cx - gap / 2, cy], [cx + gap / 2, cy]];
      await this.twoFingers(pair(startGap), pair(endGap));
    },
    /** One finger down at a point (and moved to `to`), held until release() is called. */
    async hold([x, y], to = [x, y]) {
      await send('touchStart', [[x, y]]);
      for (let i = 1; i <= 6; i++) {
        await send('touchMove', [[x + ((to[0] - x) * i) / 6, y + ((to[1] - y) * i) / 6]]);
        await page.waitForTimeout(16);
      }
      this.held = to;
    },
    async release() {
      await send('touchEnd', []);
    },
    async tap([x, y]) {
      await send('touchStart', [[x, y]]);
      await send('touchEnd', []);
    },
  };
}
