// The live data of a page (web.md §10): one WebSocket to /api/v1/ws carrying status (20 Hz), and
// the topics the page asks for (scope, trace, udp). When the WebSocket cannot be opened or drops,
// the same data is polled from the JSON API (status every 80 ms, i.e. > 10 Hz; scope, trace and
// the UDP console every 250–1000 ms) and a new WebSocket is tried every 3 s.
//
// Events (live.on(type, fn)): 'status' (the §8.2 snapshot, newest first-come; never an older seq),
// 'scope' ({t0, sampleMs, pos, vel, cur, target, sw}), 'trace' ({events}), 'udp' ({text}),
// 'udp-history' ({messages}: the console's last messages, on start and while polling), 'mode'
// ('ws' | 'poll' | 'offline': no answer from the emulator).
import { api } from './api.js';

const STATUS_POLL_MS = 80; // ≥ 10 Hz with some jitter (web.md §4.3)
const SLOW_POLL_MS = 250;
const RECONNECT_MS = 3000;
const OPEN_TIMEOUT_MS = 2500;

class Live {
  constructor() {
    this.handlers = new Map();
    this.topics = new Set(['status']);
    this.traceChannels = null;
    this.mode = 'connecting';
    this.status = null;
    this.statusCount = 0;
    this.ws = null;
    this.started = false;
    this.polling = false;
    this.scopeNext = null;
    this.traceNext = null;
    this.info = api.get('/api/v1/info');
  }

  on(type, fn) {
    if (!this.handlers.has(type)) this.handlers.set(type, []);
    this.handlers.get(type).push(fn);
    if (type === 'status' && this.status) fn(this.status);
  }

  emit(type, msg) {
    for (const fn of this.handlers.get(type) || []) {
      try {
        fn(msg);
      } catch (e) {
        // A page handler that throws must not stop the others; the error still reaches the console.
        setTimeout(() => {
          throw e;
        });
      }
    }
  }

  start(topics = []) {
    for (const t of topics) this.topics.add(t);
    if (this.started) return;
    this.started = true;
    this.connect();
  }

  // Trace channel filter (null = all channels), web.md §10.2.
  setTraceChannels(channels) {
    this.traceChannels = channels;
    if (this.ws && this.topics.has('trace')) {
      this.ws.send(JSON.stringify({ unsubscribe: ['trace'] }));
      this.sendSubscription();
    }
  }

  sendSubscription() {
    const msg = { subscribe: [...this.topics] };
    if (this.topics.has('trace') && this.traceChannels) msg.channels = this.traceChannels;
    this.ws.send(JSON.stringify(msg));
  }

  acceptStatus(s) {
    if (this.status && s.seq <= this.status.seq) return;
    this.status = s;
    this.statusCount++;
    this.emit('status', s);
  }

  setMode(mode) {
    if (this.mode === mode) return;
    this.mode = mode;
    this.emit('mode', mode);
  }

  connect() {
    const ws = new WebSocket(`${location.protocol === 'https:' ? 'wss' : 'ws'}://${location.host}/api/v1/ws`);
    let opened = false;
    const timer = setTimeout(() => {
      if (!opened) ws.close();
    }, OPEN_TIMEOUT_MS);
    ws.onopen = () => {
      opened = true;
      clearTimeout(timer);
      this.ws = ws;
      this.sendSubscription();
      this.polling = false;
      this.setMode('ws');
    };
    ws.onmessage = (ev) => {
      let m;
      try {
        m = JSON.parse(ev.data);
      } catch {
        return;
      }
      if (m.type === 'status') this.acceptStatus(m);
      else if (m.type === 'hello') this.emit('hello', m.info);
      else this.emit(m.type, m);
    };
    ws.onclose = () => {
      clearTimeout(timer);
      if (this.ws === ws) this.ws = null;
      this.startPolling();
      setTimeout(() => this.connect(), RECONNECT_MS);
    };
  }

  startPolling() {
    if (this.polling) return;
    this.polling = true;
    this.setMode('poll');
    this.pollStatus();
    if (this.topics.has('scope')) this.pollScope();
    if (this.topics.has('trace')) this.pollTrace();
    if (this.topics.has('udp')) this.pollUdp();
  }

  // Each poller starts a request every `ms` (start to start), and never two at a time.
  loop(fn, ms) {
    const run = async () => {
      if (!this.polling) return;
      const start = performance.now();
      try {
        await fn();
      } catch {
        // The emulator is away (restart, network): the footer says so; retry at the same rate.
        this.setMode('offline');
      }
      if (this.polling) setTimeout(run, Math.max(0, ms - (performance.now() - start)));
    };
    run();
  }

  // Status: a request every 80 ms even when answers are slow (up to two in flight; acceptStatus
  // drops an answer older than one already shown).
  pollStatus() {
    let inFlight = 0;
    const tick = () => {
      if (!this.polling) return;
      if (inFlight < 2) {
        inFlight++;
        api.poll('/api/v1/status')
          .then((s) => {
            this.setMode('poll');
            this.acceptStatus(s);
          })
          .catch(() => this.setMode('offline'))
          .finally(() => inFlight--);
      }
      setTimeout(tick, STATUS_POLL_MS);
    };
    tick();
  }

  pollScope() {
    this.loop(async () => {
      const since = this.scopeNext ?? Math.max(0, (this.status ? this.status.timeMs : 0) - 2000);
      const s = await api.poll(`/api/v1/scope?sinceMs=${since}`);
      if (s.pos.length) {
        this.scopeNext = s.t0 + s.sampleMs * s.pos.length;
        this.emit('scope', s);
      }
    }, SLOW_POLL_MS);
  }

  pollTrace() {
    this.loop(async () => {
      let q = `/api/v1/trace?limit=500&since=${this.traceNext ?? 0}`;
      if (this.traceChannels) q += `&channels=${this.traceChannels.join(',')}`;
      const t = await api.poll(q);
      this.traceNext = t.nextSeq;
      if (t.events.length) this.emit('trace', { events: t.events });
    }, SLOW_POLL_MS);
  }

  pollUdp() {
    this.loop(async () => {
      const u = await api.poll('/api/v1/udp');
      this.emit('udp-history', { messages: u.messages, view: u });
    }, 1000);
  }
}

export const live = new Live();
// For browser tests and the curious: how this page gets its data.
window.mcLive = {
  get mode() {
    return live.mode;
  },
  get statusCount() {
    return live.statusCount;
  },
  get status() {
    return live.status;
  },
};
