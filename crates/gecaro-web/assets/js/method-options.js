// The options a method's functions share: its plane, orientation
// difference and set size, and the data file's format (units, columns,
// separator), as fields and as the request's parts.
import { refreshDataChoices } from './data-choices.js';
import { h, $ } from './dom.js';
import { field, fieldNumber, numberInput } from './fields.js';
import { parseVector } from './format.js';
import { state, methodInfo } from './state.js';

export function optionFields(method, fn) {
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
    fields.push(field('Configurations per set', numberInput({ id: id('set-size'), placeholder: method.name === 'point-link' ? '4' : '2' })));
  }
  return fields;
}

export function methodRequest(name, fn) {
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
  if (method.uses_sets && fn === 'generate' && value('set-size')) request.set_size = fieldNumber($(`${name}-${fn}-set-size`), 'Configurations per set', { min: 2, whole: true });
  return request;
}

export function prefillPlanes() {
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

/**
 * The data file's format as an instrument writes it: units, column names,
 * separator (the command line's --length-unit, --angle-unit, --columns,
 * --delimiter).
 */
export function formatFields(name, fn) {
  const id = (what) => `${name}-${fn}-${what}`;
  return h('details', { class: 'format', id: id('format') },
    h('summary', { text: 'File format: units, column names, separator' }),
    h('div', { class: 'form' },
      field('Lengths in the file', h('select', { id: id('length-unit') },
        h('option', { value: 'm', text: 'metres' }), h('option', { value: 'mm', text: 'millimetres' }))),
      field('Joint angles in the file', h('select', { id: id('angle-unit') },
        h('option', { value: 'rad', text: 'radians' }), h('option', { value: 'deg', text: 'degrees' }))),
      field('Column names (gecaro=file, …)', h('input', { type: 'text', class: 'vector', id: id('columns'), placeholder: 'x=X_mm,qm1=A1', onchange: () => refreshDataChoices(name) })),
      field('Separator', h('select', { id: id('delimiter') },
        ['auto', 'comma', 'semicolon', 'tab'].map((d) => h('option', { value: d, text: d === 'auto' ? 'found from the header' : d })))),
      field('Orientations in the file', h('select', { id: id('rotation') },
        ROTATIONS.map(([value, text]) => h('option', { value, text }))))));
}

/** How files write orientations (gecaro_io::RotationFormat). */
const ROTATIONS = [
  ['quaternion', 'quaternion qw, qx, qy, qz'],
  ['rpy', 'rx, ry, rz: roll, pitch, yaw (fixed x, y, z)'],
  ['euler-xyz', 'rx, ry, rz: Euler x, y′, z″ (intrinsic)'],
  ['euler-zyz', 'rx, ry, rz: Euler z, y′, z″'],
  ['rotation-vector', 'rx, ry, rz: rotation vector'],
];

export function formatRequest(name, fn) {
  const value = (what) => $(`${name}-${fn}-${what}`).value.trim();
  return {
    length_unit: value('length-unit'),
    angle_unit: value('angle-unit'),
    columns: value('columns') || null,
    delimiter: value('delimiter'),
    rotation: value('rotation'),
  };
}
