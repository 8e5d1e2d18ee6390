// The FAULHABER drive's web side (web/README.md "FAULHABER drive"; issue 24 item 1, issue 25 item 3):
// mcemu --model FH_MC5005 --clock manual serves only its Emulator page — `/` and every MovingCap
// page redirect there, the menu bar has only what the drive has, the footer is the MC's. On the page:
// the status LED and state, a program with a load error marked at its line, AN165 Example B uploaded
// through the file chooser, started, the clock advanced, the running line and the variables live,
// a variable written, an input switched, a fault injected (LED red), power cycle, the object
// browser, the trace channels; keyboard reachability and the 390-px phone width.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { mkdirSync, readFileSync } from 'node:fs';
import net from 'node:net';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { startEmulator, launchBrowser, openPage, waitFor, answerNextDialog, screenshot, SCREENSHOT_DIR } from './harness.mjs';

const here = path.dirname(fileURLToPath(import.meta.url));
const EXAMPLE_B = readFileSync(path.join(here, '../scripting/basic/fixtures/example_b.bas'));
// line 4 jumps to a label that does not exist: a load error of line 4
const BAD = "' a program with a load error\r\n:Top\r\na = a + 1\r\nGOTO Nowhere\r\n";
const MOVINGCAP_PAGES = ['/', '/index.html', '/clickrun.html', '/servo.html', '/ioin.html', '/ioout.html', '/command.html', '/program.html', '/network.html'];
const FOOTER = ['state', 'statwd', 'opmode', 'basic', 'pos', 'vel', 'io'];

let emu;
let browser;
before(async () => {
  emu = await startEmulator({ args: ['--model', 'FH_MC5005', '--clock', 'manual', '--faulhaber-port', '0'] });
  browser = await launchBrowser();
});
after(async () => {
  await browser?.close();
  await emu?.stop();
});

const status = () => emu.get('/api/v1/status');
const advance = (ms) => emu.api('POST', '/api/v1/clock/advance', { ms });
const object = async (index, sub) => (await emu.get(`/api/v1/objects/${index}/${sub}`)).value;
const footerOf = (page) => page.evaluate((keys) => Object.fromEntries(keys.map((k) => [k, document.getElementById(`ft-${k}`).textContent])), FOOTER);
const sameFooter = async (page) => {
  const want = (await status()).footer;
  const got = await footerOf(page);
  return FOOTER.every((k) => got[k] === want[k]) && Object.keys(want).length === FOOTER.length;
};
const text = (page, sel) => page.locator(sel).textContent();

test('only the Emulator page: `/` and the MovingCap pages redirect to it, the menu has only what the drive has', async () => {
  for (const p of MOVINGCAP_PAGES) {
    const r = await fetch(emu.base + p, { redirect: 'manual' });
    assert.equal(r.status, 302, p);
    assert.equal(r.headers.get('location'), '/emulator.html', p);
  }
  assert.equal((await fetch(`${emu.base}/faulhaber.html`, { redirect: 'manual' })).status, 302);
  const info = await emu.get('/api/v1/info');
  assert.equal(info.personality, 'faulhaber');

  const g = await openPage(browser, emu, null);
  const { page } = g;
  for (const p of ['/', '/servo.html', '/program.html?codeAct=3']) {
    const res = await page.goto(emu.base + p);
    assert.equal(res.status(), 200, p);
    assert.equal(new URL(page.url()).pathname, '/emulator.html', `${p} lands on the Emulator page`);
  }
  await page.waitForFunction(() => window.mcLive && window.mcLive.statusCount > 0);
  assert.deepEqual(await page.locator('#menubar a').allTextContents(), ['FAULHABER MC 5005', 'Emulator']);
  assert.equal(await page.locator('#menubar a.emu').getAttribute('aria-current'), 'page');
  for (const absent of ['#sidemenu', '#menu-toggle', '#led-green', '#led-yellow', '#ft-python', '#ft-live', '#emu-console']) {
    assert.equal(await page.locator(absent).count(), 0, `${absent} is not on a FAULHABER page`);
  }
  assert.equal(await page.locator('h1').textContent(), 'Emulator — FAULHABER MC 5005');
  assert.match(await text(page, '#footer .tagline'), /FAULHABER MotionController — emulated by mcemu/);
  await waitFor(() => sameFooter(page), { what: 'footer = /api/v1/status footer' });
  assert.equal(await page.evaluate(() => window.mcLive.mode), 'ws');
  // the trace offers this drive's channels only
  const channels = await page.locator('#emu-trace-channels input').evaluateAll((els) => els.map((e) => e.id.replace('emu-trace-ch-', '')));
  assert.deepEqual(channels, ['faulhaber', 'basic', 'drive', 'api', 'http']);
  // the fault buttons are the drive core's causes with this drive's EMCY codes
  assert.equal(await page.locator('#fh-fault-buttons button').count(), 13);
  assert.equal(await text(page, '#fh-fault-stroke'), '8611h following error');
  assert.equal(await page.locator('#fh-clock-controls').isVisible(), true, 'manual clock: the Advance buttons');
  g.assertClean();
  await g.close();
});

