// The two LEDs of the page header (morse-led.md §6.3). Yellow shows led.yellow of the latest status
// message. Green plays the Morse schedule of GET /api/v1/led with its exact element lengths: drive
// time is taken from every status message's timeMs and extrapolated in between at the clock's scale
// (GET /api/v1/info; none under --clock manual); the schedule is fetched again when a repetition
// that nextText announced begins and whenever drive time goes backwards (a power cycle).
import { api } from './api.js';

// ITU Morse (morse-led.md §4 and the rest of the letters) for the running decode.
const MORSE = {
  '.-': 'A', '-...': 'B', '-.-.': 'C', '-..': 'D', '.': 'E', '..-.': 'F', '--.': 'G', '....': 'H',
  '..': 'I', '.---': 'J', '-.-': 'K', '.-..': 'L', '--': 'M', '-.': 'N', '---': 'O', '.--.': 'P',
  '--.-': 'Q', '.-.': 'R', '...': 'S', '-': 'T', '..-': 'U', '...-': 'V', '.--': 'W', '-..-': 'X',
  '-.--': 'Y', '--..': 'Z', '-----': '0', '.----': '1', '..---': '2', '...--': '3', '....-': '4',
  '.....': '5', '-....': '6', '--...': '7', '---..': '8', '----.': '9', '.-.-.': '+', '---...': ':',
};

// Runs of on/off (ms) → characters: on ≤ 2 T dot, else dash; off ≥ 2 T ends a character, ≥ 5 T a word.
export class MorseDecoder {
  constructor(unitMs) {
    this.unitMs = unitMs;
    this.symbol = '';
    this.text = '';
    this.synced = false; // the first run seen may be cut; decoding starts after the first character gap
  }
  push(on, ms) {
    const t = this.unitMs;
    if (on) {
      if (this.synced) this.symbol += ms <= 2 * t ? '.' : '-';
      return;
    }
    if (ms < 2 * t) return;
    if (this.synced && this.symbol) this.text += MORSE[this.symbol] || '?';
    if (this.synced && ms >= 5 * t) this.text += ' ';
    this.symbol = '';
    this.synced = true;
  }
}

export class Leds {
  constructor(live, green, yellow) {
    this.live = live;
    this.green = green;
    this.yellow = yellow;
    this.scale = 1;
    this.anchor = null; // {timeMs, wall}: drive time at a wall-clock instant (performance.now())
    this.shown = -Infinity; // the drive time last shown (never goes back without a refetch)
    this.schedule = null;
    this.prefix = null;
    this.fetching = null;
    this.timer = null;
    this.state = null;
    this.listeners = [];
    live.info.then((i) => (this.scale = i.clock && typeof i.clock.scale === 'number' ? i.clock.scale : 1)).catch(() => {});
    live.on('status', (s) => this.onStatus(s));
  }

  // fn(on, driveTimeMs) at every change of the green LED.
  onChange(fn) {
    this.listeners.push(fn);
  }

  // Drive time now according to the anchor (without the monotonic guard of now()).
  estimate(wall = performance.now()) {
    return this.anchor.timeMs + (wall - this.anchor.wall) * this.scale;
  }

  // A status message is never early, only late (built, sent, delivered): the anchor follows the
  // message that puts drive time furthest ahead, so a delayed message cannot pull the LED back
  // and the next prompt one then make it skip an element. Only a message far behind the estimate
  // (the drive's clock was held up) or a jump back (power cycle) re-anchors backwards.
  onStatus(s) {
    this.yellow.dataset.on = s.led && s.led.yellow ? '1' : '0';
    const wall = performance.now();
    if (this.anchor && s.timeMs + 1000 < this.shown) {
      this.shown = -Infinity; // power cycle: drive time started again at 0
      this.anchor = null;
      this.refetch();
    }
    if (!this.anchor) this.anchor = { timeMs: s.timeMs, wall };
    else {
      const est = this.estimate(wall);
      if (s.timeMs > est || est - s.timeMs > 300) this.anchor = { timeMs: s.timeMs, wall };
    }
    // Entering or leaving Fault changes the message from the next repetition on (morse-led.md
    // §2.3): fetch the schedule to learn nextText.
    const faultKey = s.state === 'F' || s.state === 'FRA' ? s.errorCode : null;
    if (this.faultKey !== undefined && faultKey !== this.faultKey) this.refetch();
    this.faultKey = faultKey;
    if (!this.schedule && !this.fetching) this.refetch();
    if (!this.schedule) this.set(s.led && s.led.green, s.timeMs);
    else this.tick();
  }

  now() {
    this.shown = Math.max(this.shown, this.estimate());
    return this.shown;
  }

  refetch() {
    if (this.fetching) return this.fetching;
    this.fetching = api
      .poll('/api/v1/led')
      .then((led) => {
        const g = led.green;
        this.schedule = g;
        this.prefix = [0];
        for (const d of g.elements) this.prefix.push(this.prefix[this.prefix.length - 1] + d);
        const wall = performance.now();
        if (!this.anchor || led.timeMs > this.estimate(wall)) this.anchor = { timeMs: led.timeMs, wall };
      })
      .catch(() => {
        this.schedule = null; // no schedule: the LED follows the status messages (20 Hz)
      })
      .finally(() => {
        this.fetching = null;
        if (this.schedule) this.tick();
      });
    return this.fetching;
  }

  // Where drive time t falls in the schedule: {on, element, phase, untilNext} or null (a new
  // message begins or time went back: refetch). Past the end of the repetition the same message
  // is assumed (nextText null) while the schedule is fetched again, once per repetition.
  locate(t) {
    const g = this.schedule;
    if (!g || t < g.cycleStartMs) return null;
    if (t >= g.cycleStartMs + g.cycleMs) {
      if (g.nextText !== null) return null;
      const cycle = Math.floor((t - g.cycleStartMs) / g.cycleMs);
      if (this.checkedCycle !== g.cycleStartMs + cycle * g.cycleMs) {
        this.checkedCycle = g.cycleStartMs + cycle * g.cycleMs;
        this.refetch();
      }
    }
    const phase = (t - g.cycleStartMs) % g.cycleMs;
    let lo = 0;
    let hi = g.elements.length - 1;
    while (lo < hi) {
      const mid = (lo + hi + 1) >> 1;
      if (this.prefix[mid] <= phase) lo = mid;
      else hi = mid - 1;
    }
    return { on: lo % 2 === 0, element: lo, phase, untilNext: this.prefix[lo + 1] - phase };
  }

  // The cycle position for the Emulator page.
  position() {
    if (!this.schedule || !this.anchor) return null;
    const where = this.locate(this.now());
    return where && { ...where, text: this.schedule.text, cycleMs: this.schedule.cycleMs, elements: this.schedule.elements.length };
  }

  tick() {
    clearTimeout(this.timer);
    if (!this.anchor || !this.schedule) return;
    const t = this.now();
    const where = this.locate(t);
    if (!where) {
      this.refetch();
      return;
    }
    this.set(where.on, t);
    if (this.scale > 0) {
      // Wake at the next edge (wall time = drive time / scale), at least every 200 ms.
      const wait = Math.min(200, Math.max(1, where.untilNext / this.scale));
      this.timer = setTimeout(() => this.tick(), wait);
    }
  }

  set(on, t) {
    const value = on ? '1' : '0';
    if (this.green.dataset.on !== value) this.green.dataset.on = value;
    if (this.state !== !!on) {
      this.state = !!on;
      for (const fn of this.listeners) fn(!!on, t);
    }
  }
}
