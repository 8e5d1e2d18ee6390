// Emulator page (web.md §5.9): LEDs with a running Morse decode, faults and injections, wiring and
// plant, power cycle, about, settings; the console and the trace are in emulator-log.js.
import { boot } from '../skeleton.js';
import { MorseDecoder } from '../led.js';
import { api, describe } from '../api.js';
import { $, action, element, parseNumber, reportError, showResult } from '../ui.js';
import { startLog } from './emulator-log.js';
import { plantControls } from '../plant-controls.js';

const { live, leds, pageData } = boot({ topics: ['trace', 'udp'] });

// ---- LEDs (morse-led.md §6.3)
const bigGreen = $('emu-led-green');
const bigYellow = $('emu-led-yellow');
new MutationObserver(() => (bigYellow.dataset.on = $('led-yellow').dataset.on)).observe($('led-yellow'), { attributes: true });
let decoder = null;
let lastEdge = null;
leds.onChange((on, t) => {
  bigGreen.dataset.on = on ? '1' : '0';
  const g = leds.schedule;
  if (!g) return;
  if (!decoder || decoder.unitMs !== g.unitMs) decoder = new MorseDecoder(g.unitMs);
  if (lastEdge !== null && t > lastEdge.t) {
    decoder.push(lastEdge.on, t - lastEdge.t);
    const text = decoder.text.slice(-120);
    if ($('emu-morse-decode').textContent !== text) $('emu-morse-decode').textContent = text;
  }
  lastEdge = { on, t };
});
setInterval(() => {
  const p = leds.position();
  if (!p) return;
  $('emu-morse-text').textContent = p.text;
  $('emu-morse-pos').textContent = `element ${p.element + 1} of ${p.elements}, ${(p.phase / 1000).toFixed(2)} s of ${(p.cycleMs / 1000).toFixed(2)} s`;
  $('emu-morse-next').textContent = leds.schedule.nextText ?? '(the same)';
}, 100);

// ---- faults (drive-core.md §11.1; names of web.md §5.1)
const CAUSES = [
  ['over_voltage', '3211h ERROR_OVER_VOLT'],
  ['under_voltage', '3221h ERROR_UNDER_VOLT'],
  ['ack_error', '5200h ERROR_ACK'],
  ['over_temperature', '4210h ERROR_OVER_TEMP'],
  ['i2t', '4220h ERROR_DERATING'],
  ['abort_connection', '8130h ERROR_ABORT_CONNECTION'],
  ['stroke', '7121h ERROR_STROKE'],
  ['motor_communication', '7510h ERROR_COMMUNICATION'],
  ['sensor', 'FFF1h ERROR_SENSOR'],
  ['hw_sw_enable', 'FFF2h ERROR_HW_SW_ENABLE'],
  ['over_current', '2220h ERROR_OVER_CURRENT'],
  ['external_torque', 'FFF4h ERROR_EXT_TORQUE'],
  ['needs_reset', 'FFF5h ERROR_NEEDS_RESET (power cycle only)'],
  ['sensor_warning', 'Sensor warning (1002h bit 16)'],
];
const faultResult = $('emu-injections-result');
for (const [cause, label] of CAUSES) {
  const b = element('button', { type: 'button', id: `emu-fault-${cause}`, text: label, title: `inject ${cause}` });
  $('emu-fault-buttons').append(b);
  action(b, async () => {
    const f = await api.post('/api/v1/faults', { kind: 'drive.inject', cause });
    loadInjections();
    return `${f.id}: ${cause} injected`;
  }, faultResult);
}

// Fault Reset: a rising edge of controlword bit 7 (CiA 402 transition 15)
action($('emu-faultreset'), async () => {
  const [cw] = await api.read([[0x6040, 0]]);
  await api.write(0x6040, 0, cw & ~0x80);
  await api.write(0x6040, 0, (cw | 0x80) & 0xffff);
  return 'controlword bit 7: 0 → 1';
}, $('emu-faultreset-result'));

action($('emu-emcy-send'), async () => {
  const code = $('emu-emcy-code').value.trim();
  if (!code) throw new Error('enter an EMCY code, e.g. 7121h or FF00h');
  await api.post('/api/v1/faults', { kind: 'drive.emcy', code: /h$/i.test(code) ? code : `${code}h` });
  loadInjections();
  return `EMCY ${code} sent`;
}, $('emu-emcy-result'));

