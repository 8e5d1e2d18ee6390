// The Emulator page's console (udp-debug.md §6: every UDP debug message, live) and trace view
// (web.md §8.6: the newest events with channel filters, pause, control bytes as <CR>, <LF>, <XX>).
import { api, describe } from '../api.js';
import { $, element, reportError, showResult } from '../ui.js';

const CHANNELS = (document.getElementById('emu-trace-channels')?.dataset.channels || 'refgo,slcan,udp,http,script,drive,api').split(',');
const MAX_LINES = 500;
const CTL = { 9: 'TAB', 10: 'LF', 13: 'CR' };

// Text with control bytes as marked <CR>, <LF>, <TAB>, <XX> elements (Docklight style).
// keepNewlines: "\n" stays a line break (the console), otherwise it is <LF> too (the trace).
function docklight(text, keepNewlines = false) {
  const parts = [];
  let plain = '';
  for (const ch of text) {
    const c = ch.codePointAt(0);
    if ((c < 32 || c === 127) && !(keepNewlines && c === 10)) {
      if (plain) parts.push(plain);
      plain = '';
      parts.push(element('span', { class: 'ctl', text: `<${CTL[c] || c.toString(16).toUpperCase().padStart(2, '0')}>` }));
    } else plain += ch;
  }
  if (plain) parts.push(plain);
  return parts;
}

function trimLines(pre) {
  while (pre.childElementCount > MAX_LINES) pre.firstElementChild.remove();
}

function stickToBottom(pre, fn) {
  const atBottom = pre.scrollTop + pre.clientHeight >= pre.scrollHeight - 8;
  fn();
  if (atBottom) pre.scrollTop = pre.scrollHeight;
}

// ---- console
function startConsole(live) {
  const pre = $('emu-console');
  // one message per line: its line end dropped, inner line ends as line breaks
  const line = (text) => element('div', {}, ...docklight(text.replace(/(\r\n|\n\r|\r|\n)$/, '').replace(/\r\n|\n\r/g, '\n'), true));
  const replace = (messages) => stickToBottom(pre, () => pre.replaceChildren(...messages.slice(-MAX_LINES).map(line)));
  live.on('udp', (m) => stickToBottom(pre, () => {
    pre.append(line(m.text));
    trimLines(pre);
  }));
  live.on('udp-history', (m) => replace(m.messages));
  $('emu-console-clear').addEventListener('click', () => pre.replaceChildren());
  const listeners = async () => {
    try {
      const u = await api.poll('/api/v1/udp');
      $('emu-listeners').textContent = u.listeners.length ? u.listeners.map((l) => `${l.address}:${l.port}`).join(', ') : 'none';
      const c = u.counters;
      $('emu-udp-counters').textContent = `datagrams sent ${c.datagramsSent}, dropped ${c.datagramsDropped}, received ${c.datagramsReceived}, ignored ${c.ignoredPayloads}; backlog ${u.backlog.messages} messages (${u.backlog.bytes} bytes)`;
      return u;
    } catch (e) {
      $('emu-listeners').textContent = describe(e);
      return null;
    }
  };
  listeners().then((u) => u && !pre.childElementCount && replace(u.messages));
  setInterval(listeners, 2000);
}

// ---- trace
function startTrace(live) {
  const pre = $('emu-trace');
  const boxes = {};
  for (const ch of CHANNELS) {
    boxes[ch] = element('input', { type: 'checkbox', id: `emu-trace-ch-${ch}`, checked: ch !== 'http' });
    $('emu-trace-channels').append(element('label', {}, boxes[ch], ` ${ch}`));
  }
  const selected = () => CHANNELS.filter((c) => boxes[c].checked);
  // The pages' own polling (web.md §8.6: events marked `polling`) is left out unless asked for.
  const hidePolling = $('emu-trace-polling');
  let paused = false;
  let lastSeq = -1;
  const held = [];
  const state = $('emu-trace-state');
  const row = (e) => {
    const flags = ['overlong', 'toScript', 'discarded', 'ignored', 'polling'].filter((f) => e[f]).map((f) => ` [${f}]`).join('');
    return element('div', { class: `trace-${e.dir}`, 'data-channel': e.channel, 'data-seq': String(e.seq) },
      `${e.timeMs} ${e.channel} ${e.dir} ${e.conn ? '#' + e.conn : '-'} `, ...docklight(e.text), flags);
  };
  const add = (events) => {
    const wanted = new Set(selected());
    const newer = events.filter((e) => e.seq > lastSeq);
    if (newer.length) lastSeq = newer[newer.length - 1].seq;
    const fresh = newer.filter((e) => wanted.has(e.channel) && !(hidePolling.checked && e.polling));
    if (!fresh.length) return;
    if (paused) {
      held.push(...fresh);
      state.textContent = `paused — ${held.length} new events held`;
      return;
    }
    stickToBottom(pre, () => {
      pre.append(...fresh.map(row));
      trimLines(pre);
    });
  };
  const load = async () => {
    const ch = selected();
    if (!ch.length) {
      pre.replaceChildren();
      return;
    }
    try {
      const polling = hidePolling.checked ? '&excludePolling=1' : '';
      const t = await api.get(`/api/v1/trace?limit=200&channels=${ch.join(',')}&since=0${polling}`);
      lastSeq = -1;
      pre.replaceChildren();
      add(t.events);
    } catch (e) {
      showResult(state, false, describe(e));
    }
  };
  live.on('trace', (m) => add(m.events));
  const changed = () => {
    const ch = selected();
    live.setTraceChannels(ch.length === CHANNELS.length ? null : ch.length ? ch : ['api']);
    load();
  };
  for (const ch of CHANNELS) boxes[ch].addEventListener('change', changed);
  hidePolling.addEventListener('change', () => load());
  live.setTraceChannels(selected());
  const pause = $('emu-trace-pause');
  pause.addEventListener('click', () => {
    paused = !paused;
    pause.textContent = paused ? 'Run' : 'Pause';
    pause.setAttribute('aria-pressed', String(paused));
    if (!paused) {
      stickToBottom(pre, () => {
        pre.append(...held.splice(0).map(row));
        trimLines(pre);
      });
      state.textContent = '';
    } else state.textContent = 'paused';
  });
  $('emu-trace-clear').addEventListener('click', () => {
    pre.replaceChildren();
    held.length = 0;
  });
  load().catch(reportError);
}

export function startLog(live) {
  if (document.getElementById('emu-console')) startConsole(live); // the FAULHABER page has no UDP console
  startTrace(live);
}