test('status LED and state follow the drive, the clock advances from the page', async () => {
  const g = await openPage(browser, emu, '/emulator.html');
  const { page } = g;
  await page.locator('#fh-clock-100').click();
  await waitFor(async () => (await status()).state === 'SOD', { what: 'Switch on disabled after 100 ms' });
  await waitFor(async () => (await page.locator('#led-status').getAttribute('data-color')) === 'green', { what: 'green LED' });
  assert.equal(await page.locator('#led-status').getAttribute('data-blink'), 'true', 'ready: green blinking');
  assert.equal(await page.locator('#fh-led').getAttribute('data-blink'), 'true');
  assert.equal(await text(page, '#fh-state'), 'Switch on disabled');
  await waitFor(async () => (await text(page, '#ft-state')) === 'Switch on disabled', { what: 'footer state' });
  const t = (await status()).timeMs;
  await page.locator('#fh-clock-ms').fill('250');
  await page.locator('#fh-clock-advance').click();
  await waitFor(async () => (await status()).timeMs === t + 250, { what: 'advanced 250 ms' });
  await waitFor(async () => (await text(page, '#fh-clock-time')) === String(t + 250), { what: 'drive time on the page' });
  g.assertClean();
  await g.close();
});

test('MC BASIC: a load error marks its line, Example B runs in drive time, variables and inputs live', async () => {
  const g = await openPage(browser, emu, '/emulator.html');
  const { page } = g;
  await waitFor(async () => (await text(page, '#fh-slot-1-state')) === 'empty', { what: 'slot 1 empty' });

  // ---- a program with a load error, uploaded through the file chooser into program 1
  let [chooser] = await Promise.all([page.waitForEvent('filechooser'), page.locator('#fh-upload-file').click()]);
  await chooser.setFiles({ name: 'bad.bas', mimeType: 'text/plain', buffer: Buffer.from(BAD) });
  await waitFor(async () => /^error in line 4: /.test(await text(page, '#fh-slot-1-state')), { what: 'slot 1: error in line 4' });
  assert.match(await text(page, '#fh-edit-status'), /Program 1: error in line 4: .*nowhere/i);
  assert.equal(await page.locator('#fh-gutter span.err').getAttribute('data-line'), '4', 'the gutter marks line 4');
  assert.equal(await page.locator('#fh-mark-error').isVisible(), true);
  assert.equal(await page.locator('#fh-mark-error').getAttribute('data-line'), '4');
  assert.equal(await page.evaluate(() => window.mcBasic.errorLine), 4);
  // the caret sits at the start of line 4
  assert.equal(await page.evaluate(() => {
    const ta = document.getElementById('fh-editor');
    return ta.value.slice(0, ta.selectionStart).split('\n').length;
  }), 4);
  assert.equal(await page.locator('#fh-slot-1-start').isDisabled(), true, 'a program with an error cannot start');
  // fixed in the editor and saved: loaded, no mark
  await page.locator('#fh-editor').fill("' fixed\n:Top\na = a + 1\nGOTO Top\n");
  await page.locator('#fh-edit-save').click();
  await waitFor(async () => (await text(page, '#fh-slot-1-state')) === 'loaded', { what: 'slot 1 loaded' });
  assert.equal(await page.locator('#fh-mark-error').isHidden(), true);

  // ---- AN165 Example B into program 2 through the file chooser
  await page.locator('#fh-edit-slot').selectOption('2');
  await waitFor(() => page.evaluate(() => window.mcBasic.editorSlot === 2), { what: 'editor on program 2' });
  [chooser] = await Promise.all([page.waitForEvent('filechooser'), page.locator('#fh-upload-file').click()]);
  await chooser.setFiles({ name: 'example_b.bas', mimeType: 'text/plain', buffer: EXAMPLE_B });
  await waitFor(async () => (await text(page, '#fh-slot-2-state')) === 'loaded', { what: 'Example B loaded' });
  assert.equal(await text(page, '#fh-slot-2-bytes'), String(EXAMPLE_B.length));
  assert.equal((await emu.get('/api/v1/faulhaber/programs/2')).source, EXAMPLE_B.toString('latin1'), 'the file as it is');
  await page.locator('#fh-slot-2-start').click();
  await waitFor(async () => (await status()).basic.running === 2, { what: 'program 2 runs' });
  await waitFor(async () => /^program 2, line \d+$/.test(await text(page, '#fh-basic-running')), { what: 'running line shown' });
  await waitFor(async () => (await text(page, '#ft-basic')) === 'BASIC RUN 2', { what: 'footer BASIC RUN 2' });

  // drive time: the program enables the drive and moves; the page shows the line and the variables
  const lines = new Set();
  const zs = new Set();
  for (let i = 0; i < 8; i++) {
    const t0 = (await status()).timeMs;
    await page.locator('#fh-clock-100').click();
    // the manual clock stands still once the advance is done: the page must then show its line
    const s = await waitFor(async () => {
      const st = await status();
      return st.timeMs === t0 + 100 && st;
    }, { what: `drive time ${t0 + 100}` });
    await waitFor(async () => (await text(page, '#fh-basic-running')) === `program 2, line ${s.basic.line}`, { what: `running line ${s.basic.line} shown` });
    lines.add(s.basic.line);
    const [y, z] = await Promise.all([object('3005', '19'), object('3005', '1A')]);
    await waitFor(async () => (await page.locator('#fh-var-y').inputValue()) === String(y) && (await page.locator('#fh-var-z').inputValue()) === String(z), { what: `y = ${y}, z = ${z} on the page` });
    zs.add(z);
    assert.equal(await page.locator('#fh-mark-run').getAttribute('data-line'), String(s.basic.line), 'the editor marks the running line');
  }
  assert.ok(lines.size >= 2, `the running line changes (${[...lines]})`);
  assert.ok(zs.size >= 2, `z changes (${[...zs]})`);
  assert.equal(await page.locator('#fh-var-y').inputValue(), '2', 'y = 2: enabled');
  assert.equal((await status()).state, 'OE');
  assert.equal(await page.locator('#led-status').getAttribute('data-color'), 'green');
  assert.equal(await page.locator('#led-status').getAttribute('data-blink'), 'false', 'Operation enabled: green steady');
  await waitFor(() => sameFooter(page), { what: 'footer = status while moving' });
  // the whole MC BASIC panel: slots, editor with the running line, inputs, variables
  // (the sticky footer would be stitched into the middle of a panel taller than the window)
  mkdirSync(SCREENSHOT_DIR, { recursive: true });
  await page.evaluate(() => (document.getElementById('footer').style.position = 'static'));
  await page.locator('#fh-basic').screenshot({ path: path.join(SCREENSHOT_DIR, 'faulhaber-basic.png') });
  await page.evaluate(() => (document.getElementById('footer').style.position = ''));

  // a variable written from the page reaches 3005h (a master's view)
  await page.locator('#fh-var-a').fill('-123');
  await page.locator('#fh-var-a').press('Enter');
  await waitFor(async () => (await object('3005', '1')) === -123, { what: '3005h.01 = -123' });

  // an input switched on the page: 2311h.02, the lamp and the footer
  await page.locator('#fh-in-3').check();
  await waitFor(async () => (await object('2311', '2')) === 4, { what: '2311h.02 = 4' });
  await waitFor(async () => (await page.locator('#fh-inlamp-3').getAttribute('data-on')) === '1', { what: 'DigIn3 lamp' });
  await waitFor(async () => (await text(page, '#ft-io')) === 'I..3.....O..', { what: 'footer I..3.....O..' });
  await page.locator('#fh-in-3').uncheck();
  await waitFor(async () => (await object('2311', '2')) === 0, { what: '2311h.02 = 0' });

  // autostart and stop
  await page.locator('#fh-basic-autostart').selectOption('2');
  await waitFor(async () => (await emu.get('/api/v1/faulhaber/programs')).autostart === 2, { what: 'autostart 2' });
  await page.locator('#fh-basic-stop').click();
  await waitFor(async () => (await status()).basic.running === 0, { what: 'stopped' });
  await waitFor(async () => (await text(page, '#fh-slot-2-state')) === 'stopped', { what: 'slot 2 stopped' });
  await waitFor(async () => (await text(page, '#fh-basic-running')) === 'none', { what: 'running: none' });
  assert.match(await text(page, '#fh-basic-saves'), /^\d+$/);
  g.assertClean();
  await g.close();
});

