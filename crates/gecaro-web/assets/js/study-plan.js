// The study's cell planned and predicted before it is measured
// (docs/planning.md, docs/tracker.md): the configurations of every set
// chosen together (D-optimal over the base parameters and the named frames'
// unknowns) as a server job with its progress, saved as a planned study
// whose sets name their files; and the precision of every unknown and the
// calibrated robot's error predicted from the sets' configurations (eq. 11).
import { api } from './api.js';
import { cellInputs } from './cell.js';
import { download, h, toast } from './dom.js';
import { field, FieldError, fieldNumber, errorBox, runButton, stat, numberInput } from './fields.js';
import { fixed, sci } from './format.js';
import { followJob } from './jobs.js';
import { refreshFiles } from './robot-menu.js';
import { state, tableDocument } from './state.js';
import { studySpec } from './study-spec.js';
import { inUnits, inPageUnits, unitName, unitOf } from './units.js';

/**
 * The robot a planned study names: the table's file or ready robot, saved
 * as it is in the table (a planned study cannot name an unsaved table).
 */
function namedRobot(studyRobot) {
  if (state.dirty || !studyRobot) {
    throw new FieldError('A planned study names its robot: save the robot in the folder first (Robot ▸ Save), or plan without saving.');
  }
  return studyRobot;
}

/**
 * The Plan and Predict part of the study card. `studyRobot()` names the
 * table's robot (or null); `openStudy(name)` opens a study file of the
 * folder in the editor.
 */
export function studyPlanSection({ studyRobot, openStudy }) {
  const result = h('div', { class: 'result', id: 'study-plan-result' });
  const count = numberInput({ value: 60, id: 'study-plan-count' });
  const pool = numberInput({ id: 'study-plan-pool', placeholder: '20 × count ÷ sets' });
  const seed = numberInput({ value: state.info.defaults.seed, id: 'study-plan-seed' });
  const saveAs = h('input', { type: 'text', class: 'vector', id: 'study-plan-save', placeholder: 'optional, e.g. planned.toml' });
  const angleUnit = h('select', { id: 'study-plan-angle-unit' },
    h('option', { value: 'rad', text: 'radians' }), h('option', { value: 'deg', text: 'degrees (a teach pendant’s)' }));
  const cell = cellInputs('study', 'plan');
  const plan = runButton('study-plan-run', 'Plan the cell', async () => {
    const cancel = h('button', { type: 'button', id: 'study-plan-cancel', text: 'Cancel', disabled: true });
    const label = h('span', { id: 'study-plan-progress', text: 'Reading the study…' });
    const bar = h('progress', { id: 'study-plan-bar', max: 1, value: 0 });
    result.replaceChildren(h('div', { class: 'progress' }, h('div', { class: 'spinner' }), label, bar, cancel));
    try {
      const request = {
        study: studySpec(state.study),
        count: fieldNumber(count, 'Configurations', { min: 1, max: state.info.limits.generate, whole: true }),
        seed: fieldNumber(seed, 'Seed', { min: 0, whole: true, empty: state.info.defaults.seed }),
        cell: cell.request(),
        format: { angle_unit: angleUnit.value },
      };
      const candidates = fieldNumber(pool, 'Candidates per set', { min: 1, max: state.info.limits.generate, whole: true, empty: null });
      if (candidates !== null) request.pool = candidates;
      const name = saveAs.value.trim();
      if (name) {
        if (!name.endsWith('.toml')) throw new FieldError('Save the planned study as: a file name ending in .toml.');
        request.save_as = name;
        request.robot = namedRobot(studyRobot());
      } else {
        request.robot = tableDocument();
      }
      const submitted = await api('/studies/plan', request);
      const job = await followJob(submitted.job, label, { bar, cancel });
      if (job.state === 'cancelled') {
        result.replaceChildren(h('div', { class: 'warnings', id: 'study-plan-cancelled', text: 'Cancelled: the server stopped planning.' }));
        return;
      }
      if (job.state === 'failed') throw new Error(job.error);
      if (job.result.output.length) {
        refreshFiles();
        toast(`Saved ${name}`);
      }
      renderPlannedStudy(result, job.result, name, openStudy);
    } catch (error) {
      result.replaceChildren(errorBox(error));
    }
  });
  const predict = runButton('study-predict-run', 'Predict the precision', async () => {
    result.replaceChildren(h('div', { class: 'progress' }, h('div', { class: 'spinner' }), h('span', { text: 'Predicting…' })));
    try {
      const predicted = await api('/studies/predict', { robot: tableDocument(), study: studySpec(state.study) });
      renderPrediction(result, predicted);
    } catch (error) {
      result.replaceChildren(errorBox(error));
    }
  });
  return [
    h('h3', { text: 'Plan and predict the cell' }),
    h('div', { class: 'form' },
      field('Configurations in all', count),
      field('Candidates per set', pool),
      field('Seed', seed),
      ...cell.fields,
      field('Save the planned study as', saveAs),
      field('Joint angles of the files written in', angleUnit),
      plan,
      predict),
    h('p', { class: 'hint', text: 'Plan: every set’s configurations chosen together, seen through its reflector from its station, so the cell determines the robot and the frames best (D-optimal). Saved, the planned study names one configuration file per set; measure them, then identify. Predict: the precision of every unknown and the calibrated robot’s error that the sets’ configurations give, before measuring (eq. 11, each set at its σ).' }),
    result,
  ];
}

