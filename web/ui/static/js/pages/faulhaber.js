// The FAULHABER drive's Emulator page (web/README.md "FAULHABER drive"; faulhaber.md §1): the status
// LED and the CiA 402 state, power cycle and the manual clock, the faults of the drive core, the
// object browser and the trace (emulator-log.js); the MC BASIC panel is faulhaber-basic.js.
import { boot, showStatusLed } from '../skeleton.js';
import { api, describe } from '../api.js';
import { $, action, element, h4, hex, parseNumber, reportError, showResult } from '../ui.js';
import { objectBrowser } from '../objects.js';
import { startLog } from './emulator-log.js';
import { plantControls } from '../plant-controls.js';
import { startBasic } from './faulhaber-basic.js';

const { live, pageData } = boot({ topics: ['trace'] });

// ---- status LED and state (faulhaber.md §7.3, §8)
// EMCY codes of this drive (the names as on the server, status.cpp)
const EMCY = {
  0x2300: 'current error', 0x3210: 'over-voltage', 0x3220: 'under-voltage', 0x4310: 'temperature error',
  0x43f0: 'temperature warning', 0x5000: 'internal hardware error', 0x7300: 'encoder error',
  0x8130: 'communication error', 0x8611: 'following error', 0xff00: 'safety monitor',
};
// 2320h (COMM Tab. 32–33; bits 13, 14 of later firmware)
const ERROR_WORD = ['speed deviation', 'following error', 'over-voltage', 'under-voltage', 'temperature warning',
  'temperature error', 'encoder error', 'internal hardware error', 'module error', 'current measurement error',
  'memory error', 'communication error', 'calculation error', 'dynamic error', 'safety monitor'];
// 2324h.01
const DEVICE_STATUS = { 2: 'velocity deviation', 5: 'following error', 6: 'positive limit switch',
  7: 'negative limit switch', 8: 'positive software limit', 9: 'negative software limit', 13: 'voltage limited',
  14: 'torque limited', 15: 'speed limited', 16: 'temperature warning', 17: 'temperature shutdown',
  18: 'supply over-voltage', 19: 'controller under-voltage', 20: 'motor under-voltage', 21: 'motor overspeed',
  22: 'safety monitoring' };

const bitNames = (value, names) => {
  const out = [];
  for (let b = 0; b < 32; b++) if ((value >>> b) & 1) out.push(names[b] || `bit ${b}`);
  return out.join(', ');
};
const setText = (id, text) => {
  const el = $(id);
  if (el.textContent !== text) el.textContent = text;
};

live.on('status', (s) => {
  if (!s.led) return;
  showStatusLed($('fh-led'), s);
  const fault = s.state === 'F' || s.state === 'FRA';
  const errorText = s.errorCode ? `${h4(s.errorCode)} ${EMCY[s.errorCode] || ''}`.trim() : '-';
  setText('fh-led-text', fault ? `${s.stateName} — ${errorText}` : s.stateName);
  $('fh-led-text').classList.toggle('error', fault);
  setText('fh-state', s.stateName);
  setText('fh-statusword', h4(s.statusword));
  setText('fh-errorcode', errorText);
  setText('fh-errorword', s.errorWord ? `${h4(s.errorWord)} ${bitNames(s.errorWord, ERROR_WORD)}` : '0000h');
  setText('fh-devstatus', s.deviceStatus ? `${hex(s.deviceStatus, 8)} ${bitNames(s.deviceStatus, DEVICE_STATUS)}` : '00000000h');
  setText('fh-lasterror', s.lastError ? s.lastError.text : '-');
  setText('fh-temp', s.temperatureC === null ? '-' : `${s.temperatureC} °C`);
  setText('fh-clock-time', String(s.timeMs));
});

// Fault Reset: a rising edge of controlword bit 7 (CiA 402 transition 15)
action($('fh-faultreset'), async () => {
  const [cw] = await api.read([[0x6040, 0]]);
  await api.write(0x6040, 0, cw & ~0x80);
  await api.write(0x6040, 0, (cw | 0x80) & 0xffff);
  return 'controlword bit 7: 0 → 1';
}, $('fh-faultreset-result'));

// ---- power cycle and clock
action($('fh-powercycle'), async () => {
  if (!confirm('Power cycle the drive - Are you sure?')) return '';
  await api.post('/api/v1/power-cycle');
  return 'powered up again';
}, $('fh-powercycle-result'));

