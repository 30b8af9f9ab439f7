// The Identification function: iterated linearised least squares (eq. 10)
// as a server job, its verdict, errors, plots and parameters with σ.
import { api } from '../api.js';
import { dataSelect, dataRequest, refreshDataChoices } from '../data-choices.js';
import { deviationTable, showOnView } from '../deviations.js';
import { h, $ } from '../dom.js';
import { emit } from '../events.js';
import { field, fieldNumber, sigmaText, degreesText, foldsOf, errorBox, runButton, observabilityLine, stat, FieldError, numberInput } from '../fields.js';
import { fmt, fixed, inFrameOrder, sci } from '../format.js';
import { recordRun } from '../history.js';
import { followJob } from '../jobs.js';
import { optionFields, methodRequest, formatFields, formatRequest } from '../method-options.js';
import { calibratedActions, correlationHeatmap, plotFigure, registrationBlock } from '../results.js';
import { refreshFiles } from '../robot-menu.js';
import { identificationBasis, refreshStale } from '../stale.js';
import { methodInfo, state, tableDocument, persist } from '../state.js';
import { unitOf, inUnits, inPageUnits, quantity, unitName, unitsLabel } from '../units.js';

export function identifyPanel(method) {
  const name = method.name;
  const result = h('div', { class: 'result', id: `${name}-identify-result` });
  const data = dataSelect(name, 'identify', false);
  const upload = h('input', { type: 'file', accept: '.csv,text/csv', id: `${name}-identify-upload`, hidden: true });
  data.addEventListener('change', () => { upload.hidden = data.value !== 'upload'; refreshStale(); persist(); });
  const solver = h('select', { id: `${name}-identify-solver` },
    h('option', { value: 'gauss-newton', text: 'Gauss–Newton (the paper)' }),
    h('option', { value: 'lm', text: 'Levenberg–Marquardt' }));
  const iterations = numberInput({ value: state.info.defaults.max_iterations, id: `${name}-identify-iterations` });
  const loss = h('select', { id: `${name}-identify-loss` },
    h('option', { value: 'l2', text: 'least squares (the paper)' }),
    h('option', { value: 'huber', text: 'Huber (mild contamination)' }),
    h('option', { value: 'cauchy', text: 'Cauchy (gross errors)' }),
    h('option', { value: 'tukey', text: 'Tukey (gross errors ignored)' }));
  const prior = h('input', { type: 'text', class: 'vector', placeholder: 'none, or e.g. 5mm,0.5deg,1%', id: `${name}-identify-prior` });
  const model = h('select', { id: `${name}-identify-model` },
    h('option', { value: 'full', text: 'geometric (the priority matrix)' }),
    h('option', { value: 'no-gains', text: 'geometric without the gains K' }),
    h('option', { value: 'kinematic', text: 'geometric without the gains K and the Hayati β' }),
    h('option', { value: 'offsets', text: 'the joint offsets only' }),
    h('option', { value: 'elastic', text: 'elastic: and every joint’s compliance' }),
    h('option', { value: 'elastic-gravity', text: 'elastic, and gravity’s tilt (a frame not levelled)' }));
  const reject = h('input', { type: 'checkbox', id: `${name}-identify-reject` });
  // The neighbouring models, by region folds: by default when the data are small.
  const checkModel = h('select', { id: `${name}-identify-check-model` },
    h('option', { value: 'auto', text: 'when the data are small (a few hundred measurements)' }),
    h('option', { value: 'always', text: 'always' }),
    h('option', { value: 'never', text: 'never' }));
  // Where the robot will be used: the verdict predicts its error there.
  const workRegion = h('input', { type: 'text', class: 'vector', placeholder: 'the joint limits, or e.g. q1=-90..90deg,q2=-45..45deg', id: `${name}-identify-work-region` });
  const sigma = numberInput({ placeholder: 'not stated', id: `${name}-identify-sigma` });
  // Frames carry their own σ for rotations (a tracker's 6D probe: 0.01 mm, 0.005°).
  const sigmaRotation = numberInput({ placeholder: 'not stated', id: `${name}-identify-sigma-rotation` });
  const folds = numberInput({ value: 0, id: `${name}-identify-cv` });
  const run = runButton(`${name}-identify-run`, 'Identify', async () => {
    result.replaceChildren(h('div', { class: 'progress' }, h('div', { class: 'spinner' }), h('span', { text: 'Reading the data…' })));
    // What this result is of: the table, the data chosen and the settings now.
    const basis = identificationBasis(name);
    try {
      const submitted = await api('/identify', {
        robot: tableDocument(),
        method: methodRequest(name, 'identify'),
        data: await dataRequest(name, 'identify'),
        format: formatRequest(name, 'identify'),
        solver: solver.value,
        max_iterations: fieldNumber(iterations, 'Iteration limit', { min: 1, max: state.info.limits.iterations, whole: true, empty: state.info.defaults.max_iterations }),
        loss: loss.value,
        model: model.value,
        prior: prior.value.trim() || null,
        reject: reject.checked,
        work_region: workRegion.value.trim() || null,
        check_model: { always: true, never: false }[checkModel.value] ?? null,
        // With its unit: a bare number would be in the data file's length unit.
        sigma: sigmaText(fieldNumber(sigma, 'Sensor σ', { min: 0, above: true, empty: null })),
        sigma_rotation: method.uses_orientation
          ? degreesText(fieldNumber(sigmaRotation, 'Sensor σ of rotations', { min: 0, above: true, empty: null }))
          : null,
        cv: foldsOf(folds),
      });
      await followIdentification(name, submitted.job, basis);
    } catch (error) {
      result.replaceChildren(errorBox(error));
    }
  });
  const panel = h('div', { class: 'panel', id: `${name}-identify` },
    h('div', { class: 'form' },
      field('Data', data),
      upload,
      field('Step rule', solver),
      field('Iteration limit', iterations),
      field('Sensor σ (mm; the verdict tests the fit against it)', sigma),
      method.uses_orientation ? field('Sensor σ of rotations (°)', sigmaRotation) : null,
      field('Loss', loss),
      field('Model', model),
      field('Prior σ (lengths, angles, gains)', prior),
      field('Drop outliers and refit', reject),
      field('Work region (joint ranges with units)', workRegion),
      field('Compare with the next smaller and larger models (region folds)', checkModel),
      field('Cross-validation folds (0: none)', folds),
      optionFields(method, 'identify'),
      run),
    formatFields(name, 'identify'),
    joinForm(name),
    h('p', { class: 'hint', text: 'Iterated linearised least squares (eq. 10): W is rebuilt at every iterate; σ of each parameter from eq. 11. A robust loss discounts gross errors; a prior keeps poorly excited parameters near nominal; cross-validation judges the fit on held-out configurations.' }),
    result);
  // A setting changed after an identification makes its result stale (stale.js).
  for (const kind of ['change', 'input']) {
    panel.addEventListener(kind, (event) => {
      if (event.target.closest('.join') || event.target.closest('.result')) return;
      refreshStale();
      persist();
    });
  }
  return panel;
}