// ---- transport faults (web.md §9)
const TF_FIELDS = {
  count: ['count', 'number', 'apply to the next n'],
  durationMs: ['for ms', 'number', 'drive time, then removed'],
  ms: ['delay ms', 'number', 'wall time'],
  status: ['status', 'number', '400 … 599'],
  path: ['path prefix', 'text', 'e.g. /servo.html'],
  cobId: ['COB-ID', 'text', 'hex, e.g. 1B2h'],
  index: ['index', 'text', 'e.g. 1008h'],
  sub: ['sub', 'number', ''],
  code: ['abort code', 'text', 'e.g. 08000000h'],
  phase: ['phase', 'text', 'initiate, segment or end'],
  text: ['text', 'text', 'printable ASCII'],
  value: ['load', 'number', 'N·m or N'],
};
const TF_KINDS = {
  'refgo.noReply': ['count', 'durationMs'],
  'refgo.delay': ['ms', 'count', 'durationMs'],
  'refgo.disconnect': [],
  'udp.drop': ['count', 'durationMs'],
  'http.error': ['status', 'path', 'count', 'durationMs'],
  'slcan.dropTx': ['cobId', 'count', 'durationMs'],
  'slcan.delayTx': ['ms', 'count', 'durationMs'],
  'slcan.sdoAbort': ['index', 'sub', 'code', 'phase', 'count'],
  'slcan.sdoNoReply': ['index', 'count', 'durationMs'],
  'slcan.heartbeatStop': ['durationMs'],
  'slcan.rawTx': ['text'],
  'slcan.bel': ['count', 'durationMs'],
  'slcan.disconnect': [],
  'script.kill': [],
};
const kindSel = $('emu-tf-kind');
kindSel.append(...Object.keys(TF_KINDS).map((k) => element('option', { value: k, text: k })));
const tfInputs = {};
for (const [name, [label, type, hint]] of Object.entries(TF_FIELDS)) {
  if (name === 'value') continue;
  const input = element('input', { type, id: `emu-tf-${name}`, size: '9', placeholder: hint, 'aria-label': label });
  tfInputs[name] = element('label', { class: 'tf-field' }, `${label} `, input);
  $('emu-tf-fields').append(tfInputs[name]);
}
const showTfFields = () => {
  for (const [name, el] of Object.entries(tfInputs)) el.hidden = !TF_KINDS[kindSel.value].includes(name);
};
kindSel.addEventListener('change', showTfFields);
showTfFields();
action($('emu-tf-add'), async () => {
  const body = { kind: kindSel.value };
  for (const name of TF_KINDS[kindSel.value]) {
    const raw = $(`emu-tf-${name}`).value.trim();
    if (raw === '') continue;
    if (TF_FIELDS[name][1] === 'number') {
      const n = parseNumber(raw);
      if (n === null) throw new Error(`${TF_FIELDS[name][0]}: "${raw}" is not a number`);
      body[name] = n;
    } else body[name] = name === 'text' ? raw.replace(/\\r/g, '\r') : raw;
  }
  const f = await api.post('/api/v1/faults', body);
  loadInjections();
  return `${f.id}: ${f.kind} added`;
}, $('emu-tf-result'));

// ---- active injections
let injections = [];
const describeFault = (f) =>
  Object.entries(f)
    .filter(([k]) => k !== 'id' && k !== 'kind')
    .map(([k, v]) => `${k}=${typeof v === 'object' ? JSON.stringify(v) : v}`)
    .join(' ');
async function loadInjections() {
  try {
    injections = (await api.poll('/api/v1/faults')).faults;
  } catch (e) {
    showResult(faultResult, false, describe(e));
    return;
  }
  const rows = injections.map((f) => {
    const remove = element('button', { type: 'button', id: `emu-remove-${f.id}`, text: 'Remove', 'aria-label': `Remove ${f.id} ${f.kind}` });
    action(remove, async () => {
      await api.del(`/api/v1/faults/${f.id}`);
      await loadInjections();
      return `${f.id} removed`;
    }, faultResult);
    return element('tr', { id: `emu-injection-${f.id}` }, element('td', { class: 'mono', text: f.id }), element('td', { text: f.kind }), element('td', { class: 'mono', text: describeFault(f) }), element('td', {}, remove));
  });
  if (!rows.length) rows.push(element('tr', {}, element('td', { colspan: '4', class: 'hint', text: 'none' })));
  $('emu-injections').tBodies[0].replaceChildren(...rows);
  plant.sync(injections);
}
action($('emu-remove-all'), async () => {
  await api.del('/api/v1/faults');
  await loadInjections();
  return 'all injections removed';
}, faultResult);
setInterval(loadInjections, 1000);
loadInjections();

