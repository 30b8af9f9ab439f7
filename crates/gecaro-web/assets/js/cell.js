// The measurement cell's fields (floor, laser tracker, acceptance angle,
// clearance: the command line's --floor, --station, --max-incidence,
// --clearance) in millimetres and degrees, and the request they make.
import { h } from './dom.js';
import { field, FieldError, fieldNumber } from './fields.js';

/**
 * The cell fields of function `fn` of method `name` (as the command line's
 * --floor, --station, --max-incidence, --clearance; millimetres and
 * degrees): where only configurations the cell can measure are drawn.
 */
export function cellInputs(name, fn) {
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
