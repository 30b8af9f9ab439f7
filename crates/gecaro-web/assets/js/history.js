// The history of the page's identifications (a method's or a study's):
// each run's robot, data, settings, verdict, errors and identified values,
// kept in this browser (the 20 latest), and two runs compared side by side
// — which parameters moved between them, by how many σ.
import { h, $ } from './dom.js';
import { fmt } from './format.js';
import { quantity, unitName, unitOf, inPageUnits } from './units.js';

const HISTORY_KEY = 'gecaro.history';

/** Runs kept; the oldest go first. */
const KEPT = 20;

/** The runs kept in this browser, newest first. */
function runs() {
  try {
    const kept = JSON.parse(localStorage.getItem(HISTORY_KEY) || '[]');
    return Array.isArray(kept) ? kept : [];
  } catch (error) {
    return [];
  }
}

function keep(list) {
  try {
    localStorage.setItem(HISTORY_KEY, JSON.stringify(list.slice(0, KEPT)));
  } catch (error) { /* over the quota: the history is what it was */ }
}

/**
 * Records an identification's `result` (as the server sends it) of
 * `robot` (its name) on `data` (words), run with `settings` (words), as
 * the newest run; the history is drawn again.
 */
export function recordRun({ what, robot, data, settings, result }) {
  const id = result.identification;
  const values = id.parameters.concat(id.auxiliary).map((p) => ({ name: p.name, identified: p.identified, std: p.std }));
  const run = {
    number: (runs()[0] ? runs()[0].number : 0) + 1,
    time: new Date().toISOString(),
    what,
    robot,
    data,
    settings,
    verdict: id.verdict.summary,
    trusted: id.verdict.trusted,
    rms_before: id.before.rms,
    rms_after: id.after.rms,
    max_after: id.after.max,
    values,
  };
  keep([run, ...runs()]);
  renderHistory();
}

/** The history's card: the runs, two of them chosen for a side-by-side comparison. */
export function renderHistory() {
  const card = $('history');
  if (!card) return;
  const list = runs();
  if (!list.length) {
    card.replaceChildren(h('p', { class: 'muted', text: 'No identification yet: each one run on this page is listed here (in this browser), to compare two side by side.' }));
    return;
  }
  const unit = unitName('length');
  const chosen = new Set(list.slice(0, 2).map((run) => run.number));
  const comparison = h('div', { id: 'history-comparison' });
  const compare = () => {
    const [b, a] = list.filter((run) => chosen.has(run.number));
    comparison.replaceChildren(a && b ? compareRuns(a, b) : h('p', { class: 'muted', text: 'Choose two runs to compare.' }));
  };
  const rows = list.map((run) => h('tr', {},
    h('td', {}, h('input', {
      type: 'checkbox', checked: chosen.has(run.number), 'aria-label': `compare run ${run.number}`, id: `history-pick-${run.number}`,
      onchange: (event) => { if (event.target.checked) chosen.add(run.number); else chosen.delete(run.number); compare(); },
    })),
    h('td', { class: 'number', text: String(run.number) }),
    h('td', { text: new Date(run.time).toLocaleString() }),
    h('td', { text: run.what }), h('td', { text: run.robot }), h('td', { text: run.data }), h('td', { text: run.settings }),
    h('td', { class: run.trusted ? 'ok' : 'bad', text: run.trusted ? 'trusted' : 'not trusted', title: run.verdict }),
    h('td', { class: 'number', title: `${run.rms_after} m`, text: quantity(run.rms_after, 'length') })));
  card.replaceChildren(
    h('div', { class: 'scroll-x' }, h('table', { class: 'values', id: 'history-runs' },
      h('thead', {}, h('tr', {}, ['compare', 'run', 'when', 'what', 'robot', 'data', 'settings', 'verdict', `RMS after (${unit})`].map((t) => h('th', { text: t })))),
      h('tbody', {}, rows))),
    h('div', { class: 'actions' }, h('button', { type: 'button', id: 'history-clear', text: 'Forget the history', onclick: () => { keep([]); renderHistory(); } })),
    comparison);
  compare();
}

/**
 * Runs `a` (the earlier) and `b` side by side: their figures, then every
 * value both identified, with its change and that change in σ of the
 * difference (`√(σa² + σb²)`): beyond 3, the data of the two runs disagree
 * on it (or the robot changed between them).
 */
function compareRuns(a, b) {
  const unit = unitName('length');
  const figures = [
    ['robot', a.robot, b.robot], ['data', a.data, b.data], ['settings', a.settings, b.settings],
    ['verdict', a.verdict, b.verdict],
    [`RMS after (${unit})`, quantity(a.rms_after, 'length'), quantity(b.rms_after, 'length')],
    [`largest after (${unit})`, quantity(a.max_after, 'length'), quantity(b.max_after, 'length')],
  ];
  const byName = new Map(a.values.map((v) => [v.name, v]));
  const shared = b.values.filter((v) => byName.has(v.name));
  const shown = (value, kind) => (kind === 'none' ? fmt(Number(value.toPrecision(6))) : inPageUnits(value, kind, 6));
  const rows = shared.map((vb) => {
    const va = byName.get(vb.name);
    const kind = unitOf(vb.name);
    const change = vb.identified - va.identified;
    const sigma = Math.hypot(va.std, vb.std);
    const ratio = Number.isFinite(sigma) && sigma > 0 ? Math.abs(change) / sigma : Number.NaN;
    return { row: h('tr', { class: ratio > 3 ? 'significant' : '' },
      h('td', { text: vb.name }),
      h('td', { class: 'number', text: shown(va.identified, kind) }),
      h('td', { class: 'number', text: shown(vb.identified, kind) }),
      h('td', { class: 'number', title: String(change), text: kind === 'none' ? fmt(Number(change.toPrecision(4))) : quantity(change, kind) }),
      h('td', { class: 'number', text: Number.isFinite(ratio) ? ratio.toFixed(1) : '–' })), ratio };
  });
  const moved = rows.filter((r) => r.ratio > 3).length;
  return h('div', {},
    h('h3', { text: `Run ${a.number} against run ${b.number}` }),
    h('table', { class: 'values', id: 'history-figures' },
      h('thead', {}, h('tr', {}, ['', `run ${a.number}`, `run ${b.number}`].map((t) => h('th', { text: t })))),
      h('tbody', {}, figures.map(([label, x, y]) => h('tr', {}, h('td', { text: label }), h('td', { text: x }), h('td', { text: y }))))),
    h('p', { id: 'history-moved', text: `${shared.length} values identified by both; ${moved} differ by more than 3σ of their difference${moved ? ' (in bold): the two runs disagree there, or the robot changed between them' : ''}.` }),
    h('div', { class: 'scroll-x' }, h('table', { class: 'values', id: 'history-values' },
      h('thead', {}, h('tr', {}, ['value', `run ${a.number}`, `run ${b.number}`, 'change', 'change / σ'].map((t) => h('th', { text: t })))),
      h('tbody', {}, rows.map((r) => r.row)))));
}
