// Parts shared by the results of single methods and studies.
import { h } from './dom.js';
import { inPageUnits, unitName } from './units.js';

/**
 * The registration an identification found: the robot's base in the
 * measurement frame and the tool in the flange frame, as calibrated, and how
 * far each is from the robot file's (the first thing a cell's user reads).
 */
export function registrationBlock(registration, id) {
  if (!registration) return null;
  const [unit, degrees] = [unitName('length'), unitName('angle')];
  const pose = (p) => `(${p.position.map((v) => inPageUnits(v, 'length')).join(', ')}) ${unit}, roll-pitch-yaw (${p.rpy.map((v) => inPageUnits(v, 'angle', 5)).join(', ')}) ${degrees}`;
  const moved = ([distance, turned]) => `${inPageUnits(distance, 'length')} ${unit} and ${inPageUnits(turned, 'angle', 5)} ${degrees} from the robot file’s`;
  return h('div', { class: 'registration', id },
    h('p', {}, h('strong', { text: 'Registration. ' }), `The robot’s base in the measurement frame: ${pose(registration.base)} — ${moved(registration.base_moved)}.`),
    h('p', { text: `The tool in the flange frame: ${pose(registration.tool)} — ${moved(registration.tool_moved)}.` }));
}
