// The study editor: several measurement sets identified together (a
// tracker cell: reflectors on the flange, stations the tracker measured
// from), as a study file states them (docs/studies.md).
import { api } from './api.js';
import { fill, h, $, toast } from './dom.js';
import { field, FieldError, errorBox, runButton, stat } from './fields.js';
import { recordRun } from './history.js';
import { followJob } from './jobs.js';
import { calibratedActions, correlationHeatmap, registrationBlock } from './results.js';
import { deviationTable, showOnView } from './deviations.js';
import { openDialog } from './dialogs.js';
import { loadStudyRobot, refreshFiles, studyRelative } from './robot-menu.js';
import { refreshStale, studyBasis } from './stale.js';
import { state, tableDocument, persist } from './state.js';
import { studyPlanSection } from './study-plan.js';
import { emptyStudy, studyOf, studySpec, studyWords } from './study-spec.js';
import { coordinate, quantity, unitName } from './units.js';

function studyFramesTable(kind, rows) {
  const lengthUnit = state.study.length_unit;
  const angleUnit = state.study.angle_unit === 'deg' ? '°' : 'rad';
  const cell = (row, key, index, label) => h('input', {
    type: 'text', class: 'study-number', value: row[key][index], 'aria-label': label,
    onchange: (event) => { row[key][index] = event.target.value; persist(); },
  });
  return h('div', { class: 'scroll-x' }, h('table', { class: 'values study-table', id: `study-${kind}s` },
    h('thead', {}, h('tr', {}, [`${kind}`, `x (${lengthUnit})`, `y (${lengthUnit})`, `z (${lengthUnit})`, `roll (${angleUnit})`, `pitch (${angleUnit})`, `yaw (${angleUnit})`, ''].map((t) => h('th', { text: t })))),
    h('tbody', {}, rows.map((row, r) => h('tr', {},
      h('td', {}, h('input', { type: 'text', value: row.name, class: 'study-name', 'aria-label': `${kind} ${r + 1} name`, onchange: (event) => renameFrame(kind, row, event.target.value) })),
      [0, 1, 2].map((k) => h('td', {}, cell(row, 'position', k, `${row.name} ${'xyz'[k]}`))),
      row.rpy ? [0, 1, 2].map((k) => h('td', {}, cell(row, 'rpy', k, `${row.name} ${['roll', 'pitch', 'yaw'][k]}`)))
        : [h('td', { colspan: 3, class: 'muted', text: 'quaternion (as stated)' })],
      h('td', {}, h('button', { type: 'button', text: 'Remove', 'aria-label': `Remove ${kind} ${r + 1}`, onclick: () => { rows.splice(r, 1); renderStudy(); } })))))));
}

/**
 * Renames a tool or station: the sets that name it follow (a set keeps
 * its frame, under the new name). The editor is redrawn once the change
 * event is over — redrawn inside it, the field being left was removed
 * while the browser still moved focus from it — and the focus stays on the
 * field the person moved to.
 */
function renameFrame(kind, row, name) {
  const old = row.name;
  row.name = name.trim();
  if (old) for (const set of state.study.measurements) if (set[kind] === old) set[kind] = row.name;
  setTimeout(() => {
    // The field focused now, by its place among the editor's fields (its
    // label may hold the old name).
    const fields = () => [...$('study-editor').querySelectorAll('input, select, button')];
    const at = fields().indexOf(document.activeElement);
    renderStudy();
    if (at >= 0 && fields()[at]) fields()[at].focus();
  }, 0);
}