function renderPlannedStudy(container, planned, name, openStudy) {
  const saved = planned.output.length > 0;
  const rows = planned.sets.map((set, index) => {
    const file = planned.files[index];
    return h('tr', {},
      h('td', { text: String(index + 1) }),
      h('td', { text: set.data }),
      h('td', { text: set.method }),
      h('td', { text: String(set.configurations) }),
      h('td', {}, set.file ? h('span', { text: set.file.split(/[\\/]/).pop() })
        : h('button', { type: 'button', text: `Download ${file.file_name}`, onclick: () => download(file.file_name, file.csv, 'text/csv') })));
  });
  const better = planned.log_det > planned.random_log_det;
  container.replaceChildren(...[
    h('div', { class: 'cards' },
      stat('configurations planned', String(planned.configurations), { id: 'study-plan-configurations', class: 'ok' }),
      stat('sets', String(planned.sets.length)),
      stat(`information: log det(W_bᵀW_b) of ${planned.unknowns} unknowns (larger: the unknowns more precise together)`, fixed(planned.log_det, 2), { id: 'study-plan-logdet', class: better ? 'ok' : '' }),
      stat('the same of a random choice', fixed(planned.random_log_det, 2), { id: 'study-plan-random' })),
    h('p', { class: 'muted', text: `A difference of ${fixed(planned.log_det - planned.random_log_det, 2)} in log det (natural log) makes the unknowns’ σ ${fixed(Math.exp((planned.random_log_det - planned.log_det) / (2 * Math.max(planned.unknowns, 1))), 2)}× a random choice’s, as a geometric mean (σ ∝ det^(−1/2p); D-optimal design, docs/planning.md).`, id: 'study-plan-gain' }),
    h('table', { class: 'values', id: 'study-plan-sets' },
      h('thead', {}, h('tr', {}, ['set', 'planned for', 'method', 'configurations', saved ? 'file written' : 'file'].map((t) => h('th', { text: t })))),
      h('tbody', {}, rows)),
    saved ? h('div', { class: 'actions' },
      h('p', { text: `Saved ${name} and its sets’ files: measure the configurations, add the measurements to each file, then identify the planned study.` }),
      h('button', { type: 'button', id: 'study-plan-open', text: `Open ${name}`, onclick: () => openStudy(name) })) : null,
  ].filter(Boolean));
}

function renderPrediction(container, predicted) {
  const errors = predicted.predicted;
  const sigmaText = (p) => {
    const kind = unitOf(p.name);
    return kind === 'none' ? sci(p.sigma) : `${sci(inUnits(p.sigma, kind))} ${unitName(kind)}`;
  };
  container.replaceChildren(...[
    h('div', { class: 'cards' },
      stat(`predicted RMS position error (${unitName('length')})`, inPageUnits(errors.position_rms, 'length', 3), { id: 'study-predicted-rms', class: 'ok' }),
      stat(`largest (${unitName('length')})`, inPageUnits(errors.position_max, 'length', 3)),
      errors.rotation_rms === null ? null
        : stat(`RMS orientation error (${unitName('angle')})`, inPageUnits(errors.rotation_rms, 'angle', 3)),
      stat('test poses', String(predicted.test_poses)),
      stat('configurations', String(predicted.sets.reduce((sum, set) => sum + set.configurations, 0)))),
    h('h3', { text: 'Predicted σ of every unknown (first order, each set at its σ)' }),
    h('table', { class: 'values', id: 'study-predicted' },
      h('thead', {}, h('tr', {}, ['unknown', 'σ'].map((t) => h('th', { text: t })))),
      h('tbody', {}, predicted.parameters.map((p) => h('tr', {}, h('td', { text: p.name }), h('td', { text: sigmaText(p) }))))),
  ].filter(Boolean));
}
