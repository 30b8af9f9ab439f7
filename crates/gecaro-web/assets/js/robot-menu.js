// The Robot menu: open a ready robot, a file of the folder (converted when
// it is a URDF, SYMORO or DH file) or an upload; new robot; Save and Save
// as (gecaro robot file or URDF).
import { api } from './api.js';
import { refreshDataChoices } from './data-choices.js';
import { openDialog, dialogError } from './dialogs.js';
import { h, $, toast } from './dom.js';
import { emit } from './events.js';
import { FieldError } from './fields.js';
import { slug } from './format.js';
import { setRobot, renderRobot } from './robot-table.js';
import { state, tableDocument } from './state.js';

export async function loadReady(name) {
  setRobot(await api(`/robots/ready/${encodeURIComponent(name)}`), null);
}

/**
 * Opens the robot a study names (`name`: a ready robot's name, or a robot
 * file relative to the study file `studyFile`, as the command line reads it).
 */
export async function loadStudyRobot(name, studyFile) {
  if (state.info.ready.includes(name)) return loadReady(name);
  return loadFile(studyRelative(name, studyFile));
}

/** The folder's name of a file a study file `studyFile` names (relative to the study's folder). */
export function studyRelative(name, studyFile) {
  const folder = studyFile && studyFile.includes('/') ? studyFile.slice(0, studyFile.lastIndexOf('/') + 1) : '';
  return `${folder}${name}`;
}

async function loadFile(name, chain = {}) {
  const query = [`name=${encodeURIComponent(name)}`];
  if (chain.base) query.push(`base=${encodeURIComponent(chain.base)}`);
  if (chain.tip) query.push(`tip=${encodeURIComponent(chain.tip)}`);
  const view = await api(`/robots/file?${query.join('&')}`);
  // A converted file is not the robot's file: saving writes a new one.
  setRobot(view, view.origin === 'imported' ? null : name);
}

export async function refreshFiles() {
  try {
    state.files = await api('/files');
  } catch (error) {
    state.files = { robots: [], data: [] };
  }
  for (const method of state.info.methods) refreshDataChoices(method.name);
  emit('files-changed');
}

export function openRobotDialog() {
  const ready = h('div', { class: 'choices' }, state.info.ready.map((name) => h('button', {
    type: 'button',
    id: `open-ready-${name}`,
    text: name,
    onclick: async () => {
      try {
        await loadReady(name);
        $('dialog').close();
      } catch (error) {
        dialogError(error.message);
      }
    },
  })));
  const list = h('div', { class: 'file-list' }, h('div', { class: 'empty', text: 'Loading…' }));
  const imports = h('div', { class: 'file-list', id: 'open-imports' }, h('div', { class: 'empty', text: 'Loading…' }));
  const base = h('input', { type: 'text', id: 'open-base', placeholder: 'root link' });
  const tip = h('input', { type: 'text', id: 'open-tip', placeholder: 'leaf with the most joints' });
  // A robot file from this computer (not the served folder): read here, sent
  // to the server to be checked or converted; nothing is written.
  const upload = h('input', { type: 'file', id: 'open-upload', accept: '.toml,.urdf,.par' });
  upload.addEventListener('change', async () => {
    const file = upload.files[0];
    if (!file) return;
    try {
      const view = await api('/robots/upload', {
        name: file.name,
        text: await file.text(),
        base: base.value.trim() || undefined,
        tip: tip.value.trim() || undefined,
      });
      view.uploaded = file.name;
      setRobot(view, null);
      $('dialog').close();
    } catch (error) {
      dialogError(error.message);
    }
  });
  openDialog({
    title: 'Open a robot',
    body: h('div', {},
      h('h3', { text: 'Ready robots' }), ready,
      h('h3', { text: `Robot files in ${state.info.folder}` }),
      h('p', { class: 'muted', text: 'gecaro robot files, and DH tables (TOML with convention = "dh" or "mdh"), converted.' }),
      list,
      h('h3', { text: 'URDF and SYMORO files (converted)' }),
      h('div', { class: 'chain-fields' },
        h('label', { class: 'dialog-field' }, 'URDF base link', base),
        h('label', { class: 'dialog-field' }, 'URDF tip link', tip)),
      imports,
      h('h3', { text: 'From this computer' }),
      h('label', { class: 'dialog-field' }, 'Upload a robot file (.toml, .urdf, .par)', upload)),
  });
  const button = (name) => h('button', {
    type: 'button',
    text: name,
    onclick: async () => {
      try {
        await loadFile(name, { base: base.value.trim(), tip: tip.value.trim() });
        $('dialog').close();
      } catch (error) {
        dialogError(error.message);
      }
    },
  });
  api('/files').then((files) => {
    state.files = files;
    list.replaceChildren(...(files.robots.length ? files.robots.map(button)
      : [h('div', { class: 'empty', text: 'No .toml files in this folder.' })]));
    imports.replaceChildren(...(files.imports && files.imports.length ? files.imports.map(button)
      : [h('div', { class: 'empty', text: 'No .urdf or .par files in this folder.' })]));
  }).catch((error) => dialogError(error.message));
}

