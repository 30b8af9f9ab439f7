// Parts shared by the results of single methods and studies: plots, the
// registration, and what to do with a calibrated robot.
import { api } from './api.js';
import { h } from './dom.js';
import { saveAsDialog } from './robot-menu.js';
import { setRobot, confirmDiscard } from './robot-table.js';
import { coordinate, quantity, unitName } from './units.js';

/** A plot the server drew (plotters' SVG), captioned, in the page's plot grid. */
export function plotFigure(caption, svg, id) {
  const holder = h('div', { class: 'plot', id });
  holder.innerHTML = svg; // SVG made by the server (plotters), not user text.
  return h('figure', {}, holder, h('figcaption', { class: 'muted', text: caption }));
}

/**
 * What to do with identification `result` of job `job` (null: the server
 * was restarted since, and keeps none of its files): save or open the
 * calibrated robot — saving is the primary step only for a result the
 * verdict trusts — and download the report and the residuals. Element ids
 * start with `prefix`; `onSaved(name)` is called once the robot is saved.
 */
export function calibratedActions(result, trusted, job, prefix, onSaved) {
  const link = (what, route, file, text) => h('a', { href: `/api/jobs/${job}/${route}`, download: file, id: `${prefix}-${what}` },
    h('button', { type: 'button', text }));
  return h('div', { class: 'actions' },
    h('button', { type: 'button', class: trusted ? 'primary' : '', 'data-primary': trusted ? '1' : null, id: `${prefix}-save`, text: trusted ? 'Save calibrated robot…' : 'Save calibrated robot anyway…', onclick: () => saveAsDialog(result.calibrated, result.calibrated_name, onSaved) }),
    h('button', {
      type: 'button',
      id: `${prefix}-open`,
      text: 'Open the calibrated robot in the table',
      // The table then holds this calibrated robot: Evaluate knows it (and does not compare it with itself).
      onclick: () => confirmDiscard(async () => setRobot({ ...(await api('/robots/check', { robot: result.calibrated })), calibratedFrom: JSON.stringify(result.calibrated) }, null, { keep: true }), 'Opening the calibrated robot'),
    }),
    job === null
      ? h('span', { class: 'muted', id: `${prefix}-no-report`, text: 'The server was restarted since: identify again for its report and residuals.' })
      : [link('report', 'report', `gecaro-report-${job}.html`, 'Download the report'),
        link('residuals', 'residuals.csv', `gecaro-residuals-${job}.csv`, 'Download the residuals (CSV)')]);
}

/**
 * The registration an identification found: the robot's base in the
 * measurement frame and the tool in the flange frame, as calibrated, and how
 * far each is from the robot file's (the first thing a cell's user reads).
 */
export function registrationBlock(registration, id) {
  if (!registration) return null;
  const [unit, degrees] = [unitName('length'), unitName('angle')];
  const pose = (p) => `(${p.position.map((v) => coordinate(v, 'length')).join(', ')}) ${unit}, roll-pitch-yaw (${p.rpy.map((v) => coordinate(v, 'angle')).join(', ')}) ${degrees}`;
  const moved = ([distance, turned]) => `${quantity(distance, 'length')} ${unit} and ${quantity(turned, 'angle')} ${degrees} from the robot file’s`;
  return h('div', { class: 'registration', id },
    h('p', {}, h('strong', { text: 'Registration. ' }), `The robot’s base in the measurement frame: ${pose(registration.base)} — ${moved(registration.base_moved)}.`),
    h('p', { text: `The tool in the flange frame: ${pose(registration.tool)} — ${moved(registration.tool_moved)}.` }));
}