test('fault: the LED turns red with the error in words; Fault Reset; power cycle starts the autostart program', async () => {
  await fetch(`${emu.base}/api/v1/faulhaber/programs/4`, { method: 'PUT', body: ':Top\r\nb = b + 1\r\nGOTO Top\r\n' });
  await emu.api('PUT', '/api/v1/faulhaber/autostart', { program: 4 });
  const g = await openPage(browser, emu, '/emulator.html');
  const { page } = g;
  await page.locator('#fh-fault-stroke').click();
  await waitFor(async () => (await emu.get('/api/v1/faults')).faults.length === 1, { what: 'the stroke injection' });
  await page.locator('#fh-clock-100').click();
  await waitFor(async () => (await status()).state === 'F', { what: 'Fault' });
  await waitFor(async () => (await page.locator('#led-status').getAttribute('data-color')) === 'red', { what: 'red LED' });
  assert.equal(await page.locator('#fh-led').getAttribute('data-color'), 'red');
  await waitFor(async () => (await text(page, '#ft-state')) === 'Fault 8611h', { what: 'footer Fault 8611h' });
  assert.equal(await page.locator('#ft-state').getAttribute('class'), 'err');
  assert.equal(await text(page, '#fh-led-text'), 'Fault — 8611h following error');
  assert.match(await text(page, '#fh-errorword'), /^0002h following error$/);
  assert.equal(await text(page, '#fh-lasterror'), '8611h / following error');
  await waitFor(async () => (await page.locator('#fh-injections tbody tr').count()) === 1, { what: 'the injection listed' });
  await page.evaluate(() => window.scrollTo(0, 0));
  await screenshot(page, 'faulhaber-emulator');

  await page.locator('#fh-remove-all').click();
  await waitFor(async () => (await emu.get('/api/v1/faults')).faults.length === 0, { what: 'injection removed' });
  await page.locator('#fh-faultreset').click();
  await waitFor(async () => (await text(page, '#fh-faultreset-result')) === 'controlword bit 7: 0 → 1', { what: 'fault reset written' });
  await page.locator('#fh-clock-1').click();
  await waitFor(async () => (await status()).state !== 'F', { what: 'fault reset' });
  await waitFor(async () => (await page.locator('#led-status').getAttribute('data-color')) === 'green', { what: 'green again' });

  // power cycle behind confirm(): Cancel does nothing, OK powers up and starts autostart program 4
  const before = (await status()).timeMs;
  let asked = answerNextDialog(g, false);
  await page.locator('#fh-powercycle').click();
  assert.equal(await asked, 'Power cycle the drive - Are you sure?');
  assert.equal((await status()).timeMs, before, 'Cancel: no power cycle (the manual clock stands still)');
  asked = answerNextDialog(g, true);
  await page.locator('#fh-powercycle').click();
  await asked;
  await waitFor(async () => (await text(page, '#fh-powercycle-result')) === 'powered up again', { what: 'powered up' });
  assert.ok((await status()).timeMs < before, 'drive time starts again after the power cycle');
  await page.locator('#fh-clock-100').click();
  await waitFor(async () => (await status()).basic.running === 4, { what: 'autostart program 4 after power on' });
  await waitFor(async () => (await text(page, '#ft-basic')) === 'BASIC RUN 4', { what: 'footer BASIC RUN 4' });
  await waitFor(async () => (await page.locator('#fh-basic-autostart').inputValue()) === '4', { what: 'autostart 4 shown' });
  await emu.api('POST', '/api/v1/faulhaber/stop', {});
  await emu.api('PUT', '/api/v1/faulhaber/autostart', { program: 0 });
  g.assertClean();
  await g.close();
});