/**
 * Follows identification job `job` of method `name` (made of `basis`) to
 * its end and shows its result; a reload during it follows it again
 * (`resume`), the page's form put back as it was.
 */
export async function followIdentification(name, job, basis) {
  const result = $(`${name}-identify-result`);
  const cancel = h('button', { type: 'button', id: `${name}-identify-cancel`, text: 'Cancel', disabled: true });
  const progress = h('div', { class: 'progress', id: `${name}-identify-progress` }, h('div', { class: 'spinner' }), h('span', { text: 'Identifying…' }), cancel);
  result.replaceChildren(progress);
  try {
    const ended = await followJob(job, progress.children[1], { cancel, resume: { kind: 'identify', name, basis } });
    if (ended.state === 'cancelled') {
      result.replaceChildren(h('div', { class: 'warnings', id: `${name}-identify-cancelled`, text: 'Cancelled: the server stopped the identification. Nothing was changed.' }));
    } else if (ended.state === 'failed') {
      result.replaceChildren(errorBox(new Error(ended.error)));
    } else {
      state.results[name] = { job, result: ended.result, basis };
      renderIdentification(result, name, job, ended.result);
      recordRun({ what: `${methodInfo(name).title}`, robot: tableDocument().name || 'unnamed', data: dataWords(basis), settings: settingsWords(basis), result: ended.result });
      // The verdict first, without scrolling for it.
      result.scrollIntoView({ block: 'start' });
      refreshStale();
      persist();
    }
  } catch (error) {
    result.replaceChildren(errorBox(error));
  }
}

