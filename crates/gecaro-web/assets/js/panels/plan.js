// The Plan function: configurations chosen for a criterion (docs/planning.md),
// with the accuracy curve.
import { api } from '../api.js';
import { cellInputs } from '../cell.js';
import { h, download } from '../dom.js';
import { emit } from '../events.js';
import { field, fieldNumber, errorBox, runButton, observabilityLine, stat, numberInput } from '../fields.js';
import { fmt, fixed, payloadList, sci } from '../format.js';
import { optionFields, methodRequest } from '../method-options.js';
import { selectFunction } from '../navigation.js';
import { plotFigure } from '../results.js';
import { refreshFiles } from '../robot-menu.js';
import { DEFAULT_COUNTS, state, tableDocument, persist } from '../state.js';
import { followJob } from '../jobs.js';
import { generateInto } from './generate.js';

const CRITERIA = [
  ['d', 'D-optimal (largest det W_bᵀW_b)'],
  ['a', 'A-optimal (smallest sum of variances)'],
  ['e', 'E-optimal (largest σL)'],
  ['o4', 'O4 = σL²/σ1'],
  ['o5', 'O5 = 1/Σ 1/σi'],
  ['test', 'predicted error at 200 random test poses'],
];

export function planPanel(method) {
  const name = method.name;
  const result = h('div', { class: 'result', id: `${name}-plan-result` });
  const count = numberInput({ value: Math.round((DEFAULT_COUNTS[name] || 50) / 2), id: `${name}-plan-count` });
  const criterion = h('select', { id: `${name}-plan-criterion` }, CRITERIA.map(([value, text]) => h('option', { value, text })));
  const pool = numberInput({ id: `${name}-plan-pool`, placeholder: '20 × count' });
  const distance = numberInput({ value: 0, id: `${name}-plan-distance` });
  const seed = numberInput({ value: state.info.defaults.seed, id: `${name}-plan-seed` });
  // Elastic joints: the payloads each candidate may be measured with.
  const payloads = h('input', { type: 'text', class: 'vector', id: `${name}-plan-payloads`, placeholder: 'none, or e.g. 0kg; 20kg,0,0,100mm' });
  const elastic = method.elastic;
  const curve = h('input', { type: 'text', class: 'vector', id: `${name}-plan-curve`, placeholder: 'optional, e.g. 10, 20, 40, 80' });
  const noise = numberInput({ value: 0.1, id: `${name}-plan-noise` });
  const saveAs = h('input', { type: 'text', id: `${name}-plan-save`, placeholder: 'optional, e.g. planned.csv', class: 'vector' });
  const overwrite = h('input', { type: 'checkbox', id: `${name}-plan-overwrite` });
  const cell = cellInputs(name, 'plan');
  // The plan in the robot's own units: degrees for a teach pendant.
  const angles = h('select', { id: `${name}-plan-angle-unit` },
    h('option', { value: 'rad', text: 'radians' }), h('option', { value: 'deg', text: 'degrees (a teach pendant)' }));
  const run = runButton(`${name}-plan-run`, 'Plan', async () => {
    // A plan is a server job: its progress names the part under way (the
    // candidates, the choice, the curve) and its steps; Cancel stops it.
    const cancel = h('button', { type: 'button', id: `${name}-plan-cancel`, text: 'Cancel', disabled: true });
    const label = h('span', { id: `${name}-plan-progress`, text: 'Checking the request…' });
    const bar = h('progress', { id: `${name}-plan-bar`, max: 1, value: 0 });
    result.replaceChildren(h('div', { class: 'progress' }, h('div', { class: 'spinner' }), label, bar, cancel));
    try {
      const request = {
        robot: tableDocument(),
        method: methodRequest(name, 'plan'),
        count: fieldNumber(count, 'Configurations', { min: 1, max: state.info.limits.generate, whole: true }),
        criterion: criterion.value,
        min_distance: fieldNumber(distance, 'Smallest distance', { min: 0, empty: 0 }),
        seed: fieldNumber(seed, 'Seed', { min: 0, whole: true, empty: state.info.defaults.seed }),
        noise: fieldNumber(noise, 'Sensor σ', { min: 0, above: true, empty: 0.1 }) * 1e-3,
      };
      const candidates = fieldNumber(pool, 'Candidates', { min: 1, max: state.info.limits.generate, whole: true, empty: null });
      if (candidates !== null) request.pool = candidates;
      if (elastic && payloadList(payloads.value).length) request.payloads = payloadList(payloads.value);
      request.cell = cell.request();
      request.format = { angle_unit: angles.value };
      if (curve.value.trim()) {
        request.curve = curve.value.split(/[\s,;]+/).filter(Boolean).map((v) => {
          const n = Number(v);
          if (!Number.isInteger(n) || n < 1) throw new Error(`The curve's counts are whole numbers ≥ 1, not “${v}”.`);
          return n;
        });
      }
      if (saveAs.value.trim()) {
        request.save_as = saveAs.value.trim();
        request.overwrite = overwrite.checked;
      }
      const submitted = await api('/plan', request);
      const job = await followJob(submitted.job, label, { bar, cancel });
      if (job.state === 'cancelled') {
        result.replaceChildren(h('div', { class: 'warnings', id: `${name}-plan-cancelled`, text: 'Cancelled: the server stopped planning.' }));
        return;
      }
      if (job.state === 'failed') throw new Error(job.error);
      const planned = job.result;
      planned.format = request.format;
      if (planned.saved) refreshFiles();
      renderPlanned(result, name, planned);
    } catch (error) {
      result.replaceChildren(errorBox(error));
    }
  });
  return h('div', { class: 'panel', id: `${name}-plan` },
    h('div', { class: 'form' },
      field('Configurations', count),
      field('Criterion', criterion),
      field('Candidate pool', pool),
      field('Minimum joint distance (rad, m)', distance),
      field('Seed', seed),
      elastic ? field('Payloads (elastic joints; “;” between them)', payloads) : null,
      optionFields(method, 'plan'),
      field('Curve: counts', curve),
      field('Sensor noise σ for the curve (mm)', noise),
      ...cell.fields,
      field('Joint angles of the plan in', angles),
      field('Save to the folder as', saveAs),
      h('label', {}, overwrite, ' replace'),
      run),
    h('p', { class: 'hint', text: 'Before measuring: the configurations that determine the identifiable parameters best, chosen from candidates within the joint limits (docs/planning.md). The curve predicts the calibrated robot’s error against the number of configurations, planned and random.' }),
    result);
}

