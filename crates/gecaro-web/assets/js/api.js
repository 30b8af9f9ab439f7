// The JSON API of docs/api.md as the page calls it: `api(path, body)`,
// its failures (`ApiFailure` with the server's problems) and one state for a
// lost server (a banner with Retry; the table is kept).
import { h, $, toast } from './dom.js';
import { emit } from './events.js';

class ApiFailure extends Error {
  constructor(status, body) {
    super(body && body.error ? body.error : `HTTP ${status}`);
    this.status = status;
    this.problems = (body && body.problems) || [];
  }
}

/** The server did not answer at all (stopped, restarted, the network gone): not the robot's fault. */
class ServerUnreachable extends Error {
  constructor() {
    super('The server is unreachable: your table is kept in this page. Start gecaro serve again, then Retry.');
    this.unreachable = true;
    this.problems = [];
  }
}

/**
 * One state for a lost server: a banner that says the table is kept, with
 * Retry (it asks the server for its info and goes once it answers).
 */
function serverLost() {
  if ($('server-lost')) return;
  const retry = h('button', { type: 'button', id: 'server-retry', text: 'Retry' });
  const banner = h('div', { class: 'server-lost', id: 'server-lost', role: 'alert' },
    h('span', { text: 'Server unreachable — your table is kept in this page.' }), retry);
  retry.addEventListener('click', async () => {
    retry.disabled = true;
    try {
      await api('/info');
      toast('The server answers again');
      emit('server-back');
    } catch (ignored) { /* still lost: the banner stays */ } finally {
      retry.disabled = false;
    }
  });
  document.body.prepend(banner);
}

/** A call of the JSON API; `signal` (an AbortController's) lets the page abandon it. */
export async function api(path, body, signal) {
  const request = body === undefined ? {} : {
    method: 'POST',
    headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify(body),
  };
  if (signal) request.signal = signal;
  let response;
  try {
    response = await fetch(`/api${path}`, request);
  } catch (error) {
    // A request the page abandoned is not a lost server.
    if (signal && signal.aborted) throw error;
    serverLost();
    throw new ServerUnreachable();
  }
  const lost = $('server-lost');
  if (lost) lost.remove();
  const text = await response.text();
  let data;
  try { data = JSON.parse(text); } catch { data = { error: text || response.statusText }; }
  if (!response.ok) throw new ApiFailure(response.status, data);
  return data;
}
