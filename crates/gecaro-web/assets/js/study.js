// The study editor: several measurement sets identified together (a
// tracker cell: reflectors on the flange, stations the tracker measured
// from), as a study file states them (docs/studies.md).
import { api } from './api.js';
import { fill, h, $, toast } from './dom.js';
import { field, FieldError, errorBox, runButton, stat } from './fields.js';
import { sci } from './format.js';
import { followJob } from './jobs.js';
import { calibratedActions, registrationBlock } from './results.js';
import { refreshFiles } from './robot-menu.js';
import { state, tableDocument, persist } from './state.js';
import { studyPlanSection } from './study-plan.js';
import { emptyStudy, studyOf, studySpec } from './study-spec.js';
import { inUnits, inPageUnits, unitName } from './units.js';

function studyFramesTable(kind, rows) {
  const lengthUnit = state.study.length_unit;
  const angleUnit = state.study.angle_unit === 'deg' ? '°' : 'rad';
  const cell = (row, key, index, label) => h('input', {
    type: 'text', class: 'study-number', value: row[key][index], 'aria-label': label,
    onchange: (event) => { row[key][index] = event.target.value; persist(); },
  });
  return h('table', { class: 'values study-table', id: `study-${kind}s` },
    h('thead', {}, h('tr', {}, [`${kind}`, `x (${lengthUnit})`, `y (${lengthUnit})`, `z (${lengthUnit})`, `roll (${angleUnit})`, `pitch (${angleUnit})`, `yaw (${angleUnit})`, ''].map((t) => h('th', { text: t })))),
    h('tbody', {}, rows.map((row, r) => h('tr', {},
      h('td', {}, h('input', { type: 'text', value: row.name, class: 'study-name', 'aria-label': `${kind} name`, onchange: (event) => { row.name = event.target.value; renderStudy(); } })),
      [0, 1, 2].map((k) => h('td', {}, cell(row, 'position', k, `${row.name} ${'xyz'[k]}`))),
      row.rpy ? [0, 1, 2].map((k) => h('td', {}, cell(row, 'rpy', k, `${row.name} ${['roll', 'pitch', 'yaw'][k]}`)))
        : [h('td', { colspan: 3, class: 'muted', text: 'quaternion (as stated)' })],
      h('td', {}, h('button', { type: 'button', text: 'Remove', onclick: () => { rows.splice(r, 1); renderStudy(); } }))))));
}

function studySetsTable() {
  const study = state.study;
  const select = (value, options, label, onchange) => h('select', { 'aria-label': label, onchange },
    options.map(([v, t]) => h('option', { value: v, text: t, selected: v === (value || '') })));
  const tools = [['', 'none'], ...study.tools.map((t) => [t.name, t.name])];
  const stations = [['', 'the measurement frame'], ...study.stations.map((t) => [t.name, t.name])];
  const files = state.files.data.map((f) => [f, f]);
  return h('table', { class: 'values study-table', id: 'study-sets' },
    h('thead', {}, h('tr', {}, ['set', 'method', 'data file', 'tool (reflector)', 'station', `σ (${study.length_unit})`, 'payload', ''].map((t) => h('th', { text: t })))),
    h('tbody', {}, study.measurements.map((set, index) => h('tr', {},
      h('td', { text: String(index + 1) }),
      h('td', {}, select(set.method, state.info.methods.map((m) => [m.name, m.title]), `set ${index + 1} method`, (e) => { set.method = e.target.value; persist(); })),
      h('td', {}, select(set.data, [['', 'choose…'], ...files], `set ${index + 1} data`, (e) => { set.data = e.target.value; persist(); })),
      h('td', {}, select(set.tool, tools, `set ${index + 1} tool`, (e) => { set.tool = e.target.value; persist(); })),
      h('td', {}, select(set.station, stations, `set ${index + 1} station`, (e) => { set.station = e.target.value; persist(); })),
      h('td', {}, h('input', { type: 'text', class: 'study-number', value: set.sigma, placeholder: 'not stated', 'aria-label': `set ${index + 1} sigma`, onchange: (e) => { set.sigma = e.target.value; persist(); } })),
      h('td', {}, h('input', { type: 'text', class: 'study-payload', id: `study-set-${index + 1}-payload`, value: set.payload || '', placeholder: 'none, or 20kg,0,0,120mm', 'aria-label': `set ${index + 1} payload`, onchange: (e) => { set.payload = e.target.value; persist(); } })),
      h('td', {}, h('button', { type: 'button', text: 'Remove', onclick: () => { study.measurements.splice(index, 1); renderStudy(); } }))))));
}

