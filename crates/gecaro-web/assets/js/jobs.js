// Following a server job (an identification, a plan) until it ends, with
// its progress in a label: an identification's residual at every
// iteration; a plan's part under way and its steps done of all, also shown
// by a <progress> bar when one is given.
import { api } from './api.js';
import { sci } from './format.js';

/** What a running job's view says of its progress, in words. */
export function progressText(job) {
  if (job.state === 'queued') return 'Waiting for a free core…';
  if (job.phase) {
    const part = job.phase.charAt(0).toUpperCase() + job.phase.slice(1);
    const steps = job.steps;
    return steps && steps.total > 0
      ? `${part}: ${steps.done} of ${steps.total} steps (${Math.round((100 * steps.done) / steps.total)} %)`
      : `${part}…`;
  }
  const history = job.history || [];
  return history.length ? `Iteration ${history.length - 1}: residual RMS ${sci(history[history.length - 1])}` : 'Starting…';
}

/**
 * Where the jobs a reload must find again are kept: the tab's
 * sessionStorage, which a reload keeps and whose quota is the tab's own —
 * the page's results in localStorage can fill that one, and a job written
 * there after them was lost (the reloaded page then showed an older result
 * and its form).
 */
const RUNNING_KEY = 'gecaro.running';

/** The jobs this page follows now: id → what a reload resumes (null: cancelled when the page goes). */
const following = new Map();

function keepRunning() {
  const resumable = [...following].filter(([, resume]) => resume).map(([id, resume]) => ({ id, ...resume }));
  try {
    sessionStorage.setItem(RUNNING_KEY, JSON.stringify(resumable));
  } catch (ignored) { /* storage unavailable: a reload then loses the job, and cancels it */ }
}

/**
 * The jobs under way when the page was left, that it follows again after a
 * reload (each `{id, kind, …}` as `followJob`'s `resume` said), taken once.
 */
export function jobsLeftRunning() {
  try {
    const left = JSON.parse(sessionStorage.getItem(RUNNING_KEY) || '[]');
    sessionStorage.removeItem(RUNNING_KEY);
    return Array.isArray(left) ? left : [];
  } catch (ignored) {
    return [];
  }
}

/**
 * When the page goes (a reload, a closed tab), the jobs it follows and
 * cannot resume are cancelled on the server — a job nobody will read does
 * not keep a core; the resumable ones run on, and the page finds them again.
 */
export function cancelJobsLeftBehind() {
  window.addEventListener('pagehide', () => {
    for (const [id, resume] of following) {
      if (resume) continue;
      fetch(`/api/jobs/${id}/cancel`, { method: 'POST', keepalive: true, headers: { 'Content-Type': 'application/json' }, body: '{}' }).catch(() => {});
    }
  });
}

/**
 * Polls job `id` until it ends and returns its last view; `label` shows its
 * progress, `bar` (a <progress>, optional) the fraction of the part under
 * way, and `cancel` (a button, optional) is enabled to stop the job.
 * `resume` (optional: `{kind, …}`) is what a reload needs to follow the job
 * again; without it, the job is cancelled when the page goes.
 */
export async function followJob(id, label, { bar, cancel, resume } = {}) {
  following.set(id, resume || null);
  keepRunning();
  try {
    return await pollJob(id, label, { bar, cancel });
  } finally {
    following.delete(id);
    keepRunning();
  }
}

async function pollJob(id, label, { bar, cancel }) {
  if (cancel) {
    cancel.disabled = false;
    cancel.onclick = async () => {
      cancel.disabled = true;
      cancel.textContent = 'Cancelling…';
      await api(`/jobs/${id}/cancel`, {});
    };
  }
  for (;;) {
    const job = await api(`/jobs/${id}`);
    if (job.state === 'done' || job.state === 'failed' || job.state === 'cancelled') return job;
    label.textContent = progressText(job);
    if (bar && job.steps && job.steps.total > 0) bar.value = job.steps.done / job.steps.total;
    await new Promise((resolve) => setTimeout(resolve, 120));
  }
}
