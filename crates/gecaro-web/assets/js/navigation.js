// The method and function tabs: which panel shows.
import { $ } from './dom.js';
import { FUNCTIONS, state, persist } from './state.js';
import { drawView } from './view.js';

export function selectMethod(name) {
  state.method = name;
  for (const button of $('method-tabs').querySelectorAll('button')) {
    button.classList.toggle('active', button.dataset.method === name);
  }
  for (const method of state.info.methods) $(`method-${method.name}`).hidden = method.name !== name;
  selectFunction(state.function);
  drawView();
}

export function selectFunction(fn) {
  state.function = fn;
  for (const button of $('function-tabs').querySelectorAll('button')) {
    button.classList.toggle('active', button.dataset.function === fn);
  }
  for (const f of FUNCTIONS) $(`${state.method}-${f}`).classList.toggle('active', f === fn);
  persist();
}