function renderPlanned(container, name, planned) {
  state.planned[name] = planned.configurations;
  state.plannedPoints[name] = planned.points || [];
  emit('overlay');
  persist();
  const better = planned.criterion === 'a' || planned.criterion === 'test'
    ? planned.value < planned.random_value : planned.value > planned.random_value;
  const preview = planned.csv.split('\n').slice(0, 6).join('\n');
  const parts = [
    h('div', { class: 'cards' },
      stat('configurations planned', String(planned.configurations), { id: `${name}-plan-count-result`, class: 'ok' }),
      // A unit is what is measured together: a configuration, or a set of
      // configurations for the link and plane methods.
      planned.units === planned.configurations
        ? stat(`chosen of ${planned.pool} candidate configurations`, String(planned.units))
        : stat(`sets measured together, chosen of ${planned.pool} candidate sets`, `${planned.units} sets`),
      stat(planned.criterion_meaning, sci(planned.value), { id: `${name}-plan-value`, class: better ? 'ok' : '' }),
      stat('a random choice', sci(planned.random_value), { id: `${name}-plan-random` })),
    observabilityLine(planned.observability, 'the plan'),
    planned.saved ? h('p', { text: `Saved to ${planned.saved}.` }) : null,
    h('div', { class: 'actions' },
      h('button', { type: 'button', id: `${name}-plan-download`, text: `Download ${planned.file_name}`, onclick: () => download(planned.file_name, planned.csv, 'text/csv') }),
      h('button', {
        type: 'button',
        id: `${name}-plan-measure`,
        text: 'Measure them (simulated)',
        title: 'Points generation at these configurations, with the settings of the Points generation function',
        onclick: async () => {
          selectFunction('generate');
          await generateInto(name, { csv: { text: planned.csv, name: planned.file_name } }, planned.format);
        },
      })),
  ];
  if (planned.curve) {
    const mm = (v) => (v === null ? 'not determined' : fixed(v * 1e3, 4));
    const rows = planned.curve.points.map((p) => h('tr', {},
      h('td', { text: String(p.configurations) }), h('td', { text: mm(p.planned) }), h('td', { text: mm(p.random) }),
      h('td', { text: p.planned && p.random ? fixed(p.random / p.planned, 2) : '—' })));
    parts.push(h('h3', { text: `Predicted RMS position error, σ ${fmt(planned.curve.noise * 1e3)} mm` }));
    parts.push(h('table', { class: 'grid', id: `${name}-plan-curve-table` },
      h('thead', {}, h('tr', {}, ['configurations', 'planned (mm)', 'random (mm)', 'random / planned'].map((t) => h('th', { text: t })))),
      h('tbody', {}, rows)));
    // In the same grid, size and caption style as every other plot of the page.
    parts.push(h('div', { class: 'plots' }, plotFigure('Predicted RMS position error against the number of configurations (mm)', planned.curve.svg, `${name}-plan-curve-plot`)));
  }
  parts.push(h('pre', { class: 'preview', text: `${preview}\n…` }));
  container.replaceChildren(...parts.filter(Boolean));
}
