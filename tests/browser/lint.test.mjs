// The Emulator page's Lint panel (docs/lint.md §5, emulator-lint.js): a sloppy RefGo master's
// findings appear with their counts, explanation and reference; every rule on request; the reset
// button clears counts and findings; on a FAULHABER drive the same panel shows what a host did over
// the JSON API. Screenshot: emulator-lint (the panel after the sloppy master).
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import net from 'node:net';
import path from 'node:path';
import { existsSync, mkdirSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { startEmulator, launchBrowser, openPage, waitFor, SCREENSHOT_DIR } from './harness.mjs';

let browser;
before(async () => {
  browser = await launchBrowser();
});
after(async () => {
  await browser?.close();
});

// Bytes to the RefGo port in one write; resolves once `prompts` replies ('>') have come back.
function refgoRaw(port, bytes, prompts) {
  return new Promise((resolve, reject) => {
    const s = net.connect(port, '127.0.0.1', () => s.write(bytes));
    let got = '';
    const timer = setTimeout(() => {
      s.destroy();
      reject(new Error(`RefGo: ${prompts} replies wanted, got ${JSON.stringify(got)}`));
    }, 5000);
    s.on('data', (d) => {
      got += d;
      if (got.split('>').length - 1 >= prompts) {
        clearTimeout(timer);
        s.end();
        resolve(got);
      }
    });
    s.on('error', reject);
  });
}

const rowCount = (page, rule) => page.locator(`#emu-lint-rules tr[data-rule="${rule}"] td.num`).first().textContent();

test('MovingCap: a sloppy master\'s findings with counts, fix and reference; every rule; reset', async () => {
  const emu = await startEmulator();
  try {
    const g = await openPage(browser, emu, '/emulator.html');
    const { page } = g;
    await waitFor(async () => (await page.locator('#emu-lint-mode').textContent()) === 'warn', { what: 'mode warn' });
    assert.equal(await page.locator('#emu-lint-empty').isVisible(), true, 'no findings yet');
    assert.equal(await page.locator('#emu-lint-rules tbody tr').count(), 1, 'the "no rule has fired" row');

    // the sloppy master: Enable operation from Switch on disabled, then three commands in one write
    await refgoRaw(emu.ports.refgo, 'OW6040,0,15\r', 1);
    await refgoRaw(emu.ports.refgo, 'TP\rTP\rTS\r', 3);
    await waitFor(async () => (await page.locator('#emu-lint-rules tbody tr[data-rule]').count()) === 2, { what: 'two rules fired' });
    assert.equal(await rowCount(page, 'cia402.command_ignored'), '1');
    assert.equal(await rowCount(page, 'refgo.request_before_reply'), '2');
    assert.match(await page.locator('#emu-lint-totals').textContent(), /^0 error, 3 warn/);
    const items = page.locator('#emu-lint-recent li');
    await waitFor(async () => (await items.count()) === 3, { what: 'three findings listed' });
    const oldest = items.nth(2);  // newest first
    assert.equal(await oldest.getAttribute('data-rule'), 'cia402.command_ignored');
    assert.match(await oldest.textContent(), /controlword 0x000F \(Enable operation\) in Switch on disabled is ignored/);
    assert.match(await oldest.locator('.lint-advice').textContent(), /^Fix: step through the states: Shutdown 0x0006/);
    assert.match(await oldest.locator('.lint-ref').textContent(), /^Reference: drive-core\.md §4\.2, §4\.3/);
    assert.match(await items.first().textContent(), /refgo\.request_before_reply — #3 · \d+ ms · refgo · conn \d+/);

    mkdirSync(SCREENSHOT_DIR, { recursive: true });
    await page.locator('#lint').scrollIntoViewIfNeeded();
    await page.locator('#lint').screenshot({ path: path.join(SCREENSHOT_DIR, 'emulator-lint.png') });

    await page.locator('#emu-lint-all').check();
    const api = await emu.get('/api/v1/lint');
    assert.equal(await page.locator('#emu-lint-rules tbody tr[data-rule]').count(), api.rules.length);

    await page.locator('#emu-lint-reset').click();
    await waitFor(async () => (await page.locator('#emu-lint-result').textContent()) === 'counts and findings cleared', { what: 'reset' });
    assert.equal((await emu.get('/api/v1/lint')).totals.warn, 0);
    assert.equal(await page.locator('#emu-lint-recent li').count(), 0);
    assert.equal(await page.locator('#emu-lint-empty').isVisible(), true);
    g.assertClean();
    await g.close();
  } finally {
    await emu.stop();
  }
});

// The FAULHABER drive's own Emulator page (web/ui/faulhaber.html) comes with the FAULHABER web work;
// in a tree without it this part has no page to test.
const fhPage = path.join(path.dirname(fileURLToPath(import.meta.url)), '../../web/ui/faulhaber.html');
const noFhPage = !existsSync(fhPage) && 'no FAULHABER Emulator page (web/ui/faulhaber.html) in this tree';

test('FAULHABER: the same panel on its Emulator page; --lint strict shown', { skip: noFhPage }, async () => {
  const emu = await startEmulator({ args: ['--model', 'FH_MC5005', '--faulhaber-port', '0', '--lint', 'strict'] });
  try {
    const g = await openPage(browser, emu, '/emulator.html');
    const { page } = g;
    await waitFor(async () => (await page.locator('#emu-lint-mode').textContent()) === 'strict', { what: 'mode strict' });
    const put = await emu.api('PUT', '/api/v1/objects/6040h/0', { value: 7 });  // Switch on from Switch on disabled
    assert.equal(put.value, 7);
    await waitFor(async () => (await page.locator('#emu-lint-recent li').count()) === 1, { what: 'the finding listed' });
    assert.match(await page.locator('#emu-lint-recent li').first().textContent(), /controlword 0x0007 \(Switch on\) in Switch on disabled is ignored/);
    assert.match(await page.locator('#emu-lint-totals').textContent(), /1 failing in strict tests/);
    await page.locator('#lint').scrollIntoViewIfNeeded();
    await page.locator('#lint').screenshot({ path: path.join(SCREENSHOT_DIR, 'emulator-lint-faulhaber.png') });
    g.assertClean();
    await g.close();
  } finally {
    await emu.stop();
  }
});
