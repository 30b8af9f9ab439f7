// gecaro's page: the robot's table, a 3D view, and a menu per calibration
// method with its three functions. It talks to the JSON API of docs/api.md;
// every computation happens on the server. No framework, no dependencies.
'use strict';

const KINDS = ['alpha', 'd', 'theta', 'r', 'beta', 'K'];
const KIND_HEADS = ['α', 'd', 'θ', 'r', 'β', 'K'];
const COLUMNS = [
  { key: 'sigma', head: 'σ' }, { key: 'alpha', head: 'α' }, { key: 'd', head: 'd' },
  { key: 'theta', head: 'θ' }, { key: 'r', head: 'r' }, { key: 'beta', head: 'β' },
  { key: 'K', head: 'K' }, { key: 'offset', head: 'offset' }, { key: 'qmin', head: 'qmin' },
  { key: 'qmax', head: 'qmax' },
];
const ANGLES = new Set(['alpha', 'theta', 'beta']);
const JOINT_KEYS = new Set(['K', 'offset', 'qmin', 'qmax']);
const JOINT_ANGLES = new Set(['offset', 'qmin', 'qmax']);
const DEFAULT_COUNTS = {
  position: 50, frame: 30, 'point-link': 80, 'frame-link': 60, plane1: 120, plane2: 120, distance: 200,
};
const FUNCTIONS = ['identifiable', 'plan', 'generate', 'identify', 'evaluate', 'compensate'];

const state = {
  info: null,
  robot: null, // {origin, name, document, problems, summary}
  file: null, // the robot's file in the folder, once opened or saved
  dirty: false,
  q: [],
  pose: null,
  localProblems: new Map(),
  files: { robots: [], data: [] },
  generated: {}, // method -> {csv, file_name, real, origin, serial}
  heldOut: {}, // method -> held-out data of the generated data's real robot
  results: {}, // method -> the last identification {job, result}, shown again after a reload
  calibrated: {}, // method -> the calibrated robot's document, for Evaluate
  study: null, // the study editor's study (see emptyStudy)
  undo: [], // earlier table documents (JSON), for Undo
  redo: [],
  units: 'mm', // results in 'mm' (mm, degrees) or 'm' (m, radians)
  method: 'position',
  function: 'identifiable',
  robotSerial: 0, // changes with every robot loaded, so late answers about the last one are dropped
  view: { azimuth: -0.9, elevation: 0.45, zoom: 1, bounds: null },
};

// ---------------------------------------------------------------- helpers

function h(tag, attributes, ...children) {
  const element = document.createElement(tag);
  for (const [name, value] of Object.entries(attributes || {})) {
    if (value === undefined || value === null || value === false) continue;
    if (name.startsWith('on')) element.addEventListener(name.slice(2), value);
    else if (name === 'class') element.className = value;
    else if (name === 'text') element.textContent = value;
    else element.setAttribute(name, value === true ? '' : value);
  }
  for (const child of children.flat()) {
    if (child === undefined || child === null || child === false) continue;
    element.append(child instanceof Node ? child : document.createTextNode(String(child)));
  }
  return element;
}

const $ = (id) => document.getElementById(id);

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
      scheduleCheck();
    } catch (ignored) { /* still lost: the banner stays */ } finally {
      retry.disabled = false;
    }
  });
  document.body.prepend(banner);
}

