// The page's entry: builds the method panels, wires the events of the
// lower modules (events.js) and of the page's buttons, restores the page
// as it was before a reload. gecaro's page talks to the JSON API of
// docs/api.md; every computation happens on the server. No framework, no
// build step: ES modules served as they are.
import { api } from './api.js';
import { h, $, toast } from './dom.js';
import { on } from './events.js';
import { buildAcceptance } from './acceptance.js';
import { buildParallel } from './parallel.js';
import { cancelJobsLeftBehind, jobsLeftRunning } from './jobs.js';
import { helpDialog } from './help.js';
import { renderHistory } from './history.js';
import { selectMethod, selectFunction, tabKeys } from './navigation.js';
import { compensatePanel } from './panels/compensate.js';
import { evaluatePanel } from './panels/evaluate.js';
import { generatePanel } from './panels/generate.js';
import { identifiablePanel } from './panels/identifiable.js';
import { followIdentification, identifyPanel, renderIdentification } from './panels/identify.js';
import { planPanel } from './panels/plan.js';
import { loadReady, refreshFiles, openRobotDialog, newRobotDialog, saveRobotAs, saveRobot } from './robot-menu.js';
import { setRobot, confirmDiscard, remember, undoEdit, renderTableUnits, renderRobot, renderFrames, markModified, scheduleCheck, renderPriority, changeAngleUnit } from './robot-table.js';
import { identificationBasis, refreshStale } from './stale.js';
import { FUNCTIONS, state, tableDocument, persist, stored } from './state.js';
import { renderSteps } from './steps.js';
import { emptyStudy } from './study-spec.js';
import { followStudy, refreshStudyRobotNote, renderStudy, renderStudyPlan } from './study.js';
import { renderSliders, refreshPose, drawView, installViewControls } from './view.js';

function buildMethodPanels() {
  const tabs = $('method-tabs');
  const panels = $('method-panels');
  for (const method of state.info.methods) {
    tabs.append(h('button', {
      type: 'button',
      role: 'tab',
      id: `tab-${method.name}`,
      'aria-controls': `method-${method.name}`,
      'data-method': method.name,
      text: method.title,
      onclick: () => selectMethod(method.name),
    }));
    panels.append(h('div', { class: 'method', id: `method-${method.name}`, role: 'tabpanel', 'aria-labelledby': `tab-${method.name}`, hidden: true },
      identifiablePanel(method), planPanel(method), generatePanel(method), identifyPanel(method), evaluatePanel(method),
      compensatePanel(method)));
  }
  for (const button of $('function-tabs').querySelectorAll('button')) {
    button.setAttribute('role', 'tab');
    button.addEventListener('click', () => selectFunction(button.dataset.function));
  }
  tabKeys(tabs);
  tabKeys($('function-tabs'));
  selectMethod(state.method);
}

async function start() {
  // What the lower modules tell (events.js), done here where every module is in reach.
  on('server-back', scheduleCheck);
  // What a lost server left in the panels is no longer true once it answers.
  on('server-back', () => { for (const box of document.querySelectorAll('.error-box.unreachable')) box.remove(); });
  on('files-changed', () => { if (state.study) renderStudy(); });
  on('changed', renderSteps);
  on('overlay', () => { state.view.bounds = null; drawView(); refreshPose(); });
  on('changed', refreshStudyRobotNote);
  // A study edited after its identification makes the result stale (stale.js).
  $('study-editor').addEventListener('change', () => refreshStale());
  state.info = await api('/info');
  $('folder').textContent = `folder: ${state.info.folder}`;
  buildMethodPanels();
  renderHistory();
  state.study = emptyStudy();
  renderStudyPlan();
  buildAcceptance();
  buildParallel();
  installViewControls();
  $('angle-unit').addEventListener('change', changeAngleUnit);
  $('robot-new').addEventListener('click', () => confirmDiscard(newRobotDialog, 'A new robot'));
  $('robot-open').addEventListener('click', () => confirmDiscard(openRobotDialog, 'Opening another robot'));
  $('help-open').addEventListener('click', helpDialog);
  $('table-undo').addEventListener('click', () => undoEdit(true));
  $('table-redo').addEventListener('click', () => undoEdit(false));
  document.addEventListener('keydown', (event) => {
    if (!(event.ctrlKey || event.metaKey) || $('dialog').open) return;
    const key = event.key.toLowerCase();
    // In a field being typed in, the browser's own undo of the text comes first.
    if (event.target.matches && event.target.matches('input, textarea, select')) return;
    if (key === 'z' && !event.shiftKey) { event.preventDefault(); undoEdit(true); }
    if (key === 'y' || (key === 'z' && event.shiftKey)) { event.preventDefault(); undoEdit(false); }
  });
  $('units').addEventListener('change', changeUnits);
  $('robot-save').addEventListener('click', saveRobot);
  $('robot-save-as').addEventListener('click', saveRobotAs);
  $('dialog-cancel').addEventListener('click', () => $('dialog').close());
  $('priority-reset').addEventListener('click', () => {
    remember();
    delete tableDocument().priority;
    markModified();
    renderPriority();
    scheduleCheck();
  });
  $('sliders-zero').addEventListener('click', () => {
    state.q = state.q.map(() => 0);
    renderSliders();
    refreshPose();
  });
  window.addEventListener('resize', () => drawView());
  cancelJobsLeftBehind();
  window.addEventListener('beforeunload', (event) => {
    if (state.dirty) event.preventDefault();
  });
  await refreshFiles();
  const before = stored();
  if (before) {
    await restore(before);
  } else {
    await loadReady('stanford');
  }
}

