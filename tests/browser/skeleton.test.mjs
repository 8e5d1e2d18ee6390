// The page skeleton beyond item 1 of web.md §11: side menu by keyboard, the 390-px phone width, the
// polling fallback without the WebSocket, the Code page's notice about the script engine.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { startEmulator, launchBrowser, openPage, waitFor, screenshot, footerOf, PAGES } from './harness.mjs';

let emu;
let browser;
before(async () => {
  emu = await startEmulator();
  browser = await launchBrowser();
});
after(async () => {
  await browser?.close();
  await emu?.stop();
});

test('/ is the Info page, and the side menu opens and closes from the keyboard', async () => {
  const g = await openPage(browser, emu, '/');
  const { page } = g;
  assert.equal(await page.locator('h1').textContent(), 'MovingCap turnTRACK 349 Eth');
  assert.equal(await page.locator('#sidemenu').isVisible(), false);
  await page.locator('#menu-toggle').focus();
  await page.keyboard.press('Enter');
  assert.equal(await page.locator('#sidemenu').isVisible(), true);
  assert.equal(await page.locator('#menu-toggle').getAttribute('aria-expanded'), 'true');
  assert.equal(await page.evaluate(() => document.activeElement.textContent), 'Info', 'focus moves into the menu');
  await page.keyboard.press('Escape');
  assert.equal(await page.locator('#sidemenu').isVisible(), false);
  await page.locator('#menu-toggle').click();
  await page.locator('#sidemenu a', { hasText: 'Network Settings' }).click();
  await page.waitForURL('**/network.html');
  g.assertClean();
  await g.close();
});

test('390 px wide: no page is wider than the screen and the footer stays readable', async () => {
  const g = await openPage(browser, emu, null, { viewport: { width: 390, height: 844 } });
  const { page } = g;
  for (const [path, name] of PAGES) {
    await g.goto(path);
    const width = await page.evaluate(() => document.documentElement.scrollWidth);
    assert.ok(width <= 390, `${path}: document is ${width} px wide at 390 px`);
    const box = await page.locator('#ft-io').boundingBox();
    assert.ok(box && box.x >= 0 && box.x + box.width <= 390, `${path}: the I/O string is on the screen`);
    if (['clickrun', 'emulator'].includes(name)) await screenshot(page, `${name}-390px`);
    g.assertClean();
  }
  await g.close();
});

test('without the WebSocket the footer is polled from the API', async (t) => {
  const g = await openPage(browser, emu, null, { allowConsole: [/WebSocket connection to .* failed/] });
  const { page } = g;
  await page.routeWebSocket(/\/api\/v1\/ws$/, (ws) => ws.close({ code: 1011, reason: 'test: no WebSocket' }));
  await page.goto(emu.base + '/clickrun.html');
  await page.waitForFunction(() => window.mcLive && window.mcLive.mode === 'poll', null, { timeout: 10000 });
  // nominal 12.5 Hz (a request every 80 ms); the bound leaves room for a loaded CI machine
  const n0 = await page.evaluate(() => window.mcLive.statusCount);
  await page.waitForTimeout(2000);
  const n1 = await page.evaluate(() => window.mcLive.statusCount);
  t.diagnostic(`polled ${n1 - n0} status snapshots in 2 s`);
  assert.ok(n1 - n0 >= 15, `polled ${n1 - n0} status snapshots in 2 s`);
  await page.locator('#cr-poweron').click();
  await waitFor(async () => (await footerOf(page)).live === 'MC Live RDY', { what: 'MC Live RDY while polling' });
  assert.match(await page.locator('#ft-conn').textContent(), /polling/);
  await emu.refgo('PQ');
  g.assertClean();
  await g.close();
});

test('the Code page says plainly whether the script engine is there', async () => {
  const info = await emu.get('/api/v1/info');
  const g = await openPage(browser, emu, '/program.html');
  const { page } = g;
  const controls = ['code-auto-on', 'code-auto-off', 'code-store', 'code-file', 'code-upload', 'code-run', 'code-pause', 'code-resume', 'code-stop', 'code-restart'];
  await waitFor(async () => (await page.locator('#code-engine').textContent()).length > 0);
  if (!info.scripting.available) {
    await waitFor(async () => page.locator('#code-run').isDisabled(), { what: 'Code page controls disabled' });
    assert.match(await page.locator('#code-engine').textContent(), /script engine is not available in this version of mcemu/);
    for (const id of controls) assert.equal(await page.locator(`#${id}`).isDisabled(), true, `#${id} disabled without an engine`);
  } else {
    assert.match(await page.locator('#code-engine').textContent(), new RegExp(`Script engine: ${info.scripting.engine.replace(/[.]/g, '\\.')}`));
    for (const id of controls) assert.equal(await page.locator(`#${id}`).isDisabled(), false, `#${id} enabled`);
  }
  assert.equal(await page.locator('#code-file').getAttribute('name'), 'Python script file for MovingCap CODE');
  assert.equal(await page.locator('#code-form').getAttribute('enctype'), 'multipart/form-data');
  g.assertClean();
  await g.close();
});
