// web.md §11 items 7 and 8: IO IN — the IN Simulator toggle for IN1 sets 3510h.01 = 0x10000 and the
// footer shows I1.........O....; a 0400h function configured on IN1 runs when toggled. IO OUT —
// function 6 on OUT1 greys row 03h; the OUT lamps follow 60FEh.01.
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

const object = async (i, s) => (await emu.get(`/api/v1/objects/${i}/${s}`)).value;

test('IN Simulator and the IN Function Configurator (§11.7)', async () => {
  const g = await openPage(browser, emu, '/ioin.html', { allow: [{ url: /\/api\/v1\/objects\/3512h\/1$/, status: 409 }] });
  const { page } = g;
  assert.equal(await page.locator('h1').textContent(), 'MovingCap IO → Digital Input Functions');

  await page.locator('#insim-1').check();
  await waitFor(async () => (await object('3510', 1)) === 0x10000, { what: '3510h.01 = 0x10000' });
  await waitFor(async () => (await footerOf(page)).io === 'I1.........O....', { what: 'footer I1.........O....' });
  await waitFor(async () => (await page.locator('#insim-lamp-1').getAttribute('data-on')) === '1', { what: 'IN1 lamp' });
  await page.locator('#insim-3').check();
  await waitFor(async () => (await object('3510', 1)) === 0x50000, { what: '3510h.01 = 0x50000' });
  await waitFor(async () => (await footerOf(page)).io === 'I1.3.......O....', { what: 'footer I1.3.......O....' });
  await page.locator('#insim-clear').click();
  await waitFor(async () => (await object('3510', 1)) === 0 && (await footerOf(page)).io === 'I..........O....', { what: 'All off' });
  assert.equal(await page.locator('#insim-1').isChecked(), false);

  // configure IN1: Timed Motion Absolute to 15000 with 500 rpm, through the drop-down and Apply
  await page.locator('#in-sel-1').check();
  await page.locator('#in-func').selectOption({ label: '0400h Timed Motion Absolute' });
  assert.equal(await page.locator('#in-edit-01').inputValue(), '0400h');
  await page.locator('#in-edit-08').fill('15000');
  await page.locator('#in-edit-06').fill('500');
  await page.locator('#in-apply').click();
  await waitFor(async () => (await page.locator('#in-apply-result').textContent()) === 'IN1 written', { what: 'IN1 written' });
  assert.equal(await object('3511', 1), 0x0400);
  assert.equal(await object('3511', 8), 15000);
  assert.equal(await object('3511', 6), 500);
  assert.equal(await page.locator('#in-edit-01').inputValue(), '0400h', 'shows the written value');

  await emu.refgo('PWC');
  await page.locator('#insim-1').check();
  await waitFor(async () => (await object('3511', 4)) === 1, { what: 'the function ran once (3511h.04 = 1)' });
  assert.equal(await object('607A', 0), 15000);
  await waitFor(async () => Math.abs((await emu.get('/api/v1/status')).posUser - 15000) <= 2, { timeout: 10000, what: 'moved to 15000' });
  await waitFor(async () => (await page.locator('#in-edit-04').inputValue()) === '1', { what: 'Result 2 shows the count' });

  // Teach copies 6064h (as the page's status stream has it) into 08h; another input, and function 7
  // relabels the rows
  await page.waitForFunction(() => Math.abs(window.mcLive.status.posUser - 15000) <= 2);
  await page.locator('#in-teach').click();
  const taught = await page.locator('#in-edit-08').inputValue();
  assert.ok(Math.abs(Number(taught) - 15000) <= 2, `Teach copies 6064h (${taught})`);
  await page.locator('#in-sel-2').check();
  await waitFor(async () => (await page.locator('#in-edit-01').inputValue()) === '0000h', { what: 'IN2 function' });
  await page.locator('#in-func').selectOption('1792'); // 0700h
  assert.equal(await page.locator('#in-name-09').textContent(), 'Homing Method');
  assert.equal(await page.locator('#in-name-08').textContent(), 'Home Offset');
  // a code the drive refuses is written as typed and the refusal shown at the field
  await page.locator('#in-edit-01').fill('0C00h');
  assert.equal(await page.locator('#in-func').inputValue(), '', '(other code)');
  await page.locator('#in-apply').click();
  await waitFor(async () => (await page.locator('#in-edit-01-error').textContent()) === '06090030h Invalid value for parameter', { what: 'refusal at 01h' });
  await waitFor(async () => /refused/.test(await page.locator('#in-apply-result').textContent()), { what: 'Apply reports the refusal' });
  // Execute function now: 3510h.02 := (n << 8) | f
  await page.locator('#in-sel-1').check();
  await page.locator('#insim-func').selectOption('4');
  await page.locator('#insim-exec').click();
  await waitFor(async () => (await object('3510', 2)) === 0x0104, { what: '3510h.02 = 0104h' });
  await waitFor(async () => (await object('3511', 4)) === 2, { what: 'the function ran again' });
  await page.locator('#insim-clear').click();
  await screenshot(page, 'ioin-configured');
  await emu.refgo('PQ');
  g.assertClean();
  await g.close();
});

