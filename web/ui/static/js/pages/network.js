// Network Settings (web.md §5.8): 5007h/5008h octets 2…4 (octet 1 is read-only), written by Apply.
import { boot } from '../skeleton.js';
import { $, action, reportError } from '../ui.js';
import { EditForm, refresh, watch } from '../fields.js';

const { live } = boot();
const form = new EditForm();
for (const [name, index] of [['ip', 0x5007], ['mask', 0x5008]]) {
  for (let k = 2; k <= 4; k++) form.add($(`net-${name}-${k}`), { key: () => [index, k] });
}
// octet 1 is read-only (5007h.01/5008h.01 are ro in the XDD): shown as text, refreshed alike
watch({
  keys: () => [[0x5007, 1], [0x5008, 1]],
  values: ([ip, mask]) => {
    if (typeof ip === 'number') $('net-ip-1').textContent = String(ip);
    if (typeof mask === 'number') $('net-mask-1').textContent = String(mask);
  },
  failed: () => {},
  active: () => true,
});

action($('net-apply'), async () => {
  const failures = await form.apply();
  if (failures) throw new Error(`${failures} value(s) refused — see the fields`);
  return 'Written to RAM: Store Permanently and a power cycle make it the active address';
}, $('net-apply-result'));

live.info.then((i) => {
  $('net-active').textContent = `${i.ip} / ${i.mask}`;
  $('net-listen').textContent = `${i.bind} — RefGo ${i.ports.refgo}, SLCAN ${i.ports.slcan}, HTTP ${i.ports.http}, UDP ${i.ports.udp}`;
}).catch(reportError);
refresh().catch(reportError);
