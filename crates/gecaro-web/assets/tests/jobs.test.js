// What a running job's view says of its progress (js/jobs.js): a plan's
// part and its fraction done, an identification's residual.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { progressText } from '../js/jobs.js';

test('a plan names the part under way and its steps done of all', () => {
  const job = { state: 'running', history: [], phase: 'choosing the configurations', steps: { done: 47, total: 180 } };
  assert.equal(progressText(job), 'Choosing the configurations: 47 of 180 steps (26 %)');
  assert.equal(progressText({ ...job, steps: undefined }), 'Choosing the configurations…', 'no step yet: no fraction made up');
  assert.equal(progressText({ ...job, steps: { done: 0, total: 0 } }), 'Choosing the configurations…');
});

test('an identification shows its last iterate, a queued job its wait', () => {
  assert.equal(progressText({ state: 'running', history: [0.02, 0.001] }), 'Iteration 1: residual RMS 1.00e-3');
  assert.equal(progressText({ state: 'running', history: [] }), 'Starting…');
  assert.equal(progressText({ state: 'queued', history: [] }), 'Waiting for a free core…');
});
