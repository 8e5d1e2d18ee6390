// The JSON API client of every page (docs/web-api.md). A call resolves with the parsed answer or
// rejects with an ApiError; describe() turns any error into the words the page shows (the abort code
// and its text, or the HTTP status and the server's message) — errors are never swallowed.

export class ApiError extends Error {
  constructor(status, body, fallback) {
    const e = body && typeof body === 'object' && body.error ? body.error : null;
    super(e && e.message ? e.message : fallback);
    this.status = status;
    this.code = e ? e.code : status === 0 ? 'network' : 'http';
    this.abortCode = e && e.abortCode ? e.abortCode : null;
  }
}

// A RefGo line whose answer is an error reply (",ERROR,"): the answer line is the message.
export class RefgoError extends Error {}

export function describe(err) {
  if (err instanceof ApiError) {
    if (err.abortCode) return `${err.abortCode} ${err.message}`;
    if (err.status === 0) return err.message;
    return `HTTP ${err.status}: ${err.message}`;
  }
  if (err instanceof RefgoError) return err.message;
  return String((err && err.message) || err);
}

// The requests a page repeats on a timer carry this header, so that the trace view can leave the
// pages' own polling out (web.md §8.6: the `polling` mark, GET /api/v1/trace?excludePolling=1).
const POLL_HEADER = 'X-Mcemu-Poll';

// docs/security.md: with `mcemu --api-token FILE` the emulator endpoints (settings, clock, power
// cycle, faults) answer 401 without the token; the page asks for it once and keeps it for the tab.
const TOKEN_KEY = 'mcemu.apiToken';
let enteredToken = '';
function storedToken() {
  try {
    return sessionStorage.getItem(TOKEN_KEY) || enteredToken;
  } catch {
    return enteredToken;
  }
}

async function call(method, path, body, contentType = 'application/json', poll = false, retried = false) {
  const init = { method, cache: 'no-store', headers: {} };
  if (poll) init.headers[POLL_HEADER] = '1';
  const token = storedToken();
  if (token) init.headers.Authorization = `Bearer ${token}`;
  if (body !== undefined) {
    init.headers['Content-Type'] = contentType;
    init.body = contentType === 'application/json' ? JSON.stringify(body) : body;
  }
  let res;
  try {
    res = await fetch(path, init);
  } catch (e) {
    throw new ApiError(0, null, `no answer from the emulator (${e.message})`);
  }
  const text = await res.text();
  let data = text;
  if ((res.headers.get('content-type') || '').includes('json') && text) {
    try {
      data = JSON.parse(text);
    } catch {
      throw new ApiError(res.status, null, `unreadable answer from ${path}`);
    }
  }
  if (res.status === 401 && !retried && typeof window !== 'undefined' && window.prompt) {
    const entered = window.prompt('This emulator endpoint needs the token of mcemu --api-token:');
    if (entered) {
      enteredToken = entered.trim();
      try {
        sessionStorage.setItem(TOKEN_KEY, enteredToken);
      } catch {
        // no session storage: the token lives as long as this page
      }
      return call(method, path, body, contentType, poll, true);
    }
  }
  if (!res.ok) throw new ApiError(res.status, data, `${res.status} ${res.statusText || 'error'}`);
  return data;
}

// "6081h" for 0x6081 (indices in paths and bodies are hex strings, web.md §8)
export const hexIndex = (i) => i.toString(16).toUpperCase().padStart(4, '0') + 'h';

export const api = {
  get: (path) => call('GET', path),
  // A GET the page repeats on a timer (marked as polling for the trace).
  poll: (path) => call('GET', path, undefined, undefined, true),
  post: (path, body = {}) => call('POST', path, body),
  put: (path, body) => call('PUT', path, body),
  del: (path) => call('DELETE', path),
  putText: (path, text, type = 'text/x-python') => call('PUT', path, text, type),

  // One RefGo line (web.md §8.4): resolves with {reply, answer, ok}; an error reply rejects.
  async refgo(line) {
    const r = await call('POST', '/api/v1/refgo', { line });
    if (!r.ok) throw new RefgoError(r.answer || `${line}: error`);
    return r;
  },
  // [[index, sub], …] → values (an entry that failed is {abortCode}), one consistent read (§8.3);
  // poll: a read the page repeats on a timer.
  async read(list, { poll = false } = {}) {
    const r = await call('POST', '/api/v1/objects/read', { objects: list.map(([i, s]) => [hexIndex(i), s]) }, 'application/json', poll);
    return r.values;
  },
  write: (index, sub, value) => call('PUT', `/api/v1/objects/${hexIndex(index)}/${sub}`, { value }),
};
