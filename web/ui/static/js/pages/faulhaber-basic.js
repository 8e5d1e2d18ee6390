// The MC BASIC panel of the FAULHABER drive's Emulator page (faulhaber.md §9.1): the eight program
// slots with their state, upload (file) and edit (PUT), start/stop and autostart; a load or
// run-time error marks its line in the editor, the running line (status `basic.line`, 20 Hz) too;
// the 26 variables a … z (3005h.01 … 1Ah) read at 5 Hz and writable; the input levels DigIn1 …
// DigIn8 as switches (PUT /api/v1/faulhaber/inputs); the SAVE count.
import { api, describe } from '../api.js';
import { $, action, element, parseNumber, showResult } from '../ui.js';
import { markError, clearError } from '../fields.js';

const SLOTS = 8;
const VARS = 'abcdefghijklmnopqrstuvwxyz';
const VAR_POLL_MS = 200; // 5 Hz
const PROGRAM_POLL_MS = 1000;
const LINE_PX = 20; // the editor's line height and top padding (mcemu.css .editor)
const PAD_PX = 4;

const base = '/api/v1/faulhaber';
const programs = { list: [], running: 0, autostart: 0, saves: 0 };
let status = { running: 0, line: null };

// Runs fn; a text it resolves with is shown in resultEl, a rejection as the error in words.
async function report(resultEl, fn) {
  try {
    const text = await fn();
    if (typeof text === 'string') showResult(resultEl, true, text);
  } catch (e) {
    showResult(resultEl, false, describe(e));
  }
}

// ---- the slot table
function buildSlots() {
  const rows = [];
  for (let n = 1; n <= SLOTS; n++) {
    const edit = element('button', { type: 'button', id: `fh-slot-${n}-edit`, text: 'Edit', 'aria-label': `Edit program ${n}` });
    const start = element('button', { type: 'button', id: `fh-slot-${n}-start`, text: 'Start', 'aria-label': `Start program ${n}` });
    edit.addEventListener('click', () => openInEditor(n, { focus: true }));
    start.addEventListener('click', () => report($('fh-basic-result'), () => startSlot(n)));
    rows.push(element('tr', { id: `fh-slot-${n}` },
      element('th', { scope: 'row', text: String(n) }),
      element('td', { id: `fh-slot-${n}-state` }),
      element('td', { id: `fh-slot-${n}-bytes`, class: 'mono' }),
      element('td', { class: 'nowrap' }, edit, start)));
  }
  document.querySelector('#fh-slots tbody').replaceChildren(...rows);
  for (let n = 1; n <= SLOTS; n++) {
    $('fh-basic-autostart').append(element('option', { value: String(n), text: `program ${n}` }));
    $('fh-edit-slot').append(element('option', { value: String(n), text: `program ${n}` }));
  }
}

function slotText(p) {
  if (p.state === 'error') return `error in line ${p.line}: ${p.message}${p.abortCode ? ` (${p.abortCode})` : ''}`;
  if (p.state === 'running') {
    const line = status.running === p.slot && status.line !== null ? status.line : p.runningLine;
    return line !== undefined && line !== null ? `running, line ${line}` : 'running';
  }
  return p.state;
}

function showPrograms() {
  for (const p of programs.list) {
    const cell = $(`fh-slot-${p.slot}-state`);
    const text = slotText(p);
    if (cell.textContent !== text) cell.textContent = text;
    cell.className = `state-${p.state}`;
    $(`fh-slot-${p.slot}`).dataset.state = p.state;
    $(`fh-slot-${p.slot}-bytes`).textContent = p.state === 'empty' ? '' : String(p.bytes);
    $(`fh-slot-${p.slot}-start`).disabled = p.state === 'empty' || p.state === 'error';
  }
  const auto = $('fh-basic-autostart');
  if (document.activeElement !== auto) auto.value = String(programs.autostart);
  $('fh-basic-saves').textContent = String(programs.saves);
  $('fh-basic-stop').disabled = !programs.running && !status.running;
  showEditStatus();
  showMarks();
}

function takePrograms(r) {
  programs.list = r.programs;
  programs.running = r.running;
  programs.autostart = r.autostart;
  programs.saves = r.saves ?? 0;
  showPrograms();
}

