// Form fields and what they say: numbers checked in the page in the
// field's own words (`fieldNumber`, `FieldError`), error boxes, stat
// cards, run buttons.
import { h } from './dom.js';
import { numberProblem, readNumber, sci } from './format.js';
import { state } from './state.js';

/**
 * A field for a number as a person types it: text, so that a decimal
 * comma reaches the page as typed (a browser's number field drops it:
 * `0,05` became `005`), read by `fieldNumber`; the phone's keyboard is the
 * decimal one.
 */
export function numberInput(attributes) {
  return h('input', { type: 'text', inputmode: 'decimal', autocomplete: 'off', spellcheck: 'false', class: 'number', ...attributes });
}

export function field(label, input) {
  return h('label', { class: 'field' }, h('span', { text: label }), input);
}

/** A field the page refuses before asking the server, in the field's own words. */
export class FieldError extends Error {
  constructor(message) {
    super(message);
    this.problems = [];
  }
}

/**
 * The number in `input` (its label `label`, as the page shows it), checked
 * in the page: the field is marked and a FieldError says what it takes when
 * it is not one. `whole` asks for a whole number; an empty field gives
 * `empty` when one is allowed (`undefined` = the field is required).
 */
export function fieldNumber(input, label, { min = -Infinity, max = Infinity, whole = false, above = false, empty } = {}) {
  input.classList.remove('invalid');
  const text = input.value.trim();
  const kind = whole ? 'a whole number' : 'a number';
  const range = [
    Number.isFinite(min) ? `${above ? 'above' : 'at least'} ${min}` : null,
    Number.isFinite(max) ? `at most ${max}` : null,
  ].filter(Boolean).join(' and ');
  const fail = (what) => {
    input.classList.add('invalid');
    input.focus();
    throw new FieldError(`${label}: ${what}; it takes ${kind}${range ? ` ${range}` : ''}.`);
  };
  if (text === '') {
    if (empty !== undefined) return empty;
    fail('it is empty');
  }
  // A decimal comma is read as one (0,05 is 0.05); text whose meaning is
  // not certain (1,500) is refused, never guessed.
  const value = readNumber(text);
  if (!Number.isFinite(value)) fail(numberProblem(text));
  if (whole && !Number.isInteger(value)) fail(`${text} is not a whole number`);
  if (value < min || (above && value === min) || value > max) fail(`${text} is out of range`);
  return value;
}

/** A stated σ (mm) as the API takes it, with its unit; none when not stated. */
export function sigmaText(millimetres) {
  return millimetres === null ? null : `${millimetres}mm`;
}

/** A stated rotation σ (degrees) as the API takes it, with its unit. */
export function degreesText(degrees) {
  return degrees === null ? null : `${degrees}deg`;
}

/** Cross-validation folds: empty or 0 for none, else 2 to 20 (1 fold holds nothing out). */
export function foldsOf(input) {
  const folds = fieldNumber(input, 'Cross-validation folds', { min: 0, max: state.info.limits.folds, whole: true, empty: 0 });
  if (folds === 1) {
    input.classList.add('invalid');
    throw new FieldError(`Cross-validation folds: 1 fold holds nothing out; 0 for none, or 2 to ${state.info.limits.folds}.`);
  }
  return folds >= 2 ? folds : null;
}

export function locationText(location) {
  switch (location.kind) {
    case 'frame': return `Frame ${location.frame}, ${location.key}`;
    case 'key': return location.key;
    case 'coupling': return `Coupling matrix ${location.matrix}`;
    case 'priority': return location.row === null || location.row === undefined
      ? 'Priority matrix' : `Priority matrix, row ${location.row}`;
    default: return 'Robot';
  }
}

export function errorBox(error) {
  const lines = [error.message];
  for (const problem of error.problems || []) lines.push(`${locationText(problem.location)}: ${problem.message}`);
  // A lost server's message goes when the server answers again (main.js).
  return h('div', { class: error.unreachable ? 'error-box unreachable' : 'error-box', text: lines.join('\n') });
}

export function runButton(id, text, action) {
  const button = h('button', { type: 'button', class: 'primary run', id, text });
  button.addEventListener('click', async () => {
    button.disabled = true;
    try {
      await action();
    } finally {
      button.disabled = (state.robot.problems || []).length > 0 || state.localProblems.size > 0;
    }
  });
  return button;
}

/** The observability indices O1–O5 (docs/planning.md) as one muted line. */
export function observabilityLine(indices, of) {
  const values = ['o1', 'o2', 'o3', 'o4', 'o5'].map((key) => `${key.toUpperCase()} ${sci(indices[key])}`);
  return h('p', { class: 'muted observability', text: `Observability of ${of} (W_b scaled to 1 cm, 1°, 1 %; larger is better): ${values.join(' · ')}` });
}

export function stat(label, value, extra) {
  return h('div', { class: `stat ${extra && extra.class ? extra.class : ''}` },
    h('div', { class: 'value', id: extra && extra.id, text: value }),
    h('div', { class: 'label', text: label }));
}

/**
 * Marks the result shown in `card` stale once one of its settings changes:
 * a warning (id `id`) above the result, until the next run replaces it.
 * Heard while capturing: a field's change event does not bubble when a
 * script sends it.
 */
export function staleOnChange(card, result, id, text) {
  for (const kind of ['input', 'change']) {
    card.addEventListener(kind, (event) => {
      if (event.target.closest('.result') || !result.firstChild || document.getElementById(id)) return;
      result.prepend(h('p', { class: 'warnings', id, text }));
    }, true);
  }
}
