// ISO 9283's acceptance test on the page (issue 78): the test planned on
// the table's robot — its cube, P1–P5 and the cycles as a program for the
// controller — and evaluated from what the instrument measured: AP and RP
// per pose (with a bullseye of the attained positions), vAP, AD and RD,
// before and after calibration.
import { api } from './api.js';
import { $, h, download } from './dom.js';
import { field, FieldError, errorBox, fieldNumber, runButton, staleOnChange } from './fields.js';
import { refreshFiles } from './robot-menu.js';
import { state, tableDocument } from './state.js';
import { quantity, unitName } from './units.js';

/** A text field. */
function text(id, placeholder, value = '') {
  return h('input', { type: 'text', id: `iso-${id}`, placeholder, value, autocomplete: 'off', spellcheck: 'false' });
}

/** A choice of `[value, label]` options. */
function choice(id, options) {
  return h('select', { id: `iso-${id}` }, options.map(([value, label]) => h('option', { value, text: label })));
}

/**
 * A bullseye of one pose: the attained positions (base frame, x–y) about
 * their barycentre, the circle of RP_l, in the page's length unit.
 */
export function bullseye(pose) {
  const size = 150;
  const centre = size / 2;
  const [bx, by] = pose.barycentre;
  const radius = pose.rp.l;
  const reach = Math.max(radius, ...pose.attained.map(([x, y]) => Math.hypot(x - bx, y - by))) || 1e-9;
  const scale = (0.42 * size) / reach;
  const svg = document.createElementNS('http://www.w3.org/2000/svg', 'svg');
  svg.setAttribute('viewBox', `0 0 ${size} ${size}`);
  svg.setAttribute('class', 'bullseye');
  svg.setAttribute('role', 'img');
  svg.setAttribute('aria-label', `P${pose.pose}: attained positions about their barycentre; circle RP ${quantity(radius, 'length')} ${unitName('length')}`);
  const add = (tag, attributes) => {
    const element = document.createElementNS('http://www.w3.org/2000/svg', tag);
    for (const [key, value] of Object.entries(attributes)) element.setAttribute(key, value);
    svg.append(element);
    return element;
  };
  add('circle', { cx: centre, cy: centre, r: radius * scale, fill: 'none', stroke: 'currentColor', 'stroke-dasharray': '4 3' });
  add('line', { x1: centre - 6, y1: centre, x2: centre + 6, y2: centre, stroke: 'currentColor' });
  add('line', { x1: centre, y1: centre - 6, x2: centre, y2: centre + 6, stroke: 'currentColor' });
  for (const [x, y] of pose.attained) {
    add('circle', { cx: centre + (x - bx) * scale, cy: centre - (y - by) * scale, r: 2.2, class: 'attained' });
  }
  const caption = add('text', { x: 4, y: 12, 'font-size': 11 });
  caption.textContent = `P${pose.pose}: RP ${quantity(radius, 'length')} ${unitName('length')}`;
  return svg;
}

/** One measured file's table: per pose AP and RP (before → after). */
function characteristicsTable(before, after) {
  const unit = unitName('length');
  const angle = unitName('angle');
  const pair = (get) => (after ? `${get(before)} → ${get(after)}` : get(before));
  const length = (value) => quantity(value, 'length');
  const rows = before.poses.map((pose, index) => {
    const other = after && after.poses[index];
    const at = (measured) => (measured === before ? pose : other);
    const cells = [
      `P${pose.pose}`,
      pair((m) => (at(m) ? length(at(m).ap.p) : '–')),
      pair((m) => (at(m) ? length(at(m).rp.l) : '–')),
      before.oriented ? pair((m) => (at(m) ? ['a', 'b', 'c'].map((k) => quantity(at(m).ap[k], 'angle')).join(' / ') : '–')) : '–',
      before.oriented ? pair((m) => (at(m) ? ['a', 'b', 'c'].map((k) => `±${quantity(at(m).rp[k], 'angle')}`).join(' / ') : '–')) : '–',
      pose.vap ? pair((m) => (at(m) && at(m).vap ? length(at(m).vap.p) : '–')) : '–',
      String(pose.cycles),
    ];
    return h('tr', {}, cells.map((cell) => h('td', { text: cell })));
  });
  return h('table', { class: 'iso-table', id: 'iso-table' },
    h('thead', {}, h('tr', {}, [
      'pose', `AP_P (${unit})`, `RP_l (${unit})`, `AP_a / b / c (${angle})`, `RP_a / b / c (${angle})`, `vAP_P (${unit})`, 'cycles',
    ].map((title) => h('th', { text: title })))),
    h('tbody', {}, rows));
}

/** The evaluated test, as the page shows it. */
function renderEvaluation(report) {
  const before = report.before;
  const after = report.after;
  const frame = { base: 'the robot’s base frame', stated: 'the stated instrument pose', best_fit: 'a best fit of the barycentres' }[before.registration];
  const distance = (measured) => measured.distance
    ? `AD ${quantity(measured.distance.ad, 'length')}, RD ±${quantity(measured.distance.rd, 'length')} ${unitName('length')}` : 'not measured';
  const conditions = Object.entries(report.conditions).map(([key, value]) => `${key.replace('_', '-')}: ${value ?? 'not stated'}`).join('; ');
  return h('div', { id: 'iso-evaluation' },
    ...report.warnings.map((warning) => h('p', { class: 'warnings', text: warning })),
    h('p', { id: 'iso-summary', text: `${before.data}${after ? ` before, ${after.data} after` : ''}: the largest AP_P ${quantity(before.worst_ap, 'length')}${after ? ` → ${quantity(after.worst_ap, 'length')}` : ''} ${unitName('length')}, the largest RP_l ${quantity(before.worst_rp, 'length')}${after ? ` → ${quantity(after.worst_rp, 'length')}` : ''} ${unitName('length')}; measurement frame: ${frame}.` }),
    characteristicsTable(before, after),
    h('p', { id: 'iso-distance', text: `Distance P2–P4: ${distance(before)}${after ? ` → ${distance(after)}` : ''}.` }),
    h('div', { class: 'bullseyes' }, (after || before).poses.map(bullseye)),
    h('button', { type: 'button', id: 'iso-report', text: 'Download the report (HTML)', onclick: () => download('iso9283-report.html', report.report, 'text/html') }),
    h('p', { class: 'hint', text: `Conditions: ${conditions}.` }));
}

