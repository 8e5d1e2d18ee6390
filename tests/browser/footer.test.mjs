// web.md §11 items 2 and 3: the footer texts equal the footer strings of /api/v1/status through
// start, PWC, a long move (MC Live MOV within 300 ms) and a stroke fault (red ERR link to the Info
// page); the Info page keeps Last Error 7121h / ERROR_STROKE after the fault reset.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { startEmulator, launchBrowser, openPage, waitFor, footerOf } from './harness.mjs';

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

// The page's footer equals the API's footer strings (fields that change while moving are left out).
async function footerMatchesApi(page, keys) {
  return waitFor(async () => {
    const [mine, api] = [await footerOf(page), (await emu.get('/api/v1/status')).footer];
    return keys.every((k) => mine[k] === api[k]) && mine;
  }, { what: `footer ${keys.join(',')} = API` });
}

test('footer through start, PWC, a long G and a stroke fault (§11.2), Last Error on the Info page (§11.3)', async () => {
  const g = await openPage(browser, emu, '/index.html');
  const { page } = g;
  const all = ['live', 'statwd', 'opmode', 'python', 'pos', 'vel', 'temp', 'io'];

  let f = await footerMatchesApi(page, all);
  assert.equal(f.live, 'MC Live OFF');
  assert.equal(f.statwd, 'StatWd 0040h');
  assert.equal(await page.locator('#info-lasterror').textContent(), '-');

  await emu.refgo('PWC');
  f = await footerMatchesApi(page, all);
  assert.equal(f.live, 'MC Live RDY');
  assert.equal(f.opmode, 'OpMode 1');

  // A long move: the footer must show MOV within 300 ms. Measured inside the page, from the moment
  // the G line is sent to the DOM change (no test-process latency in the measurement).
  const ms = await page.evaluate(async () => {
    const el = document.getElementById('ft-live');
    const start = performance.now();
    const seen = new Promise((resolve) => {
      const check = () => el.textContent === 'MC Live MOV' && (resolve(performance.now() - start), true);
      if (!check()) new MutationObserver(() => check()).observe(el, { childList: true, characterData: true, subtree: true });
    });
    await (await fetch('/api/v1/refgo', { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify({ line: 'G5000000' }) })).text();
    return Promise.race([seen, new Promise((r) => setTimeout(() => r(Infinity), 2000))]);
  });
  assert.ok(ms <= 300, `MC Live MOV after ${ms} ms`);
  await footerMatchesApi(page, ['live', 'statwd', 'opmode']);
  assert.match((await footerOf(page)).pos, /^Pos \d+ inc$/);

  await emu.api('POST', '/api/v1/faults', { kind: 'drive.inject', cause: 'stroke' });
  f = await footerMatchesApi(page, all);
  assert.equal(f.live, 'MC Live ERR 7121h');
  const link = page.locator('#ft-live a.err');
  assert.equal(await link.textContent(), 'ERR 7121h');
  assert.equal(await link.getAttribute('href'), '/index.html');
  const color = await link.evaluate((a) => getComputedStyle(a).color);
  const [r, gr, b] = color.match(/\d+/g).map(Number);
  assert.ok(r > 150 && gr < 80 && b < 80, `ERR is red (${color})`);
  assert.equal(await page.locator('#info-lasterror').textContent(), '7121h / ERROR_STROKE');
  assert.equal(await page.locator('#info-mfrstatus').textContent(), '0040h', '1002h bit 6 (stroke)');

  // fault reset: remove the injection, controlword 0 → 80h
  await emu.api('DELETE', '/api/v1/faults');
  await emu.api('PUT', '/api/v1/objects/6040h/0', { value: 0 });
  await emu.api('PUT', '/api/v1/objects/6040h/0', { value: 0x80 });
  f = await footerMatchesApi(page, all);
  assert.equal(f.live, 'MC Live OFF');
  assert.equal(await page.locator('#ft-live a').count(), 0, 'no ERR link without a fault');
  assert.equal(await page.locator('#info-lasterror').textContent(), '7121h / ERROR_STROKE', 'the last error stays after the reset');
  assert.equal(await page.locator('#info-mfrstatus').textContent(), '0000h');

  // the ERR link leads to the Info page
  await emu.refgo('PWC');
  await emu.api('POST', '/api/v1/faults', { kind: 'drive.inject', cause: 'stroke' });
  await g.goto('/command.html');
  await waitFor(async () => (await page.locator('#ft-live a.err').count()) === 1, { what: 'ERR link' });
  await page.locator('#ft-live a.err').click();
  await page.waitForURL('**/index.html');
  assert.equal(await page.locator('h1').textContent(), 'MovingCap turnTRACK 349 Eth');
  g.assertClean();
  await g.close();
});

test('curl of every page shows the footer strings and the Info values (§3.5)', async () => {
  const status = await emu.get('/api/v1/status');
  for (const p of ['/', '/clickrun.html', '/servo.html', '/ioin.html', '/ioout.html', '/command.html', '/program.html', '/network.html', '/emulator.html']) {
    const html = await (await fetch(emu.base + p)).text();
    for (const key of ['statwd', 'opmode', 'python', 'io']) {
      assert.ok(html.includes(`<span id="ft-${key}">${status.footer[key]}</span>`), `${p}: ${status.footer[key]}`);
    }
    assert.ok(html.includes('MC Live'), p);
    assert.ok(!html.includes('{{'), `${p}: every placeholder filled`);
  }
});
