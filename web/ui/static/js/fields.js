// Fields bound to objects (web.md §3.6). A field shows its object's value and is refreshed while it
// does not have the focus — from the status stream where the snapshot carries the object, otherwise
// by one POST /api/v1/objects/read for every bound field of the page every 500 ms and after each
// write. Two kinds:
//   bindField: Enter or leaving a changed field writes the object at once (PUT /api/v1/objects/…);
//   EditForm:  edited fields keep the typed value until the page's Apply button writes them.
// On refusal the field is outlined red, gets aria-invalid="true" and the element <id>-error shows
// the abort code and message; the field then shows the object's real value again.
import { api, describe } from './api.js';
import { parseNumber } from './ui.js';

const PERIOD_MS = 500;

// ---- one poller for the whole page
const watchers = new Set();
let timer = null;
let running = null;

// Each watcher's values(list, startedAt) gets the performance.now() at which the read started, so
// that a field can ignore a read that began before its own last write (it would show the old value).
async function pollOnce() {
  const list = [...watchers].filter((w) => w.active());
  const keys = list.flatMap((w) => w.keys());
  if (!keys.length) return;
  const startedAt = performance.now();
  let values;
  try {
    values = await api.read(keys, { poll: true });
  } catch (e) {
    for (const w of list) w.failed(e);
    return;
  }
  let at = 0;
  for (const w of list) {
    const n = w.keys().length;
    w.values(values.slice(at, at + n), startedAt);
    at += n;
  }
}

// Reads now (after a write): a new read starts when the one in flight, if any, has ended; resolves
// when its values are shown.
export function refresh() {
  const next = (running || Promise.resolve()).then(pollOnce).finally(() => {
    if (running === next) running = null;
  });
  running = next;
  return next;
}

function schedule() {
  clearTimeout(timer);
  timer = setTimeout(async () => {
    await refresh();
    schedule();
  }, PERIOD_MS);
}

// w: {keys(): [[index, sub], …], values(list), failed(err), active(): bool}
export function watch(w) {
  watchers.add(w);
  if (!timer) schedule();
  refresh();
  return () => watchers.delete(w);
}

// ---- error display
export function errorElement(input) {
  const id = `${input.id}-error`;
  let el = document.getElementById(id);
  if (!el) {
    el = document.createElement('span');
    el.id = id;
    el.className = 'field-error';
    el.setAttribute('role', 'alert');
    input.insertAdjacentElement('afterend', el);
  }
  return el;
}

export function markError(input, message) {
  input.setAttribute('aria-invalid', 'true');
  errorElement(input).textContent = message;
}

export function clearError(input) {
  input.removeAttribute('aria-invalid');
  const el = document.getElementById(`${input.id}-error`);
  if (el) el.textContent = '';
}

const failedRead = (v) => v !== null && typeof v === 'object' && 'abortCode' in v;
const valueText = (v, format) => (failedRead(v) ? null : format(v));

// ---- immediate fields
// opts: index, sub (the object), fromStatus(s) → value (when the status snapshot carries it),
// format(value) → text, parse(text) → value | null, write(value) → Promise (default: PUT the object),
// live: the live connection (needed with fromStatus). A field whose format changes (hex/decimal) is
// redrawn through the returned show(value, true).
export function bindField(input, opts) {
  const format = opts.format || String;
  const parse = opts.parse || ((t) => parseNumber(t));
  const write = opts.write || ((v) => api.write(opts.index, opts.sub, v));
  const show = (v, force = false) => {
    if (failedRead(v)) {
      markError(input, `${v.abortCode} (the object cannot be read)`);
      return;
    }
    const text = valueText(v, format);
    if (force || document.activeElement !== input) {
      input.value = text;
      input.dataset.shown = text;
    }
  };
  let unwatch = () => {};
  let writtenAt = -Infinity;
  if (opts.fromStatus) {
    opts.live.on('status', (s) => {
      const v = opts.fromStatus(s);
      if (v !== undefined) show(v);
    });
  } else {
    unwatch = watch({ keys: () => [[opts.index, opts.sub]], values: ([v], startedAt) => startedAt > writtenAt && show(v), failed: () => {}, active: () => true });
  }
  const commit = async () => {
    if (input.value === input.dataset.shown) return;
    const v = parse(input.value);
    if (v === null) {
      markError(input, `"${input.value}" is not a number`);
      return;
    }
    input.dataset.shown = input.value;
    writtenAt = Infinity;
    try {
      await write(v);
      clearError(input);
    } catch (e) {
      markError(input, describe(e));
      input.dataset.shown = ''; // show the real value below, even while focused
      if (opts.fromStatus) {
        const s = opts.live.status && opts.fromStatus(opts.live.status);
        if (s !== undefined) show(s, true);
      } else {
        const [real] = await api.read([[opts.index, opts.sub]]).catch(() => [null]);
        if (real !== null) show(real, true);
      }
    }
    writtenAt = performance.now();
    refresh();
  };
  input.addEventListener('keydown', (e) => {
    if (e.key === 'Enter') {
      e.preventDefault();
      commit();
    }
  });
  input.addEventListener('change', commit);
  // unbind(): stop refreshing (the field is about to leave the page)
  return { commit, unbind: () => unwatch(), show };
}

// ---- fields written by an Apply button
export class EditForm {
  constructor() {
    this.fields = [];
    this.writtenAt = -Infinity;
    watch({
      keys: () => this.fields.map((f) => f.key()),
      values: (vals, startedAt) => startedAt > this.writtenAt && vals.forEach((v, i) => this.show(this.fields[i], v)),
      failed: () => {},
      active: () => this.fields.length > 0,
    });
  }

  // key() → [index, sub] (may change with the page's selection); format/parse as bindField;
  // onShow(value) after the field shows a new object value.
  add(input, { key, format = String, parse = (t) => parseNumber(t), onShow = null }) {
    const f = { input, key, format, parse, onShow, dirty: false, value: undefined };
    input.addEventListener('input', () => {
      f.dirty = true;
      input.classList.add('dirty');
    });
    this.fields.push(f);
    return f;
  }

  show(f, v) {
    f.value = v;
    if (failedRead(v)) markError(f.input, `${v.abortCode} (the object cannot be read)`);
    const text = valueText(v, f.format);
    if (text === null || f.dirty || document.activeElement === f.input) return;
    f.input.value = text;
    if (f.onShow) f.onShow(v);
  }

  // Sets a field as if typed (e.g. from a drop-down or the Teach button).
  setValue(f, text) {
    f.input.value = text;
    f.dirty = true;
    f.input.classList.add('dirty');
  }

  // Forget the edits (e.g. another input was selected) and show the objects' values.
  reset() {
    for (const f of this.fields) {
      f.dirty = false;
      f.input.classList.remove('dirty');
      clearError(f.input);
      f.input.value = '';
    }
    return refresh();
  }

  // Writes the edited fields in order; returns the number of refusals (each shown at its field).
  async apply() {
    let failures = 0;
    this.writtenAt = Infinity;
    for (const f of this.fields) {
      if (!f.dirty || f.input.disabled) continue;
      const v = f.parse(f.input.value);
      if (v === null) {
        markError(f.input, `"${f.input.value}" is not a number`);
        failures++;
        continue;
      }
      const [index, sub] = f.key();
      try {
        await api.write(index, sub, v);
        clearError(f.input);
      } catch (e) {
        markError(f.input, describe(e));
        failures++;
      }
      f.dirty = false;
      f.input.classList.remove('dirty');
    }
    this.writtenAt = performance.now();
    await refresh();
    return failures;
  }
}