/** The data an identification ran on, in words (its menu's choice). */
function dataWords(basis) {
  const data = String((basis && basis.data) || '').split('#')[0];
  return data.startsWith('file:') ? data.slice(5) : data === 'generated' ? 'generated here' : data === 'upload' ? 'an upload' : data || '–';
}

/** The settings that decide an identification, in words: model, loss, σ. */
function settingsWords(basis) {
  const settings = (basis && basis.settings) || {};
  const value = (suffix) => {
    const entry = Object.entries(settings).find(([id]) => id.endsWith(`-identify-${suffix}`));
    return entry ? entry[1].value : '';
  };
  return [`model ${value('model') || 'full'}`, `loss ${value('loss') || 'l2'}`, `σ ${value('sigma') ? `${value('sigma')} mm` : 'not stated'}`].join(', ');
}

export function renderIdentification(container, name, job, result) {
  const id = result.identification;
  state.calibrated[name] = result.calibrated;
  const mm = (v) => fixed(v * 1e3, v * 1e3 < 0.1 ? 4 : 3);
  const unit = unitName('length');
  const verdict = id.verdict;
  const outcomes = {
    fits_noise: 'Fits the noise', untested: 'Converged (σ not stated)', incomplete: 'Incomplete (not all measured)',
    below_noise: 'Far below the stated noise', exceeds_noise: 'Exceeds the noise', implausible: 'Implausible values',
    regional: 'Holds in the measured region only', changed: 'The cell changed during the measurement',
    underdetermined: 'Data do not determine it', repeated: 'Repeated data', degenerate: 'Degenerate data', not_converged: 'Not converged', diverged: 'Diverged',
  };
  // A long verdict (implausible values, a region) reads as its first
  // sentence and a list of the rest, not one paragraph.
  const sentences = verdict.summary.split(/(?<=[.;])\s+(?=[A-Z])/);
  const headline = h('div', { class: `verdict ${verdict.trusted ? 'ok' : 'bad'}`, id: `${name}-identify-verdict` },
    h('p', {}, h('strong', { text: 'Verdict: ' }), document.createTextNode(`${sentences[0].replace(/\.$/, '')}.`)),
    sentences.length > 1 ? h('ul', {}, sentences.slice(1).map((sentence) => h('li', { text: sentence }))) : null);
  const cards = h('div', { class: 'cards' },
    stat(`after ${id.iterations} iterations (${id.route.replace(/_/g, ' ')})`, outcomes[verdict.outcome] || verdict.outcome, { id: `${name}-identify-status`, class: verdict.trusted ? 'ok' : 'bad' }),
    stat(`error RMS before (${unit})`, quantity(id.before.rms, 'length'), { id: `${name}-identify-rms-before` }),
    stat(`error RMS after (${unit})`, quantity(id.after.rms, 'length'), { id: `${name}-identify-rms-after` }),
    stat(`largest error after (${unit}; before ${quantity(id.before.max, 'length')})`, quantity(id.after.max, 'length')),
    id.after_inliers ? stat(`RMS after, without the ${id.outlier_count} outliers (${unit}; largest ${quantity(id.after_inliers.max, 'length')})`, quantity(id.after_inliers.rms, 'length'), { id: `${name}-identify-inliers` }) : null,
    id.before.rms_rotation !== undefined
      ? stat(`orientation RMS after (${unitName('angle')}; before ${quantity(id.before.rms_rotation, 'angle')})`, quantity(id.after.rms_rotation, 'angle')) : null,
    stat('identified parameters', String(id.parameters.length + id.auxiliary.length)),
    stat('condition number of W_b', fmt(Number(id.condition_number.toPrecision(4)))),
    verdict.residual_length !== null && verdict.residual_length !== undefined
      ? stat(`residual σ (${unit})`, quantity(verdict.residual_length, 'length'), { id: `${name}-identify-residual` }) : null,
    verdict.residual_angle !== null && verdict.residual_angle !== undefined
      ? stat(`residual σ (${unitName('angle')})`, quantity(verdict.residual_angle, 'angle')) : null,
    verdict.region
      ? stat(`predicted error in the ${verdict.region.work_is_limits ? 'joint limits' : 'work region'} (${unit}; in the measured region ${quantity(verdict.region.predicted_inside, 'length')})`,
        quantity(verdict.region.predicted_work, 'length'),
        { id: `${name}-identify-region`, class: verdict.region.holds_everywhere ? 'ok' : 'bad' }) : null);
  const advice = (result.identification.model_advice || []).map((a) => {
    const ratios = a.sigma_ratio !== null && a.instead_ratio !== null
      ? `σ̂/σ ${fixed(a.sigma_ratio, 2)} against ${fixed(a.instead_ratio, 2)}; ` : '';
    return `The ${a.model} model predicts better than the ${a.instead_of} one (${ratios}held out by region, the ends of each joint’s range: ${mm(a.held_out)} mm against ${mm(a.instead_held_out)} mm): choose Model “${a.model}”.`;
  });
  const notes = [...id.warnings, ...advice];
  const warnings = notes.length
    ? h('div', { class: 'warnings', id: `${name}-identify-warnings` }, h('strong', { text: 'Warnings' }), h('ul', {}, notes.map((w) => h('li', { text: w })))) : null;
  const plots = h('div', { class: 'plots' },
    plotFigure('Residual RMS per iteration', result.plots.convergence, `${name}-identify-convergence`),
    plotFigure(id.outlier_count ? `Errors before and after (mm; after: the inliers, without the ${id.outlier_count} outliers)` : 'Errors before and after (mm)', result.plots.errors_histogram, `${name}-identify-histogram`),
    plotFigure('Error of every configuration (mm; hover a dot for its file and line)', result.plots.errors_per_configuration, `${name}-identify-per-configuration`));
  // Values in the page's units; a deviation beyond 3σ is marked, a
  // regrouped parameter is a combination, not the physical value.
  // The robot's parameters in frame order (α, d, θ, r, β, K within a
  // frame), then the auxiliary unknowns as identified; one mark per row: a
  // regrouped parameter's deviation stands for a combination, so it is not
  // marked significant as well.
  const rows = inFrameOrder(id.parameters).concat(id.auxiliary).map((p) => {
    const kind = unitOf(p.name);
    const shown = (v) => (kind === 'none' ? fmt(Number(v.toPrecision(6))) : inPageUnits(v, kind, 6));
    const small = (v) => (kind === 'none' ? fmt(Number(v.toPrecision(4))) : quantity(v, kind));
    const deviation = p.identified - p.nominal;
    const significant = !p.combination && Number.isFinite(p.std) && Math.abs(deviation) > 3 * p.std;
    const classes = p.combination ? 'regrouped' : significant ? 'significant' : '';
    const title = p.combination ? `regrouped: the deviation stands for ${p.combination}, not for ${p.name} alone`
      : significant ? 'the deviation is beyond 3σ: the data moved this parameter' : '';
    return h('tr', classes ? { class: classes, title } : {},
      h('td', { text: p.combination ? `${p.name} (regrouped)` : p.name }),
      h('td', { class: 'number', title: String(p.nominal), text: shown(p.nominal) }),
      h('td', { class: 'number', title: String(p.identified), text: shown(p.identified) }),
      h('td', { class: 'number deviation', title: String(deviation), text: small(deviation) }),
      h('td', { class: 'number', title: String(p.std), text: small(p.std) }),
      id.prior ? h('td', { class: 'number', text: small(p.prior_std) }) : null);
  });
  const table = h('table', { class: 'values', id: `${name}-identify-parameters` },
    h('thead', {}, h('tr', {}, ['parameter', 'nominal', 'identified', 'deviation', 'σ'].concat(id.prior ? ['prior σ'] : []).map((t) => h('th', { text: t })))),
    h('tbody', {}, rows));
  const outlierTable = (title, list, count, tableId) => list.length ? h('div', {},
    h('h3', { text: `${title} (${count} beyond ${id.outlier_threshold} robust σ̂${count > list.length ? `; the worst ${list.length} listed` : ''})` }),
    h('table', { class: 'values', id: tableId },
      h('thead', {}, h('tr', {}, ['observation', 'lines', 'error (mm)', 'residual (σ̂)', 'weight'].map((t) => h('th', { text: t })))),
      h('tbody', {}, list.map((o) => h('tr', {},
        h('td', { text: `${o.file}: ${o.kind} ${o.observation}` }), h('td', { text: o.lines.join(', ') }),
        h('td', { text: fixed(o.error * 1e3, 3) }), h('td', { text: fixed(o.residual_sigmas, 1) }), h('td', { text: fixed(o.weight, 3) })))))) : null;
  const robustness = h('p', { class: 'muted', id: `${name}-identify-robustness`, text:
    `Loss ${id.loss.kind}${id.loss.scale ? ` (k = ${id.loss.scale} σ̂, ${id.reweightings} reweightings)` : ''}; robust σ̂ ${verdict.noise_test ? `${fixed(id.robust_sigma, 2)} × the stated σ` : `${sci(inUnits(id.robust_sigma, 'length'))} ${unitName('length')} (length rows)`}; `
    + (id.outlier_count ? `${id.outlier_count} outliers (ringed on the per-configuration plot)` : 'no outliers')
    + (id.prior ? `; prior ${fixed(id.prior.length * 1e3, 3)} mm, ${fixed(id.prior.angle * 180 / Math.PI, 3)}°, ${fixed(id.prior.gain * 100, 2)} %` : '') });
  const cv = id.cross_validation;
  const validation = cv ? h('p', { id: `${name}-identify-cv-result`, text:
    `Cross-validation, ${cv.folds} folds: held-out RMS ${mm(cv.rms)} mm${cv.rms_rotation !== null ? `, ${fixed(cv.rms_rotation * 180 / Math.PI, 4)}°` : ''} (per fold: ${cv.per_fold.map((f) => mm(f.rms)).join(', ')} mm)` }) : null;
  const moved = id.moved.length
    ? h('p', { class: 'muted', text: `Outside the base set, moved: ${id.moved.map((p) => `${p.name} ${(p.identified - p.nominal).toExponential(2)}`).join(', ')}` }) : null;
  const actions = calibratedActions(result, verdict.trusted, job, `${name}-identify`, (file) => {
    state.exported[name] = { text: `saved as ${file}`, status: 'done' };
    persist();
  });
  container.replaceChildren(...[headline, cards, observabilityLine(id.observability, 'the data'), robustness, validation, warnings, actions,
    registrationBlock(id.registration, `${name}-identify-registration`),
    outlierTable('Rejected before this fit', id.rejected, id.rejected_count, `${name}-identify-rejected`),
    outlierTable('Outliers', id.outliers, id.outlier_count, `${name}-identify-outliers`),
    plots, deviationTable(result.deviations, `${name}-identify`),
    correlationHeatmap(result.correlation, `${name}-identify`),
    h('h3', { id: `${name}-identify-parameters-title`, text: `Identified parameters (${unitsLabel()}; gains without unit; beyond 3σ in bold, regrouped in italics)` }), table, moved].filter(Boolean));
  showOnView(`the ${name} identification`, result.deviations, null);
  // The calibrated robot is drawn beside the table's (view.js).
  emit('overlay');
}

