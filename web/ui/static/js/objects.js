// The object browser (web.md §5.4, and the FAULHABER drive's Emulator page): every entry of the
// dictionary (GET /api/v1/objects) with index, sub-index, name, type, access, value (decimal or
// hex) and factory value; a filter box, an optional index-range selector; rw entries are edited in
// place with the behaviour of §3.6 (fields.js), read-only values are read again every second.
// Value cells have the id obj-IIII-SS (e.g. obj-6081-00).
import { api } from './api.js';
import { element, parseNumber, reportError } from './ui.js';
import { bindField } from './fields.js';

// opts: tbody, filter (input), hex (checkbox), count (element), group (optional select whose value
// is "" or "lo-hi", a hex index range such as "2000-3fff").
export function objectBrowser({ tbody, filter, hex: hexBox, count, group = null }) {
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
  const inGroup = (e) => {
    if (!group || !group.value) return true;
    const [lo, hi] = group.value.split('-').map((x) => parseInt(x, 16));
    const i = parseInt(e.index, 16);
    return i >= lo && i <= hi;
  };

  function render() {
    for (const b of bound) b.unbind();
    bound = [];
    const q = filter.value.trim().toLowerCase().replace(/h$/, '');
    const shown = entries.filter((e) => inGroup(e) && (!q || `${e.index} ${e.index.slice(0, 4)}.${e.sub.slice(0, 2)} ${e.name}`.toLowerCase().includes(q)));
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
    count.textContent = `${shown.length} of ${entries.length} entries`;
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
  if (group) group.addEventListener('change', render);

  api.get('/api/v1/objects').then((list) => {
    entries = list;
    render();
  }).catch(reportError);
}