// ---- wiring: physical input levels (PUT /api/v1/io/physical-inputs)
const pins = new Set(pageData.inputPins || [1, 2, 3, 4, 5, 6, 7, 8, 9, 10]);
for (let n = 1; n <= 10; n++) {
  const box = element('input', { type: 'checkbox', id: `emu-in-${n}`, disabled: !pins.has(n), role: 'switch' });
  const label = element('label', { class: pins.has(n) ? '' : 'disabled', title: pins.has(n) ? `24 V on IN${n}` : `IN${n} has no pin on this model` }, box, ` IN${n}`);
  $('emu-inputs').append(label);
  box.addEventListener('change', async () => {
    wiring.writes++;
    try {
      await api.put('/api/v1/io/physical-inputs', box.checked ? { set: [n] } : { clear: [n] });
      showResult($('emu-inputs-result'), true, `IN${n} wire ${box.checked ? 'high (24 V)' : 'low'}`);
    } catch (e) {
      showResult($('emu-inputs-result'), false, `IN${n}: ${describe(e)}`);
    } finally {
      wiring.writes++;
    }
  });
}
// The switches show GET /api/v1/io, but never an answer to a request that started before a switch
// was last changed (it could undo the click on the screen).
const wiring = { writes: 0 };
async function pollIo() {
  try {
    const before = wiring.writes;
    const io = await api.poll('/api/v1/io');
    for (let n = 1; n <= 10; n++) {
      if (wiring.writes !== before || wiring.writes % 2) break;
      $(`emu-in-${n}`).checked = (io.physical & (1 << (15 + n))) !== 0;
    }
  } catch (e) {
    showResult($('emu-inputs-result'), false, describe(e));
  }
  setTimeout(pollIo, 500);
}
pollIo();

// ---- plant: supply and ambient as injections of their kind (one at a time), load, stops
const plant = plantControls({
  prefix: 'emu',
  supply: pageData.supply || { nominalV: 48, underV: 18, overV: 60 },
  result: $('emu-plant-result'),
  reload: () => loadInjections(),
});
const plantResult = $('emu-plant-result');
const replaceInjection = plant.replaceInjection;
action($('emu-load-apply'), async () => {
  const value = Number($('emu-load').value);
  await replaceInjection('drive.load', value === 0 ? null : { value });
  return value === 0 ? 'no external load' : `external load ${value}`;
}, plantResult);
action($('emu-stop-add'), async () => {
  const positionInc = parseNumber($('emu-stop-pos').value);
  if (positionInc === null) throw new Error('stop position: not a number');
  const f = await api.post('/api/v1/faults', { kind: 'drive.obstacle', positionInc, side: Number($('emu-stop-side').value) });
  await loadInjections();
  return `${f.id}: stop at ${positionInc} inc (remove it in the list above)`;
}, plantResult);

// ---- power cycle
action($('emu-powercycle'), async () => {
  if (!confirm('Power cycle the drive - Are you sure?')) return '';
  await api.post('/api/v1/power-cycle');
  return 'powered up again';
}, $('emu-powercycle-result'));

// ---- settings (web.md §8.9)
const SETTINGS = ['udpEmulatorNotes', 'scriptStrict', 'traceScriptCalls', 'scriptMemoryMiB'];
// A reload (after any setting's change) leaves the field being edited alone: overwriting it would
// drop what the user typed, and the change event that would send it never fires.
async function loadSettings() {
  const s = await api.get('/api/v1/settings');
  for (const k of SETTINGS) {
    const el = $(`emu-set-${k}`);
    if (el === document.activeElement && el.type !== 'checkbox') continue;
    if (el.type === 'checkbox') el.checked = !!s[k];
    else el.value = String(s[k]);
  }
}
for (const k of SETTINGS) {
  const el = $(`emu-set-${k}`);
  el.addEventListener('change', async () => {
    const value = el.type === 'checkbox' ? el.checked : Number(el.value);
    try {
      await api.put('/api/v1/settings', { [k]: value });
      showResult($('emu-settings-result'), true, `${k} = ${value}`);
    } catch (e) {
      showResult($('emu-settings-result'), false, `${k}: ${describe(e)}`);
    }
    loadSettings().catch(reportError);
  });
}
loadSettings().catch(reportError);

// ---- about
live.info.then((i) => {
  $('emu-about-script').textContent = i.scripting && i.scripting.available ? i.scripting.engine : 'not available in this version';
  $('emu-about-clock').textContent = `${i.clock.mode} (drive time per wall time: ${i.clock.scale})`;
}).catch(reportError);

startLog(live);
