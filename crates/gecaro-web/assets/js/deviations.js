// The deviation of every measured point from the calibrated robot's: the
// table an engineer reads first (dx, dy, dz along the robot's base axes,
// |d| before and after, the data file's line), and what the 3D view draws
// of it and of the cell (`state.overlay`: the error vectors on the measured
// points, the instrument and its stations).
import { h } from './dom.js';
import { emit } from './events.js';
import { state } from './state.js';
import { inPageUnits, unitName } from './units.js';

/** Rows shown before "Show all". */
const FIRST_ROWS = 25;

const length = (p) => Math.hypot(...p.deviation);

/** A length in the page's units to 4 significant digits, the full value (m) on hover. */
function lengthCell(value) {
  return h('td', { class: 'number', title: `${value} m`, text: inPageUnits(value, 'length', 4) });
}

/**
 * The deviations' table (`deviations` as the server sends them, or none):
 * the largest first, `FIRST_ROWS` of them until "Show all". Element ids
 * start with `prefix`.
 */
export function deviationTable(deviations, prefix) {
  if (!deviations || !deviations.points.length) return null;
  const unit = unitName('length');
  const sorted = [...deviations.points].sort((a, b) => length(b) - length(a));
  const row = (p) => h('tr', {},
    h('td', { text: `${p.set}: ${p.file}` }), h('td', { class: 'number', text: p.line === undefined ? `#${p.observation}` : String(p.line) }),
    p.deviation.map(lengthCell), lengthCell(length(p)), lengthCell(p.before));
  const body = h('tbody', {}, sorted.slice(0, FIRST_ROWS).map(row));
  const all = sorted.length > FIRST_ROWS
    ? h('button', { type: 'button', id: `${prefix}-deviations-all`, text: `Show all ${sorted.length}`, onclick: (event) => { body.replaceChildren(...sorted.map(row)); event.target.remove(); } })
    : null;
  const kept = deviations.total > deviations.points.length ? `; the largest ${deviations.points.length} of ${deviations.total} here, every one in the residuals CSV` : '';
  return h('div', { class: 'deviations', id: `${prefix}-deviations` },
    h('h3', { text: `Deviation of every measured point from the calibrated robot (${unit})` }),
    h('p', { class: 'muted', text: `Measured minus calibrated, along the robot’s base axes; the largest first${kept}. |d| before: with the robot as stated. The 3D view draws them as vectors on the points.` }),
    h('div', { class: 'scroll-x' }, h('table', { class: 'values', id: `${prefix}-deviations-table` },
      h('thead', {}, h('tr', {}, ['set: file', 'line', 'dx', 'dy', 'dz', '|d|', '|d| before'].map((t) => h('th', { text: t })))),
      body)),
    all);
}

/**
 * What the 3D view draws of a result (`source` names it): the error vectors
 * on the measured points and, for a study, the instrument and the stations
 * (`frames` as identified, in the measurement frame). None without
 * deviations.
 */
export function showOnView(source, deviations, frames, covariances) {
  if (!deviations || !deviations.points.length) return;
  const origin = deviations.measurement_origin;
  const axes = deviations.measurement_axes;
  const turn = (p) => [0, 1, 2].map((k) => axes[0][k] * p[0] + axes[1][k] * p[1] + axes[2][k] * p[2]);
  const toView = (p) => turn(p).map((v, k) => origin[k] + v);
  // A covariance C in the measurement frame is R C Rᵀ in the view's.
  const turned = (c) => {
    const columns = [0, 1, 2].map((j) => turn([c[0][j], c[1][j], c[2][j]]));
    return [0, 1, 2].map((i) => turn([columns[0][i], columns[1][i], columns[2][i]]));
  };
  const stations = (frames || []).filter((f) => f.role === 'station').map((f) => ({
    name: f.name,
    at: toView(f.position),
    covariance: covariances && covariances[f.name] ? turned(covariances[f.name]) : null,
  }));
  state.overlay = {
    source,
    points: deviations.points.map((p) => ({ at: p.point, deviation: p.deviation })),
    instrument: { name: 'measurement frame', at: origin },
    stations,
  };
  emit('overlay');
}
