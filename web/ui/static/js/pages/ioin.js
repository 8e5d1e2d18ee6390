// IO IN (web.md §5.5): the IN Function Configurator for 3511h … 351Ah and the IN Simulator (3510h).
import { boot } from '../skeleton.js';
import { api, describe } from '../api.js';
import { $, action, element, hex, parseNumber, reportError, showResult } from '../ui.js';
import { EditForm, refresh, watch } from '../fields.js';

const { live } = boot();

// iofunc.md §4: function numbers and names (rising byte high, falling byte low)
const NAMES = ['Off', 'Capture 1', 'Capture 2', 'Counter', 'Timed Motion Absolute', 'Quick Stop', 'Timed Motion Relative', 'Set Home / Referencing', 'Teach Target', 'Software Enable', 'Jog +', 'Jog -'];
const FUNCTIONS = [
  ...NAMES.slice(0, 10).map((name, f) => [f << 8, `${hex(f << 8)} ${name}`]),
  [0x0a0a, '0A0Ah Jog +'],
  [0x0b0b, '0B0Bh Jog -'],
  ...NAMES.slice(1, 10).map((name, i) => [i + 1, `${hex(i + 1)} ${name} (Hi->Lo)`]),
];
const ROWS = ['01', '08', '06', '07', '09', '05', '0A', '03', '04'];
const LABELS = { '01': 'Input Function', '08': 'Target Position', '06': 'Positioning Velocity', '07': 'Acceleration', '09': 'Profile deceleration', '05': 'Timer [ms]', '0A': 'Max Current / Torque [0.1%]', '03': 'Result 1', '04': 'Result 2' };
const HOME_LABELS = { '06': 'Homing Velocity', '07': 'Homing Acceleration', '08': 'Home Offset', '09': 'Homing Method', '0A': 'Torque' };

const selected = () => Number(document.querySelector('input[name="in-sel"]:checked').value);
const form = new EditForm();
const fields = {};
for (const sub of ROWS) {
  fields[sub] = form.add($(`in-edit-${sub}`), {
    key: () => [0x3510 + selected(), parseInt(sub, 16)],
    format: sub === '01' ? (v) => hex(v) : String,
    parse: sub === '01' ? (t) => parseNumber(t, { hex: true }) : (t) => parseNumber(t),
    onShow: (v) => (sub === '01' ? functionChanged() : syncSlider(sub, v)),
  });
}

// ---- function drop-down and the labels that depend on the function
const funcSel = $('in-func');
funcSel.append(element('option', { value: '', text: '(other code)' }), ...FUNCTIONS.map(([v, text]) => element('option', { value: String(v), text })));
funcSel.addEventListener('change', () => {
  if (funcSel.value === '') return;
  form.setValue(fields['01'], hex(Number(funcSel.value)));
  functionChanged();
});
$('in-edit-01').addEventListener('input', functionChanged);

function functionChanged() {
  const code = parseNumber($('in-edit-01').value, { hex: true });
  const known = FUNCTIONS.some(([v]) => v === code);
  funcSel.value = known ? String(code) : '';
  const home = code !== null && ((code >> 8) === 7 || (code & 0xff) === 7);
  for (const sub of ROWS) $(`in-name-${sub}`).textContent = (home && HOME_LABELS[sub]) || LABELS[sub];
  defaultExecFunction(code);
}

// ---- sliders: 0 … 607Fh / 60C5h / 60C6h / 1000
const SLIDERS = { '06': 0x607f, '07': 0x60c5, '09': 0x60c6 };
function syncSlider(sub, v) {
  const s = document.getElementById(`in-slider-${sub}`);
  if (s && typeof v === 'number' && document.activeElement !== s) s.value = String(v);
}
for (const sub of [...Object.keys(SLIDERS), '0A']) {
  const s = $(`in-slider-${sub}`);
  s.addEventListener('input', () => form.setValue(fields[sub], s.value));
  $(`in-edit-${sub}`).addEventListener('input', () => syncSlider(sub, parseNumber($(`in-edit-${sub}`).value)));
}
watch({
  keys: () => Object.values(SLIDERS).map((i) => [i, 0]),
  values: (vals) => Object.keys(SLIDERS).forEach((sub, i) => typeof vals[i] === 'number' && ($(`in-slider-${sub}`).max = String(vals[i]))),
  failed: () => {},
  active: () => true,
});

// ---- selection, Teach, Apply
for (const r of document.querySelectorAll('input[name="in-sel"]')) {
  r.addEventListener('change', () => form.reset().then(functionChanged));
}
action($('in-teach'), async () => {
  const s = live.status || (await api.get('/api/v1/status'));
  form.setValue(fields['08'], String(s.posUser));
  return '';
});
action($('in-apply'), async () => {
  const failures = await form.apply();
  if (failures) throw new Error(`${failures} value(s) refused — see the fields`);
  return `IN${selected()} written`;
}, $('in-apply-result'));

// ---- IN Simulator: 3510h.01 bits 16…25, lamps from 60FDh
// A switch shows 3510h.01 from the status stream, except from snapshots that may predate its last
// change (until 200 ms after the write answered), which could undo the click on the screen.
const quietUntil = {};
live.on('status', (s) => {
  for (let n = 1; n <= 10; n++) {
    const bit = 1 << (15 + n);
    const box = $(`insim-${n}`);
    if (!box.dataset.pending && !(performance.now() < quietUntil[n])) box.checked = (s.virtualInputs & bit) !== 0;
    $(`insim-lamp-${n}`).dataset.on = s.inputs & bit ? '1' : '0';
  }
});
for (let n = 1; n <= 10; n++) {
  const box = $(`insim-${n}`);
  box.addEventListener('change', async () => {
    box.dataset.pending = '1';
    quietUntil[n] = Infinity;
    try {
      const [virt] = await api.read([[0x3510, 1]]);
      const bit = 1 << (15 + n);
      const next = box.checked ? (virt | bit) >>> 0 : (virt & ~bit) >>> 0;
      await api.write(0x3510, 1, next);
      showResult($('insim-result'), true, `3510h.01 := ${hex(next, 8)}`);
    } catch (e) {
      showResult($('insim-result'), false, `IN${n}: ${describe(e)}`);
    } finally {
      delete box.dataset.pending;
      quietUntil[n] = performance.now() + 200;
    }
  });
}
action($('insim-clear'), async () => {
  await api.write(0x3510, 1, 0);
  return '3510h.01 := 0';
}, $('insim-result'));

// Execute function now: 3510h.02 := (n << 8) | f (iofunc.md §4.13)
const execSel = $('insim-func');
execSel.append(...NAMES.map((name, f) => element('option', { value: String(f), text: `${hex(f, 2)} ${name}` })));
let execTouched = false;
execSel.addEventListener('change', () => (execTouched = true));
function defaultExecFunction(code) {
  if (!execTouched && code !== null && (code >> 8) <= 11) execSel.value = String(code >> 8);
}
action($('insim-exec'), async () => {
  const n = selected();
  const value = (n << 8) | Number(execSel.value);
  await api.write(0x3510, 2, value);
  return `3510h.02 := ${hex(value)}`;
}, $('insim-exec-result'));

refresh().catch(reportError);
