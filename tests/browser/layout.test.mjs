// The page on the screens it is used on (issue 24): the robot's 1280 x 800 touch screen, a tablet upright,
// a phone upright and on its side. On each, every control is in full view and clear to touch (behind Menu
// or Status on a phone), no label is clipped, Set goal and Stop keep their place however the panel grows,
// the operator can enter the token, the panel leaves the map in sight and the followed robot is drawn in the
// middle of the part of the map the bar and the panel leave uncovered.
// Usage: node --test layout.test.mjs   (env STRATA_BINARY, STRATA_ARTIFACTS)
import assert from 'node:assert/strict';
import { mkdirSync } from 'node:fs';
import path from 'node:path';
import { after, test } from 'node:test';

import { launchBrowser } from './browser.mjs';
import { openApp, TOKEN, until } from './page.mjs';
import { startServer } from './server.mjs';

const binary = process.env.STRATA_BINARY;
const artifacts = process.env.STRATA_ARTIFACTS || path.resolve('browser-artifacts');
assert.ok(binary, 'STRATA_BINARY must name the strata executable');
mkdirSync(artifacts, { recursive: true });

const server = await startServer(binary, ['--time-scale', '4', '--operator-token', TOKEN]);
const browser = await launchBrowser();
const headers = { Authorization: `Bearer ${TOKEN}`, 'Content-Type': 'application/json' };
const getJson = async (route) => (await fetch(`${server.url}${route}`)).json();
async function postGoal(goal) {
  const posted = await fetch(`${server.url}/api/v1/goal`, { method: 'POST', headers, body: JSON.stringify(goal) });
  assert.ok(posted.ok, `the goal is taken (${posted.status})`);
}

after(async () => {
  await browser.close();
  assert.equal(await server.stop(), 0, 'strata exits cleanly on SIGTERM');
});

const SCREENS = [
  { name: 'robot touch screen', width: 1280, height: 800, phone: false },
  { name: 'tablet upright', width: 800, height: 1280, phone: false },
  { name: 'phone upright', width: 390, height: 844, phone: true },
  { name: 'phone on its side', width: 844, height: 390, phone: true },
];
const ALWAYS_IN_SIGHT = ['#connection', '#role', '#goal-arm', '#goal-cancel', '#joystick'];
const PHONE_TOGGLES = ['#menu-toggle', '#panel-toggle'];
const BAR_TOOLS = [
  '#views [data-view="3d"]', '#views [data-view="top"]', '#views [data-view="occupancy"]', '#color-mode', '#follow', '#token-button',
];
const PANEL_CONTROLS = ['#world-toggle', '#pose-arm', '#map-save', '#map-load', '#map-download'];

/** What keeps these elements from being used: out of the viewport, covered at their centre by another
 * element, smaller than a finger (buttons), text clipped. [] when nothing does. */
function outOfReach(page, selectors) {
  return page.evaluate((selectors) => selectors.flatMap((selector) => {
    const element = document.querySelector(selector);
    if (!element) return [`${selector}: missing`];
    if (element.closest('.panel-body')) element.scrollIntoView({ block: 'nearest' }); // the panel scrolls
    const box = element.getBoundingClientRect();
    const problems = [];
    if (box.width === 0 || box.left < 0 || box.top < 0 || box.right > innerWidth + 0.5 || box.bottom > innerHeight + 0.5) {
      problems.push(`not in the viewport (${[box.left, box.top, box.right, box.bottom].map(Math.round).join(', ')})`);
    }
    const hit = document.elementFromPoint(box.left + box.width / 2, box.top + box.height / 2);
    if (!element.contains(hit)) problems.push(`covered by ${hit ? hit.id || hit.className || hit.tagName : 'nothing'}`);
    if (element.matches('button') && (box.width < 44 || box.height < 44)) problems.push(`${box.width} x ${box.height} px`);
    if (element.scrollWidth > element.clientWidth + 1) problems.push('its text is clipped');
    return problems.map((problem) => `${selector}: ${problem}`);
  }), selectors);
}

/** The bar's clipped content (the bar wider than the screen, a label wider than its box): [] when none. */
function clippedInBar(page) {
  return page.evaluate(() => [document.querySelector('.bar'), ...document.querySelectorAll('.bar *')]
    .filter((element) => element.getClientRects().length && element.scrollWidth > element.clientWidth + 1)
    .map((element) => `${element.id || element.className || element.tagName}: ${element.scrollWidth} > ${element.clientWidth}`));
}

const placesOfSetGoalAndStop = (page) => page.evaluate(() => ['goal-arm', 'goal-cancel'].map((id) => {
  const { left, top, width, height } = document.getElementById(id).getBoundingClientRect();
  return { id, left, top, width, height };
}));

