// What every page shares (web.md §3, §4): the menu bar and side menu, the header LEDs, the live
// footer and the page data the server rendered. A page module calls boot() once and gets the live
// connection (live.js) and the LEDs (led.js).
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

const FOOTER = ['statwd', 'opmode', 'python', 'pos', 'vel', 'temp', 'io'];

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

function markCurrent() {
  const here = location.pathname === '/' ? '/index.html' : location.pathname;
  for (const a of document.querySelectorAll('#menubar a, #sidemenu a')) {
    if (a.getAttribute('href') === here && !a.classList.contains('brand')) a.setAttribute('aria-current', 'page');
  }
}

function wireSideMenu() {
  const button = document.getElementById('menu-toggle');
  const menu = document.getElementById('sidemenu');
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
  const els = Object.fromEntries(FOOTER.map((k) => [k, document.getElementById(`ft-${k}`)]));
  const liveEl = document.getElementById('ft-live');
  live.on('status', (s) => {
    showLive(liveEl, s.footer.live);
    for (const k of FOOTER) if (els[k].textContent !== s.footer[k]) els[k].textContent = s.footer[k];
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
  const leds = new Leds(live, document.getElementById('led-green'), document.getElementById('led-yellow'));
  live.start(topics);
  return { live, leds, pageData };
}
