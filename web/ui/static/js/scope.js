// The live scope of web.md §5.3 on a <canvas>: position 6064h (left axis, user units), velocity
// 606Ch (right axis), current 6078h (‰ of rated, second right axis), optionally target 607Ah (on the
// position axis) and statusword bits 8 (moving) and 10 (target reached) as 0/1 lines. Samples are
// the drive's, every 5 ms of drive time, from the WebSocket topic "scope" (or polling, live.js);
// the last 60 s are kept. Controls: time window 2…60 s (also the mouse wheel and +/- keys), Run/
// Pause (freezes the display, not the sampling), Clear, per-channel show/hide and autoscale, a
// cursor read-out (mouse or arrow keys), CSV download. window.mcScope exposes sampleCount and
// lastSample for browser tests.
import { api } from './api.js';
import { element, reportError } from './ui.js';

const CHANNELS = [
  { key: 'pos', label: 'Position 6064h', color: '#1f6fb2', axis: 'pos', show: true },
  { key: 'target', label: 'Target 607Ah', color: '#8fb3da', axis: 'pos', show: true, dash: [6, 4] },
  { key: 'vel', label: 'Velocity 606Ch', color: '#d04a02', axis: 'vel', show: true },
  { key: 'cur', label: 'Current 6078h ‰', color: '#2a9d3a', axis: 'cur', show: true },
  { key: 'moving', label: 'Moving (bit 8)', color: '#8e44ad', axis: 'bit', show: false, bit: 8 },
  { key: 'reached', label: 'Reached (bit 10)', color: '#b8860b', axis: 'bit', show: false, bit: 10 },
];
const AXES = ['pos', 'vel', 'cur'];
const WINDOWS_S = [2, 5, 10, 30, 60];
const CAPACITY = 60000 / 5 + 200;
const MARGIN = { left: 72, right: 128, top: 10, bottom: 24 };

const fmt = (v) => {
  const a = Math.abs(v);
  if (a >= 1e6) return (v / 1e6).toFixed(a >= 1e7 ? 0 : 1) + 'M';
  if (a >= 1e4) return (v / 1e3).toFixed(a >= 1e5 ? 0 : 1) + 'k';
  return Number.isInteger(v) ? String(v) : v.toFixed(a >= 100 ? 0 : 1);
};

export class Scope {
  // prefix: id prefix of the canvas and controls ("sv" → #sv-scope, #sv-scope-pause, …)
  constructor(live, container, prefix) {
    this.live = live;
    this.prefix = prefix;
    this.t = new Float64Array(CAPACITY);
    this.data = { pos: new Float64Array(CAPACITY), vel: new Float64Array(CAPACITY), cur: new Float64Array(CAPACITY), target: new Float64Array(CAPACITY), sw: new Uint16Array(CAPACITY) };
    this.head = 0; // index of the oldest sample
    this.size = 0;
    this.sampleCount = 0;
    this.windowMs = 10000;
    this.paused = false;
    this.frozenEnd = 0;
    this.cursorT = null;
    this.auto = { pos: true, vel: true, cur: true };
    this.range = { pos: [-1, 1], vel: [-1, 1], cur: [-1, 1] };
    this.show = Object.fromEntries(CHANNELS.map((c) => [c.key, c.show]));
    this.dirty = true;
    this.build(container);
    live.on('scope', (b) => this.append(b));
    this.loadHistory();
    const draw = () => {
      if (this.dirty) this.draw();
      requestAnimationFrame(draw);
    };
    requestAnimationFrame(draw);
    const scope = this;
    window.mcScope = {
      get sampleCount() {
        return scope.sampleCount;
      },
      get lastSample() {
        return scope.size ? scope.sampleAt(scope.size - 1) : null;
      },
      get paused() {
        return scope.paused;
      },
      get windowMs() {
        return scope.windowMs;
      },
      csv: () => scope.csv(),
    };
  }

  id(name) {
    return `${this.prefix}-scope${name ? '-' + name : ''}`;
  }

