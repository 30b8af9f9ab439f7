// A study's statement and the editor's form of it (js/study-spec.js): one
// into the other and back, and what the page refuses before the server.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { emptyStudy, studyOf, studySpec, studyWords } from '../js/study-spec.js';

const statement = {
  robot: 'irb1600.toml',
  length_unit: 'mm',
  angle_unit: 'deg',
  tools: { smr_a: { position: [10, 0, 55], rpy: [0, 0, 0] }, probe: { position: [0, 0, 80], quaternion: [1, 0, 0, 0] } },
  stations: { left: { position: [2500, -800, 400], rpy: [0, 0, 90], sigma: 0.01 } },
  measurements: [
    { method: 'position', data: 'left.csv', tool: 'smr_a', station: 'left', sigma: 0.02 },
    { method: 'frame', data: 'probe.csv', tool: 'probe' },
  ],
  tracker_note: 'kept as it is',
};

test('a statement goes through the editor and comes back the same', () => {
  const form = studyOf(statement, 'cell.toml');
  assert.equal(form.name, 'cell.toml');
  assert.deepEqual(form.tools[0].position, ['10', '0', '55']);
  assert.equal(form.tools[1].rpy, null, 'a quaternion is kept as stated, not shown as angles');
  const back = studySpec(form, { robot: 'other.toml' });
  assert.deepEqual(back, statement, 'the study names its own robot first, and unknown keys are kept');
});

test('without a robot to name, the statement names none', () => {
  const form = studyOf({ ...statement, robot: undefined }, 'cell.toml');
  assert.equal(studySpec(form).robot, undefined);
  assert.throws(() => studySpec(form, { robot: null }), /names its robot: save the robot/);
  assert.equal(studySpec(form, { robot: 'stanford' }).robot, 'stanford');
});

test('the page refuses what a study cannot hold, in the field\'s words', () => {
  const form = studyOf(statement, 'cell.toml');
  form.stations[0].position[1] = 'abc';
  assert.throws(() => studySpec(form), /left y: “abc” is not a number/);
  form.stations[0].position[1] = '-800';
  form.measurements[0].sigma = '-1';
  assert.throws(() => studySpec(form), /Set 1 σ: -1 is out of range/);
  form.measurements[0].sigma = 'abc';
  assert.throws(() => studySpec(form), /Set 1 σ: “abc” is not a number, or a length with its unit/);
  form.measurements[0].sigma = '2e-5 m';
  assert.equal(studySpec(form).measurements[0].sigma, '2e-5m', 'a length with its unit, as a planned study writes it');
  form.measurements[0].sigma = '0,02';
  assert.equal(studySpec(form).measurements[0].sigma, 0.02, 'a decimal comma is read as one');
  form.measurements[0].sigma = '20,5 um';
  assert.equal(studySpec(form).measurements[0].sigma, '20.5um');
  form.measurements[0].sigma = '20um';
  assert.equal(studySpec(form).measurements[0].sigma, '20um');
  form.measurements[0].sigma = '20 parsecs';
  assert.throws(() => studySpec(form), /is not a number, or a length/);
  form.measurements[0].sigma = '-3um';
  assert.throws(() => studySpec(form), /out of range/);
  form.measurements[0].sigma = '';
  assert.equal(studySpec(form).measurements[0].sigma, undefined, 'an empty σ is not stated');
  form.tools[1].name = 'smr_a';
  assert.throws(() => studySpec(form), /Two tools are named smr_a/);
  form.tools[1].name = '2nd reflector';
  assert.throws(() => studySpec(form), /is not a name/);
  assert.throws(() => studySpec(emptyStudy()), /no measurement set/);
  const unchosen = emptyStudy();
  unchosen.measurements.push({ method: 'position', data: '', sigma: '' });
  assert.throws(() => studySpec(unchosen), /Set 1: choose its data file/);
});

test('a set\'s payload is its text, a table is shown as the same text, and a mass needs its unit', () => {
  const loaded = {
    ...statement,
    model: 'elastic',
    measurements: [
      { method: 'position', data: 'p10.csv', payload: '10kg,0,0,100mm' },
      { method: 'position', data: 'p20.csv', payload: { mass: '20kg', com: [0, 0.0, '120mm'] } },
      { method: 'position', data: 'p0.csv' },
    ],
  };
  const form = studyOf(loaded, 'payloads.toml');
  assert.equal(form.measurements[1].payload, '20kg,0,0,120mm');
  const back = studySpec(form);
  assert.equal(back.model, 'elastic', 'the study\'s model is kept');
  assert.deepEqual(back.measurements.map((set) => set.payload), ['10kg,0,0,100mm', '20kg,0,0,120mm', undefined]);
  form.measurements[0].payload = ' 5 kg , 0, 0, 80mm ';
  assert.equal(studySpec(form).measurements[0].payload, '5 kg,0,0,80mm');
  form.measurements[0].payload = '';
  assert.equal(studySpec(form).measurements[0].payload, undefined, 'an empty payload is not stated');
  form.measurements[0].payload = '20';
  assert.throws(() => studySpec(form), /Set 1 payload: “20” is not a payload: its mass with kg or g/);
  form.measurements[0].payload = '20kg,0,100mm';
  assert.throws(() => studySpec(form), /Set 1 payload/);
});


test('the server\'s set numbers (from 0) are the editor\'s (from 1)', () => {
  assert.equal(studyWords('measurements[0].tool: no tool named `bal` in this study'), 'Set 1 tool: no tool named `bal` in this study');
  assert.equal(studyWords('measurements[11]: no data'), 'Set 12: no data');
  assert.equal(studyWords('no set here'), 'no set here');
});