test('object browser: the FAULHABER objects, a filter, an edit; trace channels basic, api and faulhaber', async () => {
  const g = await openPage(browser, emu, '/emulator.html');
  const { page } = g;
  await waitFor(async () => (await page.locator('#fh-objects tbody tr').count()) > 40, { what: 'FAULHABER objects listed' });
  const first = await page.locator('#fh-objects tbody tr td:first-child').allTextContents();
  assert.ok(first.every((i) => parseInt(i, 16) >= 0x2000 && parseInt(i, 16) <= 0x3fff), 'the FAULHABER group');
  assert.ok(first.includes('2310h') && first.includes('3005h') && first.includes('2400h'));
  await page.locator('#fh-obj-filter').fill('2310');
  await waitFor(async () => (await page.locator('#fh-objects tbody tr').count()) === 7, { what: '2310h.00 … 11' });
  await page.locator('#obj-2310-01').fill('4');
  await page.locator('#obj-2310-01').press('Enter');
  await waitFor(async () => (await object('2310', '1')) === 4, { what: '2310h.01 = 4' });
  await page.locator('#obj-2310-01').fill('0');
  await page.locator('#obj-2310-01').press('Enter');
  await waitFor(async () => (await object('2310', '1')) === 0, { what: '2310h.01 = 0' });
  // a read-only entry refuses in place
  await page.locator('#fh-obj-group').selectOption('6000-6fff');
  await page.locator('#fh-obj-filter').fill('6041');
  await waitFor(async () => (await page.locator('#obj-6041-00').count()) === 1, { what: '6041h listed' });
  assert.equal(await page.locator('#obj-6041-00').evaluate((el) => el.tagName), 'TD', 'read-only: no input');

  // trace: the basic channel shows program events, api the page's writes
  await page.locator('#emu-trace-ch-http').uncheck();
  await fetch(`${emu.base}/api/v1/faulhaber/programs/3`, { method: 'PUT', body: ':Top\r\nSETOBJ $3005.01 = 7\r\nGOTO Top\r\n' });
  await emu.api('POST', '/api/v1/faulhaber/programs/3/start', {});
  await advance(20);
  await emu.api('POST', '/api/v1/faulhaber/stop', {});
  await waitFor(async () => (await page.locator('#emu-trace div[data-channel="basic"]').count()) > 0, { what: 'basic events in the trace' });
  await waitFor(async () => (await page.locator('#emu-trace div[data-channel="api"]').count()) > 0, { what: 'api events in the trace' });
  // a frame of the binary protocol (read 6041h, faulhaber.md §3) and its answer on the faulhaber channel
  const answer = await new Promise((resolve, reject) => {
    const sock = net.connect(emu.ports.faulhaber, '127.0.0.1', () => sock.write(Buffer.from('53070101416000' + '7345', 'hex')));
    sock.on('data', (d) => {
      sock.destroy();
      resolve(d);
    });
    sock.on('error', reject);
  });
  assert.equal(answer[0], 0x53, 'an answer frame');
  await waitFor(async () => (await page.locator('#emu-trace div[data-channel="faulhaber"].trace-rx').count()) > 0 && (await page.locator('#emu-trace div[data-channel="faulhaber"].trace-tx').count()) > 0, { what: 'the frame and its answer in the trace' });
  assert.match(await page.locator('#emu-trace div[data-channel="faulhaber"].trace-rx').first().textContent(), /6041/);
  assert.equal(await page.locator('#emu-trace div[data-channel="http"]').count(), 0);
  g.assertClean();
  await g.close();
});

