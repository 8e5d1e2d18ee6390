// The Emulator page (web.md §5.9): fault buttons per cause, Fault Reset, custom EMCY, active
// injections with Remove, transport faults, wiring switches, supply/ambient sliders, a mechanical
// stop, the UDP console, the trace with channel filters and control-byte rendering, settings,
// power cycle behind confirm(), about.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import net from 'node:net';
import { startEmulator, launchBrowser, openPage, waitFor, footerOf, answerNextDialog, screenshot } from './harness.mjs';

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
// Each test starts from no injections and a drive that is switched off without a fault.
async function reset() {
  await emu.api('DELETE', '/api/v1/faults');
  await emu.refgo('PQ');
}
const faults = async () => (await emu.get('/api/v1/faults')).faults;

// One RefGo line over TCP (the trace must show it as a client sent it).
function refgoTcp(line) {
  return new Promise((resolve, reject) => {
    const s = net.connect(emu.ports.refgo, '127.0.0.1', () => s.write(line));
    let got = '';
    s.on('data', (d) => {
      got += d;
      if (got.endsWith('>')) {
        s.end();
        resolve(got);
      }
    });
    s.on('error', reject);
    setTimeout(() => {
      s.destroy();
      resolve(got);
    }, 2000);
  });
}

test('faults: a button per cause, Fault Reset, custom EMCY, injections with Remove (§5.9)', async () => {
  await reset();
  const g = await openPage(browser, emu, '/emulator.html');
  const { page } = g;
  assert.equal(await page.locator('#emu-fault-buttons button').count(), 14);
  assert.equal(await page.locator('#emu-fault-stroke').textContent(), '7121h ERROR_STROKE');

  await emu.refgo('PWC');
  await page.locator('#emu-fault-stroke').click();
  await waitFor(async () => (await footerOf(page)).live === 'MC Live ERR 7121h', { what: 'ERR 7121h' });
  const [f] = await faults();
  assert.equal(f.kind, 'drive.inject');
  await waitFor(async () => (await page.locator(`#emu-injection-${f.id}`).count()) === 1, { what: 'the injection listed' });
  assert.match(await page.locator(`#emu-injection-${f.id}`).textContent(), /drive\.inject.*cause=stroke/);
  // the green LED announces the fault for the next repetition
  await waitFor(async () => (await page.locator('#emu-morse-next').textContent()) === 'MC+IP192+168+2+150+ERR7121:', { what: 'nextText with ERR7121' });

  await page.locator(`#emu-remove-${f.id}`).click();
  await waitFor(async () => (await faults()).length === 0 && (await page.locator(`#emu-injection-${f.id}`).count()) === 0, { what: 'removed' });
  assert.equal((await status()).state, 'F', 'a raised fault stays until a fault reset');
  await page.locator('#emu-faultreset').click();
  await waitFor(async () => (await status()).state === 'SOD', { what: 'fault reset → SOD' });
  await waitFor(async () => (await footerOf(page)).live === 'MC Live OFF', { what: 'MC Live OFF' });

  // a custom EMCY of no cause: one EMCY, no fault (recorded on the api trace channel)
  await page.locator('#emu-emcy-code').fill('FF00');
  await page.locator('#emu-emcy-send').click();
  await waitFor(async () => (await page.locator('#emu-emcy-result').textContent()) === 'EMCY FF00 sent', { what: 'EMCY sent' });
  assert.equal((await status()).state, 'SOD');
  const trace = await emu.get('/api/v1/trace?channels=api&limit=50');
  assert.ok(trace.events.some((e) => /drive\.emcy/.test(e.text) && /FF00/i.test(e.text)), 'drive.emcy on the api channel');

  // a transport fault with fields; Remove all
  await page.locator('#emu-tf-kind').selectOption('http.error');
  assert.equal(await page.locator('#emu-tf-status').isVisible(), true);
  assert.equal(await page.locator('#emu-tf-ms').isVisible(), false);
  await page.locator('#emu-tf-status').fill('503');
  await page.locator('#emu-tf-path').fill('/nowhere.html');
  await page.locator('#emu-tf-count').fill('2');
  await page.locator('#emu-tf-add').click();
  await waitFor(async () => (await faults()).some((x) => x.kind === 'http.error' && x.status === 503 && x.path === '/nowhere.html'), { what: 'http.error injected' });
  await page.locator('#emu-sensor_warning, #emu-fault-sensor_warning').first().click();
  await waitFor(async () => (await faults()).length === 2, { what: 'two injections' });
  await page.locator('#emu-remove-all').click();
  await waitFor(async () => (await faults()).length === 0, { what: 'all removed' });
  await waitFor(async () => (await page.locator('#emu-injections tbody').textContent()) === 'none', { what: 'list empty' });
  g.assertClean();
  await g.close();
});