const advance = async (ms) => {
  const r = await api.post('/api/v1/clock/advance', { ms });
  setText('fh-clock-time', String(r.timeMs));
  return `advanced ${ms} ms, drive time ${r.timeMs} ms`;
};
for (const [id, ms] of [['fh-clock-1', 1], ['fh-clock-100', 100], ['fh-clock-1000', 1000]]) {
  action($(id), () => advance(ms), $('fh-clock-result'));
}
action($('fh-clock-advance'), () => {
  const ms = parseNumber($('fh-clock-ms').value);
  if (ms === null || ms < 1 || ms > 3600000) throw new Error('ms: 1 … 3600000');
  return advance(ms);
}, $('fh-clock-result'));
live.info.then((i) => {
  $('fh-clock-mode').textContent = i.clock.mode === 'manual' ? 'manual (drive time moves only with Advance)' : `${i.clock.mode} (drive time per wall time: ${i.clock.scale})`;
  $('fh-clock-controls').hidden = i.clock.mode !== 'manual';
}).catch(reportError);

// ---- faults: the causes of the drive core with this drive's EMCY codes (faulhaber.md §7.3)
const CAUSES = [
  ['over_voltage', '3210h over-voltage'],
  ['under_voltage', '3220h under-voltage'],
  ['over_temperature', '4310h temperature error'],
  ['i2t', '4310h temperature error (I²t)'],
  ['stroke', '8611h following error'],
  ['external_torque', '8611h following error (external torque)'],
  ['sensor', '7300h encoder error'],
  ['over_current', '2300h current error'],
  ['ack_error', '5000h internal hardware error'],
  ['motor_communication', '5000h hardware error (motor communication)'],
  ['needs_reset', '5000h hardware error (power cycle only)'],
  ['abort_connection', '8130h communication error'],
  ['hw_sw_enable', 'FF00h safety monitor'],
];
const faultResult = $('fh-injections-result');
for (const [cause, label] of CAUSES) {
  const b = element('button', { type: 'button', id: `fh-fault-${cause}`, text: label, title: `inject ${cause}` });
  $('fh-fault-buttons').append(b);
  action(b, async () => {
    const f = await api.post('/api/v1/faults', { kind: 'drive.inject', cause });
    loadInjections();
    return `${f.id}: ${cause} injected`;
  }, faultResult);
}
action($('fh-emcy-send'), async () => {
  const code = $('fh-emcy-code').value.trim();
  if (!code) throw new Error('enter an EMCY code, e.g. 8611h or FF01h');
  await api.post('/api/v1/faults', { kind: 'drive.emcy', code: /h$/i.test(code) ? code : `${code}h` });
  loadInjections();
  return `EMCY ${code} sent`;
}, $('fh-emcy-result'));

let injections = [];
const describeFault = (f) => Object.entries(f).filter(([k]) => k !== 'id' && k !== 'kind').map(([k, v]) => `${k}=${v}`).join(' ');
async function loadInjections() {
  try {
    injections = (await api.get('/api/v1/faults')).faults;
  } catch (e) {
    showResult(faultResult, false, describe(e));
    return;
  }
  const rows = injections.map((f) => {
    const remove = element('button', { type: 'button', id: `fh-remove-${f.id}`, text: 'Remove', 'aria-label': `Remove ${f.id} ${f.kind}` });
    action(remove, async () => {
      await api.del(`/api/v1/faults/${f.id}`);
      await loadInjections();
      return `${f.id} removed`;
    }, faultResult);
    return element('tr', { id: `fh-injection-${f.id}` }, element('td', { class: 'mono', text: f.id }), element('td', { text: f.kind }), element('td', { class: 'mono', text: describeFault(f) }), element('td', {}, remove));
  });
  if (!rows.length) rows.push(element('tr', {}, element('td', { colspan: '4', class: 'hint', text: 'none' })));
  $('fh-injections').tBodies[0].replaceChildren(...rows);
  plant.sync(injections);
}
action($('fh-remove-all'), async () => {
  await api.del('/api/v1/faults');
  await loadInjections();
  return 'all injections removed';
}, faultResult);
setInterval(loadInjections, 1000);
loadInjections();

// Supply and ambient as one injection of their kind each (a move replaces it), and stops.
const plant = plantControls({
  prefix: 'fh',
  supply: pageData.supply || { nominalV: 48, underV: 18, overV: 60 },
  result: $('fh-plant-result'),
  reload: () => loadInjections(),
});
const plantResult = $('fh-plant-result');
action($('fh-stop-add'), async () => {
  const positionInc = parseNumber($('fh-stop-pos').value);
  if (positionInc === null) throw new Error('stop position: not a number');
  const f = await api.post('/api/v1/faults', { kind: 'drive.obstacle', positionInc, side: Number($('fh-stop-side').value) });
  await loadInjections();
  return `${f.id}: stop at ${positionInc} inc (remove it in the list above)`;
}, plantResult);

// ---- object browser, MC BASIC, trace
objectBrowser({ tbody: document.querySelector('#fh-objects tbody'), filter: $('fh-obj-filter'), hex: $('fh-obj-hex'), count: $('fh-obj-count'), group: $('fh-obj-group') });
startBasic(live, pageData);
startLog(live);
