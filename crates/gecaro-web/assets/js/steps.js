// The step bar: the real-cell workflow of the method shown — robot, cell and
// frames, plan, measure or import, identify, validate, export or compensate
// — each step with its state, a click away. It reads the page's state only
// (re-drawn on every `changed`, see state.js).
import { dataKey } from './data-choices.js';
import { h, $ } from './dom.js';
import { selectFunction } from './navigation.js';
import { state } from './state.js';

/** One step: its label, state ('done', 'bad', 'warn' or '' for not yet), a short status, and where a click goes. */
function step(id, label, status, text, go) {
  return h('li', { class: `step ${status}`, id: `step-${id}` },
    h('button', { type: 'button', onclick: go, 'aria-label': `${label}: ${text}` },
      h('span', { class: 'step-label', text: label }), h('span', { class: 'step-status', text })));
}

const show = (fn) => () => {
  selectFunction(fn);
  $('methods-card').scrollIntoView({ block: 'start' });
};

/** The cell fields set for the method (in its Plan or Points generation panel), or the study's frames. */
function cellText(name) {
  const set = ['floor', 'station'].filter((key) => ['plan', 'generate'].some((fn) => {
    const input = $(`${name}-${fn}-${key}`);
    return input && input.value.trim() !== '';
  }));
  const study = state.study;
  const frames = study ? study.tools.length + study.stations.length : 0;
  if (frames) return { status: 'done', text: `study: ${study.tools.length} tools, ${study.stations.length} stations` };
  if (set.length) return { status: 'done', text: set.includes('station') ? 'tracker placed' : 'floor set' };
  return { status: '', text: 'none stated (optional)' };
}

/** Re-draws the step bar from the state. */
export function renderSteps() {
  const bar = $('steps');
  if (!bar || !state.robot || !state.info) return;
  const name = state.method;
  const problems = (state.robot.problems || []).length + state.localProblems.size;
  const robot = problems ? { status: 'bad', text: `${problems} problem${problems === 1 ? '' : 's'}` }
    : state.robot.summary ? { status: 'done', text: `valid, ${state.robot.summary.letters}` } : { status: '', text: 'checking…' };
  const cell = cellText(name);
  const planned = state.planned[name];
  const data = dataKey(name, 'identify').split('#')[0];
  const measured = data === '' ? { status: '', text: 'no data chosen' }
    : { status: 'done', text: data === 'generated' ? 'generated here' : data === 'upload' ? 'an upload' : data.replace(/^file:/, '') };
  const last = state.results[name];
  const verdict = last && last.result ? last.result.identification.verdict : null;
  const identified = !verdict ? { status: '', text: 'not yet' }
    : last.stale ? { status: 'warn', text: 'stale: identify again' }
      : verdict.trusted ? { status: 'done', text: 'trusted' } : { status: 'bad', text: 'not trusted' };
  const evaluated = state.evaluated[name];
  const validated = !evaluated ? { status: '', text: verdict ? 'evaluate on held-out data' : 'not yet' }
    : evaluated === 'better' ? { status: 'done', text: 'better held out' }
      : evaluated === 'worse' ? { status: 'bad', text: 'worse held out' }
        : evaluated === 'table' ? { status: '', text: 'table only: identify first' } : { status: 'warn', text: evaluated };
  const exported = state.exported[name];
  bar.replaceChildren(h('ol', {},
    step('robot', 'Robot', robot.status, robot.text, () => $('robot-card').scrollIntoView({ block: 'start' })),
    step('cell', 'Cell and frames', cell.status, cell.text, show('plan')),
    step('plan', 'Plan', planned ? 'done' : '', planned ? `${planned} poses` : 'optional', show('plan')),
    step('measure', 'Measure or import', measured.status, measured.text, show(data === '' ? 'generate' : 'identify')),
    step('identify', 'Identify', identified.status, identified.text, show('identify')),
    step('validate', 'Validate', validated.status, validated.text, show('evaluate')),
    step('export', 'Export or compensate', exported ? exported.status : '', exported ? exported.text : 'not yet', show('compensate'))));
  // The step of the function shown is marked.
  const current = { plan: 'plan', generate: 'measure', identifiable: 'identify', identify: 'identify', evaluate: 'validate', compensate: 'export' }[state.function];
  const shown = $(`step-${current}`);
  if (shown) shown.classList.add('current');
}
