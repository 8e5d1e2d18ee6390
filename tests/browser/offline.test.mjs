// web.md §11 item 11: the embedded assets reference no other host (only XML namespace names), and
// the UI works with no network but loopback: offline.sh runs this file in a network namespace
// whose only interface is lo (MCEMU_NETNS=1; outside one the test refuses to pass).
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { readdirSync, readFileSync, statSync } from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { startEmulator, launchBrowser, openPage, waitFor, footerOf, PAGES } from './harness.mjs';

const UI = path.join(path.dirname(fileURLToPath(import.meta.url)), '../../web/ui');

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

function files(dir) {
  return readdirSync(dir).flatMap((n) => {
    const p = path.join(dir, n);
    return statSync(p).isDirectory() ? files(p) : [p];
  });
}

test('the only network is loopback', () => {
  assert.equal(process.env.MCEMU_NETNS, '1', 'run through offline.sh (a network namespace with loopback only)');
  // /proc/self/net/dev lists the interfaces of this process's network namespace
  const names = readFileSync('/proc/self/net/dev', 'utf8').split('\n').slice(2).filter(Boolean).map((l) => l.split(':')[0].trim());
  assert.deepEqual(names, ['lo']);
});

test('no asset references another host; what is served is what is in web/ui', async () => {
  const all = files(UI);
  assert.ok(all.length >= 20, `${all.length} files under web/ui`);
  let total = 0;
  for (const file of all) {
    const rel = '/' + path.relative(UI, file).split(path.sep).join('/');
    const bytes = readFileSync(file);
    total += bytes.length;
    const text = bytes.toString('utf8');
    for (const m of text.matchAll(/https?:\/\/[^\s"'<>)`]*/gi)) {
      assert.ok(m[0].startsWith('http://www.w3.org/'), `${rel}: ${m[0]}`);
    }
    assert.doesNotMatch(text, /(src|href)\s*=\s*["']\/\//i, `${rel}: protocol-relative URL`);
    assert.doesNotMatch(text, /@import|url\(\s*["']?(https?:)?\/\//i, `${rel}: external style resource`);
    if (!rel.endsWith('.html')) {
      const served = Buffer.from(await (await fetch(emu.base + rel)).arrayBuffer());
      assert.ok(served.equals(bytes), `${rel} is served as in the tree`);
    }
  }
  assert.ok(total <= 1024 * 1024, `assets ${total} bytes ≤ 1 MiB`);
});

test('every page works offline: live footer, WebSocket, a move on the scope, no other host', async () => {
  const g = await openPage(browser, emu, null);
  const { page } = g;
  for (const [p] of PAGES) {
    await g.goto(p);
    assert.equal(await page.evaluate(() => window.mcLive.mode), 'ws', `${p}: WebSocket`);
  }
  await g.goto('/clickrun.html');
  await page.locator('#cr-poweron').click();
  await waitFor(async () => (await footerOf(page)).live === 'MC Live RDY', { what: 'RDY' });
  await page.locator('#cr-target').fill('100000');
  await page.locator('#cr-moveabs').click();
  await waitFor(async () => page.evaluate(() => window.mcScope.lastSample && window.mcScope.lastSample.pos > 0), { what: 'the move on the scope' });
  const foreign = g.requests.filter((u) => !u.startsWith(emu.base) && !u.startsWith(`ws://${emu.host}/`));
  assert.deepEqual(foreign, []);
  assert.ok(g.requests.length > 50, `${g.requests.length} requests, all to ${emu.host}`);
  g.assertClean();
  await g.close();
});