  build(container) {
    const windowSel = element('select', { id: this.id('window'), 'aria-label': 'Time window', onchange: (e) => this.setWindow(Number(e.target.value) * 1000) },
      ...WINDOWS_S.map((s) => element('option', { value: s, selected: s * 1000 === this.windowMs, text: `${s} s` })));
    this.windowSel = windowSel;
    this.pauseBtn = element('button', { type: 'button', id: this.id('pause'), onclick: () => this.setPaused(!this.paused), text: 'Pause' });
    const clear = element('button', { type: 'button', id: this.id('clear'), onclick: () => this.clear(), text: 'Clear' });
    const csv = element('button', { type: 'button', id: this.id('csv'), onclick: () => this.download(), text: 'CSV' });
    const channels = element('div', { class: 'channels' });
    for (const c of CHANNELS) {
      const box = element('input', { type: 'checkbox', id: this.id(`show-${c.key}`), checked: c.show, onchange: (e) => { this.show[c.key] = e.target.checked; this.dirty = true; } });
      const swatch = element('span', { style: `color:${c.color}`, text: '■ ' });
      channels.append(element('label', {}, box, swatch, c.label));
    }
    for (const a of AXES) {
      const box = element('input', { type: 'checkbox', id: this.id(`auto-${a}`), checked: true, onchange: (e) => { this.auto[a] = e.target.checked; this.dirty = true; } });
      channels.append(element('label', { title: `autoscale the ${a} axis; off keeps the current range` }, box, `auto ${a}`));
    }
    this.canvas = element('canvas', { id: this.id(), tabindex: '0', role: 'img', 'aria-label': 'Scope: position, velocity and current over time (arrow keys move the cursor, + and - zoom, space pauses)' });
    this.readout = element('div', { class: 'readout', id: this.id('readout'), 'aria-live': 'off' });
    container.append(
      element('div', { class: 'controls' }, element('label', {}, 'Window ', windowSel), this.pauseBtn, clear, csv),
      element('div', { class: 'controls' }, channels),
      this.canvas,
      this.readout,
    );
    this.canvas.addEventListener('mousemove', (e) => {
      const r = this.canvas.getBoundingClientRect();
      this.cursorT = this.timeAt(e.clientX - r.left, r.width);
      this.dirty = true;
    });
    this.canvas.addEventListener('mouseleave', () => {
      this.cursorT = null;
      this.dirty = true;
    });
    this.canvas.addEventListener('wheel', (e) => {
      e.preventDefault();
      this.zoom(e.deltaY < 0 ? -1 : 1);
    }, { passive: false });
    this.canvas.addEventListener('keydown', (e) => {
      const [start, end] = this.span();
      if (e.key === 'ArrowLeft' || e.key === 'ArrowRight') {
        const step = (end - start) / 50;
        this.cursorT = Math.min(end, Math.max(start, (this.cursorT ?? end) + (e.key === 'ArrowLeft' ? -step : step)));
      } else if (e.key === '+' || e.key === '=') this.zoom(-1);
      else if (e.key === '-') this.zoom(1);
      else if (e.key === ' ') this.setPaused(!this.paused);
      else if (e.key === 'Escape') this.cursorT = null;
      else return;
      e.preventDefault();
      this.dirty = true;
    });
    new ResizeObserver(() => (this.dirty = true)).observe(this.canvas);
  }

  // The last 10 s before the page opened, merged in front of what the live stream already brought.
  async loadHistory() {
    try {
      const now = this.live.status ? this.live.status.timeMs : (await api.get('/api/v1/clock')).timeMs;
      const history = await api.get(`/api/v1/scope?sinceMs=${Math.max(0, now - 10000)}`);
      const kept = this.block(0, this.size);
      this.clear();
      this.append(history);
      this.append(kept);
    } catch (e) {
      reportError(e);
    }
  }

  // samples j0 … j1-1 as a block of consecutive 5 ms samples (t0 + 5k may skip: each keeps its time)
  block(j0, j1) {
    const out = { t0: 0, sampleMs: 0, times: [], pos: [], vel: [], cur: [], target: [], sw: [] };
    for (let j = j0; j < j1; j++) {
      const s = this.sampleAt(j);
      out.times.push(s.timeMs);
      for (const k of ['pos', 'vel', 'cur', 'target', 'sw']) out[k].push(s[k]);
    }
    return out;
  }

  append(b) {
    for (let k = 0; k < b.pos.length; k++) {
      const t = b.times ? b.times[k] : b.t0 + b.sampleMs * k;
      if (this.size && t <= this.t[(this.head + this.size - 1) % CAPACITY]) {
        if (t + 1000 < this.t[(this.head + this.size - 1) % CAPACITY]) this.clear(); // drive time went back: power cycle
        else continue;
      }
      const i = (this.head + this.size) % CAPACITY;
      if (this.size === CAPACITY) this.head = (this.head + 1) % CAPACITY;
      else this.size++;
      this.t[i] = t;
      this.data.pos[i] = b.pos[k];
      this.data.vel[i] = b.vel[k];
      this.data.cur[i] = b.cur[k];
      this.data.target[i] = b.target[k];
      this.data.sw[i] = b.sw[k];
      this.sampleCount++;
    }
    if (!this.paused) this.dirty = true;
  }

  clear() {
    this.head = 0;
    this.size = 0;
    this.cursorT = null;
    this.frozenEnd = 0;
    this.dirty = true;
  }

