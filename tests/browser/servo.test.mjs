// web.md §11 item 5: Servo — Set Home (Pos=0) makes 6064h = 0; the gear fields write 6091h/6092h;
// the scope's window.mcScope.sampleCount grows while a move runs and the canvas is not blank; plus
// the scope's controls: pause, zoom, cursor read-out, show/hide, CSV.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { readFile } from 'node:fs/promises';
import { startEmulator, launchBrowser, openPage, waitFor, screenshot } from './harness.mjs';

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
// at a target: the position loop holds it within an increment or so
const near = (pos, target) => Math.abs(pos - target) <= 2;

// Pixels of the canvas in the position trace's colour (#1f6fb2), and a hash of all pixels.
const canvasStats = (page) =>
  page.evaluate(() => {
    const c = document.getElementById('sv-scope');
    const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    let blue = 0;
    let hash = 0;
    for (let i = 0; i < d.length; i += 4) {
      if (Math.abs(d[i] - 0x1f) < 24 && Math.abs(d[i + 1] - 0x6f) < 24 && Math.abs(d[i + 2] - 0xb2) < 24) blue++;
      hash = (hash * 31 + d[i] + d[i + 1] * 7 + d[i + 2] * 13) | 0;
    }
    return { blue, hash };
  });

test('Set Home, gear fields and the live scope (§11.5)', async (t) => {
  const g = await openPage(browser, emu, '/servo.html', { acceptDownloads: true });
  const { page } = g;
  assert.equal(await page.locator('h1').textContent(), 'MovingCap Servo Startup (CiA 402)');
  assert.match(await page.locator('#sv-accunit').textContent(), /1 unit = 100 motor rev\/min²/);

  await emu.refgo('PWC');
  await emu.refgo('G300000');
  const before = await page.evaluate(() => window.mcScope.sampleCount);
  await waitFor(async () => near((await status()).posUser, 300000), { timeout: 10000, what: 'at 300000' });
  const during = await page.evaluate(() => window.mcScope.sampleCount);
  assert.ok(during - before >= 20, `scope samples grew by ${during - before} during the move`);
  await waitFor(async () => near(await page.evaluate(() => window.mcScope.lastSample.pos), 300000), { what: 'the scope shows the end position' });
  await page.waitForTimeout(100);
  const drawn = await canvasStats(page);
  assert.ok(drawn.blue > 200, `the position trace is drawn (${drawn.blue} px)`);

  // cursor read-out under the mouse
  await page.locator('#sv-scope-box').evaluate((el) => el.scrollIntoView({ block: 'center' }));
  const box = await page.locator('#sv-scope').boundingBox();
  await page.mouse.move(box.x + box.width - 140, box.y + box.height / 2);
  await waitFor(async () => /pos \d+/.test(await page.locator('#sv-scope-readout').textContent()), { what: 'cursor read-out' });
  await screenshot(page, 'servo-scope');
  // zoom: the window select and the wheel
  await page.locator('#sv-scope-window').selectOption('2');
  assert.equal(await page.evaluate(() => window.mcScope.windowMs), 2000);
  await page.mouse.wheel(0, 200);
  assert.equal(await page.evaluate(() => window.mcScope.windowMs), 5000, 'wheel down widens the window');
  await page.mouse.move(0, 0);

  // Pause freezes the display, not the sampling
  await page.locator('#sv-scope-pause').click();
  assert.equal(await page.evaluate(() => window.mcScope.paused), true);
  await page.waitForTimeout(100);
  const frozen = await canvasStats(page);
  const n0 = await page.evaluate(() => window.mcScope.sampleCount);
  await emu.refgo('G0');
  await page.waitForTimeout(600);
  assert.ok((await page.evaluate(() => window.mcScope.sampleCount)) > n0 + 50, 'sampling goes on while paused');
  assert.equal((await canvasStats(page)).hash, frozen.hash, 'the paused display does not change');
  await page.locator('#sv-scope-pause').click();
  await waitFor(async () => (await canvasStats(page)).hash !== frozen.hash, { what: 'Run draws again' });

  // hiding every analogue channel leaves no position trace
  await page.locator('#sv-scope-show-pos').uncheck();
  await page.locator('#sv-scope-show-target').uncheck();
  await page.waitForTimeout(100);
  assert.ok((await canvasStats(page)).blue < 40, 'position hidden');
  await page.locator('#sv-scope-show-pos').check();

  // CSV of the buffered samples
  const [download] = await Promise.all([page.waitForEvent('download'), page.locator('#sv-scope-csv').click()]);
  const csv = await readFile(await download.path(), 'utf8');
  const lines = csv.trim().split('\n');
  assert.equal(lines[0], 'timeMs,pos,vel,cur,target,moving,reached');
  assert.ok(lines.length > 500, `${lines.length} CSV lines`);
  assert.ok(lines.slice(1).some((l) => near(Number(l.split(',')[1]), 300000)), 'the move is in the CSV');
  const row = lines[lines.length - 1].split(',').map(Number);
  assert.equal(row.length, 7);
  assert.ok(row.every((v) => Number.isFinite(v)));
  assert.ok(lines.slice(2).every((l, i) => Number(l.split(',')[0]) > Number(lines[i + 1].split(',')[0])), 'timeMs increases');

  // Set Home (Pos=0): REF35 makes 6064h = 0
  await waitFor(async () => near((await status()).posUser, 0), { timeout: 10000, what: 'back at 0' });
  await emu.refgo('G12345');
  await waitFor(async () => near((await status()).posUser, 12345), { timeout: 10000, what: 'at 12345' });
  await page.locator('#sv-sethome').click();
  await waitFor(async () => (await object('6064', 0)) === 0, { what: '6064h = 0 after Set Home' });
  await waitFor(async () => /REF35/.test(await page.locator('#sv-sethome-result').textContent()), { what: 'Set Home result' });

  // Gear & Axis Configuration writes 6091h.01/.02 and 6092h.01
  for (const [id, index, sub, value] of [['sv-gearin', '6091', 1, 5], ['sv-gearout', '6091', 2, 2], ['sv-feed', '6092', 1, 360]]) {
    await page.locator(`#${id}`).fill(String(value));
    await page.locator(`#${id}`).press('Enter');
    await waitFor(async () => (await object(index, sub)) === value, { what: `${index}h.${sub} = ${value}` });
  }
  t.diagnostic(`scope samples: ${await page.evaluate(() => window.mcScope.sampleCount)}`);
  g.assertClean();
  await g.close();
});
