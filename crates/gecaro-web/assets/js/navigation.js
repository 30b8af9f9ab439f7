// The method and function tabs: which panel shows.
import { $ } from './dom.js';
import { FUNCTIONS, state, persist } from './state.js';
import { drawView, refreshPose } from './view.js';

/** Marks `button` as its tab list's selected tab or not (ARIA tabs: one tab in the Tab order). */
function markTab(button, selected) {
  button.classList.toggle('active', selected);
  button.setAttribute('aria-selected', String(selected));
  button.tabIndex = selected ? 0 : -1;
}

/**
 * The arrow keys, Home and End move along tab list `list` and select the
 * tab they reach (WAI-ARIA's tabs pattern, selection following focus).
 */
export function tabKeys(list) {
  list.addEventListener('keydown', (event) => {
    const tabs = [...list.querySelectorAll('[role="tab"]')];
    const at = tabs.indexOf(document.activeElement);
    if (at < 0) return;
    const to = { ArrowRight: at + 1, ArrowLeft: at - 1, Home: 0, End: tabs.length - 1 }[event.key];
    if (to === undefined) return;
    event.preventDefault();
    const tab = tabs[(to + tabs.length) % tabs.length];
    tab.focus();
    tab.click();
  });
}

export function selectMethod(name) {
  state.method = name;
  for (const button of $('method-tabs').querySelectorAll('button')) markTab(button, button.dataset.method === name);
  for (const method of state.info.methods) $(`method-${method.name}`).hidden = method.name !== name;
  selectFunction(state.function);
  drawView();
  // The method's calibrated robot, if any, beside the table's.
  if (state.robot) refreshPose();
}

export function selectFunction(fn) {
  state.function = fn;
  for (const button of $('function-tabs').querySelectorAll('button')) markTab(button, button.dataset.function === fn);
  for (const f of FUNCTIONS) $(`${state.method}-${f}`).classList.toggle('active', f === fn);
  persist();
}