function studySetsTable() {
  const study = state.study;
  const select = (value, options, label, onchange) => h('select', { 'aria-label': label, onchange },
    options.map(([v, t]) => h('option', { value: v, text: t, selected: v === (value || '') })));
  const tools = [['', 'none'], ...study.tools.map((t) => [t.name, t.name])];
  const stations = [['', 'the measurement frame'], ...study.stations.map((t) => [t.name, t.name])];
  const files = state.files.data.map((f) => [f, f]);
  return h('div', { class: 'scroll-x' }, h('table', { class: 'values study-table', id: 'study-sets' },
    h('thead', {}, h('tr', {}, ['set', 'method', 'data file', 'tool (reflector)', 'station', `σ (${study.length_unit})`, 'payload', ''].map((t) => h('th', { text: t })))),
    h('tbody', {}, study.measurements.map((set, index) => h('tr', {},
      h('td', { text: String(index + 1) }),
      h('td', {}, select(set.method, state.info.methods.map((m) => [m.name, m.title]), `set ${index + 1} method`, (e) => { set.method = e.target.value; persist(); })),
      h('td', {}, select(set.data, [['', 'choose…'], ...files], `set ${index + 1} data`, (e) => { set.data = e.target.value; persist(); })),
      h('td', {}, select(set.tool, tools, `set ${index + 1} tool`, (e) => { set.tool = e.target.value; persist(); })),
      h('td', {}, select(set.station, stations, `set ${index + 1} station`, (e) => { set.station = e.target.value; persist(); })),
      h('td', {}, h('input', { type: 'text', class: 'study-number', value: set.sigma, placeholder: 'not stated', 'aria-label': `set ${index + 1} sigma`, onchange: (e) => { set.sigma = e.target.value; persist(); } })),
      h('td', {}, h('input', { type: 'text', class: 'study-payload', id: `study-set-${index + 1}-payload`, value: set.payload || '', placeholder: 'none, or 20kg,0,0,120mm', 'aria-label': `set ${index + 1} payload`, onchange: (e) => { set.payload = e.target.value; persist(); } })),
      h('td', {}, h('button', { type: 'button', text: 'Remove', 'aria-label': `Remove set ${index + 1}`, onclick: () => { study.measurements.splice(index, 1); renderStudy(); } })))))));
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
      h('button', { type: 'button', id: 'study-new', text: 'New study', onclick: () => { state.study = emptyStudy(); clearStudyResult(); renderStudy(); persist(); } }),
      field('Lengths', unit('study-length-unit', study.length_unit, [['m', 'metres'], ['mm', 'millimetres']], (e) => { study.length_unit = e.target.value; renderStudy(); })),
      field('Angles', unit('study-angle-unit', study.angle_unit, [['rad', 'radians'], ['deg', 'degrees']], (e) => { study.angle_unit = e.target.value; renderStudy(); }))),
    study.robot ? studyRobotNote(study) : null,
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
      runButton('study-run', 'Identify the study', identifyStudyRobot),
      h('input', { type: 'text', id: 'study-save-as', placeholder: 'study.toml', value: study.name || '', 'aria-label': 'Save the study as (a file of the folder)' }),
      h('button', { type: 'button', id: 'study-save', text: 'Save the study', onclick: saveStudy })));
  refreshStale();
  persist();
}

/** Whether the table holds the robot study `study` names (its ready robot, or its file, edited or not). */
function tableIsStudyRobot(study) {
  if (!study.robot) return true;
  if (state.robot.origin === 'ready' && !state.file) return state.robot.name === study.robot;
  return state.file === studyRelative(study.robot, study.name);
}

/** What the editor says of the study's robot: the table holds it, or not (a warning naming both). */
function studyRobotNote(study) {
  const table = tableDocument().name || 'an unnamed robot';
  return tableIsStudyRobot(study)
    ? h('p', { class: 'muted', id: 'study-robot-note', text: `${study.name || 'This study'} names the robot ${study.robot}: the table holds it (${table}).` })
    : h('div', { class: 'warnings', id: 'study-robot-note', role: 'status', text: `${study.name || 'This study'} names the robot ${study.robot}, but the table holds ${table}${state.file ? ` (${state.file})` : ''}. Identify asks which to use.` });
}

/** Says again whether the table holds the study's robot (after another robot is opened). */
export function refreshStudyRobotNote() {
  const note = $('study-robot-note');
  if (note && state.study && state.study.robot && state.robot) note.replaceWith(studyRobotNote(state.study));
}

/**
 * Runs the study with the robot it names: when the table holds another,
 * the page asks, naming both — open the study's robot in the table and
 * identify, or identify with the table's robot as it stands.
 */
function identifyStudyRobot() {
  const study = state.study;
  if (tableIsStudyRobot(study)) return identifyStudy();
  const table = tableDocument().name || 'an unnamed robot';
  const anyway = h('button', { type: 'button', id: 'study-robot-table', text: `Identify with ${table}` });
  anyway.addEventListener('click', () => { $('dialog').close(); identifyStudy(); });
  openDialog({
    title: 'Which robot does the study run with?',
    body: h('div', {},
      h('p', { id: 'study-robot-question', text: `${study.name || 'The study'} names the robot ${study.robot}; the table holds ${table}${state.file ? ` (${state.file})` : ''}.${state.dirty ? ' The table’s unsaved edits are lost if the study’s robot is opened.' : ''}` }),
      h('p', { class: 'muted', text: 'A study’s sets were measured on its robot: identifying them with another gives a fit that means nothing.' }),
      anyway),
    ok: `Open ${study.robot} and identify`,
    onOk: async () => {
      await loadStudyRobot(study.robot, study.name);
      setTimeout(identifyStudy, 0);
    },
  });
  return undefined;
}

/** The study's result goes with the study it was of (a new or another study opened). */
function clearStudyResult() {
  state.studyResult = null;
  $('study-result').replaceChildren();
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
    clearStudyResult();
    renderStudy();
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
    const basis = studyBasis();
    const submitted = await api('/identify', { robot: tableDocument(), study: studySpec(state.study) });
    await followStudy(submitted.job, basis, progress);
  } catch (error) {
    error.message = studyWords(error.message);
    result.replaceChildren(errorBox(error));
  }
}

/**
 * Follows the study's identification job `job` (of `basis`) to its end and
 * shows its result in `progress`'s place; a reload during it follows it again.
 */
