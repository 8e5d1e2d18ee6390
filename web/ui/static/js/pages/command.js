// Command & Parameters (web.md §5.4, §7): the RefGo line, Store Permanently / Factory Reset behind
// confirm(), and the object browser with inline editing (§3.6).
import { boot } from '../skeleton.js';
import { api, describe } from '../api.js';
import { $, action, element, parseNumber, reportError } from '../ui.js';
import { bindField, markError, clearError } from '../fields.js';

boot();

// ---- RefGo line
const input = $('cmd-input');
const response = $('cmd-response');
const history = [];
let recall = 0;
input.addEventListener('keydown', async (e) => {
  if (e.key === 'ArrowUp' || e.key === 'ArrowDown') {
    e.preventDefault();
    recall = Math.max(0, Math.min(history.length, recall + (e.key === 'ArrowUp' ? -1 : 1)));
    input.value = history[recall] ?? '';
    return;
  }
  if (e.key !== 'Enter') return;
  e.preventDefault();
  const line = input.value;
  if (line.trim() !== '' && history[history.length - 1] !== line) {
    history.push(line);
    if (history.length > 50) history.shift();
  }
  recall = history.length;
  try {
    const r = await api.post('/api/v1/refgo', { line });
    response.value = r.answer ?? '';
    response.classList.toggle('error', !r.ok);
    clearError(input);
  } catch (err) {
    response.value = '';
    markError(input, describe(err));
  }
  // counts the lines answered (a command without an answer line leaves the response empty again)
  response.dataset.answered = String(Number(response.dataset.answered || 0) + 1);
});

// ---- Store / Factory Reset (web.md §7): only after the confirm dialog
action($('cmd-store'), async () => {
  if (!confirm('Store Permanently - Are you sure?')) return '';
  await api.post('/api/v1/store');
  return 'Stored';
}, $('cmd-store-result'));
action($('cmd-factory'), async () => {
  if (!confirm('Factory Reset - Are you sure?')) return '';
  await api.post('/api/v1/factory-reset');
  return 'Factory settings loaded';
}, $('cmd-factory-result'));

// ---- object browser
const tbody = document.querySelector('#cmd-objects tbody');
const filter = $('cmd-filter');
const hexBox = $('cmd-hex');
let entries = [];
let bound = [];

const bits = (type) => Number((/(\d+)$/.exec(type) || [0, 32])[1]);
const formatValue = (e) => (v) => {
  if (typeof v !== 'number' || !hexBox.checked) return String(v);
  const width = bits(e.type);
  const u = width >= 32 ? v >>> 0 : v < 0 ? v + 2 ** width : v;
  return u.toString(16).toUpperCase() + 'h';
};
const parseValue = (e) => (text) => {
  if (e.type === 'VISIBLE_STRING') return text;
  return parseNumber(text, { hex: hexBox.checked });
};
const idOf = (e) => `obj-${e.index.slice(0, 4)}-${e.sub.slice(0, 2)}`;

function render() {
  for (const b of bound) b.unbind();
  bound = [];
  const q = filter.value.trim().toLowerCase().replace(/h$/, '');
  const shown = entries.filter((e) => !q || `${e.index} ${e.index.slice(0, 4)}.${e.sub.slice(0, 2)} ${e.name}`.toLowerCase().includes(q));
  const rows = shown.map((e) => {
    const writable = e.access === 'rw' || e.access === 'wo';
    let cell;
    if (writable) {
      const field = element('input', { type: 'text', id: idOf(e), class: 'mono', size: '14', 'aria-label': `${e.index}.${e.sub} ${e.name}` });
      bound.push(bindField(field, { index: parseInt(e.index, 16), sub: parseInt(e.sub, 16), format: formatValue(e), parse: parseValue(e) }));
      cell = element('td', {}, field);
    } else {
      cell = element('td', { id: idOf(e), class: 'mono', text: formatValue(e)(e.value) });
    }
    return element('tr', {}, element('td', { class: 'mono', text: e.index }), element('td', { class: 'mono', text: e.sub }), element('td', { text: e.name }), element('td', { text: e.type }), element('td', { text: e.access }), cell, element('td', { class: 'mono', text: formatValue(e)(e.factory) }));
  });
  tbody.replaceChildren(...rows);
  $('cmd-count').textContent = `${shown.length} of ${entries.length} entries`;
  refreshReadOnly(shown);
}

// Read-only values change too (6041h, 6064h …): one read of the shown ones every second.
let readOnlyTimer = null;
function refreshReadOnly(shown) {
  clearTimeout(readOnlyTimer);
  const ro = shown.filter((e) => !(e.access === 'rw' || e.access === 'wo'));
  const tick = async () => {
    try {
      const values = ro.length ? await api.read(ro.map((e) => [parseInt(e.index, 16), parseInt(e.sub, 16)]), { poll: true }) : [];
      values.forEach((v, i) => {
        const el = document.getElementById(idOf(ro[i]));
        if (el && !(v && typeof v === 'object')) {
          ro[i].value = v;
          const text = formatValue(ro[i])(v);
          if (el.textContent !== text) el.textContent = text;
        }
      });
    } catch (e) {
      reportError(e);
    }
    readOnlyTimer = setTimeout(tick, 1000);
  };
  readOnlyTimer = setTimeout(tick, 1000);
}

let filterTimer = null;
filter.addEventListener('input', () => {
  clearTimeout(filterTimer);
  filterTimer = setTimeout(render, 150);
});
hexBox.addEventListener('change', render);

api.get('/api/v1/objects').then((list) => {
  entries = list;
  render();
}).catch(reportError);