/** The page as it was before a reload: the robot (with its unsaved edits), the method, function and units, and the last results. */
async function restore(before) {
  try {
    const view = await api('/robots/check', { robot: before.robot.document });
    setRobot({ ...view, origin: before.robot.origin, name: before.robot.name, calibratedFrom: before.robot.calibratedFrom }, before.file);
  } catch (error) {
    await loadReady('stanford');
    return;
  }
  state.dirty = Boolean(before.dirty);
  state.units = before.units === 'm' ? 'm' : 'mm';
  $('units').value = state.units;
  renderRobot();
  if (before.method && $(`method-${before.method}`)) selectMethod(before.method);
  if (before.function && FUNCTIONS.includes(before.function)) selectFunction(before.function);
  if (before.study && Array.isArray(before.study.measurements)) {
    state.study = before.study;
    renderStudy();
  }
  // The jobs under way first: their form and progress at once, and a
  // method's older result, which the running job supersedes, never shown
  // in between.
  const resumed = resumeJobs();
  for (const [name, last] of Object.entries(before.results || {})) {
    const container = $(`${name}-identify-result`);
    if (!container || !last.result || resumed.has(name)) continue;
    // A server restarted since keeps no report of the old job (and never
    // serves another job's under its number): the result stays, its report
    // link goes.
    let job = last.job;
    try { await api(`/jobs/${job}`); } catch (ignored) { job = null; }
    // Generated data are not kept across a reload: the data chosen now are
    // taken as the result's, and the table alone is compared.
    // The form as it was when the result was made: its data and settings come back.
    restoreForm(name, last.basis);
    const basis = last.basis ? { ...last.basis, data: identificationBasis(name).data } : undefined;
    state.results[name] = { ...last, job, basis };
    renderIdentification(container, name, job, last.result);
  }
  refreshStale();
  toast('Restored the page as it was before the reload');
}

/**
 * The identifications under way when the page was reloaded, followed
 * again (their form put back as it was): a job outlives a reload. Returns
 * the methods whose identification is followed again.
 */
function resumeJobs() {
  const resumed = new Set();
  for (const left of jobsLeftRunning()) {
    if (left.kind === 'identify' && $(`${left.name}-identify-result`)) {
      restoreForm(left.name, left.basis);
      resumed.add(left.name);
      followIdentification(left.name, left.id, left.basis && { ...left.basis, data: identificationBasis(left.name).data });
    } else if (left.kind === 'study') {
      followStudy(left.id, left.basis);
    }
  }
  return resumed;
}

/**
 * Puts back method `name`'s Identification form as `basis` (stale.js's)
 * recorded it: the data file chosen, when the folder still has it, and
 * every setting.
 */
function restoreForm(name, basis) {
  if (!basis) return;
  const data = $(`${name}-identify-data`);
  const file = String(basis.data || '');
  if (data && file.startsWith('file:') && [...data.options].some((o) => o.value === file)) {
    data.value = file;
    data.dispatchEvent(new Event('change'));
  }
  for (const [id, setting] of Object.entries(basis.settings || {})) {
    const input = $(id);
    if (!input) continue;
    if (input.type === 'checkbox') input.checked = setting.value === 'true';
    else if (input.tagName !== 'SELECT' || [...input.options].some((o) => o.value === setting.value)) input.value = setting.value;
  }
}

/** One choice of units for the page: mm and degrees, or metres and radians. */
function changeUnits() {
  state.units = $('units').value === 'm' ? 'm' : 'mm';
  // The table shows the same values in the new units; the document is unchanged.
  renderFrames();
  renderTableUnits();
  for (const [name, last] of Object.entries(state.results)) {
    renderIdentification($(`${name}-identify-result`), name, last.job, last.result);
  }
  refreshStale();
  renderHistory();
  persist();
}

start().catch((error) => {
  document.body.prepend(h('div', { class: 'error-box', text: `gecaro could not start: ${error.message}` }));
});
