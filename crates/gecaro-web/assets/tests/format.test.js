// The page's number formats and parsers (js/format.js), under node.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { fixed, fmt, inFrameOrder, numberProblem, parseVector, payloadList, readNumber, sci, slug } from '../js/format.js';

test('numbers keep 8 significant digits, and go exponential outside 1e-4..1e7', () => {
  assert.equal(fmt(0.1 + 0.2), '0.3');
  assert.equal(fmt(1.23456789), '1.2345679');
  assert.equal(fmt(0), '0');
  assert.equal(fmt(null), '');
  assert.equal(fmt(2.5e-5), '2.5000e-5');
  assert.equal(fmt(-3e8), '-3.0000e+8');
});

test('a value that is not finite shows as a dash, not NaN', () => {
  assert.equal(fixed(Number.NaN, 2), '–');
  assert.equal(sci(Number.POSITIVE_INFINITY), '–');
  assert.equal(fixed(1.005, 1), '1.0');
  assert.equal(sci(0.000123), '1.23e-4');
});

test('file names from robot names', () => {
  assert.equal(slug('Stanford arm (calibrated)'), 'stanford-arm-calibrated');
  assert.equal(slug('***'), 'robot');
});

test('a vector takes three numbers, separated by commas, semicolons or spaces', () => {
  assert.deepEqual(parseVector(' 0.3, 0.5;0.81 ', 'normal'), [0.3, 0.5, 0.81]);
  assert.deepEqual(parseVector('1 2 3', 'point'), [1, 2, 3]);
  assert.throws(() => parseVector('1, 2', 'The plane normal'), /The plane normal needs three numbers/);
  assert.throws(() => parseVector('1, x, 3', 'point'), /point needs three numbers/);
});

test('a plan\'s payloads are separated by semicolons, their centres keep their commas', () => {
  assert.deepEqual(payloadList('0kg; 20kg,0,0,100mm ;'), ['0kg', '20kg,0,0,100mm']);
  assert.deepEqual(payloadList('  '), []);
});

test('a decimal comma is read as one, never as a thousands separator dropped', () => {
  assert.equal(readNumber('0,05'), 0.05);
  assert.equal(readNumber(' 0,02 '), 0.02);
  assert.equal(readNumber('-1,5'), -1.5);
  assert.equal(readNumber('\u22122,5e-3'), -2.5e-3);
  assert.equal(readNumber(',5'), 0.5);
  assert.equal(readNumber('0,050'), 0.05);
  assert.equal(readNumber('12.5'), 12.5);
  assert.equal(readNumber('1e-3'), 1e-3);
  assert.equal(readNumber('30'), 30);
});

test('a number whose meaning is not certain is refused, with why', () => {
  for (const text of ['1,500', '1.234,5', '1,2,3', '5 mm', 'abc', '', '0x10', 'Infinity']) {
    assert.ok(Number.isNaN(readNumber(text)), text);
  }
  assert.match(numberProblem('1,500'), /write 1\.500 or 1500/);
  assert.match(numberProblem('1.234,5'), /mixes a decimal comma and a decimal point/);
  assert.match(numberProblem('abc'), /“abc” is not a number/);
});

test('a vector of numbers with decimal commas, separated by semicolons or spaces', () => {
  assert.deepEqual(parseVector('0,3; 0,5; 0,81', 'normal'), [0.3, 0.5, 0.81]);
  assert.deepEqual(parseVector('0,3 0,5 0,81', 'normal'), [0.3, 0.5, 0.81]);
  assert.deepEqual(parseVector('0.3,0.5,0.81', 'normal'), [0.3, 0.5, 0.81]);
});

test('identified parameters in frame order, eq. 2–4 within a frame', () => {
  const names = ['K3', 'theta2', 'd3', 'alpha7', 'beta2', 'r1', 'theta10', 'smr_a.x'];
  const ordered = inFrameOrder(names.map((name) => ({ name }))).map((p) => p.name);
  assert.deepEqual(ordered, ['r1', 'theta2', 'beta2', 'd3', 'K3', 'alpha7', 'theta10', 'smr_a.x']);
});
