// A study's statement (what a study file, Python and `/api/identify`'s
// `study` hold: docs/studies.md) and the editor's form of it (tools and
// stations as rows of text, unknown keys kept), one into the other. No DOM
// (tested under node in assets/tests).
import { FieldError } from './fields.js';
import { numberProblem, readNumber } from './format.js';

/** A new study: no frames, no sets, lengths in mm and angles in degrees. */
export function emptyStudy() {
  return { name: null, robot: null, length_unit: 'mm', angle_unit: 'deg', tools: [], stations: [], measurements: [], extra: {} };
}

/**
 * A set's payload as the editor shows it: its text (`20kg,0,0,120mm`), a
 * table (`{ mass: '20kg', com: [0, 0, '120mm'] }`) written as the same text
 * (each coordinate keeps its unit; a bare number is in metres, as in the text).
 */
function payloadText(payload) {
  if (typeof payload !== 'object' || payload === null) return String(payload);
  const mass = typeof payload.mass === 'number' ? `${payload.mass}kg` : String(payload.mass);
  return payload.com ? [mass, ...payload.com.map(String)].join(',') : mass;
}

/** The editor's form of a study statement (tools and stations as rows, unknown keys kept). */
export function studyOf(spec, name) {
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
    measurements: (measurements || []).map((set) => ({
      ...set,
      sigma: set.sigma === undefined ? '' : String(set.sigma),
      ...(set.payload === undefined ? {} : { payload: payloadText(set.payload) }),
    })),
    extra,
  };
}

/**
 * The statement of the editor's study, its numbers checked in the page.
 * `robot` (the robot's file or ready name, or null when it has none) is
 * named in the statement when given: a study file names its robot.
 */
export function studySpec(study, { robot } = {}) {
  const number = (text, what) => {
    const value = readNumber(text);
    if (!Number.isFinite(value)) throw new FieldError(`${what}: ${numberProblem(text)}.`);
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
    const sigma = String(set.sigma).trim();
    if (sigma === '') delete out.sigma;
    else {
      // A number in the study's length unit, or a length with its own unit
      // ("20um", "2e-5m": as a planned study writes it).
      // A decimal comma is read as one (0,02 is 0.02).
      const withUnit = /^([+-]?(?:\d+[.,]?\d*|[.,]\d+)(?:[eE][+-]?\d+)?)\s*(m|mm|um|µm)$/.exec(sigma);
      const value = readNumber(withUnit ? withUnit[1] : sigma);
      if (!Number.isFinite(value)) throw new FieldError(`Set ${index + 1} σ: “${set.sigma}” is not a number, or a length with its unit (20um).`);
      if (!(value > 0)) throw new FieldError(`Set ${index + 1} σ: ${set.sigma} is out of range; it takes a number above 0.`);
      out.sigma = withUnit ? `${withUnit[1].replace(',', '.')}${withUnit[2]}` : value;
    }
    for (const key of ['tool', 'station']) if (!out[key]) delete out[key];
    // The payload the set's rows carry (elastic joints, docs/elastic.md):
    // its mass with kg or g, then optionally its centre in the tool frame.
    const payload = String(set.payload ?? '').trim();
    if (payload === '') delete out.payload;
    else {
      const parts = payload.split(',').map((part) => part.trim());
      if (!(parts.length === 1 || parts.length === 4) || !/^[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?\s*(kg|g)$/.test(parts[0])) {
        throw new FieldError(`Set ${index + 1} payload: “${set.payload}” is not a payload: its mass with kg or g, then optionally its centre in the tool frame (20kg or 20kg,0,0,120mm).`);
      }
      out.payload = parts.join(',');
    }
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
  if (robot !== undefined) {
    spec.robot = study.robot || robot;
    if (!spec.robot) throw new FieldError('A study file names its robot: save the robot in the folder first.');
  }
  return spec;
}

/**
 * A message about a study statement in the editor's words: the server
 * names a set's field as JSON does (`measurements[0].tool`, from 0), the
 * editor counts its sets from 1 (`Set 1 tool`).
 */
export function studyWords(message) {
  return String(message).replace(/measurements\[(\d+)\]\.?(\w*)/g, (_, index, key) => `Set ${Number(index) + 1}${key ? ` ${key}` : ''}`);
}
