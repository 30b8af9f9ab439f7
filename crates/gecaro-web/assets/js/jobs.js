// Following a server job (an identification) until it ends, with its
// progress in a label.
import { api } from './api.js';
import { sci } from './format.js';

export async function followJob(id, label) {
  for (;;) {
    const job = await api(`/jobs/${id}`);
    if (job.state === 'done' || job.state === 'failed' || job.state === 'cancelled') return job;
    const history = job.history;
    label.textContent = job.state === 'queued' ? 'Waiting for a free core…'
      : history.length ? `Iteration ${history.length - 1}: residual RMS ${sci(history[history.length - 1])}` : 'Starting…';
    await new Promise((resolve) => setTimeout(resolve, 120));
  }
}