/** Redraws the study editor from `state.study` (the result stays). */
export function renderStudy() {
  const study = state.study;
  const unit = (id, value, options, onchange) => h('select', { id, onchange }, options.map(([v, t]) => h('option', { value: v, text: t, selected: v === value })));
  const studies = state.files.robots.map((f) => h('option', { value: f, text: f }));
  const opened = h('select', { id: 'study-file' }, h('option', { value: '', text: 'a study file of the folder…' }), studies);
  fill($('study-editor'),
    h('div', { class: 'form' },
      field('Open', opened),
      h('button', { type: 'button', id: 'study-open', text: 'Open', onclick: () => openStudy(opened.value) }),
      h('button', { type: 'button', id: 'study-new', text: 'New study', onclick: () => { state.study = emptyStudy(); renderStudy(); persist(); } }),
      field('Lengths', unit('study-length-unit', study.length_unit, [['m', 'metres'], ['mm', 'millimetres']], (e) => { study.length_unit = e.target.value; renderStudy(); })),
      field('Angles', unit('study-angle-unit', study.angle_unit, [['rad', 'radians'], ['deg', 'degrees']], (e) => { study.angle_unit = e.target.value; renderStudy(); }))),
    study.robot ? h('p', { class: 'muted', id: 'study-robot-note', text: `${study.name || 'This study'} names the robot ${study.robot}; it runs with the robot in the table (${tableDocument().name || 'unnamed'}).` }) : null,
    h('h3', { text: 'Tools (reflectors on the flange), their stated pose in the flange frame' }),
    studyFramesTable('tool', study.tools),
    h('button', { type: 'button', id: 'study-add-tool', text: 'Add a tool', onclick: () => { study.tools.push({ name: `tool_${study.tools.length + 1}`, position: ['0', '0', '0'], rpy: ['0', '0', '0'], rest: {} }); renderStudy(); } }),
    h('h3', { text: 'Stations (where the instrument stood), their stated pose in the measurement frame' }),
    studyFramesTable('station', study.stations),
    h('button', { type: 'button', id: 'study-add-station', text: 'Add a station', onclick: () => { study.stations.push({ name: `station_${study.stations.length + 1}`, position: ['0', '0', '0'], rpy: ['0', '0', '0'], rest: {} }); renderStudy(); } }),
    h('h3', { text: 'Measurement sets' }),
    studySetsTable(),
    h('div', { class: 'actions' },
      h('button', { type: 'button', id: 'study-add-set', text: 'Add a measurement set', onclick: () => { study.measurements.push({ method: 'position', data: '', sigma: '' }); renderStudy(); } }),
      runButton('study-run', 'Identify the study', identifyStudy),
      h('input', { type: 'text', id: 'study-save-as', placeholder: 'study.toml', value: study.name || '' }),
      h('button', { type: 'button', id: 'study-save', text: 'Save the study', onclick: saveStudy })));
  persist();
}

/** The study card's Plan and Predict part (drawn once; it reads the editor's study when run). */
export function renderStudyPlan() {
  fill($('study-plan'), ...studyPlanSection({ studyRobot, openStudy }));
}

