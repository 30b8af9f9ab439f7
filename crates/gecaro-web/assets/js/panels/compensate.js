// The Compensate function: a program corrected for the calibrated robot,
// target by target.
import { api } from '../api.js';
import { dataRequest } from '../data-choices.js';
import { h, download } from '../dom.js';
import { field, FieldError, errorBox, runButton, stat } from '../fields.js';
import { fmt, sci } from '../format.js';
import { formatFields, formatRequest } from '../method-options.js';
import { refreshFiles } from '../robot-menu.js';
import { state, tableDocument, persist } from '../state.js';
import { inPageUnits, inUnits, unitName } from '../units.js';

/**
 * The Compensate function: a program written for the table's robot (joint
 * or Cartesian targets, a file of the folder or an upload), corrected for
 * the last calibrated robot of this method, target by target.
 */
export function compensatePanel(method) {
  const name = method.name;
  const id = (what) => `${name}-compensate-${what}`;
  const result = h('div', { class: 'result', id: id('result') });
  const program = h('select', { id: id('data'), class: 'data-choice', 'data-method': name, 'data-function': 'compensate', 'data-program': '1' });
  const upload = h('input', { type: 'file', accept: '.csv,text/csv', id: id('upload'), hidden: true });
  program.addEventListener('change', () => { upload.hidden = program.value !== 'upload'; });
  const matching = h('select', { id: id('match') },
    h('option', { value: 'pose', text: 'the whole pose (position and orientation)' }),
    h('option', { value: 'position', text: 'the position only (a tool point)' }));
  const rebase = h('input', { type: 'checkbox', id: id('rebase') });
  const tool = h('input', { type: 'text', id: id('tool'), placeholder: 'frame n+1; or a calibrated tool (smr_a), or 0,0,120mm' });
  const maxTurn = h('input', { type: 'text', id: id('max-tool-turn'), placeholder: '1deg' });
  const basePoints = h('input', { type: 'text', id: id('base-points'), placeholder: 'e.g. plate.csv in the folder (optional)' });
  const baseCircles = h('input', { type: 'text', id: id('base-circles'), placeholder: 'e.g. circles.csv in the folder (optional)' });
  const basePointsUnit = h('select', { id: id('base-points-unit') },
    h('option', { value: 'mm', text: 'mm' }), h('option', { value: 'm', text: 'm' }));
  const saveAs = h('input', { type: 'text', id: id('save-as'), placeholder: 'e.g. program-compensated.csv (optional)' });
  const run = runButton(id('run'), 'Compensate', async () => {
    result.replaceChildren(h('div', { class: 'progress' }, h('div', { class: 'spinner' }), h('span', { text: 'Compensating…' })));
    try {
      const calibrated = state.calibrated[name];
      if (!calibrated) throw new FieldError('No calibrated robot for this method yet: identify first (Identification), then compensate a program for it.');
      const compensated = await api('/compensate', {
        nominal: tableDocument(),
        calibrated,
        program: await dataRequest(name, 'compensate'),
        format: formatRequest(name, 'compensate'),
        match: matching.value,
        rebase: rebase.checked,
        base_points: basePoints.value.trim() ? { file: basePoints.value.trim() } : null,
        base_circles: baseCircles.value.trim() ? { file: baseCircles.value.trim() } : null,
        base_points_format: { length_unit: basePointsUnit.value },
        tool: tool.value.trim() || null,
        max_tool_turn: maxTurn.value.trim() || null,
        save_as: saveAs.value.trim() || null,
      });
      renderCompensation(result, name, compensated);
      // The step bar marks a program with flagged targets as a warning, not as done.
      const flagged = compensated.targets - compensated.reached + compensated.turned.length;
      state.exported[name] = {
        text: `${compensated.output ? `program saved as ${compensated.output}` : 'program compensated'}${flagged ? `, ${flagged} of ${compensated.targets} flagged` : ''}`,
        status: flagged ? 'warn' : 'done',
      };
      persist();
      if (compensated.output) refreshFiles();
    } catch (error) {
      result.replaceChildren(errorBox(error));
    }
  });
  const frames = framesForm(name, id, tool);
  return h('div', { class: 'panel', id: `${name}-compensate` },
    h('div', { class: 'form' },
      field('Program', program), upload,
      field('A joint target asks for', matching),
      field('The tool the targets are for', tool),
      field('Largest tool turn a position match may leave', maxTurn),
      field('Save in the folder as', saveAs),
      h('label', { class: 'field checkbox' }, rebase, h('span', { text: 'Calibrated in another frame (a tracker’s): re-express it in the table’s base frame' })),
      field('Or the owner’s base, by points measured beside the drawing’s (name, x, y, z, base_x, base_y, base_z)', basePoints),
      field('Or the maker’s base, by the circles of joints 1 and 2 turned alone (qm1…qmn, x, y, z; angles in radians unless the file’s units line says otherwise)', baseCircles),
      field('Their length unit', basePointsUnit),
      run),
    formatFields(name, 'compensate'),
    frames,
    h('p', { class: 'hint', text: 'A program written for the robot in the table — joint targets qm1…qmn, or Cartesian targets x, y, z [, qw, qx, qy, qz] — corrected for the last calibrated robot of this method: the joints with which it reaches what the table’s robot would have. Other columns are kept. Targets reconfigured, outside the joint ranges the calibration measured, beyond a joint limit or not reached are flagged, never dropped.' }),
    result);
}