test('wiring, plant sliders and a mechanical stop (§5.9)', async () => {
  await reset();
  const g = await openPage(browser, emu, '/emulator.html');
  const { page } = g;
  // MC349 has pins IN1–IN4 only
  for (let n = 1; n <= 10; n++) assert.equal(await page.locator(`#emu-in-${n}`).isDisabled(), n > 4, `IN${n}`);
  await page.locator('#emu-in-2').check();
  await waitFor(async () => (await emu.get('/api/v1/io')).physical === 0x20000, { what: 'IN2 wire high' });
  await waitFor(async () => (await footerOf(page)).io === 'I.2........O....', { what: 'footer I.2' });
  assert.equal((await emu.get('/api/v1/objects/3510/1')).value, 0, 'not a virtual input');
  await page.locator('#emu-in-2').uncheck();
  await waitFor(async () => (await emu.get('/api/v1/io')).physical === 0, { what: 'IN2 wire low' });

  // supply slider: one drive.supply injection, replaced on every change, removed by Nominal
  await waitFor(async () => (await page.locator('#emu-supply-value').textContent()) === '48 V (nominal)', { what: 'nominal supply' });
  await page.locator('#emu-supply').fill('30');
  await waitFor(async () => (await faults()).filter((x) => x.kind === 'drive.supply').map((x) => x.volts).join() === '30', { what: 'supply 30 V' });
  await page.locator('#emu-supply').fill('12');
  await waitFor(async () => (await faults()).filter((x) => x.kind === 'drive.supply').map((x) => x.volts).join() === '12', { what: 'supply 12 V replaces 30 V' });
  await waitFor(async () => (await status()).lastError?.text === '3221h / ERROR_UNDER_VOLT', { what: 'under-voltage' });
  await page.locator('#emu-supply-reset').click();
  await waitFor(async () => (await faults()).length === 0, { what: 'supply nominal again' });
  await page.locator('#emu-ambient').fill('60');
  await waitFor(async () => (await faults()).some((x) => x.kind === 'drive.ambient' && x.celsius === 60), { what: 'ambient 60 °C' });
  await page.locator('#emu-ambient-reset').click();
  await waitFor(async () => (await faults()).length === 0, { what: 'ambient back' });

  // a mechanical stop at +20000 inc blocks a move to 100000
  await emu.api('PUT', '/api/v1/objects/6040h/0', { value: 0 });
  await emu.api('PUT', '/api/v1/objects/6040h/0', { value: 0x80 });
  await page.locator('#emu-stop-pos').fill('20000');
  await page.locator('#emu-stop-add').click();
  await waitFor(async () => (await faults()).some((x) => x.kind === 'drive.obstacle' && x.positionInc === 20000), { what: 'stop added' });
  await emu.refgo('PWC');
  await emu.refgo('G100000');
  await waitFor(async () => {
    const s = await status();
    return s.posInc < 21000 && s.posInc > 15000 && s.velUser === 0;
  }, { timeout: 10000, what: 'blocked at the stop' });
  await page.locator('#emu-remove-all').click();
  await waitFor(async () => (await faults()).length === 0, { what: 'stop removed' });
  await emu.refgo('PQ');
  g.assertClean();
  await g.close();
});

