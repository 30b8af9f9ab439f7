// The Points generation function: a simulated real robot measured by a
// sensor with noise; held-out data of the same real robot.
import { api } from '../api.js';
import { cellInputs } from '../cell.js';
import { refreshDataChoices, nextSerial } from '../data-choices.js';
import { h, $, download } from '../dom.js';
import { field, fieldNumber, errorBox, runButton, stat, numberInput } from '../fields.js';
import { fixed, slug } from '../format.js';
import { optionFields, methodRequest } from '../method-options.js';
import { selectFunction } from '../navigation.js';
import { refreshFiles, saveAsDialog } from '../robot-menu.js';
import { refreshStale } from '../stale.js';
import { DEFAULT_COUNTS, methodInfo, state, tableDocument } from '../state.js';
import { drawView } from '../view.js';

/**
 * Points generation with the settings of method `name`'s panel: at
 * `configurations` (a CSV of planned configurations) when given, else at as
 * many random ones as the panel says. The result shows in that panel.
 */
export async function generateInto(name, configurations, format) {
  const result = $(`${name}-generate-result`);
  const value = (what) => $(`${name}-generate-${what}`).value;
  result.replaceChildren(h('div', { class: 'progress' }, h('div', { class: 'spinner' }), 'Generating configurations…'));
  try {
    const request = {
      robot: tableDocument(),
      method: methodRequest(name, 'generate'),
      noise: fieldNumber($(`${name}-generate-noise`), 'Sensor noise σ', { min: 0, empty: 0 }) * 1e-3,
      seed: fieldNumber($(`${name}-generate-seed`), 'Seed', { min: 0, whole: true, empty: state.info.defaults.seed }),
    };
    if (configurations) {
      request.configurations = configurations;
      if (format) request.format = format;
    } else request.count = fieldNumber($(`${name}-generate-count`), 'Configurations', { min: 1, max: state.info.limits.generate, whole: true });
    request.cell = generationCells[name]();
    const real = value('real');
    if (real.startsWith('file:')) {
      request.real = (await api(`/robots/file?name=${encodeURIComponent(real.slice(5))}`)).document;
    } else {
      request.error_level = fieldNumber($(`${name}-generate-level`), 'Error level', { min: 0, empty: 0 });
      if (methodInfo(name).elastic) {
        request.compliance_level = fieldNumber($(`${name}-generate-compliance`), 'Compliance level', { min: 0, empty: null });
      }
    }
    if (methodInfo(name).elastic && value('payload').trim()) request.payload = value('payload').trim();
    if (methodInfo(name).elastic && value('tilt').trim()) request.gravity_tilt = value('tilt').trim();
    if (value('save').trim()) {
      request.save_as = value('save').trim();
      request.overwrite = $(`${name}-generate-overwrite`).checked;
    }
    const generated = await api('/generate', request);
    // Each generation is new data, under the same choice 'generated'; it
    // keeps where it came from (the real robot, the seed, the noise).
    generated.serial = nextSerial(state.generated[name]);
    generated.origin = {
      real: real.startsWith('file:') ? real.slice(5) : null,
      level: request.error_level,
      seed: request.seed,
      noise: request.noise,
    };
    state.generated[name] = generated;
    delete state.heldOut[name];
    refreshDataChoices(name, 'generated');
    refreshStale();
    if (generated.saved) refreshFiles();
    renderGenerated(result, name, generated);
    drawView();
  } catch (error) {
    result.replaceChildren(errorBox(error));
  }
}

/** The methods whose simulated sensors see an elastic robot's sag. */

/** Each method's generation cell, read when it generates. */
const generationCells = {};

export function generatePanel(method) {
  const name = method.name;
  const result = h('div', { class: 'result', id: `${name}-generate-result` });
  const count = numberInput({ value: DEFAULT_COUNTS[name] || 50, id: `${name}-generate-count` });
  const real = h('select', { id: `${name}-generate-real`, class: 'real-choice' });
  const level = numberInput({ value: 1, id: `${name}-generate-level` });
  const noise = numberInput({ value: 0.05, id: `${name}-generate-noise` });
  const seed = numberInput({ value: state.info.defaults.seed, id: `${name}-generate-seed` });
  // Elastic joints (docs/elastic.md): compliances drawn at level L, a payload carried.
  const compliance = numberInput({ placeholder: 'rigid', id: `${name}-generate-compliance` });
  const payload = h('input', { type: 'text', class: 'vector', placeholder: 'none, or e.g. 10kg,0,0,100mm', id: `${name}-generate-payload` });
  // A measurement frame that is not levelled: gravity leans by two angles.
  const tilt = h('input', { type: 'text', class: 'vector', placeholder: 'level, or e.g. 2deg,-1.5deg', id: `${name}-generate-tilt` });
  const saveAs = h('input', { type: 'text', id: `${name}-generate-save`, placeholder: 'optional, e.g. data.csv', class: 'vector' });
  const overwrite = h('input', { type: 'checkbox', id: `${name}-generate-overwrite` });
  real.addEventListener('focus', () => refreshRealChoices(real));
  refreshRealChoices(real);
  const cell = cellInputs(name, 'generate');
  generationCells[name] = cell.request;
  const run = runButton(`${name}-generate-run`, 'Generate', () => generateInto(name, null));
  return h('div', { class: 'panel', id: `${name}-generate` },
    h('div', { class: 'form' },
      field('Configurations', count),
      field('Real robot', real),
      field('Error level L (±L cm, ±L°, ±L %)', level),
      field('Sensor noise σ (mm; mrad)', noise),
      field('Seed', seed),
      methodInfo(name).elastic ? field('Compliance level L (L·2e-6…1e-5 rad/N·m)', compliance) : null,
      methodInfo(name).elastic ? field('Payload (mass[,x,y,z] in the tool frame)', payload) : null,
      methodInfo(name).elastic ? field('Gravity tilt (tilt1,tilt2: a frame not levelled)', tilt) : null,
      optionFields(method, 'generate'),
      ...cell.fields,
      field('Save to the folder as', saveAs),
      h('label', {}, overwrite, ' replace'),
      run),
    h('p', { class: 'hint', text: 'Configurations of the simulated real robot that satisfy the method’s constraint, with what the sensor measures there.' }),
    result);
}

