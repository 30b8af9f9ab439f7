// The robot's table: Khalil–Kleinfinger parameters per frame in the page's
// units (the document keeps its own), edits checked as typed and by the
// server, undo and redo, the priority matrix and the table's angle unit.
import { api } from './api.js';
import { refreshDataChoices } from './data-choices.js';
import { openDialog } from './dialogs.js';
import { h, $ } from './dom.js';
import { emit } from './events.js';
import { locationText } from './fields.js';
import { fmt, numberProblem, readNumber } from './format.js';
import { prefillPlanes } from './method-options.js';
import { refreshStale } from './stale.js';
import { KINDS, KIND_HEADS, COLUMNS, ANGLES, JOINT_KEYS, JOINT_ANGLES, state, tableDocument, persist } from './state.js';
import { renderSliders, updateSliderRanges, refreshPose } from './view.js';
import { unitName } from './units.js';

/**
 * Shows `view` in the table. Another robot clears the previous robot's
 * results and data choices; `keep` (the calibrated robot of the same arm)
 * keeps them.
 */
export function setRobot(view, file, { keep = false } = {}) {
  if (!keep && state.robot) clearResults();
  state.robot = view;
  state.file = file || null;
  state.dirty = false;
  state.undo = [];
  state.redo = [];
  state.localProblems.clear();
  const joints = view.document.frame.length - 2;
  state.q = new Array(Math.max(joints, 0)).fill(0);
  state.pose = null;
  state.robotSerial += 1;
  state.view.zoom = 1;
  state.view.bounds = null;
  renderRobot();
  refreshPose();
}

/** Empties every function's result and forgets generated data and results. */
function clearResults() {
  for (const container of document.querySelectorAll('#method-panels .result, #study-result, #study-plan-result')) container.replaceChildren();
  state.generated = {};
  state.heldOut = {};
  state.results = {};
  state.calibrated = {};
  state.planned = {};
  state.plannedPoints = {};
  state.evaluated = {};
  state.exported = {};
  state.overlay = null;
  if (state.info) {
    for (const method of state.info.methods) {
      for (const select of document.querySelectorAll(`select.data-choice[data-method="${method.name}"]`)) select.value = '';
      refreshDataChoices(method.name);
    }
  }
}

/** Runs `then` at once, or after the user agrees to lose the table's unsaved edits. */
export function confirmDiscard(then, what) {
  if (!state.dirty) return then();
  openDialog({
    title: 'Discard the unsaved edits?',
    body: h('p', { id: 'discard-text', text: `The table of ${tableDocument().name || 'this robot'} has edits that are not saved. ${what} replaces them; Save first to keep them.` }),
    ok: 'Discard edits',
    onOk: () => { setTimeout(then, 0); },
  });
  return undefined;
}

/** Keeps the table's document before an edit, for Undo. */
export function remember() {
  state.undo.push(JSON.stringify(tableDocument()));
  if (state.undo.length > 200) state.undo.shift();
  state.redo = [];
  renderUndo();
}

function renderUndo() {
  $('table-undo').disabled = state.undo.length === 0;
  $('table-redo').disabled = state.redo.length === 0;
}

/** Undo (`back`) or redo one table edit. */
export function undoEdit(back) {
  const from = back ? state.undo : state.redo;
  const to = back ? state.redo : state.undo;
  if (!from.length) return;
  to.push(JSON.stringify(tableDocument()));
  state.robot.document = JSON.parse(from.pop());
  state.localProblems.clear();
  state.dirty = true;
  renderRobot();
  renderUndo();
  refreshStale();
  scheduleCheck();
}

/** The table's caption: its units, and those the robot file keeps. */
export function renderTableUnits() {
  const file = tableDocument().angle_unit === 'deg' ? 'degrees' : 'radians';
  $('table-units').textContent = state.units === 'mm'
    ? `table in mm and degrees (the robot file keeps metres and ${file})`
    : `table in metres and radians (the robot file keeps metres and ${file})`;
}