const COMPENSATION_STATUS = {
  ok: 'reached',
  reconfigured: 'reached in another configuration',
  'outside-region': 'outside the measured region',
  'outside-limits': 'beyond a joint limit',
  'not-reached': 'not reached',
};

/** Rows of the per-target table, at most (flagged targets first). */
const COMPENSATION_ROWS = 200;

/** The largest joint correction as the command line says it: `0.936 rad (joint 5, line 7). `; nothing when none was made. */
function correctionText(largest) {
  if (!largest) return '';
  return `Largest joint correction ${fmt(Number(largest.value.toPrecision(4)))} ${largest.unit} (joint ${largest.joint}, line ${largest.line}). `;
}

/** Whether joint `j` (from 0) of the table's robot is revolute (a prismatic joint's motor value is a length). */
function revolute(j) {
  const joints = state.robot.summary ? state.robot.summary.joints : [];
  return !joints[j] || joints[j].revolute;
}

/** The corrected motor values' column heads, one per joint, each with the page's unit. */
function motorHeads() {
  const joints = state.robot.summary ? state.robot.summary.joints : [];
  return joints.map((_, j) => `qm${j + 1} (${unitName(revolute(j) ? 'angle' : 'length')})`);
}

/** A corrected motor value (rad or m from the server) in the page's units, 6 significant digits. */
function motorValue(q, j) {
  return inPageUnits(q, revolute(j) ? 'angle' : 'length', 6);
}

function renderCompensation(container, name, compensated) {
  const id = (what) => `${name}-compensate-${what}`;
  const unit = unitName('length');
  const length = (v) => sci(inUnits(v, 'length'));
  const flagged = compensated.targets - compensated.reached;
  const turned = compensated.turned.length;
  const turn = compensated.largest_tool_turn === undefined || compensated.largest_tool_turn === null ? null
    : `Largest tool turn left by the position match ${fmt(Number((compensated.largest_tool_turn * 180 / Math.PI).toPrecision(3)))}°.`;
  const verdict = h('div', { class: `verdict ${flagged || turned ? 'bad' : 'ok'}`, id: id('verdict') },
    h('p', {
      text: flagged
        ? `${flagged} of ${compensated.targets} targets are flagged: check them before running the program.`
        : turned
          ? `The position match turns the tool beyond the tolerance at ${turned} of ${compensated.targets} targets: it moves the point only. Match the pose, or accept a larger turn.`
          : `All ${compensated.targets} targets are reached within the joint limits, in the program’s configuration.`,
    }),
    h('p', { id: id('largest'), text: `${correctionText(compensated.largest_correction_at)}Largest residual ${length(compensated.largest_position_error)} ${unit}.` }),
    turn ? h('p', { id: id('tool-turn'), text: turn }) : null,
    compensated.registration ? h('p', { id: id('registration'), text: registrationText(compensated.registration, unit, length) }) : null);
  const cards = h('div', { class: 'cards' },
    stat('targets', String(compensated.targets), { id: id('targets') }),
    stat('reached', String(compensated.reached), { id: id('reached') }),
    stat('reconfigured', String(compensated.reconfigured.length), { id: id('reconfigured') }),
    stat('outside the measured region', String(compensated.outside_region.length), { id: id('outside-region') }),
    stat('beyond a limit', String(compensated.outside_limits.length), { id: id('outside') }),
    stat('not reached', String(compensated.not_reached.length), { id: id('not-reached') }),
    stat('tool turned too far', String(turned), { id: id('turned') }));
  const rows = [...compensated.points]
    .sort((a, b) => Number(a.status === 'ok') - Number(b.status === 'ok') || a.line - b.line)
    .slice(0, COMPENSATION_ROWS);
  const table = h('table', { class: 'values', id: id('table') },
    h('thead', {}, h('tr', {}, ['line', 'status', `residual (${unit})`, ...motorHeads()].map((t) => h('th', { text: t })))),
    h('tbody', {}, rows.map((point) => h('tr', { class: point.status === 'ok' ? '' : 'flagged' },
      h('td', { text: String(point.line) }),
      h('td', { text: COMPENSATION_STATUS[point.status] || point.status }),
      h('td', { text: length(point.position_error) }),
      point.motor_positions.map((q, j) => h('td', { class: 'number', title: String(q), text: motorValue(q, j) }))))));
  const more = compensated.points.length > rows.length
    ? h('p', { class: 'muted', text: `${rows.length} of ${compensated.points.length} targets shown, flagged first; the file holds them all.` }) : null;
  const last = state.results[name];
  container.replaceChildren(...[
    last && last.stale ? h('div', { class: 'warnings', id: id('stale'), text: 'The calibrated robot used here is stale: the table or the data changed after its identification.' }) : null,
    verdict,
    cards,
    compensated.csv ? h('div', { class: 'actions' },
      h('button', { type: 'button', id: id('download'), text: `Download ${compensated.file_name}`, onclick: () => download(compensated.file_name, compensated.csv, 'text/csv') }),
      compensated.output ? h('span', { class: 'muted', id: id('saved'), text: `Saved in the folder as ${compensated.output}.` }) : null) : null,
    table,
    more,
  ].filter(Boolean));
}

