// Numbers and names as a person reads them: no DOM, no state (tested
// under node in assets/tests).
/** A number as a person reads it: up to 8 significant digits. */
export function fmt(value) {
  if (value === undefined || value === null) return '';
  if (value === 0) return '0';
  const size = Math.abs(value);
  if (size >= 1e-4 && size < 1e7) return String(Number(value.toPrecision(8)));
  return value.toExponential(4);
}

export function fixed(value, digits) {
  return Number.isFinite(value) ? value.toFixed(digits) : '–';
}

export function sci(value) {
  return Number.isFinite(value) ? value.toExponential(2) : '–';
}

export function slug(text) {
  return text.toLowerCase().replace(/[^a-z0-9]+/g, '-').replace(/^-|-$/g, '') || 'robot';
}

/**
 * The number a person typed, read as they meant it: a decimal point or a
 * decimal comma (`0,05` is 0.05, never 5), a typographic minus, spaces
 * around. Returns NaN for text that is no number, and for text whose
 * meaning is not certain: a comma and a point together (`1.234,5`), two
 * commas, or a comma before exactly three digits after a non-zero whole
 * part (`1,500`: one and a half, or fifteen hundred?).
 */
export function readNumber(text) {
  const typed = String(text).trim().replace(/\u2212/g, '-');
  if (typed === '' || /\s/.test(typed)) return Number.NaN;
  if (!typed.includes(',')) return /^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$/.test(typed) ? Number(typed) : Number.NaN;
  const comma = /^([+-]?)(\d*),(\d+)([eE][+-]?\d+)?$/.exec(typed);
  if (!comma) return Number.NaN;
  const [, sign, whole, fraction, exponent] = comma;
  if (fraction.length === 3 && /[1-9]/.test(whole) && !exponent) return Number.NaN;
  return Number(`${sign}${whole || '0'}.${fraction}${exponent || ''}`);
}

/** Why `text` is not read as a number (readNumber gave NaN), in words. */
export function numberProblem(text) {
  const typed = String(text).trim();
  if (typed.includes(',') && typed.includes('.')) return `“${typed}” mixes a decimal comma and a decimal point`;
  if (/^[+-]?[1-9]\d*,\d{3}$/.test(typed)) return `“${typed}” could be a decimal comma or a thousands separator: write ${typed.replace(',', '.')} or ${typed.replace(',', '')}`;
  return `“${typed}” is not a number`;
}

/**
 * Three numbers: separated by semicolons or spaces (then each may have a
 * decimal comma: `0,3; 0,5; 0,81`), or by commas (decimal points).
 */
export function parseVector(text, what) {
  const trimmed = text.trim();
  const bySpace = trimmed.split(/[\s;]+/).filter(Boolean);
  const words = bySpace.length === 3 ? bySpace : trimmed.split(/[\s,;]+/).filter(Boolean);
  const parts = words.map((word) => (bySpace.length === 3 ? readNumber(word.replace(/,$/, '')) : Number(word)));
  if (parts.length !== 3 || !parts.every(Number.isFinite)) {
    throw new Error(`${what} needs three numbers, e.g. 0.3, 0.5, 0.81 (or 0,3; 0,5; 0,81)`);
  }
  return parts;
}

/**
 * The payloads of a plan's field, separated by semicolons (a payload's
 * centre has commas of its own): "0kg; 20kg,0,0,100mm" → ["0kg",
 * "20kg,0,0,100mm"]. The server checks each one.
 */
export function payloadList(text) {
  return text.split(';').map((part) => part.trim()).filter(Boolean);
}

/** The order of a parameter's kind within its frame (eq. 2–4). */
const KIND_ORDER = ['alpha', 'd', 'theta', 'r', 'beta', 'K', 'offset', 'c'];

/**
 * Parameters named `kind` + frame (`theta2`, `K4`) in frame order, each
 * frame's in the order of eq. 2–4; names of another form keep their place
 * after them.
 */
export function inFrameOrder(parameters) {
  const key = (p) => {
    const parts = /^([A-Za-z]+?)(\d+)$/.exec(p.name);
    const kind = parts ? KIND_ORDER.indexOf(parts[1]) : -1;
    return parts && kind >= 0 ? [Number(parts[2]), kind] : [Infinity, 0];
  };
  return parameters.map((p, index) => ({ p, index, key: key(p) }))
    .sort((a, b) => a.key[0] - b.key[0] || a.key[1] - b.key[1] || a.index - b.index)
    .map(({ p }) => p);
}
