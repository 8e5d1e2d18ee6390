// web.md §11 item 1: every page of §2 loads with 200, shows the menu bar and the footer and has no
// failed request; plus the skeleton (side menu entries, LEDs, badge, live footer equal to
// /api/v1/status), every control reachable with Tab, and a screenshot of every page.
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

const MENU = ['MovingCap Eth', 'Click&Run', 'Servo', 'IO IN', 'IO OUT', 'Command', 'Code', 'Network', 'Emulator'];
const SIDE = ['Info', 'Click & Run', 'Servo Startup', 'IO IN', 'IO OUT', 'Commands & Parameters', 'Code (Python)', 'Network Settings', 'Emulator'];

test('every page loads with the skeleton, a live footer, no failed request, every control on Tab (§11.1)', async () => {
  const g = await openPage(browser, emu, null);
  const { page } = g;
  for (const [path, name] of PAGES) {
    await g.goto(path);
    assert.deepEqual(await page.locator('#menubar a').allTextContents(), MENU, `${path}: menu bar`);
    assert.equal(await page.locator('#menubar a.emu').getAttribute('href'), '/emulator.html');
    assert.deepEqual(await page.locator('#sidemenu a').allTextContents(), SIDE, `${path}: side menu entries`);
    assert.ok(await page.locator('#led-green[data-on]').count(), `${path}: green LED`);
    assert.match(await page.locator('#led-yellow').getAttribute('data-on'), /^[01]$/);
    assert.equal(await page.locator('#badge').getAttribute('href'), '/emulator.html');
    assert.match(await page.locator('#footer .tagline').textContent(), /emulated by mcemu/);
    // the footer follows the status stream and equals the API's strings (idle drive: stable)
    const api = (await emu.get('/api/v1/status')).footer;
    const same = (a, b) => Object.keys(b).every((k) => a[k] === b[k]) && Object.keys(a).length === Object.keys(b).length;
    await waitFor(async () => same(await footerOf(page), api), { what: `${path} footer = ${JSON.stringify(api)}` });
    assert.equal(await page.evaluate(() => window.mcLive.mode), 'ws', `${path}: status over the WebSocket`);
    if (path !== '/index.html') assert.equal(await page.locator(`#menubar a[href="${path}"]`).getAttribute('aria-current'), 'page');
    await screenshot(page, name);
    await everyControlTabReachable(page, path);
    g.assertClean();
  }
  await g.close();
});

// Every visible control in <main> receives the focus when Tab is pressed often enough.
async function everyControlTabReachable(page, path) {
  if (path === '/command.html') {
    // the object browser has an input per writable entry: walk a filtered table
    await page.locator('#cmd-filter').fill('6081');
    await waitFor(async () => (await page.locator('#cmd-objects tbody tr').count()) === 1, { what: 'filtered object browser' });
  }
  await page.evaluate(() => window.scrollTo(0, 0));
  await page.locator('#menu-toggle').focus();
  const wanted = await page.evaluate(() => {
    window.focusedIds = new Set();
    document.addEventListener('focusin', (e) => window.focusedIds.add(e.target.id || e.target.textContent.trim()));
    return [...document.querySelectorAll('main button, main input, main select, main a[href], main canvas[tabindex], main pre[tabindex]')]
      // a radio group is one tab stop (its checked button); the arrow keys move inside it
      .filter((el) => el.offsetParent !== null && !el.disabled && (el.type !== 'radio' || el.checked))
      .map((el) => el.id || el.textContent.trim());
  });
  for (let i = 0; i < wanted.length + 14; i++) await page.keyboard.press('Tab');
  const reached = new Set(await page.evaluate(() => [...window.focusedIds]));
  assert.deepEqual(wanted.filter((w) => !reached.has(w)), [], `${path}: not reachable with Tab`);
}