  setWindow(ms) {
    this.windowMs = ms;
    this.windowSel.value = String(ms / 1000);
    this.dirty = true;
  }

  zoom(dir) {
    const i = WINDOWS_S.indexOf(this.windowMs / 1000);
    const next = WINDOWS_S[Math.min(WINDOWS_S.length - 1, Math.max(0, i + dir))];
    this.setWindow(next * 1000);
  }

  setPaused(p) {
    this.paused = p;
    this.frozenEnd = this.lastTime();
    this.pauseBtn.textContent = p ? 'Run' : 'Pause';
    this.pauseBtn.setAttribute('aria-pressed', String(p));
    this.dirty = true;
  }

  lastTime() {
    return this.size ? this.t[(this.head + this.size - 1) % CAPACITY] : 0;
  }

  span() {
    const end = this.paused ? this.frozenEnd : this.lastTime();
    return [end - this.windowMs, end];
  }

  // j-th sample (0 = oldest) as an object
  sampleAt(j) {
    const i = (this.head + j) % CAPACITY;
    const sw = this.data.sw[i];
    return { timeMs: this.t[i], pos: this.data.pos[i], vel: this.data.vel[i], cur: this.data.cur[i], target: this.data.target[i], sw, moving: (sw >> 8) & 1, reached: (sw >> 10) & 1 };
  }

  // first j with t ≥ time
  indexAt(time) {
    let lo = 0;
    let hi = this.size;
    while (lo < hi) {
      const mid = (lo + hi) >> 1;
      if (this.t[(this.head + mid) % CAPACITY] < time) lo = mid + 1;
      else hi = mid;
    }
    return lo;
  }

  timeAt(x, width) {
    const [start, end] = this.span();
    const plotW = width - MARGIN.left - MARGIN.right;
    return start + ((x - MARGIN.left) / plotW) * (end - start);
  }

  value(key, i) {
    if (key === 'moving') return (this.data.sw[i] >> 8) & 1;
    if (key === 'reached') return (this.data.sw[i] >> 10) & 1;
    return this.data[key][i];
  }

  csv() {
    const rows = ['timeMs,pos,vel,cur,target,moving,reached'];
    for (let j = 0; j < this.size; j++) {
      const s = this.sampleAt(j);
      rows.push(`${s.timeMs},${s.pos},${s.vel},${s.cur},${s.target},${s.moving},${s.reached}`);
    }
    return rows.join('\n') + '\n';
  }

  download() {
    const url = URL.createObjectURL(new Blob([this.csv()], { type: 'text/csv' }));
    const a = element('a', { href: url, download: `mcemu-scope-${this.lastTime()}.csv` });
    document.body.append(a);
    a.click();
    a.remove();
    setTimeout(() => URL.revokeObjectURL(url), 10000);
  }

  updateRanges(j0, j1) {
    for (const axis of AXES) {
      if (!this.auto[axis]) continue;
      let lo = Infinity;
      let hi = -Infinity;
      for (const c of CHANNELS) {
        if (c.axis !== axis || !this.show[c.key]) continue;
        const arr = this.data[c.key];
        for (let j = j0; j < j1; j++) {
          const v = arr[(this.head + j) % CAPACITY];
          if (v < lo) lo = v;
          if (v > hi) hi = v;
        }
      }
      if (lo === Infinity) continue;
      if (hi - lo < 1e-9) {
        const pad = Math.max(1, Math.abs(hi) * 0.1);
        lo -= pad;
        hi += pad;
      } else {
        const pad = (hi - lo) * 0.06;
        lo -= pad;
        hi += pad;
      }
      this.range[axis] = [lo, hi];
    }
  }

