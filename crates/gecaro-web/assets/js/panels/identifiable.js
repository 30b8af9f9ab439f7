// The Identifiable parameters function: QR of the observation matrix
// (Appendix III), regrouping relations and excitation.
import { api } from '../api.js';
import { dataSelect, dataRequest } from '../data-choices.js';
import { h } from '../dom.js';
import { field, fieldNumber, errorBox, runButton, observabilityLine, stat, numberInput } from '../fields.js';
import { fmt, sci } from '../format.js';
import { optionFields, methodRequest } from '../method-options.js';
import { KINDS, KIND_HEADS, state, tableDocument } from '../state.js';

export function identifiablePanel(method) {
  const name = method.name;
  const result = h('div', { class: 'result', id: `${name}-identifiable-result` });
  const count = numberInput({ id: `${name}-identifiable-count-input`, placeholder: 'auto' });
  const seed = numberInput({ value: state.info.defaults.seed, id: `${name}-identifiable-seed` });
  const run = runButton(`${name}-identifiable-run`, 'Compute', async () => {
    result.replaceChildren(h('div', { class: 'progress' }, h('div', { class: 'spinner' }), 'QR of the observation matrix…'));
    try {
      const request = {
        robot: tableDocument(),
        method: methodRequest(name, 'identifiable'),
        data: await dataRequest(name, 'identifiable'),
        seed: fieldNumber(seed, 'Seed', { min: 0, whole: true, empty: state.info.defaults.seed }),
      };
      const configurations = fieldNumber(count, 'Random configurations', { min: 1, max: state.info.limits.random, whole: true, empty: null });
      if (configurations !== null) request.count = configurations;
      const report = await api('/identifiable', request);
      renderIdentifiable(result, name, report);
    } catch (error) {
      result.replaceChildren(errorBox(error));
    }
  });
  return h('div', { class: 'panel', id: `${name}-identifiable` },
    h('div', { class: 'form' },
      field('Data', dataSelect(name, 'identifiable', true)),
      field('Random configurations', count),
      field('Seed', seed),
      optionFields(method, 'identifiable'),
      run),
    h('p', { class: 'hint', text: 'Appendix III: column-pivoted QR of W on configurations that satisfy the method’s constraint. Measured data are checked for excitation as well.' }),
    result);
}

function renderIdentifiable(container, name, report) {
  const frames = tableDocument().frame.length;
  const status = new Map(report.parameters.map((p) => [p.name, p.status]));
  const symbol = { identifiable: 'id', regrouped: 'n', no_effect: '0', excluded: '–' };
  const head = h('tr', {}, h('th', { text: 'j' }), KIND_HEADS.map((k) => h('th', { text: k })));
  const rows = [];
  for (let j = 0; j < frames; j += 1) {
    rows.push(h('tr', {}, h('th', { text: String(j) }), KINDS.map((kind) => {
      const s = status.get(`${kind}${j}`);
      return h('td', { class: s ? `s-${s}` : '', text: s ? symbol[s] : '' });
    })));
  }
  const parts = [
    h('div', { class: 'cards' },
      stat('identifiable parameters', String(report.count), { id: `${name}-identifiable-count`, class: 'ok' }),
      stat(`of ${report.parameters.length} parameters`, `${report.parameters.length - report.count} not`),
      stat('condition number of W_b', fmt(Number(report.condition_number.toPrecision(4)))),
      stat(`equations (${report.rows} rows)`, String(report.equations)),
      stat('configurations', String(report.configurations))),
    h('p', { class: 'muted', text: `On ${report.source}; numerical zero τ = ${sci(report.tolerance)}.` }),
    observabilityLine(report.observability, report.excitation ? 'the data' : 'these random configurations'),
  ];
  if (report.excitation) {
    parts.push(report.excitation.same_base_set
      ? h('p', { class: 'stat ok', text: `The data excite every identifiable parameter (condition number on the data ${fmt(Number(report.excitation.condition_number.toPrecision(4)))}).` })
      : h('div', { class: 'warnings', text: `The data do not excite ${report.excitation.not_excited.join(', ')}: they would stay at their nominal values.` }));
  }
  if (report.warnings.length) {
    parts.push(h('div', { class: 'warnings', id: `${name}-identifiable-warnings` }, h('strong', { text: 'The set-up' }),
      h('ul', {}, report.warnings.map((w) => h('li', { text: w })))));
  }
  parts.push(h('p', { class: 'muted', text: 'id = identifiable · n = regrouped on other parameters · 0 = no effect · – = excluded (priority 0)' }));
  parts.push(h('table', { class: 'grid', id: `${name}-identifiable-grid` }, h('thead', {}, head), h('tbody', {}, rows)));
  if (report.auxiliary.length) {
    parts.push(h('p', {}, `Plane unknowns: ${report.auxiliary.map((a) => `${a.name} ${symbol[a.status]}`).join(', ')}`));
  }
  if (report.regrouping.length) {
    parts.push(h('h3', { text: 'Regrouping relations (eq. 32)' }));
    parts.push(h('ul', { class: 'relations' }, report.regrouping.map((relation) => h('li', {
      text: `${relation.base}_b = ${relation.base} ${relation.absorbed.map((a) => `${a.coefficient < 0 ? '−' : '+'} ${fmt(Number(Math.abs(a.coefficient).toPrecision(6)))}·${a.name}`).join(' ')}`,
    }))));
  }
  const priorityRows = report.priority_matrix.map((row, j) => h('tr', {}, h('th', { text: String(j) }), row.map((v) => h('td', { text: String(v) }))));
  parts.push(h('details', {}, h('summary', { text: 'New priority matrix (non-identifiable parameters set to 0)' }),
    h('table', { class: 'grid' }, h('thead', {}, head.cloneNode(true)), h('tbody', {}, priorityRows))));
  container.replaceChildren(...parts);
}
