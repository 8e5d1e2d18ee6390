// web.md §11 item 6: Command & Parameters — TP shows the position without echo or prompt; Store
// Permanently: Cancel writes nothing, OK stores (the file appears in the state directory); Factory
// Reset likewise; plus error replies, the history and the object browser (§5.4).
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { existsSync } from 'node:fs';
import path from 'node:path';
import { startEmulator, launchBrowser, openPage, waitFor, answerNextDialog } from './harness.mjs';

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

// Executes one line on the page; resolves with the RefGo Response once the page has shown it.
async function command(page, line) {
  const before = Number((await page.locator('#cmd-response').getAttribute('data-answered')) || 0);
  await page.locator('#cmd-input').fill(line);
  await page.locator('#cmd-input').press('Enter');
  await page.waitForFunction((n) => Number(document.getElementById('cmd-response').dataset.answered || 0) > n, before);
  return page.locator('#cmd-response').textContent();
}

test('RefGo line, Store Permanently and Factory Reset behind confirm() (§11.6)', async () => {
  const g = await openPage(browser, emu, '/command.html', { allow: [{ url: /\/api\/v1\/factory-reset$/, status: 409 }] });
  const { page } = g;
  assert.equal(await page.locator('h1').textContent(), 'MC349 Command & Parameters');

  await emu.refgo('PWC');
  await emu.refgo('G180');
  await waitFor(async () => Math.abs((await emu.get('/api/v1/status')).posUser - 180) <= 2, { timeout: 10000, what: 'at 180' });
  const tp = await command(page, 'TP');
  assert.match(tp, /^\d+$/, 'the answer line only: no echo, no prompt');
  assert.ok(Math.abs(Number(tp) - 180) <= 2, `TP → ${tp}`);
  assert.equal(await command(page, 'OR1002,0'), 'OR1002,0,0');
  assert.equal(await command(page, 'OW6041,0,5'), 'OW6041,0,5,ERROR,06010002h');
  assert.equal(await command(page, 'SM'), '', 'no answer line');
  // Up recalls the last commands
  await page.locator('#cmd-input').press('ArrowUp');
  assert.equal(await page.locator('#cmd-input').inputValue(), 'SM');
  await page.locator('#cmd-input').press('ArrowUp');
  assert.equal(await page.locator('#cmd-input').inputValue(), 'OW6041,0,5');
  await page.locator('#cmd-input').press('ArrowDown');
  assert.equal(await page.locator('#cmd-input').inputValue(), 'SM');

  // Store Permanently: Cancel writes nothing
  const stateFile = path.join(emu.stateDir, 'drive-1.json');
  assert.equal(existsSync(stateFile), false);
  let asked = answerNextDialog(g, false);
  await page.locator('#cmd-store').click();
  assert.equal(await asked, 'Store Permanently - Are you sure?');
  await page.waitForTimeout(300);
  assert.equal(existsSync(stateFile), false, 'Cancel stores nothing');
  assert.equal(await page.locator('#cmd-store-result').textContent(), '');
  // OK stores
  await emu.api('PUT', '/api/v1/objects/6081h/0', { value: 1234 });
  asked = answerNextDialog(g, true);
  await page.locator('#cmd-store').click();
  await asked;
  await waitFor(async () => (await page.locator('#cmd-store-result').textContent()) === 'Stored', { what: 'Stored' });
  assert.equal(existsSync(stateFile), true, `${stateFile} written`);

  // Factory Reset: refused while Operation Enabled — the abort code and its text are shown
  await emu.refgo('PWC');
  assert.equal((await emu.get('/api/v1/status')).state, 'OE');
  asked = answerNextDialog(g, true);
  await page.locator('#cmd-factory').click();
  assert.equal(await asked, 'Factory Reset - Are you sure?');
  await waitFor(async () => /^08000022h /.test(await page.locator('#cmd-factory-result').textContent()), { what: 'the refusal 08000022h' });
  assert.ok(await page.locator('#cmd-factory-result.err').count());
  await emu.refgo('PQ');
  // Cancel changes nothing; OK loads the factory values
  asked = answerNextDialog(g, false);
  await page.locator('#cmd-factory').click();
  await asked;
  await page.waitForTimeout(300);
  assert.equal(await object('6081', 0), 1234, 'Cancel keeps the parameters');
  asked = answerNextDialog(g, true);
  await page.locator('#cmd-factory').click();
  await asked;
  await waitFor(async () => (await page.locator('#cmd-factory-result').textContent()) === 'Factory settings loaded', { what: 'Factory settings loaded' });
  assert.equal(await object('6081', 0), 1000, 'factory value of 6081h');
  g.assertClean();
  await g.close();
});

test('object browser: filter, decimal/hex, inline editing with errors in words (§5.4, §3.6)', async () => {
  const g = await openPage(browser, emu, '/command.html', { allow: [{ url: /\/api\/v1\/objects\/6060h\/0$/, status: 409 }] });
  const { page } = g;
  await waitFor(async () => (await page.locator('#cmd-objects tbody tr').count()) > 400, { what: 'the dictionary' });
  await page.locator('#cmd-filter').fill('6081');
  await waitFor(async () => (await page.locator('#cmd-objects tbody tr').count()) === 1, { what: 'one row for 6081' });
  assert.deepEqual((await page.locator('#cmd-objects tbody tr td').allTextContents()).slice(0, 5), ['6081h', '00h', 'Profile_velocity', 'UNSIGNED32', 'rw']);
  const field = page.locator('#obj-6081-00');
  await waitFor(async () => (await field.inputValue()) === '1000', { what: '6081h value' });
  await field.fill('2500');
  await field.press('Enter');
  await waitFor(async () => (await object('6081', 0)) === 2500, { what: '6081h = 2500' });
  await page.locator('#cmd-hex').check();
  await waitFor(async () => (await page.locator('#obj-6081-00').inputValue()) === '9C4h', { what: 'hex 9C4h' });
  await page.locator('#obj-6081-00').fill('A00h');
  await page.locator('#obj-6081-00').press('Enter');
  await waitFor(async () => (await object('6081', 0)) === 2560, { what: '6081h = 0xA00' });
  await page.locator('#cmd-hex').uncheck();
  // a refused write: the field says why and shows the real value again
  await page.locator('#cmd-filter').fill('modes of operation');
  await waitFor(async () => (await page.locator('#obj-6060-00').count()) === 1, { what: 'row 6060h' });
  await page.locator('#obj-6060-00').fill('99');
  await page.locator('#obj-6060-00').press('Enter');
  await waitFor(async () => (await page.locator('#obj-6060-00-error').textContent()) === '06090030h Invalid value for parameter', { what: 'the abort code at the field' });
  assert.equal(await page.locator('#obj-6060-00').getAttribute('aria-invalid'), 'true');
  await waitFor(async () => (await page.locator('#obj-6060-00').inputValue()) === String(await object('6060', 0)), { what: 'real value again' });
  // read-only rows follow the drive
  await page.locator('#cmd-filter').fill('6041');
  await emu.refgo('PWC');
  await waitFor(async () => (await page.locator('#obj-6041-00').textContent()) === String((await emu.get('/api/v1/status')).statusword), { what: 'statusword row live' });
  await emu.refgo('PQ');
  g.assertClean();
  await g.close();
});