/**
 * An instrument's export joined with a controller's log (issue 74), files
 * of the folder as they are written: by a key column of both, or by row
 * order; the joined data file is saved in the folder and offered as data.
 */
function joinForm(name) {
  const id = (what) => `${name}-join-${what}`;
  const text = (what, placeholder) => h('input', { type: 'text', id: id(what), placeholder });
  const tracker = text('tracker', 'e.g. export.csv: x, y, z per measured point');
  const log = text('log', 'e.g. log.csv: qm1…qmn per configuration');
  const key = text('key', 'e.g. Point (empty: by row order)');
  const logKey = text('log-key', 'when the log names it otherwise');
  const trackerColumns = text('tracker-columns', 'e.g. x=X,y=Y,z=Z');
  const logColumns = text('log-columns', 'e.g. qm1=A1,qm2=A2,…');
  const lengthUnit = h('select', { id: id('length-unit') },
    h('option', { value: 'mm', text: 'mm' }), h('option', { value: 'm', text: 'm' }));
  const angleUnit = h('select', { id: id('angle-unit') },
    h('option', { value: 'deg', text: 'degrees' }), h('option', { value: 'rad', text: 'radians' }));
  // A prismatic joint's values in the log.
  const logLengthUnit = h('select', { id: id('log-length-unit') },
    h('option', { value: 'mm', text: 'mm' }), h('option', { value: 'm', text: 'm' }));
  // A 6-D probe's orientations: quaternions, or rx, ry, rz in a form and unit.
  const rotation = h('select', { id: id('rotation') },
    [['quaternion', 'quaternions qw, qx, qy, qz (or none)'], ['rpy', 'rx, ry, rz: roll, pitch, yaw'], ['euler-xyz', 'rx, ry, rz: Euler x, y′, z″'],
      ['euler-zyz', 'rx, ry, rz: Euler z, y′, z″'], ['rotation-vector', 'rx, ry, rz: rotation vector']].map(([value, words]) => h('option', { value, text: words })));
  const rotationUnit = h('select', { id: id('rotation-unit') },
    h('option', { value: 'deg', text: 'degrees' }), h('option', { value: 'rad', text: 'radians' }));
  const saveAs = text('save-as', 'e.g. joined.csv');
  const result = h('div', { class: 'result', id: id('result') });
  const run = runButton(id('run'), 'Join', async () => {
    try {
      for (const [input, what] of [[tracker, 'the instrument’s export'], [log, 'the controller’s log'], [saveAs, 'the joined file']]) {
        if (!input.value.trim()) throw new FieldError(`Name ${what}.`);
      }
      const joined = await api('/join', {
        robot: tableDocument(),
        tracker: { file: tracker.value.trim() },
        log: { file: log.value.trim() },
        key: key.value.trim() || null,
        log_key: logKey.value.trim() || null,
        tracker_format: {
          length_unit: lengthUnit.value,
          columns: trackerColumns.value.trim() || null,
          rotation: rotation.value,
          angle_unit: rotation.value === 'quaternion' ? null : rotationUnit.value,
        },
        log_format: { angle_unit: angleUnit.value, length_unit: logLengthUnit.value, columns: logColumns.value.trim() || null },
        save_as: saveAs.value.trim(),
      });
      const left = joined.unmeasured_note ? ` ${joined.unmeasured_note}.` : '';
      const check = joined.distance_rms === null || joined.distance_rms === undefined ? ''
        : ` The distances between consecutive points match the table’s robot to ${(joined.distance_rms * 1000).toFixed(3)} mm RMS, and no shift of rows matches them better.`;
      result.replaceChildren(h('p', { id: id('summary'), text: `Saved ${joined.output}: ${joined.rows} configurations with their measured ${joined.orientations ? 'poses' : 'points'}.${left}${check}` }));
      await refreshFiles();
      refreshDataChoices(name, joined.output);
    } catch (error) {
      result.replaceChildren(errorBox(error));
    }
  });
  return h('details', { class: 'join', id: id('form') },
    h('summary', { text: 'Join an instrument’s export with the controller’s log' }),
    h('div', { class: 'form' },
      field('Instrument’s export', tracker),
      field('Its length unit', lengthUnit),
      field('Its columns, renamed', trackerColumns),
      field('Its orientations', rotation),
      field('Their angles in', rotationUnit),
      field('Controller’s log', log),
      field('Its angle unit', angleUnit),
      field('Its prismatic joints in', logLengthUnit),
      field('Its columns, renamed', logColumns),
      field('Key column (both files)', key),
      field('The log’s key column', logKey),
      field('Save the joined data as', saveAs),
      run),
    result);
}