export function newRobotDialog() {
  // Checked by the page, in its words (not the browser's generic pattern tooltip).
  const joints = h('input', { type: 'text', id: 'new-joints', value: 'RRRRRR' });
  const name = h('input', { type: 'text', id: 'new-name', placeholder: 'e.g. My arm' });
  openDialog({
    title: 'New robot',
    body: h('div', {},
      h('label', { class: 'dialog-field' }, 'Joint types, from joint 1 to n (R revolute, P prismatic)', joints),
      h('label', { class: 'dialog-field' }, 'Name', name),
      h('p', { class: 'muted', text: 'A template arm to edit: α alternates ±90°, the tool 0.1 m along the last z axis.' })),
    ok: 'Create',
    onOk: async () => {
      const letters = joints.value.trim();
      const bad = [...letters].find((letter) => !'RPrp'.includes(letter));
      joints.classList.toggle('invalid', !letters || bad !== undefined);
      if (!letters) throw new FieldError('Joint types: give one letter per joint, R (revolute) or P (prismatic).');
      if (bad !== undefined) throw new FieldError(`Joint types: “${bad}” is not R (revolute) or P (prismatic).`);
      const view = await api('/robots/new', { joints: letters, name: name.value.trim() || undefined });
      setRobot(view, null);
      state.dirty = true;
      renderRobot();
    },
  });
}

export function saveAsDialog(documentToSave, suggested, after) {
  const name = h('input', { type: 'text', id: 'save-name', value: suggested });
  const overwrite = h('input', { type: 'checkbox', id: 'save-overwrite' });
  const format = h('select', { id: 'save-format' },
    h('option', { value: 'toml', text: 'gecaro robot file (.toml)' }),
    h('option', { value: 'urdf', text: 'URDF (.urdf), with a joint calibration beside it if needed' }));
  format.addEventListener('change', () => {
    name.value = name.value.replace(/\.(toml|urdf)$/i, '') + `.${format.value}`;
  });
  const carried = h('p', { class: 'muted', id: 'save-urdf-note', hidden: true, text: 'A URDF carries the kinematics, joint limits and names; gains, couplings and offsets go to a joint-calibration file beside it when they are not the defaults. Meshes, inertia and collision geometry are not carried: gecaro’s robots have none, so merge the result into your original URDF for those.' });
  format.addEventListener('change', () => { carried.hidden = format.value !== 'urdf'; });
  openDialog({
    title: 'Save robot as',
    body: h('div', {},
      h('label', { class: 'dialog-field' }, 'Format', format),
      carried,
      h('label', { class: 'dialog-field' }, `File name in ${state.info.folder}`, name),
      h('label', {}, overwrite, ' Replace the file if it exists')),
    ok: 'Save',
    onOk: async () => {
      let saved;
      try {
        saved = await api('/robots/save', { robot: documentToSave, name: name.value.trim(), overwrite: overwrite.checked });
      } catch (error) {
        if ((error.problems || []).length) throw new Error(`${error.message} — fix the table first.`);
        throw error;
      }
      const beside = saved.joint_calibration ? ` and ${saved.joint_calibration} (gains and couplings)` : '';
      toast(`Saved ${saved.name}${beside}`);
      if (after) after(saved.name, saved.version);
      refreshFiles();
    },
  });
}

export function saveRobotAs() {
  const suggested = state.file || `${slug(tableDocument().name || 'robot')}.toml`;
  saveAsDialog(tableDocument(), suggested, (name, version) => {
    // A URDF is an export: the table stays tied to its robot file, if any.
    if (!name.toLowerCase().endsWith('.urdf')) {
      state.file = name;
      state.dirty = false;
      if (version) state.robot.version = version;
    }
    renderRobot();
  });
}

export async function saveRobot() {
  if (!state.file) {
    saveRobotAs();
    return;
  }
  const save = (expected) => api('/robots/save', {
    robot: tableDocument(), name: state.file, overwrite: true, expected_version: expected,
  });
  try {
    let saved;
    try {
      saved = await save(state.robot.version);
    } catch (error) {
      // Saved from elsewhere since it was opened: the user chooses.
      if (error.status !== 409) throw error;
      if (!window.confirm(`${error.message}\n\nReplace that change with this table?`)) {
        toast(`Not saved: ${state.file} changed since it was opened; reopen it to see the change`);
        return;
      }
      saved = await save(undefined);
    }
    state.robot.version = saved.version;
    state.dirty = false;
    renderRobot();
    toast(`Saved ${state.file}`);
  } catch (error) {
    toast(`Not saved: ${error.message}`);
  }
}