/** Builds the acceptance test's card. */
export function buildAcceptance() {
  const result = h('div', { class: 'result', id: 'iso-result' });
  const cube = text('cube', 'auto, or 800mm,0,600mm,400mm', 'auto');
  const cycles = text('cycles', String(state.info.defaults.cycles), String(state.info.defaults.cycles));
  const directions = choice('directions', [['1', 'one (the pose test)'], ['3', 'three (multi-directional)']]);
  const programUnit = choice('program-unit', [['mm', 'mm and degrees'], ['m', 'm and radians']]);
  const save = text('save', 'test.csv', 'iso9283-test.csv');
  const plan = runButton('iso-plan', 'Plan the test', async () => {
    try {
      if (!save.value.trim()) throw new FieldError('Name the program file to write.');
      const planned = await api('/iso9283/plan', {
        robot: tableDocument(),
        cube: cube.value.trim() || 'auto',
        cycles: fieldNumber(cycles, 'Cycles', { min: 2, max: state.info.limits.cycles, whole: true, empty: state.info.defaults.cycles }),
        directions: Number(directions.value),
        format: programUnit.value === 'mm' ? { length_unit: 'mm', angle_unit: 'deg' } : {},
        save_as: save.value.trim(),
        overwrite: true,
      });
      await refreshFiles();
      program.value = save.value.trim();
      const [x, y, z] = planned.centre;
      const length = (value) => quantity(value, 'length');
      result.replaceChildren(
        h('p', { id: 'iso-planned', text: `Test cube: centre ${length(x)}, ${length(y)}, ${length(z)} ${unitName('length')}, side ${length(planned.side)} ${unitName('length')} (${planned.searched ? 'the largest found inside the working space' : 'as stated'})${planned.orientation_held ? '' : '; fewer than 6 joints: positions only'}. ${planned.rows} rows (${planned.measured_rows} measured) written to ${save.value.trim()}.` }),
        h('table', { class: 'iso-table' },
          h('thead', {}, h('tr', {}, ['pose', `x (${unitName('length')})`, 'y', 'z'].map((title) => h('th', { text: title })))),
          h('tbody', {}, planned.poses.map((pose) => h('tr', {}, [`P${pose.pose}`, ...pose.position.map(length)].map((cell) => h('td', { text: cell })))))),
        h('button', { type: 'button', id: 'iso-download', text: 'Download the program', onclick: () => download(save.value.trim(), planned.program, 'text/csv') }));
    } catch (error) {
      result.replaceChildren(errorBox(error));
    }
  });
  const program = text('program', 'iso9283-test.csv');
  const data = text('data', 'measured.csv (pose, cycle[, direction], x, y, z[, qw, qx, qy, qz])');
  const after = text('after', 'optional: measured running the compensated program');
  const dataUnit = choice('data-unit', [['mm', 'mm'], ['m', 'm']]);
  const frame = text('frame', 'base, best-fit, or 3000mm,0,400mm[,qw,qx,qy,qz]', 'base');
  const speed = text('speed', '100 %');
  const load = text('load', 'rated');
  const evaluate = runButton('iso-evaluate', 'Evaluate the test', async () => {
    try {
      if (!program.value.trim()) throw new FieldError('Name the test’s program file.');
      if (!data.value.trim()) throw new FieldError('Name the file of what was measured.');
      const report = await api('/iso9283/evaluate', {
        robot: tableDocument(),
        program: { file: program.value.trim() },
        data: { file: data.value.trim() },
        after: after.value.trim() ? { file: after.value.trim() } : null,
        format: { length_unit: dataUnit.value },
        frame: frame.value.trim() || 'base',
        conditions: { speed: speed.value.trim() || null, load: load.value.trim() || null },
      });
      result.replaceChildren(renderEvaluation(report));
    } catch (error) {
      result.replaceChildren(errorBox(error));
    }
  });
  // A setting changed after a result makes it stale: said above it, until
  // the test is planned or evaluated again.
  const card = $('acceptance');
  staleOnChange(card, result, 'iso-stale', 'The settings changed since this result: plan or evaluate again to see theirs.');
  card.replaceChildren(
    h('div', { class: 'form' },
      field('Test cube', cube),
      field('Cycles', cycles),
      field('Approach directions', directions),
      field('Program units', programUnit),
      field('Program file', save),
      plan),
    h('div', { class: 'form' },
      field('The test’s program', program),
      field('Measured (before, or the only one)', data),
      field('Measured after calibration', after),
      field('Their length unit', dataUnit),
      field('Measurement frame', frame),
      field('Speed', speed),
      field('Load', load),
      evaluate),
    h('p', { class: 'hint', text: 'ISO 9283, clause 7: P1 at the cube’s centre, P2–P5 on the diagonals of the plane C1–C2–C7–C8 at 10 % from the corners; AP_P = ‖x̄ − x_c‖, RP_l = l̄ + 3 S_l; vAP the largest gap between the approaches’ barycentres; AD and RD between P2 and P4. After calibration, compensate the program (the Compensate function) and run it: the same test (docs/iso9283.md).' }),
    result);
}