async function openStudy(name) {
  if (!name) return;
  const result = $('study-result');
  try {
    const opened = await api(`/studies/file?name=${encodeURIComponent(name)}`);
    state.study = studyOf(opened.study, opened.name);
    renderStudy();
    result.replaceChildren();
  } catch (error) {
    result.replaceChildren(errorBox(error));
  }
}

/** The name a saved study gives its robot: the table's file, or its ready robot's name. */
function studyRobot() {
  return state.file || (state.robot.origin === 'ready' ? state.robot.name : null);
}

async function saveStudy() {
  const result = $('study-result');
  try {
    const name = $('study-save-as').value.trim();
    if (!name.endsWith('.toml')) throw new FieldError('Save the study as: a file name ending in .toml.');
    const saved = await api('/studies/save', { name, study: studySpec(state.study, { robot: studyRobot() }) });
    state.study.name = saved.saved;
    toast(`Saved ${saved.saved}`);
    refreshFiles();
  } catch (error) {
    result.replaceChildren(errorBox(error));
  }
}

async function identifyStudy() {
  const result = $('study-result');
  const progress = h('div', { class: 'progress', id: 'study-progress' }, h('div', { class: 'spinner' }), h('span', { text: 'Reading the sets…' }));
  result.replaceChildren(progress);
  try {
    const submitted = await api('/identify', { robot: tableDocument(), study: studySpec(state.study) });
    const job = await followJob(submitted.job, progress.children[1]);
    if (job.state === 'failed') throw new Error(job.error);
    if (job.state !== 'done') throw new Error('The identification was cancelled.');
    renderStudyResult(result, job.result, submitted.job);
  } catch (error) {
    result.replaceChildren(errorBox(error));
  }
}

/** The study's verdict, errors and identified frames (with σ); job `job`'s. */
function renderStudyResult(container, result, job) {
  const id = result.identification;
  const length = (v) => inPageUnits(v, 'length');
  const angle = (v) => inPageUnits(v, 'angle');
  const [unit, degrees] = [unitName('length'), unitName('angle')];
  const sigmaOf = (name) => {
    const found = (id.auxiliary || []).find((p) => p.name === name);
    return found ? found.std : null;
  };
  const plusMinus = (frame, keys, kind) => {
    const values = keys.map((k) => sigmaOf(`${frame}.${k}`)).filter((v) => v !== null);
    return values.length ? `± ${sci(inUnits(Math.max(...values), kind))}` : '(stated)';
  };
  const rows = (id.frames || []).map((frame) => h('tr', {},
    h('td', { text: frame.name }),
    h('td', { text: frame.role }),
    h('td', { text: frame.position.map(length).join(', ') }),
    h('td', { text: plusMinus(frame.name, ['x', 'y', 'z'], 'length') }),
    h('td', { text: frame.rpy.map(angle).join(', ') }),
    h('td', { text: plusMinus(frame.name, ['rx', 'ry', 'rz'], 'angle') })));
  fill(container,
    h('div', { class: `verdict ${id.verdict.trusted ? 'ok' : 'bad'}`, id: 'study-verdict' }, h('p', { text: id.verdict.summary })),
    h('div', { class: 'cards' },
      stat(`RMS error before, after (${unit})`, `${inPageUnits(id.before.rms, 'length', 4)}, ${inPageUnits(id.after.rms, 'length', 4)}`, { id: 'study-rms' }),
      stat('parameters identified', String(id.parameters.length), { id: 'study-parameters' })),
    h('h3', { text: `Identified tools and stations (${unit}, ${degrees})` }),
    h('table', { class: 'values', id: 'study-frames' },
      h('thead', {}, h('tr', {}, ['frame', 'role', 'position', 'σ', 'roll, pitch, yaw', 'σ'].map((t) => h('th', { text: t })))),
      h('tbody', {}, rows)),
    registrationBlock(id.registration, 'study-registration'),
    calibratedActions(result, id.verdict.trusted, job, 'study-calibrated'),
    (id.warnings || []).length ? h('ul', { class: 'notes' }, id.warnings.map((w) => h('li', { text: w }))) : null);
}