let loading = null;
function loadPrograms() {
  if (!loading) {
    loading = api.poll(`${base}/programs`).then(takePrograms).catch((e) => showResult($('fh-basic-result'), false, describe(e))).finally(() => (loading = null));
  }
  return loading;
}

// ---- the editor: a textarea over a gutter of line numbers and two line marks
const editor = () => $('fh-editor');
let editorSlot = 1;
let loadedText = ''; // what the slot held when the editor last loaded or saved it

function lineCount() {
  return editor().value.split(/\r\n|\r|\n/).length;
}

function errorLine() {
  const p = programs.list.find((x) => x.slot === editorSlot);
  return p && p.state === 'error' && p.line > 0 && editor().value === loadedText ? p.line : null;
}

function runLine() {
  return status.running === editorSlot && status.line !== null && editor().value === loadedText ? status.line : null;
}

let gutterLines = -1;
let gutterMarks = '';
let followed = null; // the running line last scrolled into view
function showMarks() {
  const ta = editor();
  const err = errorLine();
  const run = runLine();
  const n = lineCount();
  const marks = `${err}/${run}`;
  if (n !== gutterLines || marks !== gutterMarks) {
    const gutter = $('fh-gutter');
    const nums = [];
    for (let i = 1; i <= n; i++) nums.push(element('span', { class: i === err ? 'err' : i === run ? 'run' : '', 'data-line': String(i), text: String(i) }));
    gutter.replaceChildren(...nums);
    gutterLines = n;
    gutterMarks = marks;
  }
  $('fh-gutter').scrollTop = ta.scrollTop;
  for (const [id, line] of [['fh-mark-error', err], ['fh-mark-run', run]]) {
    const m = $(id);
    m.hidden = line === null;
    if (line !== null) {
      m.style.transform = `translateY(${PAD_PX + (line - 1) * LINE_PX - ta.scrollTop}px)`;
      m.dataset.line = String(line);
    }
  }
  ta.classList.toggle('has-error', err !== null);
  // keep the running line in view while the user is not in the editor
  if (run !== null && run !== followed && $('fh-follow').checked && document.activeElement !== ta) {
    followed = run;
    const top = PAD_PX + (run - 1) * LINE_PX;
    if (top < ta.scrollTop || top + LINE_PX > ta.scrollTop + ta.clientHeight) {
      ta.scrollTop = Math.max(0, top - ta.clientHeight / 3);
      showMarks();
    }
  }
}

// Puts the caret at the start of `line` and scrolls it into view (without taking the focus).
function goToLine(line) {
  const ta = editor();
  const lines = ta.value.split(/(\r\n|\r|\n)/);
  let at = 0;
  for (let i = 0, l = 1; i < lines.length && l < line; i += 2, l++) at += lines[i].length + (lines[i + 1] || '').length;
  ta.setSelectionRange(at, at);
  ta.scrollTop = Math.max(0, (line - 3) * LINE_PX);
  showMarks();
}

// The line under the editor: the editor's program as the slot table shows it, or the error of the
// last editor action (kept until the next action or another program is opened).
let editFailure = null;
function showEditStatus() {
  const el = $('fh-edit-status');
  if (editFailure) return showResult(el, false, editFailure);
  const p = programs.list.find((x) => x.slot === editorSlot);
  if (!p) return showResult(el, true, '');
  const text = `Program ${p.slot}: ${slotText(p)}${p.state === 'empty' || p.state === 'error' ? '' : ` (${p.bytes} bytes)`}`;
  if (el.textContent !== text) showResult(el, p.state !== 'error', text);
}
// Runs an editor action; its failure stays under the editor.
async function editAction(fn) {
  editFailure = null;
  try {
    await fn();
  } catch (e) {
    editFailure = describe(e);
  }
  showEditStatus();
}

async function openInEditor(n, { focus = false } = {}) {
  if (editor().value !== loadedText && !confirm(`Discard the unsaved changes of program ${editorSlot}?`)) {
    $('fh-edit-slot').value = String(editorSlot);
    return;
  }
  try {
    const p = await api.get(`${base}/programs/${n}`);
    editorSlot = n;
    $('fh-edit-slot').value = String(n);
    editor().value = p.source;
    loadedText = editor().value; // the textarea's value has LF line ends
    editor().scrollTop = 0;
    editFailure = null;
    await loadPrograms();
    if (p.state === 'error' && p.line > 0) goToLine(p.line);
    showMarks();
    if (focus) editor().focus();
  } catch (e) {
    editFailure = describe(e);
    showEditStatus();
  }
}

