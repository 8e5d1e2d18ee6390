// Servo Startup (web.md §5.3): Set Home, the profile fields, the Gear & Axis Configuration and the
// live scope.
import { boot } from '../skeleton.js';
import { api } from '../api.js';
import { $, action } from '../ui.js';
import { bindField } from '../fields.js';
import { Scope } from '../scope.js';

const { live, pageData } = boot({ topics: ['scope'] });

action($('sv-sethome'), async () => {
  await api.refgo('REF35');
  return 'REF35 — position set to 0';
}, $('sv-sethome-result'));

bindField($('sv-vel'), { index: 0x6081, sub: 0 });
bindField($('sv-acc'), { index: 0x6083, sub: 0 });
bindField($('sv-dec'), { index: 0x6084, sub: 0 });
bindField($('sv-gearin'), { index: 0x6091, sub: 1 });
bindField($('sv-gearout'), { index: 0x6091, sub: 2 });
bindField($('sv-feed'), { index: 0x6092, sub: 1 });

// The units in force for this model (drive-core.md §3.5, §3.6).
if (pageData.linear) {
  $('sv-note1').textContent = '(*1) Velocities are in user position units per second (µm/s with the factory Gear/Feed).';
  $('sv-note2').textContent = '(*2) Positions are in user position units (µm with the factory Gear/Feed).';
}
$('sv-accunit').textContent = pageData.accelerationUnit || 'the unit of the model';

new Scope(live, $('sv-scope-box'), 'sv');