test('IO OUT: unused rows greyed, lamps follow 60FEh.01 (§11.8)', async () => {
  const g = await openPage(browser, emu, '/ioout.html');
  const { page } = g;
  assert.equal(await page.locator('h1').textContent(), 'MovingCap IO ← Digital Output Functions');
  await page.locator('#out-sel-1').check();
  await waitFor(async () => (await page.locator('#out-edit-01').inputValue()) === '0', { what: 'OUT1 function 0' });
  for (const sub of ['02', '03', '04', '05', '06']) assert.equal(await page.locator(`#out-edit-${sub}`).isDisabled(), true, `function 0: ${sub}h unused`);

  await page.locator('#out-func').selectOption('6');
  assert.equal(await page.locator('#out-edit-03').isDisabled(), true, 'function 6: 03h greyed');
  assert.match(await page.locator('#out-row-03').getAttribute('class'), /unused/);
  assert.equal(await page.locator('#out-edit-05').isDisabled(), false, 'function 6 uses the window 05h');
  assert.match(await page.locator('#out-name-02').textContent(), /^0: last target reached, 1-10: IN1\.\.10 target reached/);
  await page.locator('#out-edit-05').fill('250');
  await page.locator('#out-apply').click();
  await waitFor(async () => (await object('3611', 1)) === 6 && (await object('3611', 5)) === 250, { what: '3611h.01 = 6, .05 = 250' });
  await page.locator('#out-func').selectOption('3');
  assert.equal(await page.locator('#out-edit-03').isDisabled(), false, 'function 3 uses 03h');
  await page.locator('#out-sel-2').check();
  await waitFor(async () => (await page.locator('#out-edit-01').inputValue()) === '0', { what: 'OUT2 shown' });

  // lamps follow 60FEh.01; Set/Clear only for manual outputs
  await waitFor(async () => page.locator('#out-set-1').isDisabled(), { what: 'OUT1 (function 6) not manual' });
  assert.match(await page.locator('#out-set-1').getAttribute('title'), /function 6/);
  await page.locator('#out-set-2').click();
  await waitFor(async () => ((await object('60FE', 1)) & 0x20000) !== 0, { what: 'OUT2 high' });
  await waitFor(async () => (await page.locator('#out-lamp-2').getAttribute('data-on')) === '1', { what: 'OUT2 lamp' });
  await emu.refgo('OW60FE,1,393216');
  await waitFor(async () => (await page.locator('#out-lamp-3').getAttribute('data-on')) === '1', { what: 'OUT3 lamp after OW60FE' });
  assert.equal(await page.locator('#out-lamp-4').getAttribute('data-on'), '0');
  await page.locator('#out-clear-2').click();
  await waitFor(async () => (await page.locator('#out-lamp-2').getAttribute('data-on')) === '0', { what: 'OUT2 lamp off' });
  const out = await object('60FE', 1);
  const lamps = await Promise.all([1, 2, 3, 4].map((n) => page.locator(`#out-lamp-${n}`).getAttribute('data-on')));
  await waitFor(async () => {
    const l = await Promise.all([1, 2, 3, 4].map((n) => page.locator(`#out-lamp-${n}`).getAttribute('data-on')));
    return l.every((v, i) => v === (out & (1 << (16 + i)) ? '1' : '0'));
  }, { what: `lamps = 60FEh.01 ${out.toString(16)} (were ${lamps})` });
  const f = await footerOf(page);
  assert.equal(f.io.slice(11), `O${[1, 2, 3, 4].map((n) => (out & (1 << (15 + n)) ? String(n) : '.')).join('')}`);
  g.assertClean();
  await g.close();
});