/** One sentence on a base registered by points: its residuals and what it adds. */
function registrationText(registration, unit, length) {
  const worst = registration.points.reduce((a, b) => (b.residual > a.residual ? b : a));
  const by = registration.by === 'circles'
    ? `the circles of joints 1 and 2 (${registration.points.length} points, radii ${registration.radii.map((r) => length(r)).join(' and ')} ${unit}): distance from the circles`
    : `${registration.points.length} points: residual`;
  return `The calibrated robot in the owner’s base, registered by ${by} RMS ${length(registration.rms)} ${unit}, largest ${length(worst.residual)} ${unit} (${worst.name}${worst.name.startsWith('joint') ? `, line ${worst.line}` : ''}); about ${length(registration.at_one_metre)} ${unit} added at 1 m from the base.`;
}

/**
 * The owner's frames (issue 74): a tool point taught by pivoting — the
 * joint values of four or more orientations with the tip on one point, a
 * file of the folder — on the calibrated robot (else the table's), offered
 * as the tool to compensate for; and a user frame from measured points.
 */
function framesForm(name, id, toolField) {
  const pivot = h('input', { type: 'text', id: id('pivot'), placeholder: 'e.g. pivot.csv: qm1…qmn of ≥ 4 orientations' });
  const pivotUnit = h('select', { id: id('pivot-angle-unit') },
    h('option', { value: 'deg', text: 'degrees' }), h('option', { value: 'rad', text: 'radians' }));
  const points = h('input', { type: 'text', id: id('frame-points'), placeholder: 'e.g. fixture.csv: name,x,y,z (origin, x, xy)' });
  const pointsUnit = h('select', { id: id('frame-points-unit') },
    h('option', { value: 'mm', text: 'mm' }), h('option', { value: 'm', text: 'm' }));
  const result = h('div', { class: 'result', id: id('frames-result') });
  const mm = (v) => (v * 1000).toFixed(4);
  const teach = runButton(id('teach'), 'Teach the tool point', async () => {
    try {
      if (!pivot.value.trim()) throw new FieldError('Name the file of the pivot’s joint values.');
      const taught = await api('/tcp', {
        robot: state.calibrated[name] || tableDocument(),
        data: { file: pivot.value.trim() },
        format: { angle_unit: pivotUnit.value },
      });
      const [x, y, z] = taught.tool;
      toolField.value = `${mm(x)}mm,${mm(y)}mm,${mm(z)}mm`;
      result.replaceChildren(
        h('p', { id: id('tool-point'), text: `Tool point in frame n+1: x ${mm(x)}, y ${mm(y)}, z ${mm(z)} mm (σ ${mm(taught.tool_sigma)} mm per axis), from ${taught.orientations} orientations spread over ${(taught.spread * 180 / Math.PI).toFixed(1)}°; residual RMS ${mm(taught.rms)} mm, max ${mm(taught.max)} mm. It is now the tool to compensate for.` }),
        ...taught.warnings.map((text) => h('p', { class: 'warnings', text })));
    } catch (error) {
      result.replaceChildren(errorBox(error));
    }
  });
  const makeFrame = runButton(id('make-frame'), 'Make the user frame', async () => {
    try {
      if (!points.value.trim()) throw new FieldError('Name the file of the frame’s points.');
      const frame = await api('/frame', { points: { file: points.value.trim() }, format: { length_unit: pointsUnit.value } });
      const [x, y, z] = frame.position;
      const [w, qx, qy, qz] = frame.quaternion;
      const sigma = frame.sigma === undefined ? 'three points: exact, no σ' : `σ ${mm(frame.sigma)} mm, origin to ${mm(frame.origin_sigma)} mm`;
      result.replaceChildren(h('p', { id: id('user-frame'), text: `User frame (${frame.way}): origin x ${mm(x)}, y ${mm(y)}, z ${mm(z)} mm; quaternion (w, x, y, z) ${[w, qx, qy, qz].map((v) => v.toFixed(8)).join(', ')}; ${sigma}.` }));
    } catch (error) {
      result.replaceChildren(errorBox(error));
    }
  });
  return h('details', { class: 'frames', id: id('frames') },
    h('summary', { text: 'The owner’s tool point and user frames' }),
    h('div', { class: 'form' },
      field('Pivot: joint values with the tip on one point', pivot),
      field('Their angle unit', pivotUnit),
      teach,
      field('A user frame’s measured points', points),
      field('Their length unit', pointsUnit),
      makeFrame),
    result);
}