// PUT the text (default: the editor's) to the editor's slot; the answer is the slot's state (an
// error with its line). A file is sent as it is and then shown in the editor.
async function saveEditor(fileText = null) {
  const text = fileText ?? editor().value;
  const p = await api.putText(`${base}/programs/${editorSlot}`, text, 'text/plain');
  if (fileText !== null) editor().value = fileText;
  loadedText = editor().value;
  await loadPrograms();
  if (p.state === 'error' && p.line > 0) goToLine(p.line);
  return p;
}

async function startSlot(n) {
  try {
    await api.post(`${base}/programs/${n}/start`);
  } catch (e) {
    await loadPrograms();
    const p = programs.list.find((x) => x.slot === n);
    if (p && (p.state === 'error' || p.state === 'empty')) throw new Error(`program ${n} cannot start: ${slotText(p)}`);
    throw e;
  }
  await loadPrograms();
  return `program ${n} started`;
}

function wireEditor() {
  const ta = editor();
  ta.addEventListener('scroll', showMarks);
  ta.addEventListener('input', showMarks);
  $('fh-edit-slot').addEventListener('change', () => openInEditor(Number($('fh-edit-slot').value)));
  $('fh-edit-save').addEventListener('click', () => editAction(saveEditor));
  $('fh-edit-start').addEventListener('click', () => editAction(async () => {
    if (editor().value !== loadedText && (await saveEditor()).state === 'error') return;
    showResult($('fh-basic-result'), true, await startSlot(editorSlot));
  }));
  $('fh-upload-file').addEventListener('change', async () => {
    const input = $('fh-upload-file');
    const file = input.files[0];
    if (!file) return;
    await editAction(async () => {
      try {
        await saveEditor(await file.text());
      } catch (e) {
        throw new Error(`${file.name}: ${describe(e)}`);
      }
    });
    input.value = '';
  });
}

// ---- stop, autostart
function wireControls() {
  action($('fh-basic-stop'), async () => {
    takePrograms(await api.post(`${base}/stop`));
    return 'stopped';
  }, $('fh-basic-result'));
  $('fh-basic-autostart').addEventListener('change', async () => {
    const program = Number($('fh-basic-autostart').value);
    try {
      takePrograms(await api.put(`${base}/autostart`, { program }));
      showResult($('fh-basic-result'), true, program ? `autostart: program ${program}` : 'no autostart');
    } catch (e) {
      showResult($('fh-basic-result'), false, describe(e));
    }
  });
}