export function renderRobot() {
  const view = state.robot;
  const doc = view.document;
  $('robot-name').textContent = doc.name || 'Unnamed robot';
  const origin = state.file ? `file ${state.file}`
    : view.origin === 'ready' ? `ready robot “${view.name}” (Save as… to keep a copy)`
      : view.origin === 'imported' ? `converted from ${view.name} (Save as… to keep it as a robot file or a URDF)`
        : view.origin === 'uploaded' ? `uploaded ${view.uploaded || ''} (not a file of the folder: Save as… to keep it there)`
          : 'not saved yet';
  $('robot-origin').textContent = (state.dirty ? '• modified · ' : '') + origin;
  $('angle-unit').value = doc.angle_unit === 'deg' ? 'deg' : 'rad';
  renderTableUnits();
  renderFrames();
  renderProblems();
  renderPriority();
  renderSliders();
  prefillPlanes();
  persist();
}

function applicable(frame, last, key) {
  if (frame === 0) return key === 'sigma' || key === 'theta' || key === 'r';
  if (frame === last) return !JOINT_KEYS.has(key);
  return true;
}

/**
 * The factor from the document's value of `key` in `frame` to what the
 * table shows in the page's units: lengths in mm or m (documents hold
 * metres), angles in degrees or radians (documents hold their own
 * angle_unit). Only the display changes: the document keeps its units.
 */
function displayScale(frame, key) {
  const revolute = (frame.sigma || 0) === 0;
  const prismatic = frame.sigma === 1;
  const angle = ANGLES.has(key) || (JOINT_ANGLES.has(key) && revolute);
  const length = key === 'd' || key === 'r' || (JOINT_ANGLES.has(key) && prismatic);
  if (angle) {
    const documentDegrees = tableDocument().angle_unit === 'deg';
    const shownDegrees = state.units === 'mm';
    if (documentDegrees === shownDegrees) return 1;
    return shownDegrees ? 180 / Math.PI : Math.PI / 180;
  }
  if (length && state.units === 'mm') return 1e3;
  return 1;
}

/** A document value as the table shows it (8 significant digits). */
function shown(frame, key) {
  const value = frame[key];
  return typeof value === 'number' ? fmt(Number((value * displayScale(frame, key)).toPrecision(12))) : fmt(value);
}

/**
 * A column's head with its unit in the page's units: lengths and angles
 * as the Units menu says; a joint's offset and limits in the unit of its
 * type (an angle, or a prismatic joint's length); compliances per joint type.
 */
function columnHead(column) {
  const [length, angle] = [unitName('length'), unitName('angle')];
  const head = ANGLES.has(column.key) ? `${column.head} (${angle})`
    : column.key === 'd' || column.key === 'r' ? `${column.head} (${length})`
      : JOINT_ANGLES.has(column.key) ? `${column.head} (${angle}; P: ${length})`
        : column.key === 'compliance' ? 'c (rad/N·m; P: m/N)'
          : column.head;
  return h('th', { text: head, title: JOINT_ANGLES.has(column.key) ? `${angle} for a revolute joint, ${length} for a prismatic one (σ = 1)` : null });
}

/** A cell's unit, for its hover text: what the number typed there is in. */
function cellUnit(frame, key) {
  const prismatic = frame.sigma === 1;
  if (ANGLES.has(key)) return unitName('angle');
  if (key === 'd' || key === 'r') return unitName('length');
  if (JOINT_ANGLES.has(key)) return prismatic ? `${unitName('length')} (prismatic joint)` : unitName('angle');
  if (key === 'compliance') return prismatic ? 'm/N (prismatic joint)' : 'rad/(N·m)';
  if (key === 'mass') return 'kg';
  return null;
}