test('keyboard: every control of the page is reachable with Tab', async () => {
  const g = await openPage(browser, emu, '/emulator.html');
  const { page } = g;
  // the object browser has an input per writable entry: walk a filtered table
  await page.locator('#fh-obj-filter').fill('2400');
  await waitFor(async () => (await page.locator('#fh-objects tbody tr').count()) === 5, { what: 'filtered object browser' });
  await page.evaluate(() => window.scrollTo(0, 0));
  await page.locator('#badge').focus();
  const wanted = await page.evaluate(() => {
    window.focusedIds = new Set();
    document.addEventListener('focusin', (e) => window.focusedIds.add(e.target.id || e.target.textContent.trim()));
    return [...document.querySelectorAll('main button, main input, main select, main textarea, main a[href], main pre[tabindex]')]
      .filter((el) => el.offsetParent !== null && !el.disabled)
      .map((el) => el.id || el.textContent.trim());
  });
  for (let i = 0; i < wanted.length + 10; i++) await page.keyboard.press('Tab');
  const reached = new Set(await page.evaluate(() => [...window.focusedIds]));
  assert.deepEqual(wanted.filter((w) => !reached.has(w)), [], 'not reachable with Tab');
  g.assertClean();
  await g.close();
});

test('390 px wide: the page fits the phone and the footer stays readable', async () => {
  const g = await openPage(browser, emu, '/emulator.html', { viewport: { width: 390, height: 844 } });
  const { page } = g;
  await page.locator('#fh-clock-100').click();
  await waitFor(async () => (await page.locator('#fh-objects tbody tr').count()) > 0, { what: 'objects listed' });
  const width = await page.evaluate(() => document.documentElement.scrollWidth);
  assert.ok(width <= 390, `the document is ${width} px wide at 390 px`);
  const box = await page.locator('#ft-io').boundingBox();
  assert.ok(box && box.x >= 0 && box.x + box.width <= 390, 'the I/O string is on the screen');
  await page.evaluate(() => window.scrollTo(0, 0));
  // a blinking LED is caught in either phase: with reduced motion it is shown lit and dimmed
  await page.emulateMedia({ reducedMotion: 'reduce' });
  await screenshot(page, 'faulhaber-390px');
  g.assertClean();
  await g.close();
});