test('console, trace with filters, settings, power cycle, about (§5.9)', async () => {
  await reset();
  const g = await openPage(browser, emu, null);
  const { page } = g;
  // the page's WebSocket goes through the test, which can add messages of its own
  let inject = () => assert.fail('no WebSocket');
  await page.routeWebSocket(/\/api\/v1\/ws$/, (ws) => {
    ws.connectToServer();
    inject = (m) => ws.send(JSON.stringify(m));
  });
  await g.goto('/emulator.html');
  const info = await emu.get('/api/v1/info');
  assert.equal(await page.locator('#emu-about-state').textContent(), info.stateDir);
  assert.match(await page.locator('#emu-about-ports').textContent(), new RegExp(`RefGo ${info.ports.refgo}, SLCAN ${info.ports.slcan}, HTTP ${info.ports.http}, UDP ${info.ports.udp}`));
  assert.equal(await page.locator('#emu-about-script').textContent(), info.scripting.available ? info.scripting.engine : 'not available in this version');
  // the console has the boot messages
  await waitFor(async () => (await page.locator('#emu-console').textContent()).includes('IP Address: 192.168.2.150'), { what: 'boot messages in the console' });

  // trace: the api channel carries this test's writes; the http channel is off by default
  await emu.refgo('TP');
  await waitFor(async () => (await page.locator('#emu-trace div[data-channel="api"]', { hasText: 'refgo "TP"' }).count()) > 0, { what: 'refgo "TP" on the api channel' });
  assert.equal(await page.locator('#emu-trace div[data-channel="http"]').count(), 0, 'http off by default');
  // filter: without api, new api events stay out; with it again, they are back (from the ring)
  await page.locator('#emu-trace-ch-api').uncheck();
  await waitFor(async () => (await page.locator('#emu-trace div[data-channel="api"]').count()) === 0, { what: 'api filtered out' });
  await emu.api('PUT', '/api/v1/objects/6081h/0', { value: 1111 });
  await page.waitForTimeout(300);
  assert.equal(await page.locator('#emu-trace div[data-channel="api"]').count(), 0);
  await page.locator('#emu-trace-ch-http').check();
  await waitFor(async () => (await page.locator('#emu-trace div[data-channel="http"]', { hasText: 'GET /api/v1/' }).count()) > 0, { what: 'http events' });
  // the pages' own polling (X-Mcemu-Poll, web.md §8.6) is left out while "hide the pages' polling"
  // is checked: the server has traced the page's GET /api/v1/io polls, the view shows none of them
  assert.equal(await page.locator('#emu-trace-polling').isChecked(), true, 'hidden by default');
  const polls = async () => (await emu.get('/api/v1/trace?channels=http&limit=10000')).events.filter((e) => e.polling && e.text === 'GET /api/v1/io');
  const before = (await polls()).length;
  await waitFor(async () => (await polls()).length > before, { what: 'a poll of /api/v1/io traced after the check' });
  await emu.get('/api/v1/clock');  // a request of the test's own after it: the view has caught up once it shows
  await waitFor(async () => (await page.locator('#emu-trace div[data-channel="http"]', { hasText: 'GET /api/v1/clock' }).count()) > 0, { what: 'the test\'s own request' });
  const shown = new Set(await page.locator('#emu-trace div[data-channel="http"]').evaluateAll((rows) => rows.map((r) => r.dataset.seq)));
  const hidden = (await polls()).map((e) => String(e.seq));
  assert.ok(hidden.length > 0);
  assert.deepEqual(hidden.filter((seq) => shown.has(seq)), [], 'no polling shown');
  assert.equal(await page.locator('#emu-trace div[data-channel="http"]', { hasText: '[polling]' }).count(), 0);
  await page.locator('#emu-trace-polling').uncheck();
  await waitFor(async () => (await page.locator('#emu-trace div[data-channel="http"]', { hasText: /GET \/api\/v1\/io \[polling\]$/ }).count()) > 0, { what: 'the polling shown when asked for' });
  await screenshot(page, 'emulator-trace-polling');
  await page.locator('#emu-trace-polling').check();
  await waitFor(async () => (await page.locator('#emu-trace div[data-channel="http"]', { hasText: '[polling]' }).count()) === 0, { what: 'hidden again' });
  await page.locator('#emu-trace-ch-http').uncheck();
  await page.locator('#emu-trace-ch-api').check();
  await waitFor(async () => (await page.locator('#emu-trace div[data-channel="api"]', { hasText: '6081h.00h = 1111' }).count()) > 0, { what: 'api back' });
  // pause holds new events
  await page.locator('#emu-trace-pause').click();
  const rows = await page.locator('#emu-trace div').count();
  await emu.refgo('TV');
  await waitFor(async () => /new events held/.test(await page.locator('#emu-trace-state').textContent()), { what: 'events held while paused' });
  assert.equal(await page.locator('#emu-trace div').count(), rows);
  await page.locator('#emu-trace-pause').click();
  await waitFor(async () => (await page.locator('#emu-trace div').count()) > rows, { what: 'held events shown' });
  // a RefGo line as a client sent it, CR and all, arrives on the WebSocket: control bytes marked
  const last = Number(await page.locator('#emu-trace div').last().getAttribute('data-seq'));
  inject({ type: 'trace', events: [{ seq: last + 0.5, timeMs: 1, wall: '', channel: 'refgo', dir: 'rx', conn: 7, peer: '127.0.0.1:1', text: 'OR6041,0,h\r\n\u0007' }] });
  const row = page.locator('#emu-trace div[data-channel="refgo"]', { hasText: 'OR6041,0,h' });
  await waitFor(async () => (await row.count()) === 1, { what: 'the refgo line' });
  assert.deepEqual(await row.locator('.ctl').allTextContents(), ['<CR>', '<LF>', '<07>']);
  assert.equal(await row.textContent(), '1 refgo rx #7 OR6041,0,h<CR><LF><07>');
  // and a real TCP client's line as the server traced it: "TP" and its CR
  await refgoTcp('TP\r');
  const tcp = page.locator('#emu-trace div.trace-rx[data-channel="refgo"]', { hasText: /^\d+ refgo rx #\d+ TP<CR>$/ });
  await waitFor(async () => (await tcp.count()) > 0, { what: 'the TCP client\'s TP<CR> on the refgo channel' });
  assert.deepEqual(await tcp.last().locator('.ctl').allTextContents(), ['<CR>']);

  // settings
  await page.locator('#emu-set-udpEmulatorNotes').check();
  await waitFor(async () => (await emu.get('/api/v1/settings')).udpEmulatorNotes === true, { what: 'udpEmulatorNotes on' });
  await page.locator('#emu-set-scriptMemoryMiB').fill('64');
  await page.locator('#emu-set-scriptMemoryMiB').press('Enter');
  await page.locator('#emu-set-scriptMemoryMiB').blur();
  await waitFor(async () => (await emu.get('/api/v1/settings')).scriptMemoryMiB === 64, { what: 'scriptMemoryMiB 64' });
  // with notes on, an injection is a console line (live over the WebSocket)
  await page.locator('#emu-fault-sensor_warning').click();
  await waitFor(async () => /mcemu: fault injection/.test(await page.locator('#emu-console').textContent()), { what: 'UDP note in the console' });
  await page.locator('#emu-remove-all').click();

  // power cycle: Cancel does nothing, OK cycles (the boot messages again, drive time from 0)
  const t0 = (await status()).timeMs;
  let asked = answerNextDialog(g, false);
  await page.locator('#emu-powercycle').click();
  assert.equal(await asked, 'Power cycle the drive - Are you sure?');
  await page.waitForTimeout(200);
  assert.ok((await status()).timeMs >= t0);
  const bootLines = (await page.locator('#emu-console').textContent()).split('IP Address').length;
  asked = answerNextDialog(g, true);
  await page.locator('#emu-powercycle').click();
  await asked;
  await waitFor(async () => (await page.locator('#emu-powercycle-result').textContent()) === 'powered up again', { what: 'powered up' });
  assert.ok((await status()).timeMs < t0, 'drive time started again');
  await waitFor(async () => (await page.locator('#emu-console').textContent()).split('IP Address').length > bootLines, { what: 'boot messages again' });
  await waitFor(async () => (await footerOf(page)).live === 'MC Live OFF', { what: 'footer after the power cycle' });
  await page.locator('#console').evaluate((el) => el.scrollIntoView());
  await screenshot(page, 'emulator-console-trace');
  g.assertClean();
  await g.close();
});
