// One choice of units for the page: mm and degrees, or metres and radians.
// Values arrive from the server in metres and radians.
import { fmt } from './format.js';
import { state } from './state.js';

/** A mm/deg or m/rad value of a parameter or unknown named `name`. */
export function unitOf(name) {
  const base = name.includes('.') ? name.split('.').pop() : name;
  if (/^(alpha|theta|beta|gamma|rx|ry|rz)/.test(base)) return 'angle';
  if (/^(d|r|b|x|y|z)\d*$/.test(base)) return 'length';
  return 'none';
}

export function inUnits(value, kind) {
  if (state.units === 'mm' && kind === 'length') return value * 1e3;
  if (state.units === 'mm' && kind === 'angle') return value * 180 / Math.PI;
  return value;
}

/** A value of `kind` ('length' or 'angle') in the page's units, to `digits` significant digits, as text. */
export function inPageUnits(value, kind, digits = 6) {
  return fmt(Number(inUnits(value, kind).toPrecision(digits)));
}

/** The page's unit of `kind` ('length' or 'angle'). */
export function unitName(kind) {
  if (kind === 'length') return state.units === 'mm' ? 'mm' : 'm';
  return state.units === 'mm' ? '°' : 'rad';
}

export function unitsLabel() {
  return state.units === 'mm' ? 'mm, °' : 'm, rad';
}

/**
 * A quantity a person reads — an error, a σ, an RMS, a distance moved — in
 * the page's units to 4 significant digits (the full value on hover: see
 * `titled`).
 */
export function quantity(value, kind) {
  return Number.isFinite(value) ? inPageUnits(value, kind, 4) : '–';
}

/**
 * A coordinate — a position, an angle of a pose — in the page's units to
 * its resolution, not its size: 0.01 mm (1e-5 m) and 0.001° (1e-5 rad). A
 * tracker 2.5 m away is at 2545.93 mm, not 2546 (4 significant digits) nor
 * 2545.9312 (more than it measured).
 */
export function coordinate(value, kind) {
  if (!Number.isFinite(value)) return '–';
  const decimals = kind === 'length' ? (state.units === 'mm' ? 2 : 5) : (state.units === 'mm' ? 3 : 5);
  const text = inUnits(value, kind).toFixed(decimals);
  return /^-0\.?0*$/.test(text) ? text.slice(1) : text;
}

/** The full value of a shown number (SI: m, rad), for its hover text. */
export function fullValue(value, kind) {
  return `${value} ${kind === 'length' ? 'm' : kind === 'angle' ? 'rad' : ''}`.trim();
}
