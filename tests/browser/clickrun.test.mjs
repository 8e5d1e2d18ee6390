// web.md §11 item 4: Click & Run — Power ON, a changed Positioning Velocity (6081h follows), Move
// Absolute to Target Pos., Back & Forth oscillates, Stop Motion stops; a refused value is shown at
// its field (§3.6); the move is on the footer and the page's scope at once; the keyboard works.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { startEmulator, launchBrowser, openPage, waitFor, footerOf, screenshot } from './harness.mjs';

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

const status = () => emu.get('/api/v1/status');
const object = async (i, s) => (await emu.get(`/api/v1/objects/${i}/${s}`)).value;

test('Click & Run drives the drive (§11.4)', async (t) => {
  const g = await openPage(browser, emu, '/clickrun.html', { allow: [{ url: /\/api\/v1\/objects\/6083h\/0$/, status: 409 }] });
  const { page } = g;
  assert.equal(await page.locator('h1').textContent(), 'MC349 Click & Run');
  for (const [id, value] of [['cr-vel', '1000'], ['cr-acc', '1000'], ['cr-dec', '1000'], ['cr-target', '0'], ['cr-distance', '0']]) {
    assert.equal(await page.locator(`#${id}`).inputValue(), value, `#${id} shows the drive's value`);
  }

  await page.locator('#cr-poweron').click();
  await waitFor(async () => (await footerOf(page)).live === 'MC Live RDY', { what: 'MC Live RDY' });
  assert.equal((await status()).state, 'OE');

  // a changed field is written on Enter; 6081h follows
  await page.locator('#cr-vel').fill('1500');
  await page.locator('#cr-vel').press('Enter');
  await waitFor(async () => (await object('6081', 0)) === 1500, { what: '6081h = 1500' });
  // a value the drive refuses: red, aria-invalid, the abort code and text, then the real value again
  await page.locator('#cr-acc').fill('0');
  await page.locator('#cr-acc').press('Tab');
  await waitFor(async () => (await page.locator('#cr-acc-error').textContent()) === '06090032h Value of parameter written too low', { what: 'cr-acc-error' });
  assert.equal(await page.locator('#cr-acc').getAttribute('aria-invalid'), 'true');
  await waitFor(async () => (await page.locator('#cr-acc').inputValue()) === '1000', { what: 'cr-acc shows 1000 again' });
  assert.equal(await object('6083', 0), 1000);
  await page.locator('#cr-acc').fill('2000');
  await page.locator('#cr-acc').press('Enter');
  await waitFor(async () => (await object('6083', 0)) === 2000, { what: '6083h = 2000' });
  await waitFor(async () => (await page.locator('#cr-acc').getAttribute('aria-invalid')) === null, { what: 'error cleared' });
  assert.equal(await page.locator('#cr-acc-error').textContent(), '');

  // Move Absolute to Target Pos.: on the footer and the scope at once
  const samples = await page.evaluate(() => window.mcScope.sampleCount);
  await page.locator('#cr-target').fill('200000');
  await page.locator('#cr-moveabs').click();
  await waitFor(async () => (await footerOf(page)).live === 'MC Live MOV', { timeout: 1000, what: 'MC Live MOV' });
  assert.equal(await object('607A', 0), 200000);
  await waitFor(async () => page.evaluate(() => window.mcScope.lastSample && window.mcScope.lastSample.vel !== 0), { timeout: 1000, what: 'the move on the scope' });
  assert.ok((await page.evaluate(() => window.mcScope.sampleCount)) > samples);
  // at the target (the position loop holds it within an increment or so), footer = API
  await waitFor(async () => Math.abs((await status()).posUser - 200000) <= 2 && (await footerOf(page)).live === 'MC Live RDY', { timeout: 10000, what: 'at 200000' });
  await waitFor(async () => {
    const [f, s] = [await footerOf(page), await status()];
    return f.pos === s.footer.pos && /^Pos (199998|199999|200000|200001|200002) inc$/.test(f.pos);
  }, { what: 'footer Pos at the target = the API footer' });
  assert.match(await page.locator('#cr-result').textContent(), /^G200000/);

  // Target Distance: RW on change; Back & Forth oscillates over it from the last target
  await page.locator('#cr-distance').fill('30000');
  await page.locator('#cr-distance').press('Enter');
  await waitFor(async () => (await status()).refgo.repeatWay === 30000, { what: 'RWAY 30000' });
  await page.locator('#cr-backforth').click();
  const seen = [];
  await waitFor(async () => {
    const s = await status();
    seen.push(s.posUser);
    return s.refgo.backAndForth && Math.max(...seen) >= 229000 && seen.some((p, i) => i > seen.indexOf(Math.max(...seen)) && p <= 201000);
  }, { timeout: 15000, interval: 50, what: 'Back & Forth between 200000 and 230000' });
  assert.ok(Math.min(...seen) >= 199000 && Math.max(...seen) <= 231000, `oscillates within the distance (${Math.min(...seen)} … ${Math.max(...seen)})`);
  await screenshot(page, 'clickrun-moving');

  // Stop Motion
  await page.locator('#cr-stop').click();
  let previous = null;
  await waitFor(async () => {
    const s = await status();
    const still = previous !== null && !s.refgo.backAndForth && s.velUser === 0 && Math.abs(s.posUser - previous) <= 1;
    previous = s.posUser;
    return still;
  }, { timeout: 5000, interval: 100, what: 'stopped' });
  await page.waitForTimeout(300);
  const p2 = (await status()).posUser;
  assert.ok(Math.abs(p2 - previous) <= 2, `stays stopped (${previous} → ${p2} inc)`);

  // the keyboard alone: Tab to Power OFF, Enter
  await page.locator('#cr-result').evaluate(() => document.getElementById('cr-stop').focus());
  await page.keyboard.press('Shift+Tab');
  await page.keyboard.press('Shift+Tab');
  assert.equal(await page.evaluate(() => document.activeElement.id), 'cr-poweroff');
  await page.keyboard.press('Enter');
  await waitFor(async () => (await footerOf(page)).live === 'MC Live OFF', { what: 'MC Live OFF after Power OFF' });
  t.diagnostic(`scope samples on the page: ${await page.evaluate(() => window.mcScope.sampleCount)}`);
  g.assertClean();
  await g.close();
});
