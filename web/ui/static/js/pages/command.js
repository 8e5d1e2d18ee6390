// Command & Parameters (web.md §5.4, §7): the RefGo line, Store Permanently / Factory Reset behind
// confirm(), and the object browser with inline editing (§3.6).
import { boot } from '../skeleton.js';
import { api, describe } from '../api.js';
import { $, action } from '../ui.js';
import { markError, clearError } from '../fields.js';
import { objectBrowser } from '../objects.js';

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

// ---- object browser (objects.js)
objectBrowser({ tbody: document.querySelector('#cmd-objects tbody'), filter: $('cmd-filter'), hex: $('cmd-hex'), count: $('cmd-count') });
