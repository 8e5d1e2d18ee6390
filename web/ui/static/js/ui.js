// Small helpers shared by the page modules: element lookup, number formats of the drive, and the
// action wrapper that shows every outcome next to the control (errors in words, never swallowed).
import { describe } from './api.js';

export const $ = (id) => {
  const el = document.getElementById(id);
  if (!el) throw new Error(`page has no element #${id}`);
  return el;
};

// H4 of web.md §4.2: upper-case hex, at least 4 digits, then "h".
export const h4 = (n) => (n >>> 0).toString(16).toUpperCase().padStart(4, '0') + 'h';
export const hex = (n, digits = 4) => (n >>> 0).toString(16).toUpperCase().padStart(digits, '0') + 'h';

// "0400h", "0x400", "400" as hex (hex = true) or "1200", "-5", "0x10", "10h" (decimal unless marked).
export function parseNumber(text, { hex: asHex = false } = {}) {
  const t = String(text).trim();
  let m = /^(-?)(?:0x([0-9a-f]+)|([0-9a-f]+)h)$/i.exec(t);
  if (m) return (m[1] ? -1 : 1) * parseInt(m[2] || m[3], 16);
  if (asHex && /^[0-9a-f]+$/i.test(t)) return parseInt(t, 16);
  if (/^-?\d+$/.test(t)) return parseInt(t, 10);
  return null;
}

// The text of a result element: ok → green, otherwise red; '' clears it.
export function showResult(el, ok, text) {
  el.textContent = text;
  el.classList.toggle('ok', !!ok && text !== '');
  el.classList.toggle('err', !ok && text !== '');
}

// Runs fn when the button is clicked: the button is disabled meanwhile; fn's resolved text (if any)
// is shown in resultEl as success, a rejection as the error in words.
export function action(button, fn, resultEl = null) {
  button.addEventListener('click', async () => {
    button.disabled = true;
    if (resultEl) showResult(resultEl, true, '');
    try {
      const text = await fn();
      if (resultEl) showResult(resultEl, true, typeof text === 'string' ? text : '');
    } catch (e) {
      if (resultEl) showResult(resultEl, false, describe(e));
      else reportError(e);
    } finally {
      button.disabled = false;
    }
  });
}

// The page-wide message area (#page-error, created on first use) for errors without a place of their own.
export function reportError(e) {
  let el = document.getElementById('page-error');
  if (!el) {
    el = document.createElement('p');
    el.id = 'page-error';
    el.className = 'notice error';
    el.setAttribute('role', 'alert');
    document.querySelector('main').prepend(el);
  }
  el.textContent = describe(e);
}

export function element(tag, attrs = {}, ...children) {
  const el = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (k === 'class') el.className = v;
    else if (k === 'text') el.textContent = v;
    else if (k.startsWith('on')) el.addEventListener(k.slice(2), v);
    else if (v === true) el.setAttribute(k, '');
    else if (v !== false && v !== null && v !== undefined) el.setAttribute(k, v);
  }
  el.append(...children);
  return el;
}