  draw() {
    this.dirty = false;
    const cv = this.canvas;
    const dpr = window.devicePixelRatio || 1;
    const w = cv.clientWidth;
    const h = cv.clientHeight;
    if (!w || !h) return;
    if (cv.width !== Math.round(w * dpr) || cv.height !== Math.round(h * dpr)) {
      cv.width = Math.round(w * dpr);
      cv.height = Math.round(h * dpr);
    }
    const g = cv.getContext('2d');
    g.setTransform(dpr, 0, 0, dpr, 0, 0);
    g.fillStyle = '#fff';
    g.fillRect(0, 0, w, h);
    const [start, end] = this.span();
    const px = MARGIN.left;
    const pw = Math.max(10, w - MARGIN.left - MARGIN.right);
    const showBits = this.show.moving || this.show.reached;
    const bitsH = showBits ? 34 : 0;
    const py = MARGIN.top;
    const ph = Math.max(10, h - MARGIN.top - MARGIN.bottom - bitsH);
    const j0 = Math.max(0, this.indexAt(start) - 1);
    const j1 = this.indexAt(end + 0.001);
    this.updateRanges(j0, j1);

    // grid and time labels
    g.strokeStyle = '#e3e8ec';
    g.lineWidth = 1;
    g.font = '11px system-ui, sans-serif';
    g.fillStyle = '#5b6670';
    g.textAlign = 'center';
    const stepS = [0.25, 0.5, 1, 2, 5, 10][[2, 5, 10, 30, 60].indexOf(this.windowMs / 1000)] ?? 1;
    for (let s = 0; s <= this.windowMs / 1000 + 1e-9; s += stepS) {
      const x = px + pw - (s * 1000 * pw) / this.windowMs;
      g.beginPath();
      g.moveTo(x, py);
      g.lineTo(x, py + ph + bitsH);
      g.stroke();
      g.fillText(s === 0 ? '0 s' : `−${s} s`, x, h - 7);
    }
    for (let k = 0; k <= 4; k++) {
      const y = py + (k * ph) / 4;
      g.beginPath();
      g.moveTo(px, y);
      g.lineTo(px + pw, y);
      g.stroke();
    }
    g.strokeStyle = '#9aa7b2';
    g.strokeRect(px, py, pw, ph + bitsH);

    // axis labels: position left, velocity and current right
    const axisX = { pos: px - 6, vel: px + pw + 6, cur: px + pw + 66 };
    const axisColor = { pos: CHANNELS[0].color, vel: CHANNELS[2].color, cur: CHANNELS[3].color };
    for (const axis of AXES) {
      const shown = CHANNELS.some((c) => c.axis === axis && this.show[c.key]);
      if (!shown) continue;
      const [lo, hi] = this.range[axis];
      g.fillStyle = axisColor[axis];
      g.textAlign = axis === 'pos' ? 'right' : 'left';
      for (let k = 0; k <= 4; k++) {
        const v = hi - ((hi - lo) * k) / 4;
        g.fillText(fmt(Math.round(v * 10) / 10), axisX[axis], py + (k * ph) / 4 + 4);
      }
    }

    // traces, decimated to min/max per pixel column
    const xOf = (t) => px + ((t - start) / (end - start)) * pw;
    g.save();
    g.beginPath();
    g.rect(px, py, pw, ph + bitsH);
    g.clip();
    for (const c of CHANNELS) {
      if (!this.show[c.key] || j1 <= j0) continue;
      let yOf;
      if (c.axis === 'bit') {
        const lane = c.key === 'moving' ? 0 : 1;
        const top = py + ph + 3 + lane * 16;
        yOf = (v) => top + (v ? 0 : 12);
      } else {
        const [lo, hi] = this.range[c.axis];
        yOf = (v) => py + ph - ((v - lo) / (hi - lo)) * ph;
      }
      g.strokeStyle = c.color;
      g.lineWidth = 1.6;
      g.setLineDash(c.dash || []);
      g.beginPath();
      let col = null;
      let mn = 0;
      let mx = 0;
      let first = true;
      const flush = () => {
        if (col === null) return;
        if (first) {
          g.moveTo(col, yOf(mn));
          first = false;
        }
        g.lineTo(col, yOf(mn));
        if (mx !== mn) g.lineTo(col, yOf(mx));
      };
      for (let j = j0; j < j1; j++) {
        const i = (this.head + j) % CAPACITY;
        const x = Math.round(xOf(this.t[i]));
        const v = this.value(c.key, i);
        if (x !== col) {
          flush();
          col = x;
          mn = mx = v;
        } else {
          if (v < mn) mn = v;
          if (v > mx) mx = v;
        }
      }
      flush();
      g.stroke();
    }
    g.restore();
    g.setLineDash([]);

    // cursor
    if (this.cursorT !== null && this.size) {
      const j = Math.min(this.size - 1, this.indexAt(this.cursorT));
      const s = this.sampleAt(j);
      const x = xOf(s.timeMs);
      g.strokeStyle = '#333';
      g.beginPath();
      g.moveTo(x, py);
      g.lineTo(x, py + ph + bitsH);
      g.stroke();
      const ago = ((this.lastTime() - s.timeMs) / 1000).toFixed(3);
      this.readout.textContent = `t=${s.timeMs} ms (−${ago} s)  pos ${s.pos}  target ${s.target}  vel ${s.vel}  cur ${s.cur}‰  moving ${s.moving}  reached ${s.reached}`;
    } else {
      this.readout.textContent = this.paused ? 'paused — sampling continues; Run shows the newest data' : `${this.size} samples (5 ms) — move the mouse over the plot for values`;
    }
    if (this.paused && !this.size) this.readout.textContent = 'paused';
  }
}