/** A call of the JSON API; `signal` (an AbortController's) lets the page abandon it. */
async function api(path, body, signal) {
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

/** A number as a person reads it: up to 8 significant digits. */
function fmt(value) {
  if (value === undefined || value === null) return '';
  if (value === 0) return '0';
  const size = Math.abs(value);
  if (size >= 1e-4 && size < 1e7) return String(Number(value.toPrecision(8)));
  return value.toExponential(4);
}

function fixed(value, digits) {
  return Number.isFinite(value) ? value.toFixed(digits) : '–';
}

function sci(value) {
  return Number.isFinite(value) ? value.toExponential(2) : '–';
}

function toast(text) {
  const element = $('toast');
  element.textContent = text;
  element.classList.add('show');
  clearTimeout(toast.timer);
  toast.timer = setTimeout(() => element.classList.remove('show'), 2600);
}

function slug(text) {
  return text.toLowerCase().replace(/[^a-z0-9]+/g, '-').replace(/^-|-$/g, '') || 'robot';
}

function download(name, text, type) {
  const url = URL.createObjectURL(new Blob([text], { type }));
  const link = h('a', { href: url, download: name });
  document.body.append(link);
  link.click();
  link.remove();
  setTimeout(() => URL.revokeObjectURL(url), 1000);
}

function parseVector(text, what) {
  const parts = text.trim().split(/[\s,;]+/).filter(Boolean).map(Number);
  if (parts.length !== 3 || !parts.every(Number.isFinite)) {
    throw new Error(`${what} needs three numbers, e.g. 0.3, 0.5, 0.81`);
  }
  return parts;
}

// ---------------------------------------------------------------- dialogs

function openDialog({ title, body, ok = 'OK', onOk }) {
  const dialog = $('dialog');
  $('dialog-title').textContent = title;
  $('dialog-body').replaceChildren(body);
  $('dialog-error').textContent = '';
  const okButton = $('dialog-ok');
  okButton.textContent = ok;
  okButton.hidden = !onOk;
  $('dialog-form').onsubmit = async (event) => {
    event.preventDefault();
    if (!onOk) return;
    okButton.disabled = true;
    try {
      await onOk();
      dialog.close();
    } catch (error) {
      $('dialog-error').textContent = error.message;
    } finally {
      okButton.disabled = false;
    }
  };
  dialog.showModal();
  const first = body.querySelector && body.querySelector('input');
  if (first) first.focus();
}

function dialogError(text) {
  $('dialog-error').textContent = text;
}

// ---------------------------------------------------------------- robot

function document_() {
  return state.robot.document;
}

/**
 * Shows `view` in the table. Another robot clears the previous robot's
 * results and data choices; `keep` (the calibrated robot of the same arm)
 * keeps them.
 */
function setRobot(view, file, { keep = false } = {}) {
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
  for (const container of document.querySelectorAll('#method-panels .result, #study-result')) container.replaceChildren();
  state.generated = {};
  state.heldOut = {};
  state.results = {};
  state.calibrated = {};
  if (state.info) {
    for (const method of state.info.methods) {
      for (const select of document.querySelectorAll(`select.data-choice[data-method="${method.name}"]`)) select.value = '';
      refreshDataChoices(method.name);
    }
  }
}

/** Runs `then` at once, or after the user agrees to lose the table's unsaved edits. */
function confirmDiscard(then, what) {
  if (!state.dirty) return then();
  openDialog({
    title: 'Discard the unsaved edits?',
    body: h('p', { id: 'discard-text', text: `The table of ${document_().name || 'this robot'} has edits that are not saved. ${what} replaces them; Save first to keep them.` }),
    ok: 'Discard edits',
    onOk: () => { setTimeout(then, 0); },
  });
  return undefined;
}

/** Keeps the table's document before an edit, for Undo. */
function remember() {
  state.undo.push(JSON.stringify(document_()));
  if (state.undo.length > 200) state.undo.shift();
  state.redo = [];
  renderUndo();
}

function renderUndo() {
  $('table-undo').disabled = state.undo.length === 0;
  $('table-redo').disabled = state.redo.length === 0;
}

/** Undo (`back`) or redo one table edit. */
function undoEdit(back) {
  const from = back ? state.undo : state.redo;
  const to = back ? state.redo : state.undo;
  if (!from.length) return;
  to.push(JSON.stringify(document_()));
  state.robot.document = JSON.parse(from.pop());
  state.localProblems.clear();
  state.dirty = true;
  renderRobot();
  renderUndo();
  refreshStale();
  scheduleCheck();
}

// ---------------------------------------------------------------- the page across reloads

const STORAGE_KEY = 'gecaro.page';

/** Keeps the robot, the settings and the last results in the browser. */
function persist() {
  if (!state.robot) return;
  const page = {
    robot: state.robot, file: state.file, dirty: state.dirty, method: state.method,
    function: state.function, units: state.units, results: state.results, study: state.study,
  };
  try {
    localStorage.setItem(STORAGE_KEY, JSON.stringify(page));
  } catch (error) {
    // Over the browser's quota: keep the robot and the settings only.
    try {
      localStorage.setItem(STORAGE_KEY, JSON.stringify({ ...page, results: {} }));
    } catch (ignored) { /* storage unavailable: nothing to restore */ }
  }
}

/** The page as it was before a reload, or null. */
function stored() {
  try {
    const page = JSON.parse(localStorage.getItem(STORAGE_KEY) || 'null');
    return page && page.robot && page.robot.document ? page : null;
  } catch (error) {
    return null;
  }
}

/** The table's caption: its units, and those the robot file keeps. */
function renderTableUnits() {
  const file = document_().angle_unit === 'deg' ? 'degrees' : 'radians';
  $('table-units').textContent = state.units === 'mm'
    ? `table in mm and degrees (the robot file keeps metres and ${file})`
    : `table in metres and radians (the robot file keeps metres and ${file})`;
}

function renderRobot() {
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
    const documentDegrees = document_().angle_unit === 'deg';
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

function renderFrames() {
  const doc = document_();
  const last = doc.frame.length - 1;
  const head = h('tr', {}, h('th', { text: 'j' }), COLUMNS.map((c) => h('th', { text: c.head })));
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
  const target = document_().frame[frame];
  state.localProblems.delete(slot);
  if (text === '') {
    delete target[key];
  } else {
    const value = Number(text);
    if (!Number.isFinite(value)) {
      state.localProblems.set(slot, { frame, key, message: `“${text}” is not a number` });
    } else if (key === 'sigma' && !Number.isInteger(value)) {
      state.localProblems.set(slot, { frame, key, message: 'sigma is 0 (revolute), 1 (prismatic) or 2 (fixed)' });
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

function markModified() {
  if (!state.dirty) {
    state.dirty = true;
    $('robot-origin').textContent = `• modified · ${$('robot-origin').textContent}`;
  }
  refreshStale();
  persist();
}

/** The data chosen in function `fn` of method `name` (a generation counted as new data). */
function dataKey(name, fn) {
  const data = $(`${name}-${fn}-data`);
  const choice = data ? data.value : '';
  const kept = { generated: state.generated[name], 'held-out': state.heldOut[name] }[choice];
  return choice + (kept ? `#${kept.serial || 0}` : '');
}

/** What an identification of method `name` is of: the table and the data chosen. */
function identificationBasis(name) {
  return { table: JSON.stringify(document_()), data: dataKey(name, 'identify') };
}

/**
 * Marks each identification whose table or data changed since as stale: its
 * verdict, its calibrated robot (Save) and Evaluate's comparison are of the
 * table as it was. Undoing back to that table clears the mark.
 */
function refreshStale() {
  for (const [name, last] of Object.entries(state.results)) {
    const container = $(`${name}-identify-result`);
    if (!container || !last.basis) continue;
    const now = identificationBasis(name);
    const changed = [
      now.table !== last.basis.table ? 'the table' : null,
      now.data !== last.basis.data ? 'the data chosen' : null,
    ].filter(Boolean);
    last.stale = changed.length > 0;
    const banner = $(`${name}-identify-stale`);
    if (!last.stale) {
      if (banner) banner.remove();
      container.classList.remove('stale');
      continue;
    }
    const text = `Stale: ${changed.join(' and ')} changed after this identification. Its verdict, its calibrated robot (Save) and Evaluate’s comparison are of the table and data as they were; identify again.`;
    if (banner) {
      banner.textContent = text;
    } else {
      container.prepend(h('div', { class: 'warnings', id: `${name}-identify-stale`, text }));
    }
    container.classList.add('stale');
  }
}

let checkTimer = null;
let checkSerial = 0;
function scheduleCheck() {
  clearTimeout(checkTimer);
  checkTimer = setTimeout(checkRobot, 180);
}

async function checkRobot() {
  const serial = ++checkSerial;
  try {
    const view = await api('/robots/check', { robot: document_() });
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

function locationText(location) {
  switch (location.kind) {
    case 'frame': return `Frame ${location.frame}, ${location.key}`;
    case 'key': return location.key;
    case 'coupling': return `Coupling matrix ${location.matrix}`;
    case 'priority': return location.row === null || location.row === undefined
      ? 'Priority matrix' : `Priority matrix, row ${location.row}`;
    default: return 'Robot';
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
}

function renderPriority() {
  const doc = document_();
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
  document_().priority = { matrix: rows };
  $('priority-origin').textContent = '(set for this robot)';
  markModified();
  scheduleCheck();
}

function changeAngleUnit(event) {
  const doc = document_();
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

// ---------------------------------------------------------------- sliders and view

function sliderValue(index) {
  const joint = state.robot.summary.joints[index];
  return Math.min(Math.max(state.q[index] || 0, joint.qmin), joint.qmax);
}

function sliderText(index) {
  const joint = state.robot.summary.joints[index];
  const value = state.q[index];
  return joint.revolute ? `${(value * 180 / Math.PI).toFixed(1)}°` : `${value.toFixed(3)} m`;
}

function renderSliders() {
  const summary = state.robot.summary;
  const container = $('sliders');
  if (!summary) {
    container.replaceChildren(h('span', { class: 'muted', text: 'Fix the table to move the robot.' }));
    return;
  }
  state.q = summary.joints.map((_, i) => state.q[i] || 0);
  const cells = summary.joints.flatMap((joint, i) => {
    state.q[i] = sliderValue(i);
    const output = h('output', { id: `slider-value-${i + 1}`, text: sliderText(i) });
    const input = h('input', {
      type: 'range',
      id: `slider-${i + 1}`,
      min: joint.qmin,
      max: joint.qmax,
      step: (joint.qmax - joint.qmin) / 2000,
      value: state.q[i],
      'aria-label': `joint ${i + 1}`,
      oninput: (event) => {
        state.q[i] = Number(event.target.value);
        output.textContent = sliderText(i);
        refreshPose();
      },
    });
    return [h('label', { for: `slider-${i + 1}`, text: `q${i + 1}` }), input, output];
  });
  container.replaceChildren(...cells);
}

function updateSliderRanges() {
  state.robot.summary.joints.forEach((joint, i) => {
    const input = $(`slider-${i + 1}`);
    if (!input) return;
    input.min = joint.qmin;
    input.max = joint.qmax;
    input.step = (joint.qmax - joint.qmin) / 2000;
    state.q[i] = sliderValue(i);
    input.value = state.q[i];
    $(`slider-value-${i + 1}`).textContent = sliderText(i);
  });
}

let poseBusy = false;
let posePending = false;
async function refreshPose() {
  if (!state.robot.summary) return;
  if (poseBusy) {
    posePending = true;
    return;
  }
  poseBusy = true;
  const serial = state.robotSerial;
  try {
    const pose = await api('/robots/pose', { robot: document_(), q: state.q });
    if (serial === state.robotSerial) {
      state.pose = pose.frames;
      drawView();
    } else {
      posePending = true;
    }
  } catch (error) {
    if (serial === state.robotSerial && !error.unreachable) {
      state.pose = null;
      drawView(error.message);
    }
  } finally {
    poseBusy = false;
    if (posePending) {
      posePending = false;
      refreshPose();
    }
  }
}

function project(point) {
  const { azimuth, elevation } = state.view;
  const right = [-Math.sin(azimuth), Math.cos(azimuth), 0];
  const up = [-Math.sin(elevation) * Math.cos(azimuth), -Math.sin(elevation) * Math.sin(azimuth), Math.cos(elevation)];
  const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  return [dot(point, right), dot(point, up)];
}

/** A round grid step: 1, 2 or 5 × 10^k, about `target`. */
function niceStep(target) {
  const power = Math.pow(10, Math.floor(Math.log10(target)));
  const mantissa = target / power;
  return (mantissa < 1.5 ? 1 : mantissa < 3.5 ? 2 : 5) * power;
}

/** Centre and radius of what is drawn: the world origin and every frame. */
function viewBounds(origins) {
  const points = [[0, 0, 0], ...origins];
  const low = [0, 1, 2].map((k) => Math.min(...points.map((p) => p[k])));
  const high = [0, 1, 2].map((k) => Math.max(...points.map((p) => p[k])));
  const centre = low.map((l, k) => (l + high[k]) / 2);
  const radius = Math.max(0.1, Math.hypot(...high.map((h_, k) => h_ - low[k])) / 2);
  return { centre, radius };
}

function drawView(message) {
  const canvas = $('robot-view');
  const ratio = window.devicePixelRatio || 1;
  const width = canvas.clientWidth;
  const height = canvas.clientHeight;
  if (canvas.width !== width * ratio) {
    canvas.width = width * ratio;
    canvas.height = height * ratio;
  }
  const context = canvas.getContext('2d');
  context.setTransform(ratio, 0, 0, ratio, 0, 0);
  context.clearRect(0, 0, width, height);
  if (!state.pose) {
    context.fillStyle = '#5b6775';
    context.font = '14px system-ui, sans-serif';
    context.fillText(message || 'No valid robot to draw.', 16, 28);
    return;
  }
  const origins = state.pose.map((f) => f.origin);
  if (!state.view.bounds) state.view.bounds = viewBounds(origins);
  const { centre, radius } = state.view.bounds;
  const scale = (Math.min(width, height) * 0.46 * state.view.zoom) / radius;
  const [cx, cy] = project(centre);
  const toScreen = (point) => {
    const [x, y] = project(point);
    return [width / 2 + (x - cx) * scale, height / 2 - (y - cy) * scale];
  };
  const line = (a, b, color, widthPx, dash) => {
    const [ax, ay] = toScreen(a);
    const [bx, by] = toScreen(b);
    context.strokeStyle = color;
    context.lineWidth = widthPx;
    context.setLineDash(dash || []);
    context.beginPath();
    context.moveTo(ax, ay);
    context.lineTo(bx, by);
    context.stroke();
    context.setLineDash([]);
  };
  // Floor grid (the world's xy plane) around the robot.
  const step = niceStep(radius / 4);
  const extent = Math.ceil((radius * 1.2) / step) * step;
  const [gx, gy] = [Math.round(centre[0] / step) * step, Math.round(centre[1] / step) * step];
  for (let v = -extent; v <= extent + 1e-9; v += step) {
    line([gx + v, gy - extent, 0], [gx + v, gy + extent, 0], '#e3e8ee', 1);
    line([gx - extent, gy + v, 0], [gx + extent, gy + v, 0], '#e3e8ee', 1);
  }
  // The current method's plane (plane methods) and the points of its
  // generated data (methods that measure a point), in the world frame.
  state.view.drawn = { plane: false, points: 0 };
  const method = state.info && methodInfo(state.method);
  if (method && method.uses_plane) {
    try {
      const normal = parseVector($(`${state.method}-identify-normal`).value, 'normal');
      const point = parseVector($(`${state.method}-identify-point`).value, 'point');
      const length = Math.hypot(...normal);
      const n = normal.map((v) => v / length);
      const helper = Math.abs(n[2]) < 0.9 ? [0, 0, 1] : [1, 0, 0];
      const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
      const u = cross(n, helper);
      const ul = Math.hypot(...u);
      const e1 = u.map((v) => v / ul);
      const e2 = cross(n, e1);
      const half = radius * 0.6;
      const corner = (a, b) => point.map((p, k) => p + (a * e1[k] + b * e2[k]) * half);
      const corners = [corner(-1, -1), corner(1, -1), corner(1, 1), corner(-1, 1)].map(toScreen);
      context.fillStyle = 'rgba(31, 111, 235, 0.10)';
      context.strokeStyle = 'rgba(31, 111, 235, 0.6)';
      context.lineWidth = 1.5;
      context.beginPath();
      corners.forEach(([x, y], i) => (i ? context.lineTo(x, y) : context.moveTo(x, y)));
      context.closePath();
      context.fill();
      context.stroke();
      state.view.drawn.plane = true;
    } catch (error) {
      // No valid plane in the fields yet: nothing to draw.
    }
  }
  // The real robot's terminal points where the generated data were measured
  // (on the plane for the plane methods, on the fixed points for the links).
  const generated = state.generated[state.method];
  if (generated && generated.points) {
    context.fillStyle = 'rgba(214, 39, 40, 0.75)';
    for (const point of generated.points) {
      const [x, y] = toScreen(point);
      context.beginPath();
      context.arc(x, y, 2.5, 0, 2 * Math.PI);
      context.fill();
      state.view.drawn.points += 1;
    }
  }
  // World axes.
  const axis = radius * 0.12;
  line([0, 0, 0], [axis, 0, 0], '#e8a3a3', 1.5);
  line([0, 0, 0], [0, axis, 0], '#9fd09f', 1.5);
  line([0, 0, 0], [0, 0, axis], '#9dbfe0', 1.5);
  line([0, 0, 0], origins[0], '#9aa6b2', 2, [5, 4]);
  // Links between successive frame origins.
  context.lineCap = 'round';
  for (let i = 0; i + 1 < origins.length; i += 1) line(origins[i], origins[i + 1], '#3b4a5a', 7);
  context.lineCap = 'butt';
  // Frame axes: x red, y green, z blue; the tool's larger.
  state.pose.forEach((frame, j) => {
    const size = j === state.pose.length - 1 ? axis * 1.6 : axis;
    const tip = (v) => frame.origin.map((o, k) => o + v[k] * size);
    line(frame.origin, tip(frame.x), '#d62728', 2);
    line(frame.origin, tip(frame.y), '#2ca02c', 2);
    line(frame.origin, tip(frame.z), '#1f77b4', 2.5);
  });
  // Origins, with the numbers of the frames that share a point.
  const spots = [];
  state.pose.forEach((frame, j) => {
    const [x, y] = toScreen(frame.origin);
    const spot = spots.find((s) => Math.hypot(s.x - x, s.y - y) < 4);
    if (spot) spot.frames.push(j); else spots.push({ x, y, frames: [j] });
  });
  context.font = '12px system-ui, sans-serif';
  const last = state.pose.length - 1;
  for (const spot of spots) {
    const joint = spot.frames.some((j) => j !== 0 && j !== last);
    context.fillStyle = '#ffffff';
    context.strokeStyle = '#14202e';
    context.lineWidth = 2;
    context.beginPath();
    context.arc(spot.x, spot.y, joint ? 6 : 4, 0, 2 * Math.PI);
    context.fill();
    context.stroke();
    context.fillStyle = '#14202e';
    context.fillText(spot.frames.join(','), spot.x + 9, spot.y - 8);
  }
  context.fillStyle = '#5b6775';
  context.fillText(`floor grid ${fmt(step)} m`, 10, height - 10);
}

function installViewControls() {
  const canvas = $('robot-view');
  let dragging = null;
  canvas.addEventListener('pointerdown', (event) => {
    dragging = { x: event.clientX, y: event.clientY };
    canvas.setPointerCapture(event.pointerId);
  });
  canvas.addEventListener('pointermove', (event) => {
    if (!dragging) return;
    state.view.azimuth -= (event.clientX - dragging.x) * 0.01;
    state.view.elevation = Math.max(-1.5, Math.min(1.5, state.view.elevation + (event.clientY - dragging.y) * 0.01));
    dragging = { x: event.clientX, y: event.clientY };
    drawView();
  });
  canvas.addEventListener('pointerup', () => { dragging = null; });
  canvas.addEventListener('wheel', (event) => {
    event.preventDefault();
    state.view.zoom = Math.max(0.2, Math.min(8, state.view.zoom * Math.exp(-event.deltaY * 0.001)));
    drawView();
  }, { passive: false });
}

// ---------------------------------------------------------------- robot menu

async function loadReady(name) {
  setRobot(await api(`/robots/ready/${encodeURIComponent(name)}`), null);
}

async function loadFile(name, chain = {}) {
  const query = [`name=${encodeURIComponent(name)}`];
  if (chain.base) query.push(`base=${encodeURIComponent(chain.base)}`);
  if (chain.tip) query.push(`tip=${encodeURIComponent(chain.tip)}`);
  const view = await api(`/robots/file?${query.join('&')}`);
  // A converted file is not the robot's file: saving writes a new one.
  setRobot(view, view.origin === 'imported' ? null : name);
}

async function refreshFiles() {
  try {
    state.files = await api('/files');
  } catch (error) {
    state.files = { robots: [], data: [] };
  }
  for (const method of state.info.methods) refreshDataChoices(method.name);
  if (state.study) renderStudy();
}

function openRobotDialog() {
  const ready = h('div', { class: 'choices' }, state.info.ready.map((name) => h('button', {
    type: 'button',
    id: `open-ready-${name}`,
    text: name,
    onclick: async () => {
      try {
        await loadReady(name);
        $('dialog').close();
      } catch (error) {
        dialogError(error.message);
      }
    },
  })));
  const list = h('div', { class: 'file-list' }, h('div', { class: 'empty', text: 'Loading…' }));
  const imports = h('div', { class: 'file-list', id: 'open-imports' }, h('div', { class: 'empty', text: 'Loading…' }));
  const base = h('input', { type: 'text', id: 'open-base', placeholder: 'root link' });
  const tip = h('input', { type: 'text', id: 'open-tip', placeholder: 'leaf with the most joints' });
  // A robot file from this computer (not the served folder): read here, sent
  // to the server to be checked or converted; nothing is written.
  const upload = h('input', { type: 'file', id: 'open-upload', accept: '.toml,.urdf,.par' });
  upload.addEventListener('change', async () => {
    const file = upload.files[0];
    if (!file) return;
    try {
      const view = await api('/robots/upload', {
        name: file.name,
        text: await file.text(),
        base: base.value.trim() || undefined,
        tip: tip.value.trim() || undefined,
      });
      view.uploaded = file.name;
      setRobot(view, null);
      $('dialog').close();
    } catch (error) {
      dialogError(error.message);
    }
  });
  openDialog({
    title: 'Open a robot',
    body: h('div', {},
      h('h3', { text: 'Ready robots' }), ready,
      h('h3', { text: `Robot files in ${state.info.folder}` }),
      h('p', { class: 'muted', text: 'gecaro robot files, and DH tables (TOML with convention = "dh" or "mdh"), converted.' }),
      list,
      h('h3', { text: 'URDF and SYMORO files (converted)' }),
      h('div', { class: 'chain-fields' },
        h('label', { class: 'dialog-field' }, 'URDF base link', base),
        h('label', { class: 'dialog-field' }, 'URDF tip link', tip)),
      imports,
      h('h3', { text: 'From this computer' }),
      h('label', { class: 'dialog-field' }, 'Upload a robot file (.toml, .urdf, .par)', upload)),
  });
  const button = (name) => h('button', {
    type: 'button',
    text: name,
    onclick: async () => {
      try {
        await loadFile(name, { base: base.value.trim(), tip: tip.value.trim() });
        $('dialog').close();
      } catch (error) {
        dialogError(error.message);
      }
    },
  });
  api('/files').then((files) => {
    state.files = files;
    list.replaceChildren(...(files.robots.length ? files.robots.map(button)
      : [h('div', { class: 'empty', text: 'No .toml files in this folder.' })]));
    imports.replaceChildren(...(files.imports && files.imports.length ? files.imports.map(button)
      : [h('div', { class: 'empty', text: 'No .urdf or .par files in this folder.' })]));
  }).catch((error) => dialogError(error.message));
}

function newRobotDialog() {
  // Checked by the page, in its words (not the browser's generic pattern tooltip).
  const joints = h('input', { type: 'text', id: 'new-joints', value: 'RRRRRR' });
  const name = h('input', { type: 'text', id: 'new-name', placeholder: 'e.g. My arm' });
  openDialog({
    title: 'New robot',
    body: h('div', {},
      h('label', { class: 'dialog-field' }, 'Joint types, from joint 1 to n (R revolute, P prismatic)', joints),
      h('label', { class: 'dialog-field' }, 'Name', name),
      h('p', { class: 'muted', text: 'A template arm to edit: α alternates ±90°, the tool 0.1 m along the last z axis.' })),
    ok: 'Create',
    onOk: async () => {
      const letters = joints.value.trim();
      const bad = [...letters].find((letter) => !'RPrp'.includes(letter));
      joints.classList.toggle('invalid', !letters || bad !== undefined);
      if (!letters) throw new FieldError('Joint types: give one letter per joint, R (revolute) or P (prismatic).');
      if (bad !== undefined) throw new FieldError(`Joint types: “${bad}” is not R (revolute) or P (prismatic).`);
      const view = await api('/robots/new', { joints: letters, name: name.value.trim() || undefined });
      setRobot(view, null);
      state.dirty = true;
      renderRobot();
    },
  });
}

function saveAsDialog(documentToSave, suggested, after) {
  const name = h('input', { type: 'text', id: 'save-name', value: suggested });
  const overwrite = h('input', { type: 'checkbox', id: 'save-overwrite' });
  const format = h('select', { id: 'save-format' },
    h('option', { value: 'toml', text: 'gecaro robot file (.toml)' }),
    h('option', { value: 'urdf', text: 'URDF (.urdf), with a joint calibration beside it if needed' }));
  format.addEventListener('change', () => {
    name.value = name.value.replace(/\.(toml|urdf)$/i, '') + `.${format.value}`;
  });
  const carried = h('p', { class: 'muted', id: 'save-urdf-note', hidden: true, text: 'A URDF carries the kinematics, joint limits and names; gains, couplings and offsets go to a joint-calibration file beside it when they are not the defaults. Meshes, inertia and collision geometry are not carried: gecaro’s robots have none, so merge the result into your original URDF for those.' });
  format.addEventListener('change', () => { carried.hidden = format.value !== 'urdf'; });
  openDialog({
    title: 'Save robot as',
    body: h('div', {},
      h('label', { class: 'dialog-field' }, 'Format', format),
      carried,
      h('label', { class: 'dialog-field' }, `File name in ${state.info.folder}`, name),
      h('label', {}, overwrite, ' Replace the file if it exists')),
    ok: 'Save',
    onOk: async () => {
      let saved;
      try {
        saved = await api('/robots/save', { robot: documentToSave, name: name.value.trim(), overwrite: overwrite.checked });
      } catch (error) {
        if ((error.problems || []).length) throw new Error(`${error.message} — fix the table first.`);
        throw error;
      }
      const beside = saved.joint_calibration ? ` and ${saved.joint_calibration} (gains and couplings)` : '';
      toast(`Saved ${saved.name}${beside}`);
      if (after) after(saved.name, saved.version);
      refreshFiles();
    },
  });
}

function saveRobotAs() {
  const suggested = state.file || `${slug(document_().name || 'robot')}.toml`;
  saveAsDialog(document_(), suggested, (name, version) => {
    // A URDF is an export: the table stays tied to its robot file, if any.
    if (!name.toLowerCase().endsWith('.urdf')) {
      state.file = name;
      state.dirty = false;
      if (version) state.robot.version = version;
    }
    renderRobot();
  });
}

async function saveRobot() {
  if (!state.file) {
    saveRobotAs();
    return;
  }
  const save = (expected) => api('/robots/save', {
    robot: document_(), name: state.file, overwrite: true, expected_version: expected,
  });
  try {
    let saved;
    try {
      saved = await save(state.robot.version);
    } catch (error) {
      // Saved from elsewhere since it was opened: the user chooses.
      if (error.status !== 409) throw error;
      if (!window.confirm(`${error.message}\n\nReplace that change with this table?`)) {
        toast(`Not saved: ${state.file} changed since it was opened; reopen it to see the change`);
        return;
      }
      saved = await save(undefined);
    }
    state.robot.version = saved.version;
    state.dirty = false;
    renderRobot();
    toast(`Saved ${state.file}`);
  } catch (error) {
    toast(`Not saved: ${error.message}`);
  }
}

// ---------------------------------------------------------------- method panels

function field(label, input) {
  return h('label', { class: 'field' }, h('span', { text: label }), input);
}

function methodInfo(name) {
  return state.info.methods.find((m) => m.name === name);
}

function optionFields(method, fn) {
  const id = (suffix) => `${method.name}-${fn}-${suffix}`;
  const fields = [];
  if (method.uses_plane) {
    fields.push(field(method.name === 'plane2' ? 'Plane normal' : 'Plane', h('select', { id: id('plane') },
      h('option', { value: 'known', text: 'known' }),
      h('option', { value: 'unknown', text: 'unknown (identified)' }))));
    fields.push(field('Normal (world)', h('input', { type: 'text', class: 'vector plane-normal', id: id('normal') })));
    fields.push(field('Point of the plane (m)', h('input', { type: 'text', class: 'vector plane-point', id: id('point') })));
  }
  if (method.uses_orientation && fn !== 'generate') {
    fields.push(field('Orientation difference', h('select', { id: id('orientation') },
      h('option', { value: 'axis-angle', text: 'axis–angle (App. I, method 2)' }),
      h('option', { value: 'cross-products', text: 'cross products (method 1)' }))));
  }
  if (method.uses_sets && fn === 'generate') {
    fields.push(field('Configurations per set', h('input', { type: 'number', min: 2, step: 1, id: id('set-size'), placeholder: method.name === 'point-link' ? '4' : '2' })));
  }
  return fields;
}

function methodRequest(name, fn) {
  const method = methodInfo(name);
  const value = (suffix) => {
    const element = $(`${name}-${fn}-${suffix}`);
    return element ? element.value.trim() : '';
  };
  const request = { name };
  if (method.uses_plane) {
    const normal = value('normal');
    const point = value('point');
    if (normal || point) {
      request.plane_normal = parseVector(normal, 'The plane normal');
      request.plane_point = parseVector(point, 'The point of the plane');
    }
    request.plane_unknown = value('plane') === 'unknown';
  }
  if (method.uses_orientation && fn !== 'generate') request.orientation = value('orientation');
  if (method.uses_sets && fn === 'generate' && value('set-size')) request.set_size = Number(value('set-size'));
  return request;
}

function prefillPlanes() {
  const summary = state.robot.summary;
  if (!summary) return;
  for (const input of document.querySelectorAll('input.plane-normal')) {
    if (!input.value) input.value = summary.plane_normal.join(', ');
  }
  if (!summary.plane_point) return;
  for (const input of document.querySelectorAll('input.plane-point')) {
    if (!input.value) input.value = summary.plane_point.map((v) => Number(v.toFixed(4))).join(', ');
  }
}

function dataSelect(name, fn, withRandom) {
  const select = h('select', { id: `${name}-${fn}-data`, class: 'data-choice', 'data-method': name, 'data-random': withRandom ? '1' : '' });
  return select;
}

/**
 * Rebuilds the data choices of method `name`. `prefer` (an option value, such
 * as 'generated' right after a generation) is selected in the Identification
 * function's selector; the others keep their choice when it still exists.
 */
function refreshDataChoices(name, prefer) {
  for (const select of document.querySelectorAll(`select.data-choice[data-method="${name}"]`)) {
    const previous = prefer && !select.dataset.random ? prefer : select.value;
    const options = [];
    if (select.dataset.random) options.push(h('option', { value: 'random', text: 'Random configurations' }));
    // A program is a file of the folder or an upload, never measurements.
    const generated = select.dataset.program ? null : state.generated[name];
    if (generated) options.push(h('option', { value: 'generated', text: `Generated here: ${generated.file_name}` }));
    const heldOut = select.dataset.program ? null : state.heldOut[name];
    if (heldOut) options.push(h('option', { value: 'held-out', text: `Held out, the same real robot: ${heldOut.file_name}` }));
    for (const file of state.files.data) options.push(h('option', { value: `file:${file}`, text: file }));
    if (!select.dataset.random) options.push(h('option', { value: 'upload', text: 'Upload a CSV file…' }));
    select.replaceChildren(...options);
    if ([...select.options].some((o) => o.value === previous)) select.value = previous;
    select.dispatchEvent(new Event('change'));
  }
}

async function dataRequest(name, fn) {
  const choice = $(`${name}-${fn}-data`).value;
  if (choice === 'random' || choice === '') return undefined;
  if (choice === 'generated' || choice === 'held-out') {
    const generated = (choice === 'generated' ? state.generated : state.heldOut)[name];
    return { csv: { text: generated.csv, name: generated.file_name } };
  }
  if (choice.startsWith('file:')) return { file: choice.slice(5) };
  const upload = $(`${name}-${fn}-upload`);
  if (!upload.files.length) throw new Error('Choose a CSV file to upload.');
  const file = upload.files[0];
  return { csv: { text: await file.text(), name: file.name } };
}

/** A field the page refuses before asking the server, in the field's own words. */
class FieldError extends Error {
  constructor(message) {
    super(message);
    this.problems = [];
  }
}

/**
 * The number in `input` (its label `label`, as the page shows it), checked
 * in the page: the field is marked and a FieldError says what it takes when
 * it is not one. `whole` asks for a whole number; an empty field gives
 * `empty` when one is allowed (`undefined` = the field is required).
 */
function fieldNumber(input, label, { min = -Infinity, max = Infinity, whole = false, above = false, empty } = {}) {
  input.classList.remove('invalid');
  const text = input.value.trim();
  const kind = whole ? 'a whole number' : 'a number';
  const range = [
    Number.isFinite(min) ? `${above ? 'above' : 'at least'} ${min}` : null,
    Number.isFinite(max) ? `at most ${max}` : null,
  ].filter(Boolean).join(' and ');
  const fail = (what) => {
    input.classList.add('invalid');
    input.focus();
    throw new FieldError(`${label}: ${what}; it takes ${kind}${range ? ` ${range}` : ''}.`);
  };
  // A number field holds '' for text that is no number ("abc"): the browser says which.
  if (input.validity && input.validity.badInput) fail('that is not a number');
  if (text === '') {
    if (empty !== undefined) return empty;
    fail('it is empty');
  }
  const value = Number(text);
  if (!Number.isFinite(value)) fail(`“${text}” is not a number`);
  if (whole && !Number.isInteger(value)) fail(`${text} is not a whole number`);
  if (value < min || (above && value === min) || value > max) fail(`${text} is out of range`);
  return value;
}

/** A stated σ (mm) as the API takes it, with its unit; none when not stated. */
function sigmaText(millimetres) {
  return millimetres === null ? null : `${millimetres}mm`;
}

/** A stated rotation σ (degrees) as the API takes it, with its unit. */
function degreesText(degrees) {
  return degrees === null ? null : `${degrees}deg`;
}

/** Cross-validation folds: empty or 0 for none, else 2 to 20 (1 fold holds nothing out). */
function foldsOf(input) {
  const folds = fieldNumber(input, 'Cross-validation folds', { min: 0, max: state.info.limits.folds, whole: true, empty: 0 });
  if (folds === 1) {
    input.classList.add('invalid');
    throw new FieldError(`Cross-validation folds: 1 fold holds nothing out; 0 for none, or 2 to ${state.info.limits.folds}.`);
  }
  return folds >= 2 ? folds : null;
}

function errorBox(error) {
  const lines = [error.message];
  for (const problem of error.problems || []) lines.push(`${locationText(problem.location)}: ${problem.message}`);
  return h('div', { class: 'error-box', text: lines.join('\n') });
}

function runButton(id, text, action) {
  const button = h('button', { type: 'button', class: 'primary run', id, text });
  button.addEventListener('click', async () => {
    button.disabled = true;
    try {
      await action();
    } finally {
      button.disabled = (state.robot.problems || []).length > 0 || state.localProblems.size > 0;
    }
  });
  return button;
}

/** The observability indices O1–O5 (docs/planning.md) as one muted line. */
function observabilityLine(indices, of) {
  const values = ['o1', 'o2', 'o3', 'o4', 'o5'].map((key) => `${key.toUpperCase()} ${sci(indices[key])}`);
  return h('p', { class: 'muted observability', text: `Observability of ${of} (W_b scaled to 1 cm, 1°, 1 %; larger is better): ${values.join(' · ')}` });
}

function stat(label, value, extra) {
  return h('div', { class: `stat ${extra && extra.class ? extra.class : ''}` },
    h('div', { class: 'value', id: extra && extra.id, text: value }),
    h('div', { class: 'label', text: label }));
}

// Identifiable parameters ---------------------------------------------------

function identifiablePanel(method) {
  const name = method.name;
  const result = h('div', { class: 'result', id: `${name}-identifiable-result` });
  const count = h('input', { type: 'number', min: 1, id: `${name}-identifiable-count-input`, placeholder: 'auto' });
  const seed = h('input', { type: 'number', min: 0, value: 1, id: `${name}-identifiable-seed` });
  const run = runButton(`${name}-identifiable-run`, 'Compute', async () => {
    result.replaceChildren(h('div', { class: 'progress' }, h('div', { class: 'spinner' }), 'QR of the observation matrix…'));
    try {
      const request = {
        robot: document_(),
        method: methodRequest(name, 'identifiable'),
        data: await dataRequest(name, 'identifiable'),
        seed: fieldNumber(seed, 'Seed', { min: 0, whole: true, empty: 1 }),
      };
      const configurations = fieldNumber(count, 'Random configurations', { min: 1, max: state.info.limits.random, whole: true, empty: null });
      if (configurations !== null) request.count = configurations;
      const report = await api('/identifiable', request);
      renderIdentifiable(result, name, report);
    } catch (error) {
      result.replaceChildren(errorBox(error));
    }
  });
  return h('div', { class: 'panel', id: `${name}-identifiable` },
    h('div', { class: 'form' },
      field('Data', dataSelect(name, 'identifiable', true)),
      field('Random configurations', count),
      field('Seed', seed),
      optionFields(method, 'identifiable'),
      run),
    h('p', { class: 'hint', text: 'Appendix III: column-pivoted QR of W on configurations that satisfy the method’s constraint. Measured data are checked for excitation as well.' }),
    result);
}

function renderIdentifiable(container, name, report) {
  const frames = document_().frame.length;
  const status = new Map(report.parameters.map((p) => [p.name, p.status]));
  const symbol = { identifiable: 'id', regrouped: 'n', no_effect: '0', excluded: '–' };
  const head = h('tr', {}, h('th', { text: 'j' }), KIND_HEADS.map((k) => h('th', { text: k })));
  const rows = [];
  for (let j = 0; j < frames; j += 1) {
    rows.push(h('tr', {}, h('th', { text: String(j) }), KINDS.map((kind) => {
      const s = status.get(`${kind}${j}`);
      return h('td', { class: s ? `s-${s}` : '', text: s ? symbol[s] : '' });
    })));
  }
  const parts = [
    h('div', { class: 'cards' },
      stat('identifiable parameters', String(report.count), { id: `${name}-identifiable-count`, class: 'ok' }),
      stat(`of ${report.parameters.length} parameters`, `${report.parameters.length - report.count} not`),
      stat('condition number of W_b', fmt(Number(report.condition_number.toPrecision(4)))),
      stat(`equations (${report.rows} rows)`, String(report.equations)),
      stat('configurations', String(report.configurations))),
    h('p', { class: 'muted', text: `On ${report.source}; numerical zero τ = ${sci(report.tolerance)}.` }),
    observabilityLine(report.observability, report.excitation ? 'the data' : 'these random configurations'),
  ];
  if (report.excitation) {
    parts.push(report.excitation.same_base_set
      ? h('p', { class: 'stat ok', text: `The data excite every identifiable parameter (condition number on the data ${fmt(Number(report.excitation.condition_number.toPrecision(4)))}).` })
      : h('div', { class: 'warnings', text: `The data do not excite ${report.excitation.not_excited.join(', ')}: they would stay at their nominal values.` }));
  }
  if (report.warnings.length) {
    parts.push(h('div', { class: 'warnings', id: `${name}-identifiable-warnings` }, h('strong', { text: 'The set-up' }),
      h('ul', {}, report.warnings.map((w) => h('li', { text: w })))));
  }
  parts.push(h('p', { class: 'muted', text: 'id = identifiable · n = regrouped on other parameters · 0 = no effect · – = excluded (priority 0)' }));
  parts.push(h('table', { class: 'grid', id: `${name}-identifiable-grid` }, h('thead', {}, head), h('tbody', {}, rows)));
  if (report.auxiliary.length) {
    parts.push(h('p', {}, `Plane unknowns: ${report.auxiliary.map((a) => `${a.name} ${symbol[a.status]}`).join(', ')}`));
  }
  if (report.regrouping.length) {
    parts.push(h('h3', { text: 'Regrouping relations (eq. 32)' }));
    parts.push(h('ul', { class: 'relations' }, report.regrouping.map((relation) => h('li', {
      text: `${relation.base}_b = ${relation.base} ${relation.absorbed.map((a) => `${a.coefficient < 0 ? '−' : '+'} ${fmt(Number(Math.abs(a.coefficient).toPrecision(6)))}·${a.name}`).join(' ')}`,
    }))));
  }
  const priorityRows = report.priority_matrix.map((row, j) => h('tr', {}, h('th', { text: String(j) }), row.map((v) => h('td', { text: String(v) }))));
  parts.push(h('details', {}, h('summary', { text: 'New priority matrix (non-identifiable parameters set to 0)' }),
    h('table', { class: 'grid' }, h('thead', {}, head.cloneNode(true)), h('tbody', {}, priorityRows))));
  container.replaceChildren(...parts);
}

// Plan ------------------------------------------------------------------------

const CRITERIA = [
  ['d', 'D-optimal (largest det W_bᵀW_b)'],
  ['a', 'A-optimal (smallest sum of variances)'],
  ['e', 'E-optimal (largest σL)'],
  ['o4', 'O4 = σL²/σ1'],
  ['o5', 'O5 = 1/Σ 1/σi'],
  ['test', 'predicted error at 200 random test poses'],
];

/**
 * The cell fields of function `fn` of method `name` (as the command line's
 * --floor, --station, --max-incidence, --clearance; millimetres and
 * degrees): where only configurations the cell can measure are drawn.
 */
function cellInputs(name, fn) {
  const input = (key, placeholder) => h('input', { type: 'text', class: 'vector', id: `${name}-${fn}-${key}`, placeholder });
  const floor = input('floor', 'none, e.g. 0');
  const station = input('station', 'none, e.g. 2500, 0, 400');
  const incidence = input('incidence', 'any, e.g. 30');
  const clearance = input('clearance', '50');
  const fields = [
    field('Floor: z ≥ (mm, world frame)', floor),
    field('Laser tracker at x, y, z (mm)', station),
    field('Reflector acceptance half-angle (°)', incidence),
    field('Line of sight clear of the arm by (mm)', clearance),
  ];
  const request = () => {
    const millimetres = (element, label) => {
      const value = fieldNumber(element, label, { empty: null });
      return value === null ? null : value * 1e-3;
    };
    const cell = {};
    const z = millimetres(floor, 'Floor');
    if (z !== null) cell.floor = z;
    const text = station.value.trim();
    station.classList.remove('invalid');
    if (text) {
      const parts = text.split(/[\s,;]+/).filter(Boolean).map(Number);
      if (parts.length !== 3 || !parts.every(Number.isFinite)) {
        station.classList.add('invalid');
        throw new FieldError(`Laser tracker: “${text}” is not three numbers x, y, z (mm).`);
      }
      cell.station = parts.map((v) => v * 1e-3);
    }
    const angle = fieldNumber(incidence, 'Reflector acceptance half-angle', { min: 0, max: 90, above: true, empty: null });
    if (angle !== null) cell.max_incidence = `${angle}deg`;
    const gap = millimetres(clearance, 'Clearance');
    if (gap !== null) cell.clearance = gap;
    if (!cell.station && (cell.max_incidence || cell.clearance !== undefined)) {
      incidence.classList.add('invalid');
      throw new FieldError('The acceptance angle and the clearance are of a laser tracker: give its position too.');
    }
    return cell;
  };
  return { fields, request };
}

function planPanel(method) {
  const name = method.name;
  const result = h('div', { class: 'result', id: `${name}-plan-result` });
  const count = h('input', { type: 'number', min: 1, value: Math.round((DEFAULT_COUNTS[name] || 50) / 2), id: `${name}-plan-count` });
  const criterion = h('select', { id: `${name}-plan-criterion` }, CRITERIA.map(([value, text]) => h('option', { value, text })));
  const pool = h('input', { type: 'number', min: 1, id: `${name}-plan-pool`, placeholder: '20 × count' });
  const distance = h('input', { type: 'number', min: 0, step: 0.1, value: 0, id: `${name}-plan-distance` });
  const seed = h('input', { type: 'number', min: 0, value: 1, id: `${name}-plan-seed` });
  const curve = h('input', { type: 'text', class: 'vector', id: `${name}-plan-curve`, placeholder: 'optional, e.g. 10, 20, 40, 80' });
  const noise = h('input', { type: 'number', min: 0, step: 0.01, value: 0.1, id: `${name}-plan-noise` });
  const saveAs = h('input', { type: 'text', id: `${name}-plan-save`, placeholder: 'optional, e.g. planned.csv', class: 'vector' });
  const overwrite = h('input', { type: 'checkbox', id: `${name}-plan-overwrite` });
  const cell = cellInputs(name, 'plan');
  // The plan in the robot's own units: degrees for a teach pendant.
  const angles = h('select', { id: `${name}-plan-angle-unit` },
    h('option', { value: 'rad', text: 'radians' }), h('option', { value: 'deg', text: 'degrees (a teach pendant)' }));
  const run = runButton(`${name}-plan-run`, 'Plan', async () => {
    // Cancel aborts the request; the server then stops the plan at its next step.
    const abort = new AbortController();
    const cancel = h('button', { type: 'button', id: `${name}-plan-cancel`, text: 'Cancel', onclick: () => abort.abort() });
    result.replaceChildren(h('div', { class: 'progress' }, h('div', { class: 'spinner' }), h('span', { text: 'Choosing configurations…' }), cancel));
    try {
      const request = {
        robot: document_(),
        method: methodRequest(name, 'plan'),
        count: fieldNumber(count, 'Configurations', { min: 1, max: state.info.limits.generate, whole: true }),
        criterion: criterion.value,
        min_distance: fieldNumber(distance, 'Smallest distance', { min: 0, empty: 0 }),
        seed: fieldNumber(seed, 'Seed', { min: 0, whole: true, empty: 1 }),
        noise: fieldNumber(noise, 'Sensor σ', { min: 0, above: true, empty: 0.1 }) * 1e-3,
      };
      const candidates = fieldNumber(pool, 'Candidates', { min: 1, max: state.info.limits.generate, whole: true, empty: null });
      if (candidates !== null) request.pool = candidates;
      request.cell = cell.request();
      request.format = { angle_unit: angles.value };
      if (curve.value.trim()) {
        request.curve = curve.value.split(/[\s,;]+/).filter(Boolean).map((v) => {
          const n = Number(v);
          if (!Number.isInteger(n) || n < 1) throw new Error(`The curve's counts are whole numbers ≥ 1, not “${v}”.`);
          return n;
        });
      }
      if (saveAs.value.trim()) {
        request.save_as = saveAs.value.trim();
        request.overwrite = overwrite.checked;
      }
      const planned = await api('/plan', request, abort.signal);
      planned.format = request.format;
      if (planned.saved) refreshFiles();
      renderPlanned(result, name, planned);
    } catch (error) {
      if (abort.signal.aborted) {
        result.replaceChildren(h('div', { class: 'warnings', id: `${name}-plan-cancelled`, text: 'Cancelled: the server stopped planning.' }));
      } else {
        result.replaceChildren(errorBox(error));
      }
    }
  });
  return h('div', { class: 'panel', id: `${name}-plan` },
    h('div', { class: 'form' },
      field('Configurations', count),
      field('Criterion', criterion),
      field('Candidate pool', pool),
      field('Minimum joint distance (rad, m)', distance),
      field('Seed', seed),
      optionFields(method, 'plan'),
      field('Curve: counts', curve),
      field('Sensor noise σ for the curve (mm)', noise),
      ...cell.fields,
      field('Joint angles of the plan in', angles),
      field('Save to the folder as', saveAs),
      h('label', {}, overwrite, ' replace'),
      run),
    h('p', { class: 'hint', text: 'Before measuring: the configurations that determine the identifiable parameters best, chosen from candidates within the joint limits (docs/planning.md). The curve predicts the calibrated robot’s error against the number of configurations, planned and random.' }),
    result);
}

function renderPlanned(container, name, planned) {
  const better = planned.criterion === 'a' || planned.criterion === 'test'
    ? planned.value < planned.random_value : planned.value > planned.random_value;
  const preview = planned.csv.split('\n').slice(0, 6).join('\n');
  const parts = [
    h('div', { class: 'cards' },
      stat('configurations planned', String(planned.configurations), { id: `${name}-plan-count-result`, class: 'ok' }),
      stat(`of a pool of ${planned.pool}`, `${planned.units} units`),
      stat(planned.criterion_meaning, sci(planned.value), { id: `${name}-plan-value`, class: better ? 'ok' : '' }),
      stat('a random choice', sci(planned.random_value), { id: `${name}-plan-random` })),
    observabilityLine(planned.observability, 'the plan'),
    planned.saved ? h('p', { text: `Saved to ${planned.saved}.` }) : null,
    h('div', { class: 'actions' },
      h('button', { type: 'button', id: `${name}-plan-download`, text: `Download ${planned.file_name}`, onclick: () => download(planned.file_name, planned.csv, 'text/csv') }),
      h('button', {
        type: 'button',
        id: `${name}-plan-measure`,
        text: 'Measure them (simulated)',
        title: 'Points generation at these configurations, with the settings of the Points generation function',
        onclick: async () => {
          selectFunction('generate');
          await generateInto(name, { csv: { text: planned.csv, name: planned.file_name } }, planned.format);
        },
      })),
  ];
  if (planned.curve) {
    const mm = (v) => (v === null ? 'not determined' : fixed(v * 1e3, 4));
    const rows = planned.curve.points.map((p) => h('tr', {},
      h('td', { text: String(p.configurations) }), h('td', { text: mm(p.planned) }), h('td', { text: mm(p.random) }),
      h('td', { text: p.planned && p.random ? fixed(p.random / p.planned, 2) : '—' })));
    parts.push(h('h3', { text: `Predicted RMS position error, σ ${fmt(planned.curve.noise * 1e3)} mm` }));
    parts.push(h('table', { class: 'grid', id: `${name}-plan-curve-table` },
      h('thead', {}, h('tr', {}, ['configurations', 'planned (mm)', 'random (mm)', 'random / planned'].map((t) => h('th', { text: t })))),
      h('tbody', {}, rows)));
    // In the same grid, size and caption style as every other plot of the page.
    const figure = h('div', { class: 'plot', id: `${name}-plan-curve-plot` });
    figure.innerHTML = planned.curve.svg; // SVG made by the server (plotters), not user text.
    parts.push(h('div', { class: 'plots' }, h('figure', {}, figure,
      h('figcaption', { class: 'muted', text: 'Predicted RMS position error against the number of configurations (mm)' }))));
  }
  parts.push(h('pre', { class: 'preview', text: `${preview}\n…` }));
  container.replaceChildren(...parts.filter(Boolean));
}

// Points generation -----------------------------------------------------------

/**
 * Points generation with the settings of method `name`'s panel: at
 * `configurations` (a CSV of planned configurations) when given, else at as
 * many random ones as the panel says. The result shows in that panel.
 */
async function generateInto(name, configurations, format) {
  const result = $(`${name}-generate-result`);
  const value = (what) => $(`${name}-generate-${what}`).value;
  result.replaceChildren(h('div', { class: 'progress' }, h('div', { class: 'spinner' }), 'Generating configurations…'));
  try {
    const request = {
      robot: document_(),
      method: methodRequest(name, 'generate'),
      noise: fieldNumber($(`${name}-generate-noise`), 'Sensor noise σ', { min: 0, empty: 0 }) * 1e-3,
      seed: fieldNumber($(`${name}-generate-seed`), 'Seed', { min: 0, whole: true, empty: 1 }),
    };
    if (configurations) {
      request.configurations = configurations;
      if (format) request.format = format;
    } else request.count = fieldNumber($(`${name}-generate-count`), 'Configurations', { min: 1, max: state.info.limits.generate, whole: true });
    request.cell = generationCells[name]();
    const real = value('real');
    if (real.startsWith('file:')) {
      request.real = (await api(`/robots/file?name=${encodeURIComponent(real.slice(5))}`)).document;
    } else {
      request.error_level = fieldNumber($(`${name}-generate-level`), 'Error level', { min: 0, empty: 0 });
    }
    if (value('save').trim()) {
      request.save_as = value('save').trim();
      request.overwrite = $(`${name}-generate-overwrite`).checked;
    }
    const generated = await api('/generate', request);
    // Each generation is new data, under the same choice 'generated'; it
    // keeps where it came from (the real robot, the seed, the noise).
    generated.serial = nextSerial(state.generated[name]);
    generated.origin = {
      real: real.startsWith('file:') ? real.slice(5) : null,
      level: request.error_level,
      seed: request.seed,
      noise: request.noise,
    };
    state.generated[name] = generated;
    delete state.heldOut[name];
    refreshDataChoices(name, 'generated');
    refreshStale();
    if (generated.saved) refreshFiles();
    renderGenerated(result, name, generated);
    drawView();
  } catch (error) {
    result.replaceChildren(errorBox(error));
  }
}

/** The number of the next data kept in a slot whose data are `kept` now: a new generation is new data. */
function nextSerial(kept) {
  return (kept ? kept.serial || 0 : 0) + 1;
}

/** Each method's generation cell, read when it generates. */
const generationCells = {};

function generatePanel(method) {
  const name = method.name;
  const result = h('div', { class: 'result', id: `${name}-generate-result` });
  const count = h('input', { type: 'number', min: 1, value: DEFAULT_COUNTS[name] || 50, id: `${name}-generate-count` });
  const real = h('select', { id: `${name}-generate-real`, class: 'real-choice' });
  const level = h('input', { type: 'number', min: 0, step: 0.5, value: 1, id: `${name}-generate-level` });
  const noise = h('input', { type: 'number', min: 0, step: 0.01, value: 0.05, id: `${name}-generate-noise` });
  const seed = h('input', { type: 'number', min: 0, value: 1, id: `${name}-generate-seed` });
  const saveAs = h('input', { type: 'text', id: `${name}-generate-save`, placeholder: 'optional, e.g. data.csv', class: 'vector' });
  const overwrite = h('input', { type: 'checkbox', id: `${name}-generate-overwrite` });
  real.addEventListener('focus', () => refreshRealChoices(real));
  refreshRealChoices(real);
  const cell = cellInputs(name, 'generate');
  generationCells[name] = cell.request;
  const run = runButton(`${name}-generate-run`, 'Generate', () => generateInto(name, null));
  return h('div', { class: 'panel', id: `${name}-generate` },
    h('div', { class: 'form' },
      field('Configurations', count),
      field('Real robot', real),
      field('Error level L (±L cm, ±L°, ±L %)', level),
      field('Sensor noise σ (mm; mrad)', noise),
      field('Seed', seed),
      optionFields(method, 'generate'),
      ...cell.fields,
      field('Save to the folder as', saveAs),
      h('label', {}, overwrite, ' replace'),
      run),
    h('p', { class: 'hint', text: 'Configurations of the simulated real robot that satisfy the method’s constraint, with what the sensor measures there.' }),
    result);
}

function refreshRealChoices(select) {
  const previous = select.value;
  select.replaceChildren(h('option', { value: 'random', text: 'nominal + random errors' }),
    ...state.files.robots.map((file) => h('option', { value: `file:${file}`, text: file })));
  if ([...select.options].some((o) => o.value === previous)) select.value = previous;
}

function renderGenerated(container, name, generated) {
  const preview = generated.csv.split('\n').slice(0, 6).join('\n');
  container.replaceChildren(...[
    h('div', { class: 'cards' },
      stat('configurations', String(generated.configurations), { id: `${name}-generate-count-result`, class: 'ok' }),
      stat('terminal point moved, RMS (mm)', fixed(generated.displacement_rms * 1e3, 2)),
      stat('largest (mm)', fixed(generated.displacement_max * 1e3, 2))),
    generated.saved ? h('p', { text: `Saved to ${generated.saved}.` }) : null,
    h('div', { class: 'actions' },
      h('button', { type: 'button', id: `${name}-generate-download`, text: `Download ${generated.file_name}`, onclick: () => download(generated.file_name, generated.csv, 'text/csv') }),
      h('button', {
        type: 'button',
        id: `${name}-generate-identify`,
        text: 'Identify these data',
        onclick: () => {
          selectFunction('identify');
          $(`${name}-identify-data`).value = 'generated';
          $(`${name}-identify-data`).dispatchEvent(new Event('change'));
        },
      }),
      h('button', {
        type: 'button',
        id: `${name}-generate-held-out`,
        text: 'Held-out data: the same real robot, new configurations',
        onclick: () => generateHeldOut(name),
      }),
      h('button', { type: 'button', text: 'Save the real robot as…', onclick: () => saveAsDialog(generated.real, `${slug(document_().name || 'robot')}-real.toml`) })),
    h('p', { class: 'muted', id: `${name}-generate-origin`, text: originText(generated.origin) }),
    h('p', { class: 'muted', id: `${name}-generate-held-out-status` }),
    h('pre', { class: 'preview', text: `${preview}\n…` })].filter(Boolean));
}

/** Where generated data came from, in words. */
function originText(origin) {
  if (!origin) return '';
  const real = origin.real
    ? `the real robot of ${origin.real}`
    : `a real robot drawn from the table's at error level ${origin.level} (seed ${origin.seed})`;
  const noise = `sensor noise σ ${fixed(origin.noise * 1e3, 3)} mm`;
  return origin.heldOutOf
    ? `Held out: the same real robot as ${origin.heldOutOf}, new configurations (seed ${origin.seed}), ${noise}.`
    : `Measured on ${real}, configurations seed ${origin.seed}, ${noise}.`;
}

/**
 * Held-out data for the data generated last: the same real robot (not one
 * drawn again with another seed), new configurations, the same noise; they
 * are chosen in Evaluate.
 */
async function generateHeldOut(name) {
  const source = state.generated[name];
  const status = $(`${name}-generate-held-out-status`);
  status.textContent = 'Generating held-out data…';
  const serial = nextSerial(state.heldOut[name]);
  try {
    const request = {
      robot: document_(),
      method: methodRequest(name, 'generate'),
      count: source.configurations,
      noise: source.origin.noise,
      seed: source.origin.seed + 1000 * serial,
      real: source.real,
      cell: generationCells[name](),
    };
    const heldOut = await api('/generate', request);
    heldOut.serial = serial;
    heldOut.file_name = heldOut.file_name.replace(/\.csv$/, '-held-out.csv');
    heldOut.origin = { ...source.origin, seed: request.seed, heldOutOf: source.file_name };
    state.heldOut[name] = heldOut;
    refreshDataChoices(name);
    const evaluate = $(`${name}-evaluate-data`);
    evaluate.value = 'held-out';
    evaluate.dispatchEvent(new Event('change'));
    status.textContent = `${originText(heldOut.origin)} ${heldOut.configurations} configurations, chosen in Evaluate.`;
  } catch (error) {
    status.textContent = error.message;
  }
}

// Identification --------------------------------------------------------------

/**
 * The data file's format as an instrument writes it: units, column names,
 * separator (the command line's --length-unit, --angle-unit, --columns,
 * --delimiter).
 */
function formatFields(name, fn) {
  const id = (what) => `${name}-${fn}-${what}`;
  return h('details', { class: 'format', id: id('format') },
    h('summary', { text: 'File format: units, column names, separator' }),
    h('div', { class: 'form' },
      field('Lengths in the file', h('select', { id: id('length-unit') },
        h('option', { value: 'm', text: 'metres' }), h('option', { value: 'mm', text: 'millimetres' }))),
      field('Joint angles in the file', h('select', { id: id('angle-unit') },
        h('option', { value: 'rad', text: 'radians' }), h('option', { value: 'deg', text: 'degrees' }))),
      field('Column names (gecaro=file, …)', h('input', { type: 'text', class: 'vector', id: id('columns'), placeholder: 'x=X_mm,qm1=A1' })),
      field('Separator', h('select', { id: id('delimiter') },
        ['auto', 'comma', 'semicolon', 'tab'].map((d) => h('option', { value: d, text: d === 'auto' ? 'found from the header' : d }))))));
}

function formatRequest(name, fn) {
  const value = (what) => $(`${name}-${fn}-${what}`).value.trim();
  return {
    length_unit: value('length-unit'),
    angle_unit: value('angle-unit'),
    columns: value('columns') || null,
    delimiter: value('delimiter'),
  };
}

/** A mm/deg or m/rad value of a parameter or unknown named `name`. */
function unitOf(name) {
  const base = name.includes('.') ? name.split('.').pop() : name;
  if (/^(alpha|theta|beta|gamma|rx|ry|rz)/.test(base)) return 'angle';
  if (/^(d|r|b|x|y|z)\d*$/.test(base)) return 'length';
  return 'none';
}

function inUnits(value, kind) {
  if (state.units === 'mm' && kind === 'length') return value * 1e3;
  if (state.units === 'mm' && kind === 'angle') return value * 180 / Math.PI;
  return value;
}

/** A value of `kind` ('length' or 'angle') in the page's units, to `digits` significant digits, as text. */
function inPageUnits(value, kind, digits = 6) {
  return fmt(Number(inUnits(value, kind).toPrecision(digits)));
}

/** The page's unit of `kind` ('length' or 'angle'). */
function unitName(kind) {
  if (kind === 'length') return state.units === 'mm' ? 'mm' : 'm';
  return state.units === 'mm' ? '°' : 'rad';
}

function unitsLabel() {
  return state.units === 'mm' ? 'mm, °' : 'm, rad';
}

function identifyPanel(method) {
  const name = method.name;
  const result = h('div', { class: 'result', id: `${name}-identify-result` });
  const data = dataSelect(name, 'identify', false);
  const upload = h('input', { type: 'file', accept: '.csv,text/csv', id: `${name}-identify-upload`, hidden: true });
  data.addEventListener('change', () => { upload.hidden = data.value !== 'upload'; refreshStale(); });
  const solver = h('select', { id: `${name}-identify-solver` },
    h('option', { value: 'gauss-newton', text: 'Gauss–Newton (the paper)' }),
    h('option', { value: 'lm', text: 'Levenberg–Marquardt' }));
  const iterations = h('input', { type: 'number', min: 1, max: state.info.limits.iterations, value: 30, id: `${name}-identify-iterations` });
  const loss = h('select', { id: `${name}-identify-loss` },
    h('option', { value: 'l2', text: 'least squares (the paper)' }),
    h('option', { value: 'huber', text: 'Huber (mild contamination)' }),
    h('option', { value: 'cauchy', text: 'Cauchy (gross errors)' }),
    h('option', { value: 'tukey', text: 'Tukey (gross errors ignored)' }));
  const prior = h('input', { type: 'text', class: 'vector', placeholder: 'none, or e.g. 5mm,0.5deg,1%', id: `${name}-identify-prior` });
  const reject = h('input', { type: 'checkbox', id: `${name}-identify-reject` });
  const sigma = h('input', { type: 'number', min: 0, step: 'any', placeholder: 'not stated', id: `${name}-identify-sigma` });
  // Frames carry their own σ for rotations (a tracker's 6D probe: 0.01 mm, 0.005°).
  const sigmaRotation = h('input', { type: 'number', min: 0, step: 'any', placeholder: 'not stated', id: `${name}-identify-sigma-rotation` });
  const folds = h('input', { type: 'number', min: 0, max: state.info.limits.folds, value: 0, id: `${name}-identify-cv` });
  const run = runButton(`${name}-identify-run`, 'Identify', async () => {
    const cancel = h('button', { type: 'button', id: `${name}-identify-cancel`, text: 'Cancel', disabled: true });
    const progress = h('div', { class: 'progress', id: `${name}-identify-progress` }, h('div', { class: 'spinner' }), h('span', { text: 'Reading the data…' }), cancel);
    result.replaceChildren(progress);
    // What this result is of: the table and the data chosen now.
    const basis = identificationBasis(name);
    try {
      const submitted = await api('/identify', {
        robot: document_(),
        method: methodRequest(name, 'identify'),
        data: await dataRequest(name, 'identify'),
        format: formatRequest(name, 'identify'),
        solver: solver.value,
        max_iterations: fieldNumber(iterations, 'Iteration limit', { min: 1, max: state.info.limits.iterations, whole: true, empty: 30 }),
        loss: loss.value,
        prior: prior.value.trim() || null,
        reject: reject.checked,
        // With its unit: a bare number would be in the data file's length unit.
        sigma: sigmaText(fieldNumber(sigma, 'Sensor σ', { min: 0, above: true, empty: null })),
        sigma_rotation: method.uses_orientation
          ? degreesText(fieldNumber(sigmaRotation, 'Sensor σ of rotations', { min: 0, above: true, empty: null }))
          : null,
        cv: foldsOf(folds),
      });
      cancel.disabled = false;
      cancel.onclick = async () => {
        cancel.disabled = true;
        cancel.textContent = 'Cancelling…';
        await api(`/jobs/${submitted.job}/cancel`, {});
      };
      const job = await followJob(submitted.job, progress.children[1]);
      if (job.state === 'cancelled') {
        result.replaceChildren(h('div', { class: 'warnings', id: `${name}-identify-cancelled`, text: 'Cancelled: the server stopped the identification. Nothing was changed.' }));
      } else if (job.state === 'failed') {
        result.replaceChildren(errorBox(new Error(job.error)));
      } else {
        state.results[name] = { job: submitted.job, result: job.result, basis };
        renderIdentification(result, name, submitted.job, job.result);
        refreshStale();
        persist();
      }
    } catch (error) {
      result.replaceChildren(errorBox(error));
    }
  });
  return h('div', { class: 'panel', id: `${name}-identify` },
    h('div', { class: 'form' },
      field('Data', data),
      upload,
      field('Step rule', solver),
      field('Iteration limit', iterations),
      field('Sensor σ (mm; the verdict tests the fit against it)', sigma),
      method.uses_orientation ? field('Sensor σ of rotations (°)', sigmaRotation) : null,
      field('Loss', loss),
      field('Prior σ (lengths, angles, gains)', prior),
      field('Drop outliers and refit', reject),
      field('Cross-validation folds (0: none)', folds),
      optionFields(method, 'identify'),
      run),
    formatFields(name, 'identify'),
    h('p', { class: 'hint', text: 'Iterated linearised least squares (eq. 10): W is rebuilt at every iterate; σ of each parameter from eq. 11. A robust loss discounts gross errors; a prior keeps poorly excited parameters near nominal; cross-validation judges the fit on held-out configurations.' }),
    result);
}

async function followJob(id, label) {
  for (;;) {
    const job = await api(`/jobs/${id}`);
    if (job.state === 'done' || job.state === 'failed' || job.state === 'cancelled') return job;
    const history = job.history;
    label.textContent = job.state === 'queued' ? 'Waiting for a free core…'
      : history.length ? `Iteration ${history.length - 1}: residual RMS ${sci(history[history.length - 1])}` : 'Starting…';
    await new Promise((resolve) => setTimeout(resolve, 120));
  }
}

/**
 * The registration an identification found: the robot's base in the
 * measurement frame and the tool in the flange frame, as calibrated, and how
 * far each is from the robot file's (the first thing a cell's user reads).
 */
function registrationBlock(registration, id) {
  if (!registration) return null;
  const [unit, degrees] = [unitName('length'), unitName('angle')];
  const pose = (p) => `(${p.position.map((v) => inPageUnits(v, 'length')).join(', ')}) ${unit}, roll-pitch-yaw (${p.rpy.map((v) => inPageUnits(v, 'angle', 5)).join(', ')}) ${degrees}`;
  const moved = ([distance, turned]) => `${inPageUnits(distance, 'length')} ${unit} and ${inPageUnits(turned, 'angle', 5)} ${degrees} from the robot file’s`;
  return h('div', { class: 'registration', id },
    h('p', {}, h('strong', { text: 'Registration. ' }), `The robot’s base in the measurement frame: ${pose(registration.base)} — ${moved(registration.base_moved)}.`),
    h('p', { text: `The tool in the flange frame: ${pose(registration.tool)} — ${moved(registration.tool_moved)}.` }));
}

function renderIdentification(container, name, job, result) {
  const id = result.identification;
  state.calibrated[name] = result.calibrated;
  const mm = (v) => fixed(v * 1e3, v * 1e3 < 0.1 ? 4 : 3);
  const verdict = id.verdict;
  const outcomes = {
    fits_noise: 'Fits the noise', untested: 'Converged (σ not stated)', incomplete: 'Incomplete (not all measured)',
    below_noise: 'Far below the stated noise', exceeds_noise: 'Exceeds the noise', implausible: 'Implausible values',
    underdetermined: 'Data do not determine it', repeated: 'Repeated data', degenerate: 'Degenerate data', not_converged: 'Not converged', diverged: 'Diverged',
  };
  const headline = h('p', { class: `verdict ${verdict.trusted ? 'ok' : 'bad'}`, id: `${name}-identify-verdict` },
    h('strong', { text: 'Verdict: ' }), document.createTextNode(`${verdict.summary}.`));
  const cards = h('div', { class: 'cards' },
    stat(`after ${id.iterations} iterations (${id.route.replace(/_/g, ' ')})`, outcomes[verdict.outcome] || verdict.outcome, { id: `${name}-identify-status`, class: verdict.trusted ? 'ok' : 'bad' }),
    stat('error RMS before → after (mm)', `${mm(id.before.rms)} → ${mm(id.after.rms)}`),
    stat('largest error (mm)', `${mm(id.before.max)} → ${mm(id.after.max)}`),
    id.after_inliers ? stat(`after, without the ${id.outlier_count} outliers (mm)`, `RMS ${mm(id.after_inliers.rms)}, max ${mm(id.after_inliers.max)}`, { id: `${name}-identify-inliers` }) : null,
    id.before.rms_rotation !== undefined
      ? stat('orientation RMS (°)', `${fixed(id.before.rms_rotation * 180 / Math.PI, 3)} → ${fixed(id.after.rms_rotation * 180 / Math.PI, 4)}`) : null,
    stat('identified parameters', String(id.parameters.length + id.auxiliary.length)),
    stat('condition number of W_b', fmt(Number(id.condition_number.toPrecision(4)))),
    verdict.residual_length !== null && verdict.residual_length !== undefined
      ? stat(`residual σ (${unitName('length')})`, sci(inUnits(verdict.residual_length, 'length')), { id: `${name}-identify-residual` }) : null,
    verdict.residual_angle !== null && verdict.residual_angle !== undefined
      ? stat(`residual σ (${unitName('angle')})`, sci(inUnits(verdict.residual_angle, 'angle'))) : null);
  const warnings = id.warnings.length
    ? h('div', { class: 'warnings' }, h('strong', { text: 'Warnings' }), h('ul', {}, id.warnings.map((w) => h('li', { text: w })))) : null;
  const plot = (title, svg, plotId) => {
    const holder = h('div', { class: 'plot', id: plotId });
    holder.innerHTML = svg; // SVG made by the server (plotters), not user text.
    return h('figure', {}, holder, h('figcaption', { class: 'muted', text: title }));
  };
  const plots = h('div', { class: 'plots' },
    plot('Residual RMS per iteration', result.plots.convergence, `${name}-identify-convergence`),
    plot(id.outlier_count ? `Errors before and after (mm; after: the inliers, without the ${id.outlier_count} outliers)` : 'Errors before and after (mm)', result.plots.errors_histogram, `${name}-identify-histogram`),
    plot('Error of every configuration (mm)', result.plots.errors_per_configuration, `${name}-identify-per-configuration`));
  // Values in the page's units; a deviation beyond 3σ is marked, a
  // regrouped parameter is a combination, not the physical value.
  const rows = id.parameters.concat(id.auxiliary).map((p) => {
    const kind = unitOf(p.name);
    const value = (v) => inUnits(v, kind);
    const deviation = p.identified - p.nominal;
    const significant = Number.isFinite(p.std) && Math.abs(deviation) > 3 * p.std;
    const classes = [p.combination ? 'regrouped' : '', significant ? 'significant' : ''].join(' ').trim();
    const title = p.combination ? `regrouped: the deviation stands for ${p.combination}, not for ${p.name} alone`
      : significant ? 'the deviation is beyond 3σ: the data moved this parameter' : '';
    return h('tr', classes ? { class: classes, title } : {},
      h('td', { text: p.combination ? `${p.name} (regrouped)` : p.name }), h('td', { text: fmt(value(p.nominal)) }), h('td', { text: fmt(value(p.identified)) }),
      h('td', { class: 'deviation', text: value(deviation).toExponential(3) }), h('td', { text: sci(value(p.std)) }),
      id.prior ? h('td', { text: sci(value(p.prior_std)) }) : null);
  });
  const table = h('table', { class: 'values', id: `${name}-identify-parameters` },
    h('thead', {}, h('tr', {}, ['parameter', 'nominal', 'identified', 'deviation', 'σ'].concat(id.prior ? ['prior σ'] : []).map((t) => h('th', { text: t })))),
    h('tbody', {}, rows));
  const outlierTable = (title, list, count, tableId) => list.length ? h('div', {},
    h('h3', { text: `${title} (${count} beyond ${id.outlier_threshold} robust σ̂${count > list.length ? `; the worst ${list.length} listed` : ''})` }),
    h('table', { class: 'values', id: tableId },
      h('thead', {}, h('tr', {}, ['observation', 'lines', 'error (mm)', 'residual (σ̂)', 'weight'].map((t) => h('th', { text: t })))),
      h('tbody', {}, list.map((o) => h('tr', {},
        h('td', { text: `${o.file}: ${o.kind} ${o.observation}` }), h('td', { text: o.lines.join(', ') }),
        h('td', { text: fixed(o.error * 1e3, 3) }), h('td', { text: fixed(o.residual_sigmas, 1) }), h('td', { text: fixed(o.weight, 3) })))))) : null;
  const robustness = h('p', { class: 'muted', id: `${name}-identify-robustness`, text:
    `Loss ${id.loss.kind}${id.loss.scale ? ` (k = ${id.loss.scale} σ̂, ${id.reweightings} reweightings)` : ''}; robust σ̂ ${verdict.noise_test ? `${fixed(id.robust_sigma, 2)} × the stated σ` : `${sci(inUnits(id.robust_sigma, 'length'))} ${unitName('length')} (length rows)`}; `
    + (id.outlier_count ? `${id.outlier_count} outliers (ringed on the per-configuration plot)` : 'no outliers')
    + (id.prior ? `; prior ${fixed(id.prior.length * 1e3, 3)} mm, ${fixed(id.prior.angle * 180 / Math.PI, 3)}°, ${fixed(id.prior.gain * 100, 2)} %` : '') });
  const cv = id.cross_validation;
  const validation = cv ? h('p', { id: `${name}-identify-cv-result`, text:
    `Cross-validation, ${cv.folds} folds: held-out RMS ${mm(cv.rms)} mm${cv.rms_rotation !== null ? `, ${fixed(cv.rms_rotation * 180 / Math.PI, 4)}°` : ''} (per fold: ${cv.per_fold.map((f) => mm(f.rms)).join(', ')} mm)` }) : null;
  const moved = id.moved.length
    ? h('p', { class: 'muted', text: `Outside the base set, moved: ${id.moved.map((p) => `${p.name} ${(p.identified - p.nominal).toExponential(2)}`).join(', ')}` }) : null;
  // Saving is the next step only for a result the verdict trusts.
  const actions = h('div', { class: 'actions' },
    h('button', { type: 'button', class: verdict.trusted ? 'primary' : '', id: `${name}-identify-save`, text: verdict.trusted ? 'Save calibrated robot…' : 'Save calibrated robot anyway…', onclick: () => saveAsDialog(result.calibrated, result.calibrated_name) }),
    h('button', {
      type: 'button',
      id: `${name}-identify-open`,
      text: 'Open the calibrated robot in the table',
      onclick: () => confirmDiscard(async () => setRobot(await api('/robots/check', { robot: result.calibrated }), null, { keep: true }), 'Opening the calibrated robot'),
    }),
    job === null
      ? h('span', { class: 'muted', id: `${name}-identify-no-report`, text: 'The server was restarted since: identify again for its report.' })
      : h('a', { href: `/api/jobs/${job}/report`, download: `gecaro-report-${job}.html` }, h('button', { type: 'button', text: 'Download the report' })));
  container.replaceChildren(...[headline, cards, observabilityLine(id.observability, 'the data'), robustness, validation, warnings, actions,
    registrationBlock(id.registration, `${name}-identify-registration`),
    outlierTable('Rejected before this fit', id.rejected, id.rejected_count, `${name}-identify-rejected`),
    outlierTable('Outliers', id.outliers, id.outlier_count, `${name}-identify-outliers`),
    plots, h('h3', { text: `Identified parameters (${unitsLabel()}; gains without unit; beyond 3σ in bold, regrouped in italics)` }), table, moved].filter(Boolean));
}

// ---------------------------------------------------------------- evaluate

/** The Evaluate function: the table's robot, and the calibrated one, on held-out data. */
function evaluatePanel(method) {
  const name = method.name;
  const result = h('div', { class: 'result', id: `${name}-evaluate-result` });
  const data = dataSelect(name, 'evaluate', false);
  const upload = h('input', { type: 'file', accept: '.csv,text/csv', id: `${name}-evaluate-upload`, hidden: true });
  data.addEventListener('change', () => { upload.hidden = data.value !== 'upload'; });
  const run = runButton(`${name}-evaluate-run`, 'Evaluate', async () => {
    result.replaceChildren(h('div', { class: 'progress' }, h('div', { class: 'spinner' }), h('span', { text: 'Evaluating…' })));
    try {
      const compared = state.calibrated[name];
      const evaluated = await api('/evaluate', {
        robot: document_(),
        compared: compared || null,
        method: methodRequest(name, 'evaluate'),
        data: await dataRequest(name, 'evaluate'),
        format: formatRequest(name, 'evaluate'),
      });
      renderEvaluation(result, name, evaluated, Boolean(compared));
      if (compared && state.results[name] && state.results[name].stale) {
        result.prepend(h('div', { class: 'warnings', id: `${name}-evaluate-stale`, text: 'The calibrated robot compared here is stale: the table or the data changed after its identification.' }));
      }
    } catch (error) {
      result.replaceChildren(errorBox(error));
    }
  });
  return h('div', { class: 'panel', id: `${name}-evaluate` },
    h('div', { class: 'form' }, field('Held-out data', data), upload, optionFields(method, 'evaluate'), run),
    formatFields(name, 'evaluate'),
    h('p', { class: 'hint', text: 'The errors of the robot in the table on measurements the identification has not seen, beside those of the last calibrated robot of this method (the Identification function’s). This is the honest measure of a calibration: the training residual always looks better.' }),
    result);
}

function renderEvaluation(container, name, evaluated, compared) {
  const length = (v) => inPageUnits(v, 'length', 4);
  const unit = unitName('length');
  const summary = (label, errors, id) => stat(`${label}: RMS, max (${unit}) over ${errors.count}`, `${length(errors.rms)}, ${length(errors.max)}`, { id });
  const plot = (title, svg, plotId) => {
    const holder = h('div', { class: 'plot', id: plotId });
    holder.innerHTML = svg; // SVG made by the server (plotters), not user text.
    return h('figure', {}, holder, h('figcaption', { class: 'muted', text: title }));
  };
  const notes = (evaluated.notes || []).length ? h('ul', { class: 'notes' }, evaluated.notes.map((n) => h('li', { text: n }))) : null;
  // The verdict: better or worse than the table's robot, against the
  // training error, and whether these are the training data at all.
  const last = state.results[name];
  const comparison = evaluated.comparison;
  let verdict = null;
  if (comparison) {
    const lines = [`The calibrated robot against the table’s robot on these data: ${comparison.summary}.`];
    const training = last && last.result ? last.result.identification.after.rms : null;
    if (training > 0 && evaluated.compared) {
      lines.push(`Its error here is ${fixed(evaluated.compared.rms / training, 2)}× its training error (${length(training)} ${unit}).`);
    }
    if (last && last.basis && dataKey(name, 'evaluate') === last.basis.data) {
      lines.push('These are the data it was identified from: this is its training residual, not a held-out check. Evaluate it on other measurements.');
    }
    verdict = h('div', { class: `verdict ${comparison.outcome === 'worse' ? 'bad' : comparison.outcome === 'better' ? 'ok' : ''}`, id: `${name}-evaluate-verdict` },
      lines.map((line) => h('p', { text: line })));
  }
  container.replaceChildren(...[
    verdict,
    h('div', { class: 'cards' },
      summary('the table’s robot', evaluated.errors, `${name}-evaluate-table`),
      evaluated.compared ? summary('calibrated', evaluated.compared, `${name}-evaluate-calibrated`) : null),
    compared ? null : h('p', { class: 'muted', text: 'No calibrated robot yet: identify first to compare it here.' }),
    notes,
    h('div', { class: 'plots' },
      plot(compared ? 'Held-out errors: the table’s robot (before) and the calibrated one (after), mm' : 'Held-out errors of the table’s robot, mm', evaluated.plots.errors_histogram, `${name}-evaluate-histogram`),
      plot('Held-out error of every configuration (mm)', evaluated.plots.errors_per_configuration, `${name}-evaluate-per-configuration`)),
  ].filter(Boolean));
}

// ---------------------------------------------------------------- compensate

/**
 * The Compensate function: a program written for the table's robot (joint
 * or Cartesian targets, a file of the folder or an upload), corrected for
 * the last calibrated robot of this method, target by target.
 */
function compensatePanel(method) {
  const name = method.name;
  const id = (what) => `${name}-compensate-${what}`;
  const result = h('div', { class: 'result', id: id('result') });
  const program = h('select', { id: id('data'), class: 'data-choice', 'data-method': name, 'data-program': '1' });
  const upload = h('input', { type: 'file', accept: '.csv,text/csv', id: id('upload'), hidden: true });
  program.addEventListener('change', () => { upload.hidden = program.value !== 'upload'; });
  const matching = h('select', { id: id('match') },
    h('option', { value: 'pose', text: 'the whole pose (position and orientation)' }),
    h('option', { value: 'position', text: 'the position only (a tool point)' }));
  const rebase = h('input', { type: 'checkbox', id: id('rebase') });
  const saveAs = h('input', { type: 'text', id: id('save-as'), placeholder: 'e.g. program-compensated.csv (optional)' });
  const run = runButton(id('run'), 'Compensate', async () => {
    result.replaceChildren(h('div', { class: 'progress' }, h('div', { class: 'spinner' }), h('span', { text: 'Compensating…' })));
    try {
      const calibrated = state.calibrated[name];
      if (!calibrated) throw new FieldError('No calibrated robot for this method yet: identify first (Identification), then compensate a program for it.');
      const compensated = await api('/compensate', {
        nominal: document_(),
        calibrated,
        program: await dataRequest(name, 'compensate'),
        format: formatRequest(name, 'compensate'),
        match: matching.value,
        rebase: rebase.checked,
        save_as: saveAs.value.trim() || null,
      });
      renderCompensation(result, name, compensated);
      if (compensated.output) refreshFiles();
    } catch (error) {
      result.replaceChildren(errorBox(error));
    }
  });
  return h('div', { class: 'panel', id: `${name}-compensate` },
    h('div', { class: 'form' },
      field('Program', program), upload,
      field('A joint target asks for', matching),
      field('Save in the folder as', saveAs),
      h('label', { class: 'field checkbox' }, rebase, h('span', { text: 'Calibrated in another frame (a tracker’s): re-express it in the table’s base frame' })),
      run),
    formatFields(name, 'compensate'),
    h('p', { class: 'hint', text: 'A program written for the robot in the table — joint targets qm1…qmn, or Cartesian targets x, y, z [, qw, qx, qy, qz] — corrected for the last calibrated robot of this method: the joints with which it reaches what the table’s robot would have. Other columns are kept. Targets reconfigured, beyond a joint limit or not reached are flagged, never dropped.' }),
    result);
}

const COMPENSATION_STATUS = {
  ok: 'reached',
  reconfigured: 'reached in another configuration',
  'outside-limits': 'beyond a joint limit',
  'not-reached': 'not reached',
};

/** Rows of the per-target table, at most (flagged targets first). */
const COMPENSATION_ROWS = 200;

function renderCompensation(container, name, compensated) {
  const id = (what) => `${name}-compensate-${what}`;
  const unit = unitName('length');
  const length = (v) => sci(inUnits(v, 'length'));
  const flagged = compensated.targets - compensated.reached;
  const verdict = h('div', { class: `verdict ${flagged ? 'bad' : 'ok'}`, id: id('verdict') },
    h('p', {
      text: flagged
        ? `${flagged} of ${compensated.targets} targets are flagged: check them before running the program.`
        : `All ${compensated.targets} targets are reached within the joint limits, in the program’s configuration.`,
    }),
    h('p', { text: `Largest joint correction ${fmt(Number(compensated.largest_correction.toPrecision(3)))} (in the program’s units); largest residual ${length(compensated.largest_position_error)} ${unit}.` }));
  const cards = h('div', { class: 'cards' },
    stat('targets', String(compensated.targets), { id: id('targets') }),
    stat('reached', String(compensated.reached), { id: id('reached') }),
    stat('reconfigured', String(compensated.reconfigured.length), { id: id('reconfigured') }),
    stat('beyond a limit', String(compensated.outside_limits.length), { id: id('outside') }),
    stat('not reached', String(compensated.not_reached.length), { id: id('not-reached') }));
  const rows = [...compensated.points]
    .sort((a, b) => Number(a.status === 'ok') - Number(b.status === 'ok') || a.line - b.line)
    .slice(0, COMPENSATION_ROWS);
  const table = h('table', { class: 'values', id: id('table') },
    h('thead', {}, h('tr', {}, ['line', 'status', `residual (${unit})`, 'corrected motor values (rad, m)'].map((t) => h('th', { text: t })))),
    h('tbody', {}, rows.map((point) => h('tr', { class: point.status === 'ok' ? '' : 'flagged' },
      h('td', { text: String(point.line) }),
      h('td', { text: COMPENSATION_STATUS[point.status] || point.status }),
      h('td', { text: length(point.position_error) }),
      h('td', { text: point.motor_positions.map((q) => fmt(Number(q.toPrecision(6)))).join(', ') })))));
  const more = compensated.points.length > rows.length
    ? h('p', { class: 'muted', text: `${rows.length} of ${compensated.points.length} targets shown, flagged first; the file holds them all.` }) : null;
  const last = state.results[name];
  container.replaceChildren(...[
    last && last.stale ? h('div', { class: 'warnings', id: id('stale'), text: 'The calibrated robot used here is stale: the table or the data changed after its identification.' }) : null,
    verdict,
    cards,
    compensated.csv ? h('div', { class: 'actions' },
      h('button', { type: 'button', id: id('download'), text: `Download ${compensated.file_name}`, onclick: () => download(compensated.file_name, compensated.csv, 'text/csv') }),
      compensated.output ? h('span', { class: 'muted', id: id('saved'), text: `Saved in the folder as ${compensated.output}.` }) : null) : null,
    table,
    more,
  ].filter(Boolean));
}

// ---------------------------------------------------------------- study

/**
 * The study editor: several measurement sets identified together (a tracker
 * cell: reflectors on the flange, stations the tracker measured from), as a
 * study file states them (docs/studies.md). It runs with the robot in the
 * table; its statement is what `/api/identify` takes as `study`.
 */
function emptyStudy() {
  return { name: null, robot: null, length_unit: 'mm', angle_unit: 'deg', tools: [], stations: [], measurements: [], extra: {} };
}

/** The editor's form of a study statement (tools and stations as rows, unknown keys kept). */
function studyOf(spec, name) {
  const frames = (map) => Object.entries(map || {}).map(([frame, stated]) => ({
    name: frame,
    position: (stated.position || [0, 0, 0]).map(String),
    rpy: stated.quaternion ? null : (stated.rpy || [0, 0, 0]).map(String),
    rest: Object.fromEntries(Object.entries(stated).filter(([key]) => key !== 'position' && key !== 'rpy')),
  }));
  const { robot, length_unit: lengthUnit, angle_unit: angleUnit, tools, stations, measurements, ...extra } = spec;
  return {
    name,
    robot: robot || null,
    length_unit: lengthUnit || 'm',
    angle_unit: angleUnit || 'rad',
    tools: frames(tools),
    stations: frames(stations),
    measurements: (measurements || []).map((set) => ({ ...set, sigma: set.sigma === undefined ? '' : String(set.sigma) })),
    extra,
  };
}

/** The statement of the editor's study, its numbers checked in the page. */
function studySpec(study, { withRobot }) {
  const number = (text, what) => {
    const value = Number(String(text).trim());
    if (String(text).trim() === '' || !Number.isFinite(value)) throw new FieldError(`${what}: “${text}” is not a number.`);
    return value;
  };
  const frames = (rows, kind) => {
    const map = {};
    for (const row of rows) {
      const name = row.name.trim();
      if (!/^[A-Za-z_][A-Za-z0-9_-]*$/.test(name)) throw new FieldError(`A ${kind}'s name “${row.name}” is not a name (letters, digits, _ and -).`);
      if (map[name]) throw new FieldError(`Two ${kind}s are named ${name}.`);
      map[name] = {
        ...row.rest,
        position: row.position.map((v, k) => number(v, `${name} ${'xyz'[k]}`)),
        ...(row.rpy ? { rpy: row.rpy.map((v, k) => number(v, `${name} ${['roll', 'pitch', 'yaw'][k]}`)) } : {}),
      };
    }
    return map;
  };
  if (!study.measurements.length) throw new FieldError('The study has no measurement set: add one.');
  const measurements = study.measurements.map((set, index) => {
    const out = { ...set };
    if (!set.data) throw new FieldError(`Set ${index + 1}: choose its data file.`);
    if (String(set.sigma).trim() === '') delete out.sigma;
    else {
      out.sigma = number(set.sigma, `Set ${index + 1} σ`);
      if (!(out.sigma > 0)) throw new FieldError(`Set ${index + 1} σ: ${set.sigma} is out of range; it takes a number above 0.`);
    }
    for (const key of ['tool', 'station']) if (!out[key]) delete out[key];
    return out;
  });
  const spec = {
    ...study.extra,
    length_unit: study.length_unit,
    angle_unit: study.angle_unit,
    tools: frames(study.tools, 'tool'),
    stations: frames(study.stations, 'station'),
    measurements,
  };
  if (withRobot) spec.robot = study.robot || state.file || (state.robot.origin === 'ready' ? state.robot.name : null);
  if (withRobot && !spec.robot) throw new FieldError('A study file names its robot: save the robot in the folder first.');
  return spec;
}

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
    h('thead', {}, h('tr', {}, ['set', 'method', 'data file', 'tool (reflector)', 'station', `σ (${study.length_unit})`, ''].map((t) => h('th', { text: t })))),
    h('tbody', {}, study.measurements.map((set, index) => h('tr', {},
      h('td', { text: String(index + 1) }),
      h('td', {}, select(set.method, state.info.methods.map((m) => [m.name, m.title]), `set ${index + 1} method`, (e) => { set.method = e.target.value; persist(); })),
      h('td', {}, select(set.data, [['', 'choose…'], ...files], `set ${index + 1} data`, (e) => { set.data = e.target.value; persist(); })),
      h('td', {}, select(set.tool, tools, `set ${index + 1} tool`, (e) => { set.tool = e.target.value; persist(); })),
      h('td', {}, select(set.station, stations, `set ${index + 1} station`, (e) => { set.station = e.target.value; persist(); })),
      h('td', {}, h('input', { type: 'text', class: 'study-number', value: set.sigma, placeholder: 'not stated', 'aria-label': `set ${index + 1} sigma`, onchange: (e) => { set.sigma = e.target.value; persist(); } })),
      h('td', {}, h('button', { type: 'button', text: 'Remove', onclick: () => { study.measurements.splice(index, 1); renderStudy(); } }))))));
}

/** Redraws the study editor from `state.study` (the result stays). */
function renderStudy() {
  const study = state.study;
  const unit = (id, value, options, onchange) => h('select', { id, onchange }, options.map(([v, t]) => h('option', { value: v, text: t, selected: v === value })));
  const studies = state.files.robots.map((f) => h('option', { value: f, text: f }));
  const opened = h('select', { id: 'study-file' }, h('option', { value: '', text: 'a study file of the folder…' }), studies);
  $('study-editor').replaceChildren(
    h('div', { class: 'form' },
      field('Open', opened),
      h('button', { type: 'button', id: 'study-open', text: 'Open', onclick: () => openStudy(opened.value) }),
      h('button', { type: 'button', id: 'study-new', text: 'New study', onclick: () => { state.study = emptyStudy(); renderStudy(); persist(); } }),
      field('Lengths', unit('study-length-unit', study.length_unit, [['m', 'metres'], ['mm', 'millimetres']], (e) => { study.length_unit = e.target.value; renderStudy(); })),
      field('Angles', unit('study-angle-unit', study.angle_unit, [['rad', 'radians'], ['deg', 'degrees']], (e) => { study.angle_unit = e.target.value; renderStudy(); }))),
    study.robot ? h('p', { class: 'muted', id: 'study-robot-note', text: `${study.name || 'This study'} names the robot ${study.robot}; it runs with the robot in the table (${document_().name || 'unnamed'}).` }) : null,
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

async function saveStudy() {
  const result = $('study-result');
  try {
    const name = $('study-save-as').value.trim();
    if (!name.endsWith('.toml')) throw new FieldError('Save the study as: a file name ending in .toml.');
    const saved = await api('/studies/save', { name, study: studySpec(state.study, { withRobot: true }) });
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
    const submitted = await api('/identify', { robot: document_(), study: studySpec(state.study, { withRobot: false }) });
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
  container.replaceChildren(
    h('div', { class: `verdict ${id.verdict.trusted ? 'ok' : 'bad'}`, id: 'study-verdict' }, h('p', { text: id.verdict.summary })),
    h('div', { class: 'cards' },
      stat(`RMS error before, after (${unit})`, `${inPageUnits(id.before.rms, 'length', 4)}, ${inPageUnits(id.after.rms, 'length', 4)}`, { id: 'study-rms' }),
      stat('parameters identified', String(id.parameters.length), { id: 'study-parameters' })),
    h('h3', { text: `Identified tools and stations (${unit}, ${degrees})` }),
    h('table', { class: 'values', id: 'study-frames' },
      h('thead', {}, h('tr', {}, ['frame', 'role', 'position', 'σ', 'roll, pitch, yaw', 'σ'].map((t) => h('th', { text: t })))),
      h('tbody', {}, rows)),
    registrationBlock(id.registration, 'study-registration'),
    h('div', { class: 'actions' },
      h('button', { type: 'button', class: id.verdict.trusted ? 'primary' : '', id: 'study-save-calibrated', text: id.verdict.trusted ? 'Save calibrated robot…' : 'Save calibrated robot anyway…', onclick: () => saveAsDialog(result.calibrated, result.calibrated_name) }),
      h('button', {
        type: 'button',
        id: 'study-open-calibrated',
        text: 'Open the calibrated robot in the table',
        onclick: () => confirmDiscard(async () => setRobot(await api('/robots/check', { robot: result.calibrated }), null, { keep: true }), 'Opening the calibrated robot'),
      }),
      job === null ? null : h('a', { href: `/api/jobs/${job}/report`, download: `gecaro-report-${job}.html` }, h('button', { type: 'button', text: 'Download the report' }))),
    (id.warnings || []).length ? h('ul', { class: 'notes' }, id.warnings.map((w) => h('li', { text: w }))) : null);
}

// ---------------------------------------------------------------- tabs

function buildMethodPanels() {
  const tabs = $('method-tabs');
  const panels = $('method-panels');
  for (const method of state.info.methods) {
    tabs.append(h('button', {
      type: 'button',
      role: 'tab',
      id: `tab-${method.name}`,
      'data-method': method.name,
      text: method.title,
      onclick: () => selectMethod(method.name),
    }));
    panels.append(h('div', { class: 'method', id: `method-${method.name}`, hidden: true },
      identifiablePanel(method), planPanel(method), generatePanel(method), identifyPanel(method), evaluatePanel(method),
      compensatePanel(method)));
  }
  for (const button of $('function-tabs').querySelectorAll('button')) {
    button.addEventListener('click', () => selectFunction(button.dataset.function));
  }
  selectMethod(state.method);
}

function selectMethod(name) {
  state.method = name;
  for (const button of $('method-tabs').querySelectorAll('button')) {
    button.classList.toggle('active', button.dataset.method === name);
  }
  for (const method of state.info.methods) $(`method-${method.name}`).hidden = method.name !== name;
  selectFunction(state.function);
  drawView();
}

function selectFunction(fn) {
  state.function = fn;
  for (const button of $('function-tabs').querySelectorAll('button')) {
    button.classList.toggle('active', button.dataset.function === fn);
  }
  for (const f of FUNCTIONS) $(`${state.method}-${f}`).classList.toggle('active', f === fn);
  persist();
}

// ---------------------------------------------------------------- start

async function start() {
  state.info = await api('/info');
  $('folder').textContent = `folder: ${state.info.folder}`;
  buildMethodPanels();
  state.study = emptyStudy();
  installViewControls();
  $('angle-unit').addEventListener('change', changeAngleUnit);
  $('robot-new').addEventListener('click', () => confirmDiscard(newRobotDialog, 'A new robot'));
  $('robot-open').addEventListener('click', () => confirmDiscard(openRobotDialog, 'Opening another robot'));
  $('help-open').addEventListener('click', helpDialog);
  $('table-undo').addEventListener('click', () => undoEdit(true));
  $('table-redo').addEventListener('click', () => undoEdit(false));
  document.addEventListener('keydown', (event) => {
    if (!(event.ctrlKey || event.metaKey) || $('dialog').open) return;
    const key = event.key.toLowerCase();
    // In a field being typed in, the browser's own undo of the text comes first.
    if (event.target.matches && event.target.matches('input, textarea, select')) return;
    if (key === 'z' && !event.shiftKey) { event.preventDefault(); undoEdit(true); }
    if (key === 'y' || (key === 'z' && event.shiftKey)) { event.preventDefault(); undoEdit(false); }
  });
  $('units').addEventListener('change', changeUnits);
  $('robot-save').addEventListener('click', saveRobot);
  $('robot-save-as').addEventListener('click', saveRobotAs);
  $('dialog-cancel').addEventListener('click', () => $('dialog').close());
  $('priority-reset').addEventListener('click', () => {
    remember();
    delete document_().priority;
    markModified();
    renderPriority();
    scheduleCheck();
  });
  $('sliders-zero').addEventListener('click', () => {
    state.q = state.q.map(() => 0);
    renderSliders();
    refreshPose();
  });
  window.addEventListener('resize', () => drawView());
  window.addEventListener('beforeunload', (event) => {
    if (state.dirty) event.preventDefault();
  });
  await refreshFiles();
  const before = stored();
  if (before) {
    await restore(before);
  } else {
    await loadReady('stanford');
  }
}

/** The page as it was before a reload: the robot (with its unsaved edits), the method, function and units, and the last results. */
async function restore(before) {
  try {
    const view = await api('/robots/check', { robot: before.robot.document });
    setRobot({ ...view, origin: before.robot.origin, name: before.robot.name }, before.file);
  } catch (error) {
    await loadReady('stanford');
    return;
  }
  state.dirty = Boolean(before.dirty);
  state.units = before.units === 'm' ? 'm' : 'mm';
  $('units').value = state.units;
  renderRobot();
  if (before.method && $(`method-${before.method}`)) selectMethod(before.method);
  if (before.function && FUNCTIONS.includes(before.function)) selectFunction(before.function);
  if (before.study && Array.isArray(before.study.measurements)) {
    state.study = before.study;
    renderStudy();
  }
  for (const [name, last] of Object.entries(before.results || {})) {
    const container = $(`${name}-identify-result`);
    if (!container || !last.result) continue;
    // A server restarted since keeps no report of the old job (and never
    // serves another job's under its number): the result stays, its report
    // link goes.
    let job = last.job;
    try { await api(`/jobs/${job}`); } catch (ignored) { job = null; }
    // Generated data are not kept across a reload: the data chosen now are
    // taken as the result's, and the table alone is compared.
    const basis = last.basis ? { ...last.basis, data: identificationBasis(name).data } : undefined;
    state.results[name] = { ...last, job, basis };
    renderIdentification(container, name, job, last.result);
  }
  refreshStale();
  toast('Restored the page as it was before the reload');
}

/** One choice of units for the page: mm and degrees, or metres and radians. */
function changeUnits() {
  state.units = $('units').value === 'm' ? 'm' : 'mm';
  // The table shows the same values in the new units; the document is unchanged.
  renderFrames();
  renderTableUnits();
  for (const [name, last] of Object.entries(state.results)) {
    renderIdentification($(`${name}-identify-result`), name, last.job, last.result);
  }
  refreshStale();
  persist();
}

/** What each function does, with the paper's equations and the docs. */
function helpDialog() {
  const item = (title, text) => h('div', { class: 'help-item' }, h('h3', { text: title }), h('p', { text }));
  openDialog({
    title: 'Help',
    body: h('div', { id: 'help-body' },
      item('The robot table', 'Khalil–Kleinfinger parameters of frames 0…n+1 (eq. 2–3): σ (0 revolute, 1 prismatic, 2 fixed), α, d, θ, r, Hayati β for parallel axes, the gain K and offset of every joint (eq. 4) and its limits. Edits are checked as you type; Ctrl+Z and Ctrl+Y undo and redo them. The page keeps the table in this browser across reloads; Save writes it to the folder.'),
      item('Identifiable parameters', 'The QR decomposition of the observation matrix W on random configurations (Appendix III, eq. 34): which parameters the method can identify, which are regrouped with others (and how), which have no effect. The priority matrix decides which of a regrouped set is kept: by decreasing priority.'),
      item('Plan', 'Chooses the configurations to measure from a pool (D-, A-, E-optimal or the test-pose error): the fewer measurements for the same precision, and the accuracy curve against their number (docs/planning.md).'),
      item('Points generation', 'Simulates a real robot (the nominal one with random errors) and what a sensor with the given noise would measure: data with a known answer, to try a method before measuring.'),
      item('Identification', 'Iterated linearised least squares (eq. 10) with the precision of every parameter (eq. 11), robust losses, priors, cross-validation. The verdict says whether the result can be trusted: converged, and whether the residuals fit the stated sensor noise (a χ² test). Read the files as the instrument wrote them: units, column names and separator under “File format”.'),
      item('Evaluate', 'The errors of the table’s robot and of the calibrated one on held-out measurements: the honest measure of a calibration.'),
      item('Compensate', 'A program written for the table’s robot (joint or Cartesian targets, a CSV file of the folder or an upload) corrected for the calibrated robot of this method, target by target: each one reached, reached in another configuration, beyond a joint limit or not reached. The corrected file keeps the program’s columns and units; download it or save it in the folder.'),
      item('Units', 'The Units menu shows the whole page in mm and degrees, or in metres and radians: the robot table, the identified parameters, the residual σ and the evaluation. It changes what is shown and typed, not the robot file, which keeps metres and its own angle unit.'),
      h('p', { class: 'muted', text: 'More in the docs folder of gecaro: docs/methods.md (methods and verdict), docs/planning.md, docs/tracker.md (a laser-tracker cell from end to end), docs/web.md (this page), docs/api.md (its JSON API).' })),
  });
}

start().catch((error) => {
  document.body.prepend(h('div', { class: 'error-box', text: `gecaro could not start: ${error.message}` }));
});
