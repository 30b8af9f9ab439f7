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
