// The Emulator page's Lint panel (docs/lint.md §5): what the masters, hosts and scripts did to this
// drive that a real drive would punish — each rule with its count, the recent findings with their
// explanation and reference, and a reset (DELETE /api/v1/lint, which --api-token protects).
// Self-contained: it fills <section id="lint"> of any Emulator page (MovingCap or FAULHABER) and
// polls GET /api/v1/lint once a second while the page is visible.
import { api, describe } from '../api.js';
import { element, showResult } from '../ui.js';

const POLL_MS = 1000;
const SHOWN = 20; // recent findings listed, newest first

const STYLE = `
#lint .lint-sev { display: inline-block; min-width: 3.2em; text-align: center; font-size: 12px; font-weight: 700;
  border-radius: 3px; padding: 1px 5px; color: #fff; background: var(--muted, #5b6670); }
#lint .lint-sev-warn { background: #b35c00; }
#lint .lint-sev-error { background: var(--err, #c01818); }
#lint .lint-sev-off { background: #fff; color: var(--muted, #5b6670); border: 1px solid var(--line, #cfd6dc); }
#lint table { width: 100%; }
#lint td, #lint th { padding: 3px 8px; border-bottom: 1px solid var(--line, #cfd6dc); text-align: left; vertical-align: top; }
#lint td.num { text-align: right; font-variant-numeric: tabular-nums; }
#lint code { font-size: 13px; }
#lint ol.lint-recent { list-style: none; padding: 0; margin: 4px 0; }
#lint ol.lint-recent li { border-left: 4px solid var(--line, #cfd6dc); padding: 4px 10px; margin: 6px 0; background: var(--soft, #f3f5f7); }
#lint ol.lint-recent li.lint-warn { border-left-color: #b35c00; }
#lint ol.lint-recent li.lint-error { border-left-color: var(--err, #c01818); }
#lint .lint-head { font-family: "DejaVu Sans Mono", monospace; font-size: 13px; color: var(--muted, #5b6670); }
#lint .lint-detail { font-weight: 600; margin: 2px 0; }
#lint .lint-advice, #lint .lint-ref { margin: 2px 0; font-size: 14px; }
#lint .lint-ref { color: var(--muted, #5b6670); }
`;

function badge(severity) {
  return element('span', { class: `lint-sev lint-sev-${severity}`, text: severity });
}

function ruleRow(r) {
  return element('tr', { 'data-rule': r.id },
    element('td', {}, element('code', { text: r.id }), element('div', { class: 'hint', text: r.summary })),
    element('td', {}, badge(r.severity)),
    element('td', { class: 'num', text: String(r.count) }),
    element('td', { class: 'num', text: r.suppressed ? String(r.suppressed) : '' }),
    element('td', { class: 'num', text: r.count ? `${r.last_time_ms} ms` : '' }));
}

function findingItem(f) {
  const where = [`#${f.seq}`, `${f.time_ms} ms`, f.origin, f.conn ? `conn ${f.conn}` : null].filter(Boolean).join(' · ');
  return element('li', { class: `lint-${f.severity}`, 'data-seq': String(f.seq), 'data-rule': f.rule },
    element('div', { class: 'lint-head' }, badge(f.severity), ` ${f.rule} — ${where}`),
    element('p', { class: 'lint-detail', text: f.detail }),
    element('p', { class: 'lint-advice', text: `Fix: ${f.advice}` }),
    element('p', { class: 'lint-ref', text: `Reference: ${f.reference}` }));
}

export function startLint(section) {
  if (!document.getElementById('lint-style')) {
    document.head.append(element('style', { id: 'lint-style', text: STYLE }));
  }
  const mode = element('span', { id: 'emu-lint-mode', class: 'mono', text: '-' });
  const totals = element('span', { id: 'emu-lint-totals', text: '' });
  const all = element('input', { type: 'checkbox', id: 'emu-lint-all' });
  const reset = element('button', { type: 'button', id: 'emu-lint-reset', text: 'Reset counts' });
  const result = element('span', { id: 'emu-lint-result', class: 'result', role: 'status' });
  const body = element('tbody');
  const empty = element('p', { id: 'emu-lint-empty', class: 'hint', text: 'No findings so far.' });
  const recent = element('ol', { id: 'emu-lint-recent', class: 'lint-recent', 'aria-live': 'off' });
  section.replaceChildren(
    element('h2', { id: 'lint-h', text: 'Master lint' }),
    element('p', { class: 'hint' },
      'What the masters, hosts and scripts did to this drive that a real drive would punish: ignored controlwords, lost set-points, flash wear, SDO to a stopped node, requests that race their replies. ',
      'Configure it with ', element('code', { text: '--lint off|warn|strict' }), ' and the ', element('code', { text: '"lint"' }),
      ' section of --config (docs/lint.md).'),
    element('p', {}, 'Mode ', mode, ' — ', totals),
    element('div', { class: 'buttons' }, reset, element('label', {}, all, ' show every rule'), result),
    element('div', { class: 'scroll' },
      element('table', { id: 'emu-lint-rules' },
        element('thead', {}, element('tr', {},
          element('th', { scope: 'col', text: 'Rule' }), element('th', { scope: 'col', text: 'Severity' }),
          element('th', { scope: 'col', text: 'Count' }), element('th', { scope: 'col', text: 'Suppressed' }),
          element('th', { scope: 'col', text: 'Last (drive time)' }))),
        body)),
    element('h3', { text: 'Recent findings' }),
    empty,
    recent);

  let last = null;
  const render = (l) => {
    last = l;
    mode.textContent = l.mode + (l.timing ? '' : ' (timing rules off)');
    const t = l.totals;
    totals.textContent = `${t.error} error, ${t.warn} warn, ${t.info} info` +
      (t.suppressed ? `, ${t.suppressed} over the rate limit` : '') + (t.failing ? ` — ${t.failing} failing in strict tests` : '');
    body.replaceChildren(...l.rules.filter((r) => all.checked || r.count > 0).map(ruleRow));
    if (!body.childElementCount) {
      body.append(element('tr', {}, element('td', { colspan: '5', class: 'hint', text: 'No rule has fired.' })));
    }
    const newest = l.recent.slice(-SHOWN).reverse();
    empty.hidden = newest.length > 0;
    const seqs = newest.map((f) => String(f.seq)).join(',');
    if (recent.dataset.seqs !== seqs) {
      recent.replaceChildren(...newest.map(findingItem));
      recent.dataset.seqs = seqs;
    }
  };
  let busy = false;
  const poll = async () => {
    if (busy || document.hidden) return;
    busy = true;
    try {
      render(await api.get('/api/v1/lint'));
    } catch (e) {
      mode.textContent = describe(e);
    } finally {
      busy = false;
    }
  };
  all.addEventListener('change', () => last && render(last));
  reset.addEventListener('click', async () => {
    reset.disabled = true;
    showResult(result, true, '');
    try {
      render(await api.del('/api/v1/lint'));
      showResult(result, true, 'counts and findings cleared');
    } catch (e) {
      showResult(result, false, describe(e));
    } finally {
      reset.disabled = false;
    }
  });
  poll();
  setInterval(poll, POLL_MS);
  document.addEventListener('visibilitychange', poll);
}

const section = document.getElementById('lint');
if (section) startLint(section);
