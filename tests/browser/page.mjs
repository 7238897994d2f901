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
 * pick, with its screen point; or null. Tried nearest first, each one checked: on screen, nothing of the
 * page over it (bar, panel, joystick, notices), and no wall or floor of the map in front of it (a hallway's
 * walls hide much of its floor from an oblique camera).
 */
export async function floorPointNearRobot(page, { radius = 4, minDistance = 1.5, timeout = 20000 } = {}) {
  // The tiles around the robot may still be arriving (a page just opened on a busy machine): look again.
  const deadline = Date.now() + timeout;
  for (;;) {
    const found = await floorPointOnScreen(page, radius, minDistance);
    if (found || Date.now() > deadline) return found;
    await new Promise((resolve) => setTimeout(resolve, 250));
  }
}

async function floorPointOnScreen(page, radius, minDistance) {
  return page.evaluate(
    ({ radius, minDistance }) => {
      const [x, y, level] = window.strata.robotPosition(); // the robot's ground: goals on its storey
      const canvas = document.querySelector('#view canvas');
      const surfaces = window.strata.findSurfaces({ x, y, radius: minDistance + 3 * radius, minDistance, level });
      const step = Math.max(1, Math.floor(surfaces.length / 400)); // a few hundred tries at most
      for (let k = 0; k < surfaces.length; k += step) {
        const surface = surfaces[k];
        const point = window.strata.screenPoint([surface.x, surface.y, surface.z]);
        if (!point.visible || document.elementFromPoint(point.x, point.y) !== canvas) continue;
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
