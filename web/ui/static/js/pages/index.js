// Info page (web.md §5.1): last error, device information and the emulator box, kept live.
import { boot } from '../skeleton.js';
import { $, h4, reportError } from '../ui.js';
import { api } from '../api.js';

const { live } = boot();
const set = (id, text) => {
  const el = $(id);
  if (el.textContent !== text) el.textContent = text;
};

live.on('status', (s) => {
  set('info-lasterror', s.lastError ? s.lastError.text : '-');
  set('info-codeid', s.python.id);
  set('info-mfrstatus', h4(s.mfrStatus));
});

live.info.then((i) => {
  set('info-title', i.displayName);
  set('info-model', i.model);
  set('info-mcemu', i.version);
  set('info-listen', `${i.bind} — RefGo ${i.ports.refgo}, SLCAN ${i.ports.slcan}, HTTP ${i.ports.http}, UDP ${i.ports.udp}`);
  set('info-ip', `${i.ip} / ${i.mask}`);
}).catch(reportError);

// 1008h, 100Ah and the serial number are constant; read once so that a page served without the
// server's rendering still shows them.
api.read([[0x1008, 0], [0x100a, 0], [0x3404, 4]]).then(([name, version, serial]) => {
  if (typeof name === 'string') set('info-name', name);
  if (typeof version === 'string') set('info-version', version);
  if (typeof serial === 'number') set('info-serial', String(serial));
}).catch(reportError);
