// The Evaluate function: the table's robot, and the calibrated one, on
// held-out data, with a verdict.
import { api } from '../api.js';
import { dataKey, dataSelect, dataRequest } from '../data-choices.js';
import { h } from '../dom.js';
import { field, errorBox, runButton, stat } from '../fields.js';
import { fixed } from '../format.js';
import { optionFields, methodRequest, formatFields, formatRequest } from '../method-options.js';
import { plotFigure } from '../results.js';
import { state, tableDocument, persist } from '../state.js';
import { inPageUnits, unitName } from '../units.js';

/** The Evaluate function: the table's robot, and the calibrated one, on held-out data. */
export function evaluatePanel(method) {
  const name = method.name;
  const result = h('div', { class: 'result', id: `${name}-evaluate-result` });
  const data = dataSelect(name, 'evaluate', false);
  const upload = h('input', { type: 'file', accept: '.csv,text/csv', id: `${name}-evaluate-upload`, hidden: true });
  data.addEventListener('change', () => { upload.hidden = data.value !== 'upload'; });
  const register = h('input', { type: 'text', id: `${name}-evaluate-register`, placeholder: 'optional: 30% (data of another tracker position)' });
  const run = runButton(`${name}-evaluate-run`, 'Evaluate', async () => {
    result.replaceChildren(h('div', { class: 'progress' }, h('div', { class: 'spinner' }), h('span', { text: 'Evaluating…' })));
    try {
      const calibrated = state.calibrated[name];
      // The table opened from this very calibrated robot: comparing them
      // would compare the robot with itself; it is evaluated alone, and
      // the page says so.
      const itself = Boolean(calibrated) && state.robot.calibratedFrom === JSON.stringify(calibrated);
      const compared = itself ? null : calibrated;
      const evaluated = await api('/evaluate', {
        robot: tableDocument(),
        compared: compared || null,
        method: methodRequest(name, 'evaluate'),
        data: await dataRequest(name, 'evaluate'),
        format: formatRequest(name, 'evaluate'),
        register: register.value.trim() || null,
      });
      renderEvaluation(result, name, evaluated, Boolean(compared));
      if (itself) {
        result.prepend(h('div', { class: 'warnings', id: `${name}-evaluate-itself`, role: 'status', text: `The table holds this method’s calibrated robot (opened from its identification${state.dirty ? ', edited since' : ''}): it is evaluated alone, not compared with itself. To see what the calibration gained, open the robot it was identified from in the table and evaluate again.` }));
      }
      state.evaluated[name] = evaluated.comparison ? evaluated.comparison.outcome : 'table';
      persist();
      if (compared && state.results[name] && state.results[name].stale) {
        result.prepend(h('div', { class: 'warnings', id: `${name}-evaluate-stale`, text: 'The calibrated robot compared here is stale: the table or the data changed after its identification.' }));
      }
    } catch (error) {
      result.replaceChildren(errorBox(error));
    }
  });
  return h('div', { class: 'panel', id: `${name}-evaluate` },
    h('div', { class: 'form' }, field('Held-out data', data), upload, optionFields(method, 'evaluate'),
      field('Register their measurement frame on (a share of the rows)', register), run),
    formatFields(name, 'evaluate'),
    h('p', { class: 'hint', text: 'The errors of the robot in the table on measurements the identification has not seen, beside those of the last calibrated robot of this method (the Identification function’s). This is the honest measure of a calibration: the training residual always looks better.' }),
    result);
}

function renderEvaluation(container, name, evaluated, compared) {
  const length = (v) => inPageUnits(v, 'length', 4);
  const unit = unitName('length');
  const summary = (label, errors, id) => stat(`${label}: RMS, max (${unit}) over ${errors.count}`, `${length(errors.rms)}, ${length(errors.max)}`, { id });
  const notes = (evaluated.notes || []).length ? h('ul', { class: 'notes' }, evaluated.notes.map((n) => h('li', { text: n }))) : null;
  // The verdict: better or worse than the table's robot, against the
  // training error, and whether these are the training data at all.
  const last = state.results[name];
  const comparison = evaluated.comparison;
  let verdict = null;
  if (comparison) {
    const lines = [`The calibrated robot against the table’s robot on these data: ${comparison.summary}.`];
    const training = last && last.result ? last.result.identification.after.rms : null;
    if (training > 0 && evaluated.compared) {
      lines.push(`Its error here is ${fixed(evaluated.compared.rms / training, 2)}× its training error (${length(training)} ${unit}).`);
    }
    if (last && last.basis && dataKey(name, 'evaluate') === last.basis.data) {
      lines.push('These are the data it was identified from: this is its training residual, not a held-out check. Evaluate it on other measurements.');
    }
    verdict = h('div', { class: `verdict ${comparison.outcome === 'worse' ? 'bad' : comparison.outcome === 'better' ? 'ok' : ''}`, id: `${name}-evaluate-verdict` },
      lines.map((line) => h('p', { text: line })));
  }
  container.replaceChildren(...[
    verdict,
    h('div', { class: 'cards' },
      summary('the table’s robot', evaluated.errors, `${name}-evaluate-table`),
      evaluated.compared ? summary('calibrated', evaluated.compared, `${name}-evaluate-calibrated`) : null),
    compared || state.calibrated[name] ? null : h('p', { class: 'muted', text: 'No calibrated robot yet: identify first to compare it here.' }),
    notes,
    h('div', { class: 'plots' },
      plotFigure(compared ? 'Held-out errors: the table’s robot (left) and the calibrated one (right), mm' : 'Held-out errors of the table’s robot, mm', evaluated.plots.errors_histogram, `${name}-evaluate-histogram`),
      plotFigure('Held-out error of every configuration (mm; hover a dot for its file and line)', evaluated.plots.errors_per_configuration, `${name}-evaluate-per-configuration`)),
  ].filter(Boolean));
}
