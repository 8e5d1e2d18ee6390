// IO OUT (web.md §5.6): the OUT Function Configurator for 3611h … 3614h, the output lamps and the
// manual Set/Clear buttons.
import { boot } from '../skeleton.js';
import { api } from '../api.js';
import { $, action, element, parseNumber, reportError } from '../ui.js';
import { EditForm, refresh, watch } from '../fields.js';

const { live, pageData } = boot();

// iofunc.md §5.1 (names from KT-IO)
const FUNCTIONS = ['Off', 'Statusword 6041h Monitor', 'Error Register 1002h Monitor', 'Limit Monitor right/left', 'Position Reached', 'Drive Status OK', 'Position Reached and Status OK'];
const CONFIG_LABEL = {
  1: 'Bit mask 6041h',
  2: 'Bit mask 1002h',
  3: '1: right, 2: left, 3: both',
  4: '0: last target reached, 1-10: IN1..10 target reached, 255:bit output: INx reached',
  6: '0: last target reached, 1-10: IN1..10 target reached, 255:bit output: INx reached',
};
// Which of 02h … 06h a function uses (iofunc.md §5: .03/.04 limit monitor only; .05/.06 for 3, 4, 6)
const USES = {
  '02': (f) => f !== 0 && f !== 5,
  '03': (f) => f === 3,
  '04': (f) => f === 3,
  '05': (f) => f === 3 || f === 4 || f === 6,
  '06': (f) => f === 3 || f === 4 || f === 6,
};
const SUBS = ['01', '02', '03', '04', '05', '06'];

const selected = () => Number(document.querySelector('input[name="out-sel"]:checked').value);
const form = new EditForm();
const fields = {};
for (const sub of SUBS) {
  fields[sub] = form.add($(`out-edit-${sub}`), {
    key: () => [0x3610 + selected(), parseInt(sub, 16)],
    onShow: () => sub === '01' && functionChanged(),
  });
}

const funcSel = $('out-func');
funcSel.append(element('option', { value: '', text: '(other)' }), ...FUNCTIONS.map((name, f) => element('option', { value: String(f), text: `${f} ${name}` })));
funcSel.addEventListener('change', () => {
  if (funcSel.value === '') return;
  form.setValue(fields['01'], funcSel.value);
  functionChanged();
});
$('out-edit-01').addEventListener('input', functionChanged);

function functionChanged() {
  const f = parseNumber($('out-edit-01').value);
  funcSel.value = f !== null && f >= 0 && f < FUNCTIONS.length ? String(f) : '';
  $('out-name-02').textContent = CONFIG_LABEL[f] || 'Configuration (not used by this function)';
  for (const sub of Object.keys(USES)) {
    const used = f !== null && USES[sub](f);
    $(`out-edit-${sub}`).disabled = !used;
    $(`out-row-${sub}`).classList.toggle('unused', !used);
  }
}
functionChanged();

for (const r of document.querySelectorAll('input[name="out-sel"]')) {
  r.addEventListener('change', () => form.reset().then(functionChanged));
}
action($('out-apply'), async () => {
  const failures = await form.apply();
  if (failures) throw new Error(`${failures} value(s) refused — see the fields`);
  return `OUT${selected()} written`;
}, $('out-apply-result'));

// ---- output state (an output without a pin on the model works in the OD, only the wire is missing)
const outPins = new Set(pageData.outputPins || [1, 2, 3, 4]);
for (let n = 1; n <= 4; n++) {
  if (!outPins.has(n)) $(`out-lamp-${n}`).closest('tr').cells[0].append(element('span', { class: 'hint', text: ' (no pin on this model)' }));
}
live.on('status', (s) => {
  for (let n = 1; n <= 4; n++) $(`out-lamp-${n}`).dataset.on = s.outputs & (1 << (15 + n)) ? '1' : '0';
});
for (let n = 1; n <= 4; n++) {
  action($(`out-set-${n}`), async () => (await api.refgo(`SO${n}`), `SO${n} — done`), $('out-result'));
  action($(`out-clear-${n}`), async () => (await api.refgo(`CO${n}`), `CO${n} — done`), $('out-result'));
}
// Set/Clear only where the output is manual (function 0)
watch({
  keys: () => [1, 2, 3, 4].map((n) => [0x3610 + n, 1]),
  values: (vals) => vals.forEach((f, i) => {
    const manual = f === 0;
    for (const b of [$(`out-set-${i + 1}`), $(`out-clear-${i + 1}`)]) {
      b.disabled = !manual;
      b.title = manual ? '' : `OUT${i + 1} is driven by output function ${f}; set its function to 0 to switch it by hand`;
    }
  }),
  failed: () => {},
  active: () => true,
});

refresh().catch(reportError);
