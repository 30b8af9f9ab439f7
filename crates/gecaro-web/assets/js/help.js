// The Help dialog: what each function does, with the paper's equations.
import { openDialog } from './dialogs.js';
import { h } from './dom.js';

/** What each function does, with the paper's equations and the docs. */
export function helpDialog() {
  const item = (title, text) => h('div', { class: 'help-item' }, h('h3', { text: title }), h('p', { text }));
  openDialog({
    title: 'Help',
    body: h('div', { id: 'help-body' },
      item('The robot table', 'Khalil–Kleinfinger parameters of frames 0…n+1 (eq. 2–3): σ (0 revolute, 1 prismatic, 2 fixed), α, d, θ, r, Hayati β for parallel axes, the gain K and offset of every joint (eq. 4) and its limits. Edits are checked as you type; Ctrl+Z and Ctrl+Y undo and redo them. The page keeps the table in this browser across reloads; Save writes it to the folder.'),
      item('Identifiable parameters', 'The QR decomposition of the observation matrix W on random configurations (Appendix III, eq. 34): which parameters the method can identify, which are regrouped with others (and how), which have no effect. The priority matrix decides which of a regrouped set is kept: by decreasing priority.'),
      item('Plan', 'Chooses the configurations to measure from a pool (D-, A-, E-optimal or the test-pose error): the fewer measurements for the same precision, and the accuracy curve against their number (docs/planning.md).'),
      item('Points generation', 'Simulates a real robot (the nominal one with random errors) and what a sensor with the given noise would measure: data with a known answer, to try a method before measuring.'),
      item('Identification', 'Iterated linearised least squares (eq. 10) with the precision of every parameter (eq. 11), robust losses, priors, cross-validation. The verdict says whether the result can be trusted: converged, and whether the residuals fit the stated sensor noise (a χ² test). Read the files as the instrument wrote them: units, column names and separator under “File format”.'),
      item('Evaluate', 'The errors of the table’s robot and of the calibrated one on held-out measurements: the honest measure of a calibration.'),
      item('Compensate', 'A program written for the table’s robot (joint or Cartesian targets, a CSV file of the folder or an upload) corrected for the calibrated robot of this method, target by target: each one reached, reached in another configuration, beyond a joint limit or not reached. The corrected file keeps the program’s columns and units; download it or save it in the folder.'),
      item('Units', 'The Units menu shows the whole page in mm and degrees, or in metres and radians: the robot table, the identified parameters, the residual σ and the evaluation. It changes what is shown and typed, not the robot file, which keeps metres and its own angle unit.'),
      h('p', { class: 'muted', text: 'More in the docs folder of gecaro: docs/methods.md (methods and verdict), docs/planning.md, docs/tracker.md (a laser-tracker cell from end to end), docs/web.md (this page), docs/api.md (its JSON API).' })),
  });
}