// ---- variables and inputs: one read of 3005h.01 … 1Ah and 2311h.01 … 03 at 5 Hz
const inputs = { writes: 0 };
function buildVarsAndInputs(inputCount, outputCount) {
  const cells = [];
  [...VARS].forEach((v, i) => {
    const sub = i + 1;
    const input = element('input', { type: 'text', id: `fh-var-${v}`, class: 'mono', size: '11', inputmode: 'numeric', 'aria-label': `variable ${v} (3005h.${sub.toString(16).toUpperCase().padStart(2, '0')})` });
    const commit = async () => {
      if (input.value === input.dataset.shown) return;
      const value = parseNumber(input.value);
      if (value === null) return markError(input, `"${input.value}" is not a number`);
      input.dataset.shown = input.value;
      try {
        await api.write(0x3005, sub, value);
        clearError(input);
      } catch (e) {
        markError(input, describe(e));
        input.dataset.shown = '';
      }
    };
    input.addEventListener('keydown', (e) => {
      if (e.key === 'Enter') {
        e.preventDefault();
        commit();
      }
    });
    input.addEventListener('change', commit);
    cells.push(element('label', { class: 'var', for: `fh-var-${v}` }, element('span', { class: 'mono', text: v }), input));
  });
  $('fh-vars').replaceChildren(...cells);

  const switches = [];
  for (let n = 1; n <= inputCount; n++) {
    const box = element('input', { type: 'checkbox', id: `fh-in-${n}`, role: 'switch' });
    box.addEventListener('change', async () => {
      inputs.writes++;
      let levels = 0;
      for (let k = 1; k <= inputCount; k++) if ($(`fh-in-${k}`).checked) levels |= 1 << (k - 1);
      try {
        await api.put(`${base}/inputs`, { levels });
        showResult($('fh-inputs-result'), true, `DigIn${n} ${box.checked ? 'high' : 'low'} (levels ${levels})`);
      } catch (e) {
        showResult($('fh-inputs-result'), false, `DigIn${n}: ${describe(e)}`);
      } finally {
        inputs.writes++;
      }
    });
    switches.push(element('label', { title: `wire level of DigIn${n}` }, box, ` DigIn${n}`));
  }
  $('fh-inputs').replaceChildren(...switches);
  const lamps = (prefix, count, label) => Array.from({ length: count }, (_, i) => element('span', { class: 'lamp', id: `${prefix}-${i + 1}`, 'data-on': '0', role: 'img', 'aria-label': `${label}${i + 1}`, title: `${label}${i + 1}` }));
  $('fh-inlamps').replaceChildren(...lamps('fh-inlamp', inputCount, 'DigIn'));
  $('fh-outlamps').replaceChildren(...lamps('fh-outlamp', outputCount, 'DigOut'));
}

async function pollValues(inputCount, outputCount) {
  const keys = [...VARS].map((_, i) => [0x3005, i + 1]).concat([[0x2311, 1], [0x2311, 2], [0x2311, 3]]);
  const started = performance.now();
  try {
    const before = inputs.writes;
    const values = await api.read(keys, { poll: true });
    [...VARS].forEach((v, i) => {
      const input = $(`fh-var-${v}`);
      const value = values[i];
      if (value !== null && typeof value === 'object') return;
      const text = String(value);
      if (document.activeElement === input || input.value === text) return;
      if (input.getAttribute('aria-invalid') === 'true' && input.value !== input.dataset.shown) return;
      input.value = text;
      input.dataset.shown = text;
    });
    const [logical, physical, outs] = values.slice(VARS.length);
    for (let n = 1; n <= inputCount; n++) {
      $(`fh-inlamp-${n}`).dataset.on = (logical >> (n - 1)) & 1 ? '1' : '0';
      // never an answer to a read that started before a switch was last changed (or during a write)
      if (inputs.writes === before && inputs.writes % 2 === 0) $(`fh-in-${n}`).checked = ((physical >> (n - 1)) & 1) === 1;
    }
    for (let n = 1; n <= outputCount; n++) $(`fh-outlamp-${n}`).dataset.on = (outs >> (n - 1)) & 1 ? '1' : '0';
  } catch (e) {
    showResult($('fh-inputs-result'), false, describe(e));
  }
  setTimeout(() => pollValues(inputCount, outputCount), Math.max(0, VAR_POLL_MS - (performance.now() - started)));
}

export function startBasic(live, pageData) {
  buildSlots();
  wireEditor();
  wireControls();
  const inputCount = (pageData.inputPins || [1, 2, 3, 4, 5, 6, 7, 8]).length;
  const outputCount = (pageData.outputPins || [1, 2]).length;
  buildVarsAndInputs(inputCount, outputCount);
  live.on('status', (s) => {
    if (!s.basic) return;
    const changed = s.basic.running !== status.running;
    status = { running: s.basic.running, line: s.basic.line };
    const text = s.basic.running ? `program ${s.basic.running}, line ${s.basic.line ?? '-'}` : 'none';
    if ($('fh-basic-running').textContent !== text) $('fh-basic-running').textContent = text;
    if (changed) loadPrograms();
    else showPrograms();
  });
  const poll = async () => {
    await loadPrograms();
    setTimeout(poll, PROGRAM_POLL_MS);
  };
  poll();
  openInEditor(1);
  pollValues(inputCount, outputCount);
  // for browser tests: what the panel shows
  window.mcBasic = {
    get editorSlot() {
      return editorSlot;
    },
    get errorLine() {
      return errorLine();
    },
    get runLine() {
      return runLine();
    },
  };
}
