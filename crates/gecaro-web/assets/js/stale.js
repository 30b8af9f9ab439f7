// Stale results: an identification is of the table, the data chosen and
// the settings it ran with (model, σ, loss, file format, …); when any of
// them changes after, its result is marked as such — the banner names what
// changed, the verdict loses its green and Save is no longer the primary
// step. Undoing back to what it was clears the mark.
import { dataKey } from './data-choices.js';
import { h, $ } from './dom.js';
import { readNumber } from './format.js';
import { state, tableDocument } from './state.js';

/**
 * The settings of method `name`'s Identification function as they stand:
 * every field of its form and of its file format (the data menu and the
 * join form aside), by id, with the label a person reads.
 */
function identifySettings(name) {
  const panel = $(`${name}-identify`);
  const settings = {};
  if (!panel) return settings;
  for (const input of panel.querySelectorAll('.form input, .form select, .format input, .format select')) {
    if (!input.id || input.id === `${name}-identify-data` || input.type === 'file' || input.closest('.join')) continue;
    const label = input.closest('label');
    const words = label && label.querySelector('span') ? label.querySelector('span').textContent : input.id;
    settings[input.id] = { value: settingValue(input), label: words };
  }
  return settings;
}

/** A field's value as it counts: a number field's number (0,05 and 0.05 are one value), a checkbox's state, else its text. */
function settingValue(input) {
  if (input.type === 'checkbox') return String(input.checked);
  const text = input.value.trim();
  if (input.inputMode === 'decimal' && Number.isFinite(readNumber(text))) return String(readNumber(text));
  return text;
}

/** What an identification of method `name` is of: the table, the data chosen and the settings. */
export function identificationBasis(name) {
  return { table: JSON.stringify(tableDocument()), data: dataKey(name, 'identify'), settings: identifySettings(name) };
}

/** What changed between `then` (a basis) and `now`, in words; empty when nothing did. */
export function basisChanges(then, now) {
  const changed = [
    now.table !== then.table ? 'the table' : null,
    now.data !== then.data ? 'the data chosen' : null,
  ].filter(Boolean);
  // A basis kept from before settings were recorded compares the table and data only.
  if (then.settings) {
    const settings = Object.entries(now.settings)
      .filter(([id, setting]) => then.settings[id] !== undefined && then.settings[id].value !== setting.value)
      .map(([, setting]) => `“${setting.label}”`);
    if (settings.length) changed.push(`${settings.length === 1 ? 'the setting' : 'the settings'} ${settings.join(', ')}`);
  }
  return changed;
}

/**
 * Marks a result `container` stale or not (`changed`: what changed, in
 * words, or empty): a banner (id `bannerId`) that names it, the verdict
 * without its green, and Save (button `saveId`) no longer primary.
 */
export function markStale(container, bannerId, saveId, changed, what) {
  const stale = changed.length > 0;
  container.classList.toggle('stale', stale);
  const save = $(saveId);
  if (save) {
    if (stale) save.classList.remove('primary');
    else if (save.dataset.primary === '1') save.classList.add('primary');
  }
  const banner = $(bannerId);
  if (!stale) {
    if (banner) banner.remove();
    return;
  }
  const text = `Stale: ${changed.join(' and ')} changed after this ${what}. Its verdict, its calibrated robot (Save) and Evaluate’s comparison are of what it ran with; run it again.`;
  if (banner) banner.textContent = text;
  else container.prepend(h('div', { class: 'warnings stale-banner', id: bannerId, role: 'status', text }));
}

/** What a study's identification is of: the table and the study as the editor holds it (its file name aside). */
export function studyBasis() {
  const study = { ...(state.study || {}), name: null };
  return { table: JSON.stringify(tableDocument()), study: JSON.stringify(study) };
}

/** Marks each identification (of a method, or of the study) whose table, data or settings changed since as stale. */
export function refreshStale() {
  const study = state.studyResult;
  if (study && $('study-result')) {
    const now = studyBasis();
    const changed = [now.table !== study.basis.table ? 'the table' : null, now.study !== study.basis.study ? 'the study' : null].filter(Boolean);
    study.stale = changed.length > 0;
    markStale($('study-result'), 'study-stale', 'study-calibrated-save', changed, 'identification of the study');
  }
  for (const [name, last] of Object.entries(state.results)) {
    const container = $(`${name}-identify-result`);
    if (!container || !last.basis) continue;
    const changed = basisChanges(last.basis, identificationBasis(name));
    last.stale = changed.length > 0;
    markStale(container, `${name}-identify-stale`, `${name}-identify-save`, changed, 'identification');
  }
}
