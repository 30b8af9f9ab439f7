// The page's state (one object, read and written by the modules above),
// its constants, and its keeping across reloads (localStorage).
import { emit } from './events.js';

export const KINDS = ['alpha', 'd', 'theta', 'r', 'beta', 'K'];

export const KIND_HEADS = ['α', 'd', 'θ', 'r', 'β', 'K'];

export const COLUMNS = [
  { key: 'sigma', head: 'σ' }, { key: 'alpha', head: 'α' }, { key: 'd', head: 'd' },
  { key: 'theta', head: 'θ' }, { key: 'r', head: 'r' }, { key: 'beta', head: 'β' },
  { key: 'K', head: 'K' }, { key: 'offset', head: 'offset' }, { key: 'qmin', head: 'qmin' },
  { key: 'qmax', head: 'qmax' },
  // Elastic joints: a compliance on any joint makes the robot elastic
  // (rad/(N·m), m/N if prismatic); the masses load them (kg).
  { key: 'compliance', head: 'c (rad/N·m)' }, { key: 'mass', head: 'mass (kg)' },
];

export const ANGLES = new Set(['alpha', 'theta', 'beta']);

export const JOINT_KEYS = new Set(['K', 'offset', 'qmin', 'qmax', 'compliance']);

export const JOINT_ANGLES = new Set(['offset', 'qmin', 'qmax']);

export const DEFAULT_COUNTS = {
  position: 50, frame: 30, 'point-link': 80, 'frame-link': 60, plane1: 120, plane2: 120, distance: 200,
};

export const FUNCTIONS = ['identifiable', 'plan', 'generate', 'identify', 'evaluate', 'compensate'];

export const state = {
  info: null,
  robot: null, // {origin, name, document, problems, summary}
  file: null, // the robot's file in the folder, once opened or saved
  dirty: false,
  q: [],
  pose: null,
  calibratedPose: null, // the shown method's calibrated robot's frames at the same joints (the 3D view)
  localProblems: new Map(),
  files: { robots: [], data: [] },
  generated: {}, // method -> {csv, file_name, real, origin, serial}
  heldOut: {}, // method -> held-out data of the generated data's real robot
  results: {}, // method -> the last identification {job, result}, shown again after a reload
  calibrated: {}, // method -> the calibrated robot's document, for Evaluate
  planned: {}, // method -> the last plan's configuration count
  plannedPoints: {}, // method -> the last plan's tool points with the table's robot (the 3D view)
  evaluated: {}, // method -> the last evaluation's comparison outcome ('better', 'worse', …, or 'table')
  exported: {}, // method -> what was done with the calibrated robot: {text, status ('done' or 'warn': targets flagged)}
  study: null, // the study editor's study (see emptyStudy)
  studyResult: null, // the study's last identification {basis, stale}, for its stale mark
  undo: [], // earlier table documents (JSON), for Undo
  redo: [],
  units: 'mm', // results in 'mm' (mm, degrees) or 'm' (m, radians)
  method: 'position',
  function: 'identifiable',
  robotSerial: 0, // changes with every robot loaded, so late answers about the last one are dropped
  view: { azimuth: -0.9, elevation: 0.45, zoom: 1, bounds: null },
  overlay: null, // what the 3D view draws of the last result: {source, points, instrument, stations} (deviations.js)
};

export function tableDocument() {
  return state.robot.document;
}

export function methodInfo(name) {
  return state.info.methods.find((m) => m.name === name);
}

const STORAGE_KEY = 'gecaro.page';

/**
 * Keeps the robot, the settings and the last results in the browser, and
 * tells the page (`changed`: the step bar follows).
 */
export function persist() {
  emit('changed');
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
export function stored() {
  try {
    const page = JSON.parse(localStorage.getItem(STORAGE_KEY) || 'null');
    return page && page.robot && page.robot.document ? page : null;
  } catch (error) {
    return null;
  }
}
