// A parallel robot on the page (issue 79): a Gough–Stewart platform or a
// Delta robot of the folder (or the ready hexapod and delta) — its measurements simulated, its
// identifiable parameters, its identification with every parameter's
// precision and the verdict, and its direct model judged on held-out poses.
import { api } from './api.js';
import { $, download, h } from './dom.js';
import { field, FieldError, errorBox, fieldNumber, numberInput, runButton, staleOnChange } from './fields.js';
import { refreshFiles } from './robot-menu.js';
import { state } from './state.js';
import { quantity, unitName } from './units.js';

/** A text field. */
function text(id, placeholder, value = '') {
  return h('input', { type: 'text', id: `parallel-${id}`, placeholder, value, autocomplete: 'off', spellcheck: 'false' });
}

/** A name a field must hold. */
function required(input, what) {
  const value = input.value.trim();
  if (!value) {
    input.classList.add('invalid');
    input.focus();
    throw new FieldError(`Name ${what}.`);
  }
  input.classList.remove('invalid');
  return value;
}

/** Lengths in the page's unit, angles in its angle unit; of distances for the `distance` method. */
function errorsText(errors, method) {
  const length = (value) => quantity(value, 'length');
  const angles = errors.angle_rms === null || errors.angle_rms === undefined ? ''
    : `; orientation RMS ${quantity(errors.angle_rms, 'angle')}, max ${quantity(errors.angle_max, 'angle')} ${unitName('angle')}`;
  return `${method === 'distance' ? 'distance' : 'position'} RMS ${length(errors.position_rms)}, max ${length(errors.position_max)} ${unitName('length')}${angles}`;
}

/** The instrument's frame registered before the data were used (the base in it). */
function registeredLine(pose) {
  const at = pose.position.map((value) => quantity(value, 'length')).join(', ');
  return h('p', { id: 'parallel-registered', class: 'hint', text: `The data were in another frame than the base: the instrument's frame was registered first (the base at ${at} ${unitName('length')} in it).` });
}

/** The parameters' table: status, nominal, identified, σ. */
function parameterTable(parameters) {
  const shown = (parameter, value) => (value === null || value === undefined ? '–'
    : parameter.name.startsWith('K') ? value.toPrecision(9) : quantity(value, 'length'));
  return h('table', { class: 'iso-table', id: 'parallel-parameters' },
    h('thead', {}, h('tr', {}, ['parameter', `nominal (${unitName('length')})`, 'identified', 'σ', 'status']
      .map((title) => h('th', { text: title })))),
    h('tbody', {}, parameters.map((parameter) => h('tr', {}, [
      parameter.name, shown(parameter, parameter.nominal), shown(parameter, parameter.identified),
      shown(parameter, parameter.sigma), parameter.status,
    ].map((cell) => h('td', { text: cell }))))));
}

/**
 * The σ field's text, which must carry its unit (`20um`, `0.02mm`): a bare
 * number beside the data's unit menu is refused, not read in metres.
 */
function sigmaWithUnit(input) {
  const text = input.value.trim();
  input.classList.remove('invalid');
  if (text === '') return null;
  if (/^[-+0-9.,eE]+$/.test(text)) {
    input.classList.add('invalid');
    input.focus();
    throw new FieldError(`Sensor σ: ${text} has no unit; give it with one, as 20um or 0.02mm.`);
  }
  return text;
}

