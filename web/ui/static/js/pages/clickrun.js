// Click & Run (web.md §5.2): six buttons that execute RefGo lines, the positioning fields bound to
// 6081h/6083h/6084h, Target Pos. (a page value) and Target Distance (the RefGo repeat way), plus the
// scope so that a move started here is seen at once.
import { boot } from '../skeleton.js';
import { api } from '../api.js';
import { $, action, parseNumber } from '../ui.js';
import { bindField, markError, clearError } from '../fields.js';
import { Scope } from '../scope.js';

const { live } = boot({ topics: ['scope'] });
const result = $('cr-result');

// A number from a page field, or an error next to it.
function fieldNumber(id) {
  const input = $(id);
  const n = parseNumber(input.value);
  if (n === null) {
    markError(input, `"${input.value}" is not a number`);
    throw new Error(`${input.labels[0].textContent}: not a number`);
  }
  clearError(input);
  return n;
}

const run = (line) => async () => {
  const text = typeof line === 'function' ? line() : line;
  const r = await api.refgo(text);
  return r.answer ? `${text} → ${r.answer}` : `${text} — done`;
};

action($('cr-poweroff'), run('PQ'), result);
action($('cr-poweron'), run('PWC'), result);
action($('cr-stop'), run('SM'), result);
action($('cr-moveabs'), run(() => `G${fieldNumber('cr-target')}`), result);
action($('cr-moverel'), run(() => `GW${fieldNumber('cr-distance')}`), result);
action($('cr-backforth'), run(() => `RR${fieldNumber('cr-distance')}`), result);

bindField($('cr-vel'), { index: 0x6081, sub: 0 });
bindField($('cr-acc'), { index: 0x6083, sub: 0 });
bindField($('cr-dec'), { index: 0x6084, sub: 0 });

// Target Pos.: a page value, initialised from 607Ah when the page loads (the server rendered it;
// a page without that rendering takes it from the first status message).
const target = $('cr-target');
if (target.value === '') live.on('status', (s) => target.value === '' && (target.value = String(s.targetPos)));

// Target Distance = RWAY; a change executes RW<n> (refgo.md §7.7).
bindField($('cr-distance'), {
  live,
  fromStatus: (s) => s.refgo.repeatWay,
  write: (n) => api.refgo(`RW${n}`),
});

new Scope(live, $('cr-scope-box'), 'cr');