export function renderFrames() {
  const doc = tableDocument();
  const last = doc.frame.length - 1;
  const head = h('tr', {}, h('th', { text: 'j' }), COLUMNS.map(columnHead));
  const rows = doc.frame.map((frame, j) => h('tr', {},
    h('td', { text: String(j) }),
    COLUMNS.map((column) => {
      if (!applicable(j, last, column.key)) return h('td', { class: 'none', text: '·' });
      const input = h('input', {
        type: 'text',
        inputmode: 'decimal',
        class: column.key === 'sigma' ? 'sigma' : '',
        value: shown(frame, column.key),
        placeholder: column.key === 'K' ? '1' : column.key === 'sigma' ? '' : '0',
        'data-frame': j,
        'data-key': column.key,
        'aria-label': `frame ${j} ${column.key}`,
        title: cellUnit(frame, column.key),
        onchange: (event) => editCell(j, column.key, event.target),
      });
      return h('td', {}, input);
    })));
  $('frames-table').replaceChildren(h('thead', {}, head), h('tbody', {}, rows));
}

function editCell(frame, key, input) {
  remember();
  const text = input.value.trim();
  const slot = `${frame}/${key}`;
  const target = tableDocument().frame[frame];
  state.localProblems.delete(slot);
  if (text === '') {
    delete target[key];
  } else {
    const value = readNumber(text);
    if (!Number.isFinite(value)) {
      state.localProblems.set(slot, { frame, key, message: numberProblem(text) });
    } else if (key === 'sigma' && !Number.isInteger(value)) {
      state.localProblems.set(slot, { frame, key, message: 'sigma is 0 (revolute), 1 (prismatic) or 2 (fixed)' });
    } else if ((key === 'compliance' || key === 'mass') && value < 0) {
      state.localProblems.set(slot, { frame, key, message: `${text} is negative: a ${key === 'mass' ? 'mass' : 'compliance'} is 0 or more` });
    } else if (key !== 'sigma' && Math.abs(value / displayScale(target, key)) > 1000) {
      state.localProblems.set(slot, { frame, key, message: `${text} is beyond ±1000 m or rad: no robot has such a value` });
    } else {
      // What is typed is in the page's units; the document keeps its own.
      target[key] = key === 'sigma' ? value : value / displayScale(target, key);
    }
  }
  markModified();
  renderProblems();
  scheduleCheck();
}

export function markModified() {
  if (!state.dirty) {
    state.dirty = true;
    $('robot-origin').textContent = `• modified · ${$('robot-origin').textContent}`;
  }
  refreshStale();
  persist();
}

let checkTimer = null;

let checkSerial = 0;

export function scheduleCheck() {
  clearTimeout(checkTimer);
  checkTimer = setTimeout(checkRobot, 180);
}

async function checkRobot() {
  const serial = ++checkSerial;
  try {
    const view = await api('/robots/check', { robot: tableDocument() });
    if (serial !== checkSerial) return;
    const jointsBefore = state.robot.summary ? state.robot.summary.joints.length : -1;
    state.robot.problems = view.problems;
    state.robot.summary = view.summary || null;
    renderProblems();
    if (view.summary) {
      renderPriority();
      if (view.summary.joints.length !== jointsBefore) renderSliders();
      else updateSliderRanges();
      // An edit may move the frames anywhere: frame them again.
      state.view.bounds = null;
      refreshPose();
    }
  } catch (error) {
    if (serial !== checkSerial) return;
    // A lost server says so once (its banner); the table is not to blame.
    if (error.unreachable) return;
    state.robot.problems = [{ location: { kind: 'document' }, message: error.message }];
    state.robot.summary = null;
    renderProblems();
  }
}

