// web.md §11 item 10 (morse-led.md §7.7): #led-green[data-on], sampled every 10 ms in the page,
// decodes within at most 2 × cycleMs of sampling to a character stream that contains the Morse
// text; the run lengths are the schedule's element lengths (the page blinks from the schedule, not
// at the 20 Hz of the status stream). The Emulator page shows the text and a running decode.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { startEmulator, launchBrowser, openPage, waitFor } from './harness.mjs';

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

// ITU Morse, the test's own table (morse-led.md §4)
const MORSE = { '--': 'M', '-.-.': 'C', '.-.-.': '+', '..': 'I', '.--.': 'P', '-----': '0', '.----': '1', '..---': '2', '...--': '3', '....-': '4', '.....': '5', '-....': '6', '--...': '7', '---..': '8', '----.': '9', '---...': ':', '.': 'E', '.-.': 'R', '.-': 'A', '-...': 'B', '-..': 'D', '..-.': 'F' };

// runs [[on, ms], …] → text; on ≤ 2T dot else dash; off ≥ 2T ends a character (≥ 5T a word).
// The first runs up to the first character gap are skipped (sampling starts at a random phase).
function decode(runs, unit) {
  let out = '';
  let symbol = '';
  let synced = false;
  for (const [on, ms] of runs) {
    if (on) {
      symbol += ms <= 2 * unit ? '.' : '-';
    } else if (ms >= 2 * unit) {
      if (synced) out += MORSE[symbol] ?? '?';
      if (synced && ms >= 5 * unit) out += ' ';
      symbol = '';
      synced = true;
    }
  }
  return out;
}

test('the header LED sends the Morse text with the exact element lengths (§11.10)', async (t) => {
  const led = await emu.get('/api/v1/led');
  const { text, cycleMs, unitMs } = led.green;
  assert.equal(text, 'MC+IP192+168+2+150:');
  const g = await openPage(browser, emu, '/index.html');
  const { page } = g;
  // the schedule is fetched once the first status arrived; sample from then on
  await page.waitForFunction(() => document.getElementById('led-green').dataset.on !== undefined);
  await page.evaluate(() => {
    const el = document.getElementById('led-green');
    window.ledRuns = [];
    window.ledStalls = []; // sampler ticks more than 60 ms apart: the page's main thread was held up
    let state = el.dataset.on;
    let since = performance.now();
    let last = since;
    setInterval(() => {
      const now = performance.now();
      if (now - last > 60) window.ledStalls.push(Math.round(now - last));
      last = now;
      if (el.dataset.on !== state) {
        window.ledRuns.push([state === '1', now - since]);
        state = el.dataset.on;
        since = now;
      }
    }, 10);
  });
  const started = Date.now();
  let decoded = '';
  let stalls = [];
  await waitFor(async () => {
    stalls = await page.evaluate(() => window.ledStalls);
    decoded = decode(await page.evaluate(() => window.ledRuns), unitMs);
    return decoded.includes(text);
  }, {
    // web.md §11.10 asks for the text within 2 cycles; a main-thread stall of the page (a loaded CI
    // machine) can cost one element of a repetition, so the wait allows a third and the 2-cycle
    // bound is asserted below when the page ran without stalls over 100 ms
    timeout: 3 * cycleMs + 2000,
    interval: 500,
    what: () => `"${text}" in the decoded stream (so far "${decoded}"; main-thread stalls of the page > 60 ms: ${stalls.length ? stalls.join(', ') + ' ms — an overloaded machine' : 'none'})`,
  });
  t.diagnostic(`decoded "${decoded}" after ${((Date.now() - started) / 1000).toFixed(1)} s (cycle ${cycleMs / 1000} s)`);
  if (!stalls.some((ms) => ms > 100)) assert.ok(Date.now() - started <= 2 * cycleMs + 1000);

  // element lengths: 120 or 360 ms (on and off), measured with 10 ms sampling
  const runs = (await page.evaluate(() => window.ledRuns)).slice(1);
  const errors = runs.map(([, ms]) => Math.min(Math.abs(ms - unitMs), Math.abs(ms - 3 * unitMs))).sort((a, b) => a - b);
  const median = errors[Math.floor(errors.length / 2)];
  const p90 = errors[Math.floor(errors.length * 0.9)];
  t.diagnostic(`${runs.length} runs; deviation from 120/360 ms: median ${median.toFixed(1)} ms, 90% ${p90.toFixed(1)} ms`);
  assert.ok(median <= 12, `median deviation ${median} ms`);
  assert.ok(p90 <= 25, `90th percentile deviation ${p90} ms`);
  g.assertClean();
  await g.close();
});

test('the Emulator page shows the Morse text, a running decode and the cycle position', async () => {
  const g = await openPage(browser, emu, '/emulator.html');
  const { page } = g;
  await waitFor(async () => (await page.locator('#emu-morse-text').textContent()) === 'MC+IP192+168+2+150:', { what: 'Morse text' });
  assert.match(await page.locator('#emu-morse-pos').textContent(), /^element \d+ of 176, \d+\.\d\d s of 37\.20 s$/);
  const decoded = await waitFor(async () => {
    const d = await page.locator('#emu-morse-decode').textContent();
    return d.length >= 4 && d;
  }, { timeout: 15000, interval: 200, what: 'four decoded characters' });
  // '?' is a symbol the page could not decode (a stall of its main thread cut an element): it
  // stands for any one character of the text
  const pattern = new RegExp(decoded.replace(/[.*+^${}()|[\]\\]/g, '\\$&').replace(/\?/g, '.'));
  assert.ok(decoded.replace(/\?/g, '').length >= 3, `"${decoded}" has at least three decoded characters`);
  assert.ok(pattern.test('MC+IP192+168+2+150:MC+IP192+168+2+150:'), `"${decoded}" is part of the repeated text`);
  g.assertClean();
  await g.close();
});

test('under --clock manual the LED shows the schedule at the drive time, without extrapolating', async () => {
  const manual = await startEmulator({ args: ['--clock', 'manual'] });
  try {
    const g = await openPage(browser, manual, '/index.html');
    const { page } = g;
    const { green } = await manual.get('/api/v1/led');
    // the LED at drive time t from the schedule (morse-led.md §6.2)
    const expected = (t) => {
      let phase = (t - green.cycleStartMs) % green.cycleMs;
      let i = 0;
      while (phase >= green.elements[i]) phase -= green.elements[i++];
      return i % 2 === 0 ? '1' : '0';
    };
    // steps of 50 ms (some inside an element, some across edges); the page must follow each one
    let changes = 0;
    let last = await page.locator('#led-green').getAttribute('data-on');
    for (let k = 0; k < 24; k++) {
      const { timeMs } = await manual.api('POST', '/api/v1/clock/advance', { ms: 50 });
      await waitFor(async () => (await page.evaluate(() => window.mcLive.status.timeMs)) === timeMs, { what: `status at ${timeMs}` });
      await waitFor(async () => (await page.locator('#led-green').getAttribute('data-on')) === expected(timeMs), { what: `LED at ${timeMs} ms = ${expected(timeMs)}` });
      await page.waitForTimeout(60); // wall time passes, drive time does not: no change
      const now = await page.locator('#led-green').getAttribute('data-on');
      assert.equal(now, expected(timeMs), `still the state of ${timeMs} ms`);
      if (now !== last) changes++;
      last = now;
    }
    assert.ok(changes >= 3, `${changes} LED changes over 1.2 s of drive time`);
    g.assertClean();
    await g.close();
  } finally {
    await manual.stop();
  }
});
