// The data menus of each method: generated, held-out, files of the folder
// and uploads, and the request's data (`dataRequest`).
import { h, $ } from './dom.js';
import { FieldError } from './fields.js';
import { columnMap, dataColumns, fits, isProgram } from './file-fit.js';
import { methodInfo, state } from './state.js';

/** The data chosen in function `fn` of method `name` (a generation counted as new data). */
export function dataKey(name, fn) {
  const data = $(`${name}-${fn}-data`);
  const choice = data ? data.value : '';
  const kept = { generated: state.generated[name], 'held-out': state.heldOut[name] }[choice];
  return choice + (kept ? `#${kept.serial || 0}` : '');
}

export function dataSelect(name, fn, withRandom) {
  const select = h('select', { id: `${name}-${fn}-data`, class: 'data-choice', 'data-method': name, 'data-function': fn, 'data-random': withRandom ? '1' : '' });
  return select;
}

/**
 * Rebuilds the data choices of method `name`. `prefer` (an option value, such
 * as 'generated' right after a generation) is selected in the Identification
 * function's selector; the others keep their choice when it still exists.
 */
export function refreshDataChoices(name, prefer) {
  for (const select of document.querySelectorAll(`select.data-choice[data-method="${name}"]`)) {
    const previous = prefer && !select.dataset.random ? prefer : select.value;
    const options = [];
    if (select.dataset.random) options.push(h('option', { value: 'random', text: 'Random configurations' }));
    // Nothing is chosen for the person: a file of the folder is data only
    // once picked (the step bar and Identify count what was chosen).
    else options.push(h('option', { value: '', text: select.dataset.program ? 'choose a program…' : 'choose the data…' }));
    // A program is a file of the folder or an upload, never measurements.
    const generated = select.dataset.program ? null : state.generated[name];
    if (generated) options.push(h('option', { value: 'generated', text: `Generated here: ${generated.file_name}` }));
    const heldOut = select.dataset.program ? null : state.heldOut[name];
    if (heldOut) options.push(h('option', { value: 'held-out', text: `Held out, the same real robot: ${heldOut.file_name}` }));
    // The folder's files whose columns this method (or a program) reads
    // first; the others after, to map under File format.
    const format = $(`${name}-${select.dataset.function}-columns`);
    const map = columnMap(format ? format.value : '');
    const method = methodInfo(name);
    const readable = (file) => {
      const columns = (state.files.data_columns || {})[file];
      return select.dataset.program ? isProgram(columns, map) : fits(columns, dataColumns(method), map);
    };
    const files = state.files.data.filter(readable);
    const others = state.files.data.filter((file) => !readable(file));
    for (const file of files) options.push(h('option', { value: `file:${file}`, text: file }));
    if (others.length) {
      options.push(h('optgroup', { label: `Other CSV files: columns that do not fit ${select.dataset.program ? 'a program' : method.title} (map them under File format)` },
        others.map((file) => h('option', { value: `file:${file}`, text: file }))));
    }
    if (!select.dataset.random) options.push(h('option', { value: 'upload', text: 'Upload a CSV file…' }));
    select.replaceChildren(...options);
    if ([...select.options].some((o) => o.value === previous)) select.value = previous;
    select.dispatchEvent(new Event('change'));
  }
}

export async function dataRequest(name, fn) {
  const choice = $(`${name}-${fn}-data`).value;
  if (choice === 'random') return undefined;
  if (choice === '') {
    throw new FieldError(fn === 'compensate' ? 'Program: choose the program to compensate (a file of the folder, or upload one).'
      : 'Data: choose the measurements (generate them under Points generation, a file of the folder, or upload one).');
  }
  if (choice === 'generated' || choice === 'held-out') {
    const generated = (choice === 'generated' ? state.generated : state.heldOut)[name];
    return { csv: { text: generated.csv, name: generated.file_name } };
  }
  if (choice.startsWith('file:')) return { file: choice.slice(5) };
  const upload = $(`${name}-${fn}-upload`);
  if (!upload.files.length) throw new Error('Choose a CSV file to upload.');
  const file = upload.files[0];
  return { csv: { text: await file.text(), name: file.name } };
}

/** The number of the next data kept in a slot whose data are `kept` now: a new generation is new data. */
export function nextSerial(kept) {
  return (kept ? kept.serial || 0 : 0) + 1;
}
