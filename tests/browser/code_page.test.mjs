// web.md §11 item 9: the Code page with a real upload. Through the form's file chooser a script of
// the test's own (an #id line, a loop that keeps it running, a #private line followed by text) is
// uploaded; RUN → footer "Python RUN", code-status begins with "RUN ", the Viewer shows the id line
// and not the text after #private; ON → "ON [X]" and footer "Python RUN/A". Needs the script engine:
// where the server has none wired (info.scripting.available false or the script endpoints answer
// 503), this test FAILS with "script engine not wired" — it does not skip.
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

const SCRIPT = [
  '# a test script of mcemu\'s browser tests',
  '#id mcemu ui test 1',
  'import sys',
  'while True:',
  '    sys.wait(100)',
  '#private',
  'SECRET_AFTER_PRIVATE = "must not be shown"',
  '',
].join('\r\n');

test('Code page: upload through the form, RUN, Script Viewer with #private, autostart (§11.9)', async () => {
  const info = await emu.get('/api/v1/info');
  const probe = await fetch(emu.base + '/api/v1/script');
  await probe.text();
  if (!info.scripting || !info.scripting.available || probe.status === 503) {
    assert.fail(`script engine not wired: /api/v1/info scripting.available = ${info.scripting && info.scripting.available}, GET /api/v1/script → ${probe.status}`);
  }
  const g = await openPage(browser, emu, '/program.html');
  const { page } = g;
  assert.equal(await page.locator('#code-run').isDisabled(), false);

  // upload through the file chooser and the form's own POST /program.html
  const [chooser] = await Promise.all([page.waitForEvent('filechooser'), page.locator('#code-file').click()]);
  await chooser.setFiles({ name: 'mcemu_ui_test.py', mimeType: 'text/x-python', buffer: Buffer.from(SCRIPT) });
  const [upload] = await Promise.all([
    page.waitForResponse((r) => r.request().method() === 'POST' && new URL(r.url()).pathname === '/program.html'),
    page.locator('#code-upload').click(),
  ]);
  assert.equal(upload.status(), 200);
  await page.waitForLoadState('load');
  const script = await emu.get('/api/v1/script');
  assert.equal(script.id, 'mcemu ui test 1');
  assert.equal(script.length, Buffer.byteLength(SCRIPT));
  assert.equal(script.hasPrivate, true);
  await waitFor(async () => (await page.locator('#code-viewer').textContent()).includes('#id mcemu ui test 1'), { what: 'the id line in the Viewer' });
  const viewer = await page.locator('#code-viewer').textContent();
  assert.ok(viewer.includes('while True:'), viewer);
  assert.ok(!viewer.includes('SECRET_AFTER_PRIVATE') && !viewer.includes('#private'), `the Viewer hides #private and after: ${viewer}`);
  assert.equal(script.state, 'OFF', 'an upload does not start the script');

  // RUN: ?codeAct=3, then the address is /program.html again
  await page.locator('#code-run').click();
  await page.waitForURL((u) => u.pathname === '/program.html' && u.search === '');
  await waitFor(async () => (await footerOf(page)).python === 'Python RUN', { timeout: 10000, what: 'footer Python RUN' });
  await waitFor(async () => (await page.locator('#code-status').textContent()).startsWith('RUN '), { what: 'code-status RUN …' });
  assert.equal(await page.locator('#code-status').textContent(), 'RUN mcemu ui test 1');
  await waitFor(async () => /^~live\(.\)~$/.test(await page.locator('#code-live').textContent()), { what: 'the live marker' });

  // autostart ON
  await page.locator('#code-auto-on').click();
  await waitFor(async () => (await page.locator('#code-auto-on').textContent()) === 'ON [X]', { what: 'ON [X]' });
  assert.equal(await page.locator('#code-auto-off').textContent(), 'OFF');
  await waitFor(async () => (await footerOf(page)).python === 'Python RUN/A', { what: 'footer Python RUN/A' });
  await screenshot(page, 'program-running');

  // Pause/Break, Resume, Stop; a reload repeats nothing
  await page.locator('#code-pause').click();
  await waitFor(async () => (await footerOf(page)).python === 'Python BRK/A', { what: 'Python BRK/A' });
  await page.locator('#code-resume').click();
  await waitFor(async () => (await footerOf(page)).python === 'Python RUN/A', { what: 'resumed' });
  await page.locator('#code-stop').click();
  await waitFor(async () => (await footerOf(page)).python === 'Python OFF/A', { what: 'Python OFF/A' });
  await page.reload();
  await page.waitForTimeout(500);
  assert.equal((await emu.get('/api/v1/script')).state, 'OFF', 'the reload did not start it again');
  await page.locator('#code-auto-off').click();
  await waitFor(async () => (await page.locator('#code-auto-off').textContent()) === 'OFF [X]', { what: 'OFF [X]' });
  g.assertClean();
  await g.close();
});

// web.md §6.1, issue 23: a refused upload shows its error inside the page — in the upload section
// under the controls, below the menu bar and the heading — whether the page refuses it (no file
// chosen) or the server does (an empty file: 400 with the Code page and the note).
test('Code page: an upload error appears inside the page, under the upload controls (§6.1)', async () => {
  const g = await openPage(browser, emu, '/program.html', { allow: [{ url: /\/program\.html$/, status: 400 }] });
  const { page } = g;
  const note = page.locator('#code-error');
  // where it must be: inside <main>, inside the upload form after the file hint, below the menu bar
  const placed = async (what) => {
    assert.equal(await note.count(), 1, what);
    assert.ok(await note.isVisible(), what);
    const inForm = await note.evaluate((el) => !!el.closest('main #code-form') && !!(el.compareDocumentPosition(document.getElementById('code-file-hint')) & Node.DOCUMENT_POSITION_PRECEDING));
    assert.ok(inForm, `${what}: in the upload form, after the hint`);
    const bar = await page.locator('#menubar').boundingBox();
    const heading = await page.locator('main h1').boundingBox();
    const box = await note.boundingBox();
    assert.ok(box.y >= bar.y + bar.height && box.y > heading.y + heading.height, `${what}: below the menu bar and the heading (${JSON.stringify({ bar, heading, box })})`);
  };

  // Upload without a file: the page's own refusal
  assert.equal(await note.count(), 0);
  await page.locator('#code-upload').click();
  await waitFor(async () => (await note.count()) === 1, { what: 'the note' });
  assert.equal(await note.textContent(), 'Please select *.py script file to upload');
  await placed('no file');
  assert.equal(await page.locator('#page-error').count(), 0, 'not the page-wide message above the content');

  // An empty file: the server refuses it (400) and answers the Code page with the note in place
  const [chooser] = await Promise.all([page.waitForEvent('filechooser'), page.locator('#code-file').click()]);
  await chooser.setFiles({ name: 'empty.py', mimeType: 'text/x-python', buffer: Buffer.alloc(0) });
  const [upload] = await Promise.all([
    page.waitForResponse((r) => r.request().method() === 'POST' && new URL(r.url()).pathname === '/program.html'),
    page.locator('#code-upload').click(),
  ]);
  assert.equal(upload.status(), 400);
  await page.waitForLoadState('load');
  assert.equal(await note.textContent(), 'upload refused: the script file is empty');
  await placed('refused by the server');
  await screenshot(page, 'program-upload-error');
  g.assertClean();
  await g.close();
});
