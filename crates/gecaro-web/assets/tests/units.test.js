// One choice of units for the page (js/units.js): the server's metres and
// radians shown in mm and degrees, or as they are.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { state } from '../js/state.js';
import { coordinate, inPageUnits, inUnits, quantity, unitName, unitOf } from '../js/units.js';

test('parameter and unknown names have their kind', () => {
  for (const name of ['alpha2', 'theta0', 'beta3', 'station_1.rx', 'tool.gamma']) assert.equal(unitOf(name), 'angle', name);
  for (const name of ['d3', 'r7', 'tool.x', 'plane.b', 'z']) assert.equal(unitOf(name), 'length', name);
  for (const name of ['K1', 'offset2']) assert.equal(unitOf(name), 'none', name);
});

test('mm and degrees, or metres and radians, for the whole page', () => {
  state.units = 'mm';
  assert.equal(inUnits(0.0125, 'length'), 12.5);
  assert.equal(inPageUnits(Math.PI / 2, 'angle'), '90');
  assert.equal(inUnits(1.01, 'none'), 1.01);
  assert.equal(unitName('length'), 'mm');
  assert.equal(unitName('angle'), '°');
  state.units = 'm';
  assert.equal(inUnits(0.0125, 'length'), 0.0125);
  assert.equal(inPageUnits(Math.PI / 2, 'angle'), '1.5708');
  assert.equal(unitName('angle'), 'rad');
  state.units = 'mm';
});

test('a quantity has 4 significant digits, a coordinate its resolution', () => {
  state.units = 'mm';
  assert.equal(quantity(3.11812e-5, 'length'), '0.03118');
  assert.equal(quantity(2.676, 'length'), '2676');
  assert.equal(coordinate(2.54593123, 'length'), '2545.93');
  assert.equal(coordinate(-0.0000001, 'length'), '0.00');
  assert.equal(coordinate(Math.PI / 4, 'angle'), '45.000');
  assert.equal(quantity(Number.NaN, 'length'), '–');
  state.units = 'm';
  assert.equal(coordinate(2.54593123, 'length'), '2.54593');
  state.units = 'mm';
});
