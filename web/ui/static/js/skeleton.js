// What every page shares (web.md §3, §4): the menu bar and side menu, the header LEDs, the live
// footer and the page data the server rendered. A page module calls boot() once and gets the live
// connection (live.js) and the LEDs (led.js). The FAULHABER drive's page (web/README.md "FAULHABER
// drive") has no side menu, one bicolour status LED (#led-status) and its own footer fields: every
// footer field the status carries is shown in the element #ft-<name>, when the page has one.
import { live } from './live.js';
import { Leds } from './led.js';

// The model facts the server filled into the page (web/api/pages.hpp, page.data).
export const pageData = (() => {
  try {
    return JSON.parse(document.getElementById('page-data').textContent);
  } catch {
    return {};
  }
})();


// #ft-live: "MC Live ERR 7121h" with the ERR part a red link to the Info page (§4.2).
function showLive(el, text) {
  if (el.textContent === text && (!text.startsWith('MC Live ERR') || el.querySelector('a.err'))) return;
  if (text.startsWith('MC Live ERR')) {
    el.textContent = 'MC Live ';
    const a = document.createElement('a');
    a.href = '/index.html';
    a.className = 'err';
    a.textContent = text.slice('MC Live '.length);
    el.append(a);
  } else {
    el.textContent = text;
  }
}

// The FAULHABER MC's bicolour LED: data-color green/red/off, data-blink true/false (status `led`).
export function showStatusLed(el, s) {
  if (!s.led || !s.led.color) return;
  if (el.dataset.color !== s.led.color) el.dataset.color = s.led.color;
  const blink = String(!!s.led.blink);
  if (el.dataset.blink !== blink) el.dataset.blink = blink;
  if (s.stateName) el.setAttribute('aria-label', `status LED: ${s.stateName}`);
}

function markCurrent() {
  const here = location.pathname === '/' ? '/index.html' : location.pathname;
  for (const a of document.querySelectorAll('#menubar a, #sidemenu a')) {
    if (a.getAttribute('href') === here && !a.classList.contains('brand')) a.setAttribute('aria-current', 'page');
  }
}

function wireSideMenu() {
  const button = document.getElementById('menu-toggle');
  const menu = document.getElementById('sidemenu');
  if (!button || !menu) return;
  const set = (open) => {
    menu.hidden = !open;
    button.setAttribute('aria-expanded', String(open));
  };
  button.addEventListener('click', () => {
    set(menu.hidden);
    if (!menu.hidden) menu.querySelector('a').focus();
  });
  document.addEventListener('keydown', (e) => {
    if (e.key === 'Escape' && !menu.hidden) {
      set(false);
      button.focus();
    }
  });
  document.addEventListener('click', (e) => {
    if (!menu.hidden && !menu.contains(e.target) && e.target !== button) set(false);
  });
}

function wireFooter() {
  const els = new Map();
  const el = (k) => {
    if (!els.has(k)) els.set(k, document.getElementById(`ft-${k}`));
    return els.get(k);
  };
  live.on('status', (s) => {
    for (const [k, text] of Object.entries(s.footer)) {
      const e = el(k);
      if (!e) continue;
      if (k === 'live') showLive(e, text);
      else if (e.textContent !== text) e.textContent = text;
      // FAULHABER: the state field is red in Fault (like the LED)
      if (k === 'state') e.classList.toggle('err', text.startsWith('Fault'));
    }
  });
  const conn = document.getElementById('ft-conn');
  const words = { ws: 'live (WebSocket, 20 Hz)', poll: 'live (polling the JSON API)', offline: 'no answer from the emulator — retrying', connecting: 'connecting…' };
  const show = (m) => {
    conn.textContent = words[m] || m;
    conn.classList.toggle('error', m === 'offline');
  };
  show(live.mode);
  live.on('mode', show);
}

// topics: the WebSocket topics the page needs besides status ('scope', 'trace', 'udp').
export function boot({ topics = [] } = {}) {
  markCurrent();
  wireSideMenu();
  wireFooter();
  const green = document.getElementById('led-green');
  const leds = green ? new Leds(live, green, document.getElementById('led-yellow')) : null;
  const status = document.getElementById('led-status');
  if (status) live.on('status', (s) => showStatusLed(status, s));
  live.start(topics);
  return { live, leds, pageData };
}