for (const { name, width, height, phone } of SCREENS) {
  test(`${name}, ${width} x ${height}: every control in reach, Stop in one place, the robot in sight`, async () => {
    const page = await openApp(browser, server.url, { touch: true, viewport: { width, height }, mobile: phone });
    await until(page, () => window.strata.robotVisible());
    // A short goal line to start from: no goal yet, or after the last screen's failed goal (which ended the
    // demo drive: the robot stands) one where the robot stands, reached at once.
    if ((await getJson('/api/v1/goal')).phase !== 'none') {
      const { x, y, z } = await getJson('/api/v1/pose');
      await postGoal({ x, y, z });
      await page.locator('#goal-state[data-phase="reached"]').waitFor({ timeout: 30000 });
    }
    const setGoalAndStop = await placesOfSetGoalAndStop(page);
    const goalLineHeight = () => page.locator('#goal-state').evaluate((element) => element.getBoundingClientRect().height);
    const shortGoalLine = await goalLineHeight();

    // In sight as the page opens: the link, the role, Set goal, Stop, the joystick (and a phone's toggles).
    assert.deepEqual(await outOfReach(page, [...ALWAYS_IN_SIGHT, ...(phone ? PHONE_TOGGLES : [])]), []);
    const covers = await page.evaluate(() => {
      const panel = document.querySelector('.panel');
      const box = panel.getBoundingClientRect();
      const alpha = (element) => Number(getComputedStyle(element).backgroundColor.split(',')[3]?.slice(0, -1) ?? 1);
      const share = (box.width * box.height) / (innerWidth * innerHeight);
      return { share, panel: alpha(panel), bar: alpha(document.querySelector('.bar')) };
    });
    assert.ok(covers.panel >= 0.95 && covers.bar >= 0.95, `the bar and the panel are opaque: ${JSON.stringify(covers)}`);
    if (phone) assert.ok(covers.share < 0.25, `the folded panel covers ${Math.round(covers.share * 100)} % of the screen`);

    // The bar's tools (behind Menu on a phone), their labels whole, Colour's longest too.
    if (phone) await page.locator('#menu-toggle').tap();
    assert.deepEqual(await outOfReach(page, BAR_TOOLS), []);
    await page.locator('#color-mode').tap();
    await page.locator('#color-mode', { hasText: 'traversability' }).waitFor();
    assert.deepEqual(await outOfReach(page, BAR_TOOLS), []);
    assert.deepEqual(await clippedInBar(page), []);

    if (phone) { // a touch on the map closes the menu
      await page.touchscreen.tap(width / 2, height / 2);
      await page.locator('#menu-toggle[aria-expanded="false"]').waitFor();
      assert.equal(await page.locator('#token-button').isVisible(), false, 'the menu is closed');
      await page.locator('#menu-toggle').tap();
    }

    // The operator enters the token with the bar's Token button (behind Menu on a phone, which is then closed).
    await page.locator('#token-button').tap();
    await page.locator('#token-input').fill(TOKEN);
    await page.getByRole('button', { name: 'Use token' }).tap();
    await page.locator('#role', { hasText: 'operator' }).waitFor({ timeout: 15000 });
    assert.deepEqual(await outOfReach(page, ALWAYS_IN_SIGHT), [], 'the menu closed after the choice');

    // The panel's controls (behind Status on a phone); opening it moves neither Set goal nor Stop.
    if (phone) await page.locator('#panel-toggle').tap();
    assert.deepEqual(await outOfReach(page, [...PANEL_CONTROLS, ...ALWAYS_IN_SIGHT]), []);
    assert.deepEqual(await placesOfSetGoalAndStop(page), setGoalAndStop, 'Set goal and Stop stay put as the status opens');

    // The panel grows: the status fills in and a goal fails, with the server's reason in the goal line.
    await page.locator('#loc-reason').filter({ hasText: /\w/ }).waitFor({ timeout: 30000 });
    await postGoal({ x: 900.5, y: -900.5 });
    await page.locator('#goal-state[data-phase="failed"]').waitFor({ timeout: 30000 });
    assert.ok((await goalLineHeight()) > shortGoalLine, 'the goal line takes more room with the reason');
    assert.deepEqual(await placesOfSetGoalAndStop(page), setGoalAndStop, 'Set goal and Stop stay put as the panel grows');
    assert.deepEqual(await outOfReach(page, ['#goal-state', ...ALWAYS_IN_SIGHT]), []);
    if (phone) {
      await page.screenshot({ path: path.join(artifacts, `layout_${width}x${height}_status.png`) });
      await page.locator('#panel-toggle').tap(); // folded again for the map
    }
    // The page learns of the panel's new size in its next frame (a ResizeObserver), before drawing it.
    await page.evaluate(() => new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve))));

    // Following the robot, the camera draws it in the middle of the map the bar and the panel leave in sight.
    assert.equal(await page.evaluate(() => window.strata.follow()), true);
    const sight = await page.evaluate(() => {
      const area = window.strata.uncoveredArea();
      const robot = window.strata.screenPoint(window.strata.robotPosition());
      const bar = document.querySelector('.bar').getBoundingClientRect();
      const panel = document.querySelector('.panel').getBoundingClientRect();
      return {
        area, robot, barBottom: bar.bottom, panel: { left: panel.left, top: panel.top },
        share: ((area.right - area.left) * (area.bottom - area.top)) / (innerWidth * innerHeight),
        robotOnMap: document.elementFromPoint(robot.x, robot.y)?.tagName === 'CANVAS',
      };
    });
    const detail = JSON.stringify(sight);
    assert.ok(sight.area.top >= sight.barBottom - 1, `the area starts below the bar: ${detail}`);
    const clearOfPanel = sight.area.right <= sight.panel.left + 1 || sight.area.bottom <= sight.panel.top + 1;
    assert.ok(clearOfPanel, `the area is clear of the panel: ${detail}`);
    assert.ok(sight.share > 0.5, `most of the map is in sight: ${detail}`);
    assert.ok(Math.abs(sight.robot.x - (sight.area.left + sight.area.right) / 2) < 2, `the robot is centred across: ${detail}`);
    assert.ok(Math.abs(sight.robot.y - (sight.area.top + sight.area.bottom) / 2) < 2, `the robot is centred up and down: ${detail}`);
    assert.ok(sight.robotOnMap, `nothing covers the robot: ${detail}`);
    await page.screenshot({ path: path.join(artifacts, `layout_${width}x${height}.png`) });
    assert.deepEqual(page.errors, []);
    await page.context().close();
  });
}
