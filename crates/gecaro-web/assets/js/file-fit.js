// Which data files a method can read, from their header's column names (the
// folder's listing has them): the data menus list those first. No DOM (tested
// under node in assets/tests).

/** A column map as the File format field takes it (`x=X_mm, qm1=A1`): gecaro's name → the file's. */
export function columnMap(text) {
  const map = {};
  for (const pair of (text || '').split(',')) {
    const [ours, theirs] = pair.split('=').map((part) => (part || '').trim());
    if (ours && theirs) map[ours.toLowerCase()] = theirs.toLowerCase();
  }
  return map;
}

/**
 * Whether a file whose header names `columns` holds every column of
 * `required` (gecaro's names, e.g. ['qm1', 'x', 'y', 'z']), each under its
 * name in `map` (see `columnMap`) or its own; names compared without case.
 * `columns` null (a header not read) fits nothing.
 */
export function fits(columns, required, map = {}) {
  if (!columns) return false;
  const present = new Set(columns.map((name) => name.toLowerCase()));
  return required.every((name) => present.has(map[name] || name));
}

/** The columns a data file of `method` (its info from /api/info) needs: the first joint and the method's own. */
export function dataColumns(method) {
  return ['qm1', ...method.columns];
}

/** Whether a file is a program a robot can run: joint targets (qm1…) or Cartesian targets (x, y, z). */
export function isProgram(columns, map = {}) {
  return fits(columns, ['qm1'], map) || fits(columns, ['x', 'y', 'z'], map);
}