export async function followStudy(job, basis, progress = null) {
  const result = $('study-result');
  const shown = progress || h('div', { class: 'progress', id: 'study-progress' }, h('div', { class: 'spinner' }), h('span', { text: 'Identifying the study…' }));
  if (!progress) result.replaceChildren(shown);
  const cancel = h('button', { type: 'button', id: 'study-cancel', text: 'Cancel', disabled: true });
  shown.append(cancel);
  try {
    const ended = await followJob(job, shown.children[1], { cancel, resume: { kind: 'study', basis } });
    if (ended.state === 'failed') throw new Error(ended.error);
    if (ended.state !== 'done') throw new Error('The identification was cancelled.');
    renderStudyResult(result, ended.result, job);
    state.studyResult = { basis, stale: false };
    recordRun({
      what: `study ${state.study.name || '(not saved)'}`,
      robot: tableDocument().name || 'unnamed',
      data: `${state.study.measurements.length} sets`,
      settings: `${state.study.tools.length} tools, ${state.study.stations.length} stations`,
      result: ended.result,
    });
    refreshStale();
  } catch (error) {
    error.message = studyWords(error.message);
    result.replaceChildren(errorBox(error));
  }
}

/**
 * A study's errors by set or by station (`groups` as the server sends
 * them): observations, RMS before and after, largest after, and a bar of
 * the RMS after against the largest group's — the set that fits worse than
 * the others stands out.
 */
function groupTable(title, groups, id) {
  if (!groups.length) return null;
  const unit = unitName('length');
  const widest = Math.max(...groups.map((g) => g.rms_after), 1e-15);
  // A set names its tool and station; a station is its own name.
  const sets = Boolean(groups[0].method);
  return h('div', {},
    h('h3', { text: `${title} (${unit})` }),
    h('div', { class: 'scroll-x' }, h('table', { class: 'values', id },
      h('thead', {}, h('tr', {}, [sets ? 'set' : 'station', ...(sets ? ['tool', 'station'] : []), 'observations', 'RMS before', 'RMS after', 'largest after', ''].map((t) => h('th', { text: t })))),
      h('tbody', {}, groups.map((g) => h('tr', {},
        h('td', { text: g.name }), sets ? [h('td', { text: g.tool || '' }), h('td', { text: g.station || 'the measurement frame' })] : null,
        h('td', { class: 'number', text: String(g.observations) }),
        h('td', { class: 'number', title: `${g.rms_before} m`, text: quantity(g.rms_before, 'length') }),
        h('td', { class: 'number', title: `${g.rms_after} m`, text: quantity(g.rms_after, 'length') }),
        h('td', { class: 'number', title: `${g.max_after} m`, text: quantity(g.max_after, 'length') }),
        h('td', { class: 'bar-cell' }, h('div', { class: 'bar', style: `width: ${Math.round((100 * g.rms_after) / widest)}%` })))))))); 
}

/** The study's verdict, errors and identified frames (with σ); job `job`'s. */
function renderStudyResult(container, result, job) {
  const id = result.identification;
  showOnView(`the study${state.study && state.study.name ? ` ${state.study.name}` : ''}`, result.deviations, id.frames, result.frame_covariances);
  const length = (v) => coordinate(v, 'length');
  const angle = (v) => coordinate(v, 'angle');
  const [unit, degrees] = [unitName('length'), unitName('angle')];
  const sigmaOf = (name) => {
    const found = (id.auxiliary || []).find((p) => p.name === name);
    return found ? found.std : null;
  };
  const plusMinus = (frame, keys, kind) => {
    const values = keys.map((k) => sigmaOf(`${frame}.${k}`)).filter((v) => v !== null);
    return values.length ? `± ${quantity(Math.max(...values), kind)}` : '(stated)';
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
      stat(`RMS error before (${unit}): the robot and frames as stated`, quantity(id.before.rms, 'length'), { id: 'study-rms-before' }),
      stat(`RMS error after (${unit})`, quantity(id.after.rms, 'length'), { id: 'study-rms', class: id.verdict.trusted ? 'ok' : '' }),
      stat('parameters identified', String(id.parameters.length), { id: 'study-parameters' })),
    h('h3', { text: `Identified tools and stations (${unit}, ${degrees})` }),
    h('table', { class: 'values', id: 'study-frames' },
      h('thead', {}, h('tr', {}, ['frame', 'role', 'position', 'σ', 'roll, pitch, yaw', 'σ'].map((t) => h('th', { text: t })))),
      h('tbody', {}, rows)),
    groupTable('Errors set by set', id.sets || [], 'study-sets-errors'),
    groupTable('Errors station by station', id.stations || [], 'study-stations-errors'),
    registrationBlock(id.registration, 'study-registration'),
    calibratedActions(result, id.verdict.trusted, job, 'study-calibrated'),
    deviationTable(result.deviations, 'study'),
    correlationHeatmap(result.correlation, 'study'),
    (id.warnings || []).length ? h('div', { class: 'warnings', id: 'study-warnings', role: 'status' }, h('strong', { text: 'Warnings' }), h('ul', {}, id.warnings.map((w) => h('li', { text: w })))) : null);
}