function refreshRealChoices(select) {
  const previous = select.value;
  select.replaceChildren(h('option', { value: 'random', text: 'nominal + random errors' }),
    ...state.files.robots.map((file) => h('option', { value: `file:${file}`, text: file })));
  if ([...select.options].some((o) => o.value === previous)) select.value = previous;
}

function renderGenerated(container, name, generated) {
  const preview = generated.csv.split('\n').slice(0, 6).join('\n');
  container.replaceChildren(...[
    h('div', { class: 'cards' },
      stat('configurations', String(generated.configurations), { id: `${name}-generate-count-result`, class: 'ok' }),
      stat('terminal point moved, RMS (mm)', fixed(generated.displacement_rms * 1e3, 2)),
      stat('largest (mm)', fixed(generated.displacement_max * 1e3, 2))),
    generated.saved ? h('p', { text: `Saved to ${generated.saved}.` }) : null,
    h('div', { class: 'actions' },
      h('button', { type: 'button', id: `${name}-generate-download`, text: `Download ${generated.file_name}`, onclick: () => download(generated.file_name, generated.csv, 'text/csv') }),
      h('button', {
        type: 'button',
        id: `${name}-generate-identify`,
        text: 'Identify these data',
        onclick: () => {
          selectFunction('identify');
          $(`${name}-identify-data`).value = 'generated';
          $(`${name}-identify-data`).dispatchEvent(new Event('change'));
        },
      }),
      h('button', {
        type: 'button',
        id: `${name}-generate-held-out`,
        text: 'Held-out data: the same real robot, new configurations',
        onclick: () => generateHeldOut(name),
      }),
      h('button', { type: 'button', text: 'Save the real robot as…', onclick: () => saveAsDialog(generated.real, `${slug(tableDocument().name || 'robot')}-real.toml`) })),
    h('p', { class: 'muted', id: `${name}-generate-origin`, text: originText(generated.origin) }),
    h('p', { class: 'muted', id: `${name}-generate-held-out-status` }),
    h('pre', { class: 'preview', text: `${preview}\n…` })].filter(Boolean));
}

/** Where generated data came from, in words. */
function originText(origin) {
  if (!origin) return '';
  const real = origin.real
    ? `the real robot of ${origin.real}`
    : `a real robot drawn from the table's at error level ${origin.level} (seed ${origin.seed})`;
  const noise = `sensor noise σ ${fixed(origin.noise * 1e3, 3)} mm`;
  return origin.heldOutOf
    ? `Held out: the same real robot as ${origin.heldOutOf}, new configurations (seed ${origin.seed}), ${noise}.`
    : `Measured on ${real}, configurations seed ${origin.seed}, ${noise}.`;
}

/**
 * Held-out data for the data generated last: the same real robot (not one
 * drawn again with another seed), new configurations, the same noise; they
 * are chosen in Evaluate.
 */
async function generateHeldOut(name) {
  const source = state.generated[name];
  const status = $(`${name}-generate-held-out-status`);
  status.textContent = 'Generating held-out data…';
  const serial = nextSerial(state.heldOut[name]);
  try {
    const request = {
      robot: tableDocument(),
      method: methodRequest(name, 'generate'),
      count: source.configurations,
      noise: source.origin.noise,
      seed: source.origin.seed + 1000 * serial,
      real: source.real,
      cell: generationCells[name](),
    };
    const heldOut = await api('/generate', request);
    heldOut.serial = serial;
    heldOut.file_name = heldOut.file_name.replace(/\.csv$/, '-held-out.csv');
    heldOut.origin = { ...source.origin, seed: request.seed, heldOutOf: source.file_name };
    state.heldOut[name] = heldOut;
    refreshDataChoices(name);
    const evaluate = $(`${name}-evaluate-data`);
    evaluate.value = 'held-out';
    evaluate.dispatchEvent(new Event('change'));
    status.textContent = `${originText(heldOut.origin)} ${heldOut.configurations} configurations, chosen in Evaluate.`;
  } catch (error) {
    status.textContent = error.message;
  }
}
