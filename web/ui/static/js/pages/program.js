// Code (Python), web.md §5.7: the real drive's page. Its buttons navigate to
// /program.html?codeAct=N (the drive's own protocol, §6.2) and the upload is the form POST of §6.1;
// the page then drops ?codeAct from its address so that a reload repeats nothing. Without a script
// engine (GET /api/v1/info: scripting.available false) the page says so and its controls are off.
import { boot } from '../skeleton.js';
import { api, describe } from '../api.js';
import { $, action, element, reportError } from '../ui.js';

const { live } = boot();

if (new URLSearchParams(location.search).has('codeAct')) history.replaceState(null, '', '/program.html');

const controls = ['code-auto-on', 'code-auto-off', 'code-store', 'code-file', 'code-upload', 'code-run', 'code-pause', 'code-resume', 'code-stop', 'code-restart'].map($);
for (const b of controls) {
  if (b.dataset.act) b.addEventListener('click', () => location.assign(`/program.html?codeAct=${b.dataset.act}`));
}

action($('code-store'), async () => {
  if (!confirm('Store Permanently - Are you sure?')) return '';
  await api.post('/api/v1/store');
  return 'Stored';
}, $('code-store-result'));

// The upload's refusal is shown in the upload section: the server's answer (web.md §6.1) puts it
// there as #code-error, and so does a click on Upload without a file.
function showUploadError(text) {
  let el = document.getElementById('code-error');
  if (!el) {
    el = element('p', { id: 'code-error', class: 'notice error', role: 'alert' });
    $('code-file-hint').after(el);
  }
  el.textContent = text;
}
$('code-form').addEventListener('submit', (e) => {
  if (!$('code-file').files.length) {
    e.preventDefault();
    showUploadError('Please select *.py script file to upload');
  }
});

// "~live(|)~" while the script runs (MAN §8.3 shows ~live(d)~)
const SPIN = '|/-\\';
let spin = 0;
setInterval(() => {
  const el = $('code-live');
  const running = live.status && live.status.python.state === 'RUN';
  el.textContent = running ? `~live(${SPIN[spin++ % 4]})~` : '';
}, 250);

let shownId = null;
async function loadViewer() {
  try {
    const s = await api.get('/api/v1/script');
    $('code-viewer').textContent = s.source;
  } catch (e) {
    $('code-viewer').textContent = `(the script cannot be shown: ${describe(e)})`;
  }
}

live.info.then((info) => {
  if (!info.scripting || !info.scripting.available) {
    $('code-engine').textContent = info.scripting && info.scripting.reason
      ? `The script engine is not available: ${info.scripting.reason}. Running, stopping and autostart are switched off; RefGo, CANopen, the I/O functions and every other page work as usual.`
      : 'The script engine is not available in this version of mcemu: uploading, running, stopping and autostart are switched off. RefGo, CANopen, the I/O functions and every other page work as usual.';
    for (const c of controls) c.disabled = true;
    $('code-viewer').textContent = '(no script to show: the script engine is not available)';
    return;
  }
  const sandbox = info.scripting.sandbox;
  if (sandbox && sandbox.unsafe) {  // --unsafe-scripts: say so where scripts are started
    $('code-engine').textContent = `Script engine: ${info.scripting.engine}. ${sandbox.reason}.`;
  } else {
    $('code-engine').textContent = `Script engine: ${info.scripting.engine}`;
    $('code-engine').className = 'hint';
  }
  live.on('status', (s) => {
    const text = `${s.python.state} ${s.python.id}`;
    if ($('code-status').textContent !== text) $('code-status').textContent = text;
    $('code-auto-on').textContent = s.python.autostart ? 'ON [X]' : 'ON';
    $('code-auto-off').textContent = s.python.autostart ? 'OFF' : 'OFF [X]';
    if (s.python.id !== shownId) {
      shownId = s.python.id;
      loadViewer();
    }
  });
}).catch(reportError);
