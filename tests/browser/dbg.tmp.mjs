import { launchBrowser } from './browser.mjs';
import { floorPointNearRobot, openApp, until } from './page.mjs';
import { touchSession } from './touch.mjs';
const browser = await launchBrowser();
const page = await openApp(browser, 'http://127.0.0.1:8099/', { touch: true });
page.on('console', (m) => { if (!m.text().includes('GL Driver')) console.log('CONSOLE', m.text()); });
await until(page, () => window.strata.drawnPatches() > 0 && window.strata.robotVisible());
await page.evaluate(() => document.getElementById('view').addEventListener('pointerup', (e) => console.log('pointerup', e.pointerType, e.clientX, e.clientY)));
await page.evaluate(() => document.querySelector('#view canvas').addEventListener('pointerdown', (e) => console.log('pointerdown', e.pointerType, e.clientX, e.clientY)));
await page.getByRole('button', { name: 'Follow robot' }).click(); // hold the camera still
await page.getByRole('button', { name: 'Set goal' }).click();
const target = await floorPointNearRobot(page);
console.log(target);
await (await touchSession(page)).tap([target.point.x, target.point.y]);
await page.waitForTimeout(3000);
console.log(await page.evaluate(() => ({ n: window.strata.notice(), sent: window.strata.goalSent(), armed: window.strata.goalArmed() })));
await page.screenshot({ path: '/tmp/ui-probe/dbg.png' });
await browser.close();