/** Builds the parallel robot's card. */
export function buildParallel() {
  const result = h('div', { class: 'result', id: 'parallel-result' });
  const robot = text('robot', 'hexapod, delta, or a parallel robot file of the folder', 'hexapod');
  const method = h('select', { id: 'parallel-method' },
    [['frame', 'frame: the platform’s pose'], ['position', 'position: its tool point'], ['distance', 'distance: between two tool points'], ['leg', 'leg: a measuring leg’s readings (no instrument)']]
      .map(([value, label]) => h('option', { value, text: label })));
  const data = text('data', 'poses.csv (qm1…qm6, x, y, z[, qw, qx, qy, qz])');
  const legBase = text('leg-base', 'for leg: its base socket, 250mm,-100mm,0');
  const legPlatform = text('leg-platform', 'for leg: its platform socket, -120mm,80mm,0');
  // A measuring leg's sockets, for the leg method only.
  const leg = () => (method.value === 'leg'
    ? { leg_base: required(legBase, 'the measuring leg’s base socket'), leg_platform: required(legPlatform, 'the measuring leg’s platform socket') }
    : {});
  const stations = text('stations', 'station2.csv, station3.csv (optional: the same measure from other tracker stations)');
  const dataUnit = h('select', { id: 'parallel-data-unit' }, [['m', 'm'], ['mm', 'mm']].map(([value, label]) => h('option', { value, text: label })));
  const sigma = text('sigma', '20um, 0.02mm');
  const saveAs = text('save', 'calibrated.toml (optional)');
  const workRegion = text('work-region', 'qm1=-10..10mm,qm4=-5..5mm (optional: the actuators’ ranges)');
  const reject = h('input', { type: 'checkbox', id: 'parallel-reject' });
  const prior = text('prior', '1mm,0.05deg,0.1% (optional: σ of lengths, angles, gains)');
  const criterion = h('select', { id: 'parallel-criterion' },
    [['d', 'D-optimal (the parameters’ confidence volume)'], ['test', 'the predicted error over the workspace'], ['a', 'A-optimal'], ['e', 'E-optimal'], ['o4', 'O4'], ['o5', 'O5']].map(([value, label]) => h('option', { value, text: label })));
  const loss = h('select', { id: 'parallel-loss' },
    [['l2', 'least squares'], ['huber', 'Huber (mild contamination)'], ['cauchy', 'Cauchy (gross errors)'], ['tukey', 'Tukey (gross errors ignored)']]
      .map(([value, label]) => h('option', { value, text: label })));
  const count = numberInput({ id: 'parallel-count', value: String(state.info.defaults.parallel_poses) });
  const noise = numberInput({ id: 'parallel-noise', value: '0.02' });
  const generated = text('generated', 'poses.csv', 'parallel-poses.csv');
  const real = text('real', 'real platform: real.toml (optional)', 'parallel-real.toml');
  const common = () => ({ robot: required(robot, 'the parallel robot (hexapod, or a file)'), method: method.value });
  const format = () => ({ length_unit: dataUnit.value });

  const generate = runButton('parallel-generate', 'Simulate measurements', async () => {
    try {
      const answer = await api('/parallel/generate', {
        ...common(),
        count: fieldNumber(count, 'Poses', { min: 1, max: state.info.limits.generate, whole: true }),
        noise: fieldNumber(noise, 'Sensor noise σ', { min: 0, empty: 0 }) * 1e-3,
        seed: state.info.defaults.seed,
        save_as: required(generated, 'the data file to write'),
        real_save_as: real.value.trim() || null,
        ...leg(),
        overwrite: true,
      });
      await refreshFiles();
      data.value = generated.value.trim();
      result.replaceChildren(h('p', { id: 'parallel-written', text: `${answer.configurations} poses of a simulated real platform written to ${answer.written.join(' and ')} (metres).` }));
      dataUnit.value = 'm';
    } catch (error) {
      result.replaceChildren(errorBox(error));
    }
  });
  const plan = runButton('parallel-plan', 'Plan the poses', async () => {
    try {
      const answer = await api('/parallel/plan', {
        ...common(),
        count: fieldNumber(count, 'Poses', { min: 1, max: state.info.limits.generate, whole: true }),
        seed: state.info.defaults.seed,
        criterion: criterion.value,
        save_as: 'parallel-planned.csv',
        overwrite: true,
      });
      await refreshFiles();
      const aim = answer.criterion_name === 'test' ? 'for the predicted error over the workspace' : `${answer.criterion_name.toUpperCase()}-optimal`;
      result.replaceChildren(h('p', { id: 'parallel-planned', text: `${answer.count} poses of ${answer.pool} candidates chosen for the ${answer.rank} identifiable parameters (${aim}: ${answer.criterion_meaning} ${answer.criterion.toPrecision(4)}, random poses ${answer.random_criterion.toPrecision(4)}); their actuator values written to parallel-planned.csv.` }));
    } catch (error) {
      result.replaceChildren(errorBox(error));
    }
  });
  const predict = runButton('parallel-predict', 'Predict the precision', async () => {
    try {
      const answer = await api('/parallel/predict', {
        ...common(),
        data: { file: required(data, 'the configurations to be measured (a plan)') },
        format: format(),
        sigma: required(sigma, 'the sensor σ') && sigmaWithUnit(sigma),
        work_region: workRegion.value.trim() || null,
      });
      const region = answer.region;
      const what = region.error;
      const length = (value) => `${quantity(value, 'length')} ${unitName('length')}`;
      result.replaceChildren(
        h('p', { id: 'parallel-prediction', class: region.holds_everywhere ? '' : 'warnings', text: `${answer.robot} — ${answer.method} method at the ${answer.configurations} configurations of ${answer.data}: ${answer.rank} parameters identifiable; predicted ${what} ${length(region.predicted_inside)} RMS there, ${length(region.predicted_work)} over ${region.work_name} (a held-out measurement's noise ${length(region.noise_floor)})${region.holds_everywhere ? '' : ': these configurations calibrate the platform where they are only'}.` }));
    } catch (error) {
      result.replaceChildren(errorBox(error));
    }
  });
  const identifiable = runButton('parallel-identifiable', 'Identifiable parameters', async () => {
    try {
      const report = await api('/parallel/identifiable', {
        ...common(),
        data: data.value.trim() ? { file: data.value.trim() } : null,
        format: format(),
      });
      result.replaceChildren(
        h('p', { id: 'parallel-rank', text: `${report.rank} of ${report.parameters.length} parameters identifiable (${report.method} method, ${report.equations} equations from ${report.source}); condition number ${report.condition_number.toPrecision(4)}.` }),
        ...report.regrouped.map((relation) => h('p', { class: 'hint', text: `${relation.parameter} is regrouped into ${relation.into.map(([name, coefficient]) => `${coefficient.toPrecision(4)} ${name}`).join(', ')}.` })));
    } catch (error) {
      result.replaceChildren(errorBox(error));
    }
  });
  const identify = runButton('parallel-identify', 'Identify', async () => {
    try {
      const answer = await api('/parallel/identify', {
        ...common(),
        data: { file: required(data, 'the measurements file') },
        stations: stations.value.split(',').map((file) => file.trim()).filter((file) => file !== '').map((file) => ({ file })),
        ...leg(),
        format: format(),
        sigma: sigmaWithUnit(sigma),
        work_region: workRegion.value.trim() || null,
        loss: loss.value,
        reject: reject.checked,
        prior: prior.value.trim() || null,
        save_as: saveAs.value.trim() || null,
        overwrite: true,
      });
      if (answer.written) await refreshFiles();
      result.replaceChildren(
        h('p', { id: 'parallel-verdict', class: answer.trusted ? '' : 'warnings', text: `${answer.robot} — ${answer.method} method on ${answer.data} (${answer.configurations} poses): ${answer.summary}.` }),
        h('p', { id: 'parallel-errors', text: `At the measured poses: nominal ${errorsText(answer.errors_before, answer.method)}; calibrated ${errorsText(answer.errors_after, answer.method)}.${answer.written ? ` The calibrated platform was written to ${answer.written}.` : ''}` }),
        ...(answer.region ? [h('p', { id: 'parallel-region', class: answer.region.holds_everywhere ? '' : 'warnings', text: `Predicted ${answer.region.error}: ${quantity(answer.region.predicted_inside, 'length')} ${unitName('length')} RMS at the measured poses, ${quantity(answer.region.predicted_work, 'length')} ${unitName('length')} over ${answer.region.work_name} (noise floor ${quantity(answer.region.noise_floor, 'length')} ${unitName('length')})${answer.region.holds_everywhere ? '' : ': the result holds only where the data were taken'}.` })] : []),
        ...answer.warnings.map((warning) => h('p', { class: 'warnings', text: `Warning: ${warning}.` })),
        ...(answer.registered ? [registeredLine(answer.registered)] : []),
        ...answer.stations.map((station) => h('p', { class: 'parallel-station hint', text: `${station.data} was measured from another station, identified with the platform: the base at ${station.frame.position.map((value) => quantity(value, 'length')).join(', ')} ${unitName('length')} in it.` })),
        h('button', { type: 'button', id: 'parallel-report', text: 'Download the report (HTML)', onclick: () => download(`${answer.robot}-report.html`, answer.report, 'text/html') }),
        h('button', { type: 'button', id: 'parallel-residuals', text: 'Download the residuals (CSV)', onclick: () => download(`${answer.robot}-residuals.csv`, answer.residuals, 'text/csv') }),
        parameterTable(answer.parameters));
    } catch (error) {
      result.replaceChildren(errorBox(error));
    }
  });
  const evaluate = runButton('parallel-evaluate', 'Evaluate', async () => {
    try {
      const answer = await api('/parallel/evaluate', {
        ...common(),
        data: { file: required(data, 'the held-out measurements file') },
        format: format(),
      });
      result.replaceChildren(...(answer.registered ? [registeredLine(answer.registered)] : []), h('p', { id: 'parallel-evaluation', text: `${answer.robot} on ${answer.data} (${answer.configurations} poses): its direct model against the measured, ${errorsText(answer.errors, answer.method)}.` }));
    } catch (error) {
      result.replaceChildren(errorBox(error));
    }
  });
  const program = text('program', 'job.csv (x, y, z, qw, qx, qy, qz)');
  const matching = h('select', { id: 'parallel-match' },
    [['pose', 'platform poses'], ['position', 'tool points (x, y, z; calibrated from one point)']].map(([value, label]) => h('option', { value, text: label })));
  const corrected = text('corrected', 'job-compensated.csv', 'job-compensated.csv');
  const compensate = runButton('parallel-compensate', 'Compensate the program', async () => {
    try {
      const answer = await api('/parallel/compensate', {
        nominal: required(robot, 'the nominal parallel robot'),
        calibrated: required(saveAs, 'the calibrated platform (saved above)'),
        program: { file: required(program, 'the program of targets') },
        format: format(),
        match: matching.value,
        save_as: required(corrected, 'the compensated program to write'),
        overwrite: true,
      });
      await refreshFiles();
      const lines = (flagged) => flagged.map(([line]) => line).join(', ');
      const flagged = (answer.outside_range.length
        ? ` ${answer.outside_range.length} targets need an actuator beyond its range (lines ${lines(answer.outside_range)}).` : '')
        + (answer.outside_measured.length
          ? ` ${answer.outside_measured.length} targets are outside the actuator values the calibration measured, where it holds (lines ${lines(answer.outside_measured)}).` : '');
      result.replaceChildren(h('p', { id: 'parallel-compensated', class: flagged ? 'warnings' : '', text: `${answer.targets} targets (${answer.matched === 'position' ? 'tool points' : 'platform poses'}): the calibrated platform’s actuator values (the largest change from the nominal one ${quantity(answer.largest_correction, 'length')} ${unitName('length')}) written to ${answer.written}.${flagged}` }),
        ...(answer.note ? [h('p', { id: 'parallel-compensation-note', class: 'hint', text: `Note: ${answer.note}.` })] : []));
    } catch (error) {
      result.replaceChildren(errorBox(error));
    }
  });
  staleOnChange($('parallel'), result, 'parallel-stale', 'The settings changed since this result: run it again to see theirs.');
  $('parallel').replaceChildren(
    h('div', { class: 'form' },
      field('Parallel robot', robot),
      field('Measured', method),
      field('Measurements', data),
      field('From other tracker stations', stations),
      field('Measuring leg’s base socket', legBase),
      field('Measuring leg’s platform socket', legPlatform),
      field('Their length unit', dataUnit),
      field('Sensor σ (with its unit)', sigma),
      field('Save the calibrated platform as', saveAs),
      field('Work region (actuator ranges with units)', workRegion),
      field('Loss', loss),
      field('Drop outliers and refit', reject),
      field('Prior about the nominal values', prior),
      identifiable, predict, identify, evaluate),
    h('div', { class: 'form' },
      field('Simulated poses', count),
      field('Sensor noise σ (mm; mrad)', noise),
      field('Write them to', generated),
      field('Write the real platform to', real),
      field('Plan the poses for', criterion),
      plan,
      generate),
    h('div', { class: 'form' },
      field('Program of targets', program),
      field('Its targets are', matching),
      field('Write the compensated program to', corrected),
      compensate),
    h('p', { class: 'hint', text: 'A Gough–Stewart platform: leg i from its base joint aᵢ to its platform joint bᵢ, length ℓᵢ = ‖p + R·bᵢ − aᵢ‖ = lᵢ + Kᵢ·qmᵢ; measured poses identify every leg’s aᵢ, bᵢ, lᵢ, Kᵢ (48 parameters) through the inverse model, one measured point the tool point and all but six platform-joint coordinates. A Delta robot (three arms, the plate only translates) is measured by its tool point: 24 of its 36 parameters (docs/parallel.md).' }),
    result);
}