function renderProblems() {
  for (const input of document.querySelectorAll('#frames-table input.invalid')) {
    input.classList.remove('invalid');
    input.removeAttribute('title');
  }
  const items = [];
  const mark = (frame, key, message) => {
    const input = document.querySelector(`#frames-table input[data-frame="${frame}"][data-key="${key}"]`);
    if (input) {
      input.classList.add('invalid');
      input.title = message;
    }
  };
  for (const problem of state.localProblems.values()) {
    mark(problem.frame, problem.key, problem.message);
    items.push(h('li', { text: `Frame ${problem.frame}, ${problem.key}: ${problem.message}` }));
  }
  for (const problem of state.robot.problems || []) {
    if (problem.location.kind === 'frame') mark(problem.location.frame, problem.location.key, problem.message);
    items.push(h('li', { text: `${locationText(problem.location)}: ${problem.message}` }));
  }
  $('problems').replaceChildren(...items);
  $('notes').replaceChildren(...(state.robot.notes || []).map((note) => h('li', { text: note })));
  const badge = $('robot-status');
  const summary = state.robot.summary;
  if (items.length === 0 && summary) {
    badge.className = 'badge ok';
    badge.textContent = `valid · ${summary.letters.length} joints ${summary.letters} · ${summary.parameter_count} parameters`;
  } else {
    badge.className = 'badge bad';
    badge.textContent = `${items.length} problem${items.length === 1 ? '' : 's'}`;
  }
  for (const button of document.querySelectorAll('button.run')) {
    button.disabled = items.length > 0;
  }
  emit('changed');
}

export function renderPriority() {
  const doc = tableDocument();
  const summary = state.robot.summary;
  const matrix = doc.priority ? doc.priority.matrix : summary ? summary.priority : null;
  $('priority-origin').textContent = doc.priority ? '(set for this robot)' : '(the paper’s default rules)';
  if (!matrix) {
    $('priority-table').replaceChildren();
    return;
  }
  const head = h('tr', {}, h('th', { text: 'j' }), KIND_HEADS.map((k) => h('th', { text: k })));
  const rows = matrix.map((row, j) => h('tr', {}, h('th', { text: String(j) }),
    row.map((value, c) => h('td', {}, h('input', {
      type: 'text',
      inputmode: 'numeric',
      value: String(value),
      'data-row': j,
      'data-column': c,
      'aria-label': `priority of ${KINDS[c]}${j}`,
      onchange: editPriority,
    })))));
  $('priority-table').replaceChildren(h('thead', {}, head), h('tbody', {}, rows));
}

function editPriority(event) {
  const edited = event && event.target;
  if (edited) {
    const text = edited.value.trim();
    const value = Number(text);
    const name = `${KINDS[Number(edited.dataset.column)]}${edited.dataset.row}`;
    if (text === '' || !Number.isInteger(value) || value < 0) {
      edited.classList.add('invalid');
      $('priority-problem').textContent = `Priority of ${name}: “${text}” is not a priority (0 = not identified, or a positive whole number)`;
      return;
    }
    edited.classList.remove('invalid');
    $('priority-problem').textContent = '';
  }
  remember();
  const rows = [];
  for (const input of document.querySelectorAll('#priority-table input')) {
    const row = Number(input.dataset.row);
    rows[row] = rows[row] || [];
    const value = Number(input.value.trim());
    rows[row][Number(input.dataset.column)] = Number.isInteger(value) && value >= 0 ? value : 0;
  }
  tableDocument().priority = { matrix: rows };
  $('priority-origin').textContent = '(set for this robot)';
  markModified();
  scheduleCheck();
}

export function changeAngleUnit(event) {
  const doc = tableDocument();
  const toDegrees = event.target.value === 'deg';
  const wasDegrees = doc.angle_unit === 'deg';
  if (toDegrees === wasDegrees) return;
  remember();
  const factor = toDegrees ? 180 / Math.PI : Math.PI / 180;
  for (const frame of doc.frame) {
    for (const key of Object.keys(frame)) {
      const angle = ANGLES.has(key) || (JOINT_ANGLES.has(key) && frame.sigma === 0);
      if (angle && typeof frame[key] === 'number') frame[key] *= factor;
    }
  }
  if (toDegrees) doc.angle_unit = 'deg'; else delete doc.angle_unit;
  markModified();
  renderTableUnits();
  renderFrames();
  scheduleCheck();
}
