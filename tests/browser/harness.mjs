// Browser tests of mcemu's web UI (web.md §11): the real mcemu binary on 127.0.0.1 with every port 0,
// Debian's /usr/bin/chromium driven by playwright-core (nothing downloads a browser).
//
// Every page a test opens is guarded: a JavaScript error, a console error, a failed request, an HTTP
// error status that the test did not announce, or a request to any host but the emulator's is
// recorded, and guard.assertClean() (called by the tests at the end of each case) fails on it.
import { spawn } from 'node:child_process';
import { mkdtempSync, mkdirSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import assert from 'node:assert/strict';
import { chromium } from 'playwright-core';

const here = path.dirname(fileURLToPath(import.meta.url));
export const MCEMU = process.env.MCEMU_BIN || path.join(here, '../../build/server/mcemu');
export const CHROMIUM = process.env.MCEMU_CHROMIUM || '/usr/bin/chromium';
export const SCREENSHOT_DIR = process.env.MCEMU_SCREENSHOT_DIR || path.join(here, '../../build/browser-screenshots');
const LISTEN_RE = /listening: (\w+) (tcp|udp) ([^ ]+):(\d+)/;

export const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

// Polls fn until it returns a truthy value (returned) or the time is up (throws with `what`, a text
// or a function giving one).
export async function waitFor(fn, { timeout = 5000, interval = 20, what = 'condition' } = {}) {
  const end = Date.now() + timeout;
  let last;
  for (;;) {
    try {
      last = await fn();
      if (last) return last;
    } catch (e) {
      last = e;
    }
    if (Date.now() > end) throw new Error(`timed out after ${timeout} ms waiting for ${typeof what === 'function' ? what() : what} (last: ${last instanceof Error ? last.message : JSON.stringify(last)})`);
    await sleep(interval);
  }
}

// One mcemu process. await emu.stop() at the end (kills it and removes its state directory).
export async function startEmulator({ args = [], stateDir = null } = {}) {
  const tmp = mkdtempSync(path.join(tmpdir(), 'mcemu-browser-'));
  const dir = stateDir || path.join(tmp, 'state');
  const proc = spawn(MCEMU, ['--state-dir', dir, '--refgo-port', '0', '--slcan-port', '0', '--http-port', '0', '--udp-port', '0', ...args], { stdio: ['ignore', 'ignore', 'pipe'] });
  const lines = [];
  const ports = {};
  let ready = false;
  let exited = null;
  let buffer = '';
  proc.stderr.setEncoding('utf8');
  proc.stderr.on('data', (chunk) => {
    buffer += chunk;
    let nl;
    while ((nl = buffer.indexOf('\n')) >= 0) {
      const line = buffer.slice(0, nl);
      buffer = buffer.slice(nl + 1);
      lines.push(line);
      const m = LISTEN_RE.exec(line);
      if (m) ports[m[1]] = Number(m[4]);
      if (/ ready( |$)/.test(line)) ready = true;
    }
  });
  proc.on('exit', (code, signal) => (exited = { code, signal }));
  await waitFor(() => ready || exited, { timeout: 15000, what: 'mcemu ready' });
  if (exited) throw new Error(`mcemu exited at start-up (${JSON.stringify(exited)}):\n${lines.join('\n')}`);
  const base = `http://127.0.0.1:${ports.http}`;
  return {
    proc,
    ports,
    base,
    host: `127.0.0.1:${ports.http}`,
    stateDir: dir,
    log: () => lines.join('\n'),
    async api(method, p, body) {
      const init = { method, headers: {} };
      if (body !== undefined) {
        init.headers['Content-Type'] = 'application/json';
        init.body = JSON.stringify(body);
      }
      const r = await fetch(base + p, init);
      const text = await r.text();
      const data = (r.headers.get('content-type') || '').includes('json') && text ? JSON.parse(text) : text;
      if (!r.ok) throw new Error(`${method} ${p} → ${r.status}: ${text}`);
      return data;
    },
    get: function (p) {
      return this.api('GET', p);
    },
    refgo: function (line) {
      return this.api('POST', '/api/v1/refgo', { line });
    },
    async stop() {
      if (!exited) {
        proc.kill('SIGTERM');
        await waitFor(() => exited, { timeout: 5000, what: 'mcemu exit' }).catch(() => proc.kill('SIGKILL'));
      }
      rmSync(tmp, { recursive: true, force: true });
    },
  };
}

export async function launchBrowser() {
  return chromium.launch({
    executablePath: CHROMIUM,
    // --no-sandbox: CI runs as root, where Chromium's sandbox refuses to start.
    args: ['--no-sandbox', '--disable-gpu', '--disable-dev-shm-usage', '--no-first-run', '--disable-background-networking'],
  });
}

// A new page (own context) guarded against errors and foreign hosts. allow: [{url: RegExp, status}]
// HTTP error answers the test expects; allowConsole: RegExps of console errors it expects.
export async function openPage(browser, emu, target = '/', { viewport = { width: 1280, height: 800 }, allow = [], allowConsole = [], acceptDownloads = false } = {}) {
  const context = await browser.newContext({ viewport, acceptDownloads });
  const page = await context.newPage();
  const problems = [];
  const requests = [];
  // A request of a document that is being replaced is cancelled by the browser (ERR_ABORTED). Such
  // a failure is excused when a main-frame navigation started or committed between the request and
  // 2 s after its failure (judged in assertClean, as the events may arrive in either order).
  const navTimes = [];
  const issued = new WeakMap();
  const aborted = [];
  page.on('framenavigated', (f) => {
    if (f === page.mainFrame()) navTimes.push(Date.now());
  });
  const foreign = (url) => {
    const u = new URL(url);
    if (u.protocol === 'blob:' || u.protocol === 'data:' || url === 'about:blank') return false;
    return u.host !== emu.host;
  };
  page.on('request', (r) => {
    issued.set(r, Date.now());
    if (r.isNavigationRequest() && r.frame() === page.mainFrame()) navTimes.push(Date.now());
    requests.push(r.url());
    if (foreign(r.url())) problems.push(`request to another host: ${r.url()}`);
  });
  page.on('websocket', (ws) => {
    requests.push(ws.url());
    if (foreign(ws.url())) problems.push(`WebSocket to another host: ${ws.url()}`);
  });
  page.on('pageerror', (e) => problems.push(`JavaScript error on ${page.url()}: ${e.stack || e.message}`));
  page.on('console', (m) => {
    if (m.type() !== 'error') return;
    const text = m.text();
    // An HTTP error answer is logged by Chromium as "Failed to load resource"; 'response' judges it.
    if (/^Failed to load resource: the server responded with a status of/.test(text)) return;
    if (allowConsole.some((re) => re.test(text))) return;
    problems.push(`console error on ${page.url()}: ${text}`);
  });
  page.on('requestfailed', (r) => {
    const failure = r.failure() ? r.failure().errorText : 'failed';
    const text = `request failed: ${r.method()} ${r.url()} (${failure})`;
    if (failure === 'net::ERR_ABORTED') aborted.push({ from: issued.get(r) ?? 0, to: Date.now(), text });
    else problems.push(text);
  });
  page.on('response', (r) => {
    if (r.status() < 400) return;
    const expected = allow.some((a) => a.url.test(r.url()) && (a.status === undefined || a.status === r.status()));
    if (!expected) problems.push(`HTTP ${r.status()} for ${r.request().method()} ${r.url()}`);
  });
  page.on('dialog', (d) => problems.push(`unexpected dialog: ${d.type()} "${d.message()}"`));
  const guard = {
    page,
    context,
    problems,
    requests,
    allow,
    assertClean() {
      const unexplained = aborted.filter((a) => !navTimes.some((t) => t >= a.from - 5 && t <= a.to + 2000)).map((a) => a.text);
      const all = [...problems, ...unexplained];
      assert.deepEqual(all, [], `the page had problems:\n${all.join('\n')}`);
    },
    // Loads a page of the emulator and waits until its footer is live.
    async goto(p) {
      const res = await page.goto(emu.base + p);
      assert.equal(res.status(), 200, `GET ${p}`);
      await waitForLive(page);
    },
    async close() {
      await context.close();
    },
  };
  if (target !== null) await guard.goto(target);
  return guard;
}

// The page has its live footer going (first status message shown).
export async function waitForLive(page) {
  await page.waitForFunction(() => window.mcLive && window.mcLive.statusCount > 0, null, { timeout: 10000 });
}

// The next confirm() of the page is answered with `accept`; resolves with its message.
export function answerNextDialog(guard, accept) {
  return new Promise((resolve) => {
    guard.page.removeAllListeners('dialog');
    guard.page.once('dialog', async (d) => {
      const message = d.message();
      if (accept) await d.accept();
      else await d.dismiss();
      guard.page.on('dialog', (x) => guard.problems.push(`unexpected dialog: ${x.type()} "${x.message()}"`));
      resolve(message);
    });
  });
}

export async function screenshot(page, name) {
  mkdirSync(SCREENSHOT_DIR, { recursive: true });
  await page.screenshot({ path: path.join(SCREENSHOT_DIR, `${name}.png`) });
}

export const PAGES = [
  ['/index.html', 'info'],
  ['/clickrun.html', 'clickrun'],
  ['/servo.html', 'servo'],
  ['/ioin.html', 'ioin'],
  ['/ioout.html', 'ioout'],
  ['/command.html', 'command'],
  ['/program.html', 'program'],
  ['/network.html', 'network'],
  ['/emulator.html', 'emulator'],
];

// The footer texts of the page, by field.
export async function footerOf(page) {
  return page.evaluate(() => Object.fromEntries(['live', 'statwd', 'opmode', 'python', 'pos', 'vel', 'temp', 'io'].map((k) => [k, document.getElementById(`ft-${k}`).textContent])));
}
