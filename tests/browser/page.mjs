// Opening the app in a test: a 1280 x 800 page (the robot's touch screen) unless another viewport is
// asked for (`mobile`: a phone's browser), collecting uncaught errors, waiting for the live connection.
export const TOKEN = 'browser-test-operator-token-0123';

/** `beforeLoad(page)`: installs what must run before the app's own scripts (addInitScript). */
export async function openApp(
  browser,
  url,
  { touch = false, token = null, beforeLoad = null, viewport = { width: 1280, height: 800 }, mobile = false } = {},
) {
  const context = await browser.newContext({ viewport, hasTouch: touch, isMobile: mobile });
  const page = await context.newPage();
  page.errors = [];
  page.on('pageerror', (error) => page.errors.push(error.message));
  if (token) {
    // As if the operator had entered it earlier in this session.
    await page.addInitScript((t) => sessionStorage.setItem('strata.operatorToken', t), token);
  }
  await beforeLoad?.(page);
  await page.goto(url);
  await page.locator('#connection[data-state="connected"]').waitFor({ timeout: 15000 });
  return page;
}

/** Waits until fn(page's window.strata) is truthy; returns its value. */
export async function until(page, fn, arg, timeout = 60000) {
  const handle = await page.waitForFunction(fn, arg, { timeout, polling: 200 });
  return handle.jsonValue();
}

/**
 * A traversable floor patch near the robot (at least minDistance away, on its storey) that a tap would
 * pick (nothing in front of it on screen), with its screen point; or null.
 */
export async function floorPointNearRobot(page, { radius = 4, minDistance = 1.5 } = {}) {
  return page.evaluate(
    ({ radius, minDistance }) => {
      const [x, y, level] = window.strata.robotPosition(); // the robot's ground: goals on its storey
      const rect = document.querySelector('.panel').getBoundingClientRect();
      for (let near = minDistance; near <= minDistance + 3 * radius; near += 0.3) {
        const surface = window.strata.findSurface({ x, y, radius: near + 0.3, minDistance: near, level });
        if (!surface) continue;
        const point = window.strata.screenPoint([surface.x, surface.y, surface.z]);
        // On screen, clear of the panel and the top bar.
        if (!point.visible || point.x <= 0 || point.x >= rect.left - 10 || point.y <= 70 || point.y >= 790) continue;
        const picked = window.strata.surfaceAt(point.x, point.y);
        if (picked && Math.abs(picked.z - surface.z) < 0.1 && Math.hypot(picked.x - surface.x, picked.y - surface.y) < 0.3) {
          return { surface, point };
        }
      }
      return null;
    },
    { radius, minDistance },
  );
}

/** Waits until the page has drawn a new frame (so a screenshot shows what was just switched on). */
export async function nextFrame(page) {
  const frames = await page.evaluate(() => window.strata.frames());
  await until(page, (n) => window.strata.frames() > n, frames, 15000);
}
