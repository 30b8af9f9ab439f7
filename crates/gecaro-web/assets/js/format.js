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

export function parseVector(text, what) {
  const parts = text.trim().split(/[\s,;]+/).filter(Boolean).map(Number);
  if (parts.length !== 3 || !parts.every(Number.isFinite)) {
    throw new Error(`${what} needs three numbers, e.g. 0.3, 0.5, 0.81`);
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
