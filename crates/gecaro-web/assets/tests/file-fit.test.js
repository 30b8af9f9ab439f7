// Which data files a method can read (js/file-fit.js): the data menus list
// those first.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { columnMap, dataColumns, fits, isProgram } from '../js/file-fit.js';

const position = { name: 'position', columns: ['x', 'y', 'z'] };
const frame = { name: 'frame', columns: ['x', 'y', 'z', 'qw', 'qx', 'qy', 'qz'] };
const pointLink = { name: 'point-link', columns: ['set'] };

test('a file fits a method when its header holds the method\'s columns', () => {
  const positions = ['qm1', 'qm2', 'qm3', 'x', 'y', 'z'];
  assert.ok(fits(positions, dataColumns(position)));
  assert.ok(!fits(positions, dataColumns(frame)), 'no orientation');
  assert.ok(!fits(positions, dataColumns(pointLink)), 'no set column');
  assert.ok(fits(['QM1', 'X', 'Y', 'Z', 'time'], dataColumns(position)), 'case and extra columns do not matter');
  assert.ok(!fits(null, dataColumns(position)), 'a header not read fits nothing');
});

test('a column map renames the file\'s columns as the File format field says', () => {
  const tracker = ['A1', 'A2', 'X_mm', 'Y_mm', 'Z_mm'];
  assert.ok(!fits(tracker, dataColumns(position)));
  const map = columnMap(' qm1=A1, x = X_mm,y=Y_mm,z=Z_mm,bad, =nothing');
  assert.deepEqual(map, { qm1: 'a1', x: 'x_mm', y: 'y_mm', z: 'z_mm' });
  assert.ok(fits(tracker, dataColumns(position), map));
});

test('a program has joint or Cartesian targets', () => {
  assert.ok(isProgram(['qm1', 'qm2', 'speed']));
  assert.ok(isProgram(['x', 'y', 'z', 'qw', 'qx', 'qy', 'qz']));
  assert.ok(!isProgram(['time', 'speed']));
});
