// Stale results: an identification is of the table and the data chosen
// when it ran; when either changes after, its result is marked as such.
import { dataKey } from './data-choices.js';
import { h, $ } from './dom.js';
import { state, tableDocument } from './state.js';

/** What an identification of method `name` is of: the table and the data chosen. */
export function identificationBasis(name) {
  return { table: JSON.stringify(tableDocument()), data: dataKey(name, 'identify') };
}

/**
 * Marks each identification whose table or data changed since as stale: its
 * verdict, its calibrated robot (Save) and Evaluate's comparison are of the
 * table as it was. Undoing back to that table clears the mark.
 */
export function refreshStale() {
  for (const [name, last] of Object.entries(state.results)) {
    const container = $(`${name}-identify-result`);
    if (!container || !last.basis) continue;
    const now = identificationBasis(name);
    const changed = [
      now.table !== last.basis.table ? 'the table' : null,
      now.data !== last.basis.data ? 'the data chosen' : null,
    ].filter(Boolean);
    last.stale = changed.length > 0;
    const banner = $(`${name}-identify-stale`);
    if (!last.stale) {
      if (banner) banner.remove();
      container.classList.remove('stale');
      continue;
    }
    const text = `Stale: ${changed.join(' and ')} changed after this identification. Its verdict, its calibrated robot (Save) and Evaluate’s comparison are of the table and data as they were; identify again.`;
    if (banner) {
      banner.textContent = text;
    } else {
      container.prepend(h('div', { class: 'warnings', id: `${name}-identify-stale`, text }));
    }
    container.classList.add('stale');
  }
}
