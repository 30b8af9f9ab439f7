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
 * Polls job `id` until it ends and returns its last view; `label` shows its
 * progress, `bar` (a <progress>, optional) the fraction of the part under
 * way, and `cancel` (a button, optional) is enabled to stop the job.
 */
export async function followJob(id, label, { bar, cancel } = {}) {
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
