// The measurement cell's fields (floor, laser tracker, acceptance angle,
// clearance: the command line's --floor, --station, --max-incidence,
// --clearance) in millimetres and degrees, and the request they make.
import { h } from './dom.js';
import { emit } from './events.js';
import { field, FieldError, fieldNumber } from './fields.js';
import { parseVector, readNumber } from './format.js';

/**
 * The cell fields of function `fn` of method `name` (as the command line's
 * --floor, --station, --max-incidence, --clearance; millimetres and
 * degrees): where only configurations the cell can measure are drawn.
 */
export function cellInputs(name, fn) {
  // The floor and the tracker are drawn in the 3D view as they are typed.
  const input = (key, placeholder) => h('input', { type: 'text', class: 'vector', id: `${name}-${fn}-${key}`, placeholder, onchange: () => emit('overlay') });
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
      // Decimal commas too, when the numbers are separated by semicolons or spaces.
      let parts;
      try {
        parts = parseVector(text, 'Laser tracker');
      } catch (error) {
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

/**
 * The cell the fields of method `name` state (its Plan's, else its Points
 * generation's), for the 3D view: the floor's height and the tracker's
 * position (m), each `null` when not stated or not readable.
 */
export function statedCell(name) {
  const value = (key) => ['plan', 'generate'].map((fn) => document.getElementById(`${name}-${fn}-${key}`))
    .map((input) => (input ? input.value.trim() : '')).find((text) => text !== '') || '';
  const floorText = value('floor');
  const floor = floorText === '' ? null : readNumber(floorText);
  let station = null;
  try {
    station = value('station') ? parseVector(value('station'), 'tracker').map((v) => v * 1e-3) : null;
  } catch (error) { /* not three numbers yet: nothing to draw */ }
  return { floor: Number.isFinite(floor) ? floor * 1e-3 : null, station };
}
