// Parts shared by the results of single methods and studies: plots, the
// registration, and what to do with a calibrated robot.
import { api } from './api.js';
import { openDialog } from './dialogs.js';
import { h, download } from './dom.js';
import { saveAsDialog } from './robot-menu.js';
import { setRobot, confirmDiscard } from './robot-table.js';
import { coordinate, quantity, unitName } from './units.js';

/**
 * A plot the server drew (plotters' SVG), captioned, in the page's plot
 * grid: enlarged in a dialog on request, and downloaded as SVG or PNG
 * (named after its element id).
 */
export function plotFigure(caption, svg, id) {
  const holder = h('div', { class: 'plot', id });
  holder.innerHTML = svg; // SVG made by the server (plotters), not user text.
  const enlarge = () => {
    const large = h('div', { class: 'plot plot-large', id: `${id}-large` });
    large.innerHTML = svg;
    openDialog({ title: caption, body: large });
  };
  const tools = h('span', { class: 'plot-tools' },
    h('button', { type: 'button', class: 'link', id: `${id}-enlarge`, text: 'Enlarge', onclick: enlarge }),
    h('button', { type: 'button', class: 'link', id: `${id}-svg`, text: 'SVG', onclick: () => download(`${id}.svg`, svg, 'image/svg+xml') }),
    h('button', { type: 'button', class: 'link', id: `${id}-png`, text: 'PNG', onclick: () => downloadPng(svg, `${id}.png`) }));
  holder.addEventListener('click', enlarge);
  return h('figure', {}, holder, h('figcaption', { class: 'muted' }, caption, ' ', tools));
}

/** The SVG `svg` drawn at twice its size into a PNG file named `name` (a report's figure). */
function downloadPng(svg, name) {
  const image = new Image();
  const url = URL.createObjectURL(new Blob([svg], { type: 'image/svg+xml' }));
  image.onload = () => {
    const canvas = document.createElement('canvas');
    canvas.width = image.naturalWidth * 2;
    canvas.height = image.naturalHeight * 2;
    const context = canvas.getContext('2d');
    context.fillStyle = '#ffffff';
    context.fillRect(0, 0, canvas.width, canvas.height);
    context.drawImage(image, 0, 0, canvas.width, canvas.height);
    URL.revokeObjectURL(url);
    canvas.toBlob((blob) => {
      const link = h('a', { href: URL.createObjectURL(blob), download: name });
      document.body.append(link);
      link.click();
      link.remove();
    }, 'image/png');
  };
  image.src = url;
}

/** A correlation's colour: blue for −1, white for 0, red for +1. */
function correlationColour(rho) {
  const t = Math.min(1, Math.abs(rho));
  const fade = Math.round(255 * (1 - t));
  return rho >= 0 ? `rgb(255, ${fade}, ${fade})` : `rgb(${fade}, ${fade}, 255)`;
}

/**
 * The correlation matrix of the identified unknowns as a heatmap
 * (`correlation` as the server sends it, or none): red +1, white 0, blue
 * −1, the unknowns' names along both sides; the pair under the pointer
 * and its ρ said under it. Ids start with `prefix`.
 */
export function correlationHeatmap(correlation, prefix) {
  if (!correlation || !correlation.names.length) return null;
  const { names, values } = correlation;
  const n = names.length;
  const cell = Math.max(6, Math.min(16, Math.floor(560 / n)));
  const label = n <= 80 ? 84 : 0;
  const canvas = h('canvas', { id: `${prefix}-correlation`, width: label + n * cell, height: label + n * cell, 'data-size': n, 'aria-label': `Correlations of the ${n} identified unknowns` });
  const said = h('p', { class: 'muted', id: `${prefix}-correlation-at`, text: 'Point at a cell for its pair and ρ.' });
  const context = canvas.getContext('2d');
  for (let i = 0; i < n; i += 1) {
    for (let j = 0; j < n; j += 1) {
      context.fillStyle = correlationColour(values[i][j]);
      context.fillRect(label + j * cell, label + i * cell, cell, cell);
    }
  }
  if (label) {
    context.fillStyle = '#14202e';
    context.font = `${Math.min(11, cell)}px system-ui, sans-serif`;
    context.textBaseline = 'middle';
    names.forEach((name, i) => {
      context.textAlign = 'right';
      context.fillText(name, label - 4, label + (i + 0.5) * cell);
      context.save();
      context.translate(label + (i + 0.5) * cell, label - 4);
      context.rotate(-Math.PI / 2);
      context.textAlign = 'left';
      context.fillText(name, 0, 0);
      context.restore();
    });
  }
  canvas.addEventListener('mousemove', (event) => {
    const box = canvas.getBoundingClientRect();
    const j = Math.floor(((event.clientX - box.left) * (canvas.width / box.width) - label) / cell);
    const i = Math.floor(((event.clientY - box.top) * (canvas.height / box.height) - label) / cell);
    if (i >= 0 && j >= 0 && i < n && j < n) said.textContent = `ρ(${names[i]}, ${names[j]}) = ${values[i][j].toFixed(3)}`;
  });
  const strongest = [];
  for (let i = 0; i < n; i += 1) for (let j = i + 1; j < n; j += 1) strongest.push([Math.abs(values[i][j]), i, j]);
  strongest.sort((a, b) => b[0] - a[0]);
  const top = strongest.slice(0, 3).map(([, i, j]) => `${names[i]} ~ ${names[j]} ${values[i][j].toFixed(2)}`).join(', ');
  return h('details', { class: 'correlation', id: `${prefix}-correlation-details` },
    h('summary', { text: `Correlations of the ${n} identified unknowns (heatmap: red +1, white 0, blue −1)${top ? `; the strongest: ${top}` : ''}` }),
    h('div', { class: 'scroll-x' }, canvas), said);
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
