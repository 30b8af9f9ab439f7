// The joint sliders and the 3D view of the robot (a projection on a
// canvas, dragged to turn and wheeled to zoom), with the method's plane
// and the generated data's points.
import { api } from './api.js';
import { statedCell } from './cell.js';
import { h, $ } from './dom.js';
import { fmt, parseVector } from './format.js';
import { state, tableDocument, methodInfo } from './state.js';

function sliderValue(index) {
  const joint = state.robot.summary.joints[index];
  return Math.min(Math.max(state.q[index] || 0, joint.qmin), joint.qmax);
}

function sliderText(index) {
  const joint = state.robot.summary.joints[index];
  const value = state.q[index];
  return joint.revolute ? `${(value * 180 / Math.PI).toFixed(1)}°` : `${value.toFixed(3)} m`;
}

export function renderSliders() {
  const summary = state.robot.summary;
  const container = $('sliders');
  if (!summary) {
    container.replaceChildren(h('span', { class: 'muted', text: 'Fix the table to move the robot.' }));
    return;
  }
  state.q = summary.joints.map((_, i) => state.q[i] || 0);
  const cells = summary.joints.flatMap((joint, i) => {
    state.q[i] = sliderValue(i);
    const output = h('output', { id: `slider-value-${i + 1}`, text: sliderText(i) });
    const input = h('input', {
      type: 'range',
      id: `slider-${i + 1}`,
      min: joint.qmin,
      max: joint.qmax,
      step: (joint.qmax - joint.qmin) / 2000,
      value: state.q[i],
      'aria-label': `joint ${i + 1}`,
      oninput: (event) => {
        state.q[i] = Number(event.target.value);
        output.textContent = sliderText(i);
        refreshPose();
      },
    });
    return [h('label', { for: `slider-${i + 1}`, text: `q${i + 1}` }), input, output];
  });
  container.replaceChildren(...cells);
}

export function updateSliderRanges() {
  state.robot.summary.joints.forEach((joint, i) => {
    const input = $(`slider-${i + 1}`);
    if (!input) return;
    input.min = joint.qmin;
    input.max = joint.qmax;
    input.step = (joint.qmax - joint.qmin) / 2000;
    state.q[i] = sliderValue(i);
    input.value = state.q[i];
    $(`slider-value-${i + 1}`).textContent = sliderText(i);
  });
}

let poseBusy = false;

let posePending = false;

export async function refreshPose() {
  if (!state.robot.summary) return;
  if (poseBusy) {
    posePending = true;
    return;
  }
  poseBusy = true;
  const serial = state.robotSerial;
  try {
    const pose = await api('/robots/pose', { robot: tableDocument(), q: state.q });
    // The shown method's calibrated robot at the same joints, beside it.
    const calibrated = state.calibrated[state.method];
    const other = calibrated && calibrated.frame && calibrated.frame.length === tableDocument().frame.length
      ? await api('/robots/pose', { robot: calibrated, q: state.q }).catch(() => null) : null;
    if (serial === state.robotSerial) {
      state.pose = pose.frames;
      state.calibratedPose = other ? other.frames : null;
      drawView();
    } else {
      posePending = true;
    }
  } catch (error) {
    if (serial === state.robotSerial && !error.unreachable) {
      state.pose = null;
      drawView(error.message);
    }
  } finally {
    poseBusy = false;
    if (posePending) {
      posePending = false;
      refreshPose();
    }
  }
}

/** The view's right and up directions in the world (the screen's x, and −y). */
function screenAxes() {
  const { azimuth, elevation } = state.view;
  return {
    right: [-Math.sin(azimuth), Math.cos(azimuth), 0],
    up: [-Math.sin(elevation) * Math.cos(azimuth), -Math.sin(elevation) * Math.sin(azimuth), Math.cos(elevation)],
  };
}

const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];

function project(point) {
  const { right, up } = screenAxes();
  return [dot(point, right), dot(point, up)];
}

/**
 * The screen ellipse of a 3D covariance `c` (m², the view's world) at `k`
 * σ, `pixels` per metre: the covariance projected on the screen,
 * `P C Pᵀ` with P's rows the view's right and −up, and its eigenvalues.
 */
function screenEllipse(c, k, pixels) {
  const { right, up } = screenAxes();
  const down = up.map((v) => -v);
  const times = (v) => [0, 1, 2].map((i) => dot(c[i], v));
  const a = dot(right, times(right));
  const b = dot(right, times(down));
  const d = dot(down, times(down));
  const mean = (a + d) / 2;
  const spread = Math.hypot((a - d) / 2, b);
  const radius = (value) => k * Math.sqrt(Math.max(value, 0)) * pixels;
  return { major: radius(mean + spread), minor: radius(mean - spread), angle: 0.5 * Math.atan2(2 * b, a - d) };
}

/** A round grid step: 1, 2 or 5 × 10^k, about `target`. */
function niceStep(target) {
  const power = Math.pow(10, Math.floor(Math.log10(target)));
  const mantissa = target / power;
  return (mantissa < 1.5 ? 1 : mantissa < 3.5 ? 2 : 5) * power;
}

/**
 * The calibrated robot's frame origins in the view (`state.calibratedPose`
 * placed on the table's by frame 0: `N₀·C₀⁻¹·p`), each one's difference
 * from the table's magnified by a round factor that makes the largest a
 * twelfth of the view; none without a calibrated robot or a difference.
 */
function calibratedGhost(radius) {
  const nominal = state.pose;
  const calibrated = state.calibratedPose;
  if (!nominal || !calibrated || calibrated.length !== nominal.length) return null;
  const [n0, c0] = [nominal[0], calibrated[0]];
  const placed = calibrated.map((frame) => {
    const v = frame.origin.map((value, k) => value - c0.origin[k]);
    const local = [dot(v, c0.x), dot(v, c0.y), dot(v, c0.z)];
    return [0, 1, 2].map((k) => n0.origin[k] + local[0] * n0.x[k] + local[1] * n0.y[k] + local[2] * n0.z[k]);
  });
  const differences = placed.map((p, j) => p.map((value, k) => value - nominal[j].origin[k]));
  const largest = Math.max(...differences.map((d) => Math.hypot(...d)));
  if (!(largest > 1e-9)) return null;
  const gain = roundGain((radius / 12) / largest);
  return { gain, origins: nominal.map((frame, j) => frame.origin.map((value, k) => value + gain * differences[j][k])) };
}

/** The places the view draws beyond the robot: the cell's tracker, a result's measured points, instrument and stations. */
function overlayPlaces() {
  const overlay = state.overlay;
  const cell = state.info ? statedCell(state.method) : { station: null };
  const tracker = cell.station ? [cell.station] : [];
  if (!overlay) return tracker;
  return [...tracker, ...overlay.points.map((p) => p.at), overlay.instrument.at, ...overlay.stations.map((s) => s.at)];
}

/** A round magnification: 1, 2 or 5 × 10^k, at most `target`. */
function roundGain(target) {
  const power = Math.pow(10, Math.floor(Math.log10(target)));
  const mantissa = target / power;
  return (mantissa >= 5 ? 5 : mantissa >= 2 ? 2 : 1) * power;
}

/** A filled and outlined polygon through the screen points `corners`. */
function polygon(context, corners, fill, stroke, width) {
  context.fillStyle = fill;
  context.strokeStyle = stroke;
  context.lineWidth = width;
  context.beginPath();
  corners.forEach(([x, y], i) => (i ? context.lineTo(x, y) : context.moveTo(x, y)));
  context.closePath();
  context.fill();
  context.stroke();
}

/** An instrument on its tripod: a triangle at screen point `at`, with its name. */
function tripod(context, [x, y], colour, name) {
  context.fillStyle = colour;
  context.beginPath();
  context.moveTo(x, y - 8);
  context.lineTo(x - 7, y + 6);
  context.lineTo(x + 7, y + 6);
  context.closePath();
  context.fill();
  context.font = '12px system-ui, sans-serif';
  context.fillText(name, x + 10, y + 4);
}

/**
 * The overlay of the last result (`state.overlay`, deviations.js): each
 * measured point with its error vector (magnified, the largest about a
 * seventh of the view, green to red by size), the instrument and its
 * stations; returns what it drew.
 */
function drawOverlay(context, toScreen, radius, pixels) {
  const overlay = state.overlay;
  if (!overlay || !state.pose) return { vectors: 0, stations: 0, ellipses: 0, gain: 0 };
  const base = state.pose[0];
  // Deviations are along the robot's base axes: into the view's world.
  const inWorld = (d) => [0, 1, 2].map((k) => d[0] * base.x[k] + d[1] * base.y[k] + d[2] * base.z[k]);
  const largest = Math.max(1e-12, ...overlay.points.map((p) => Math.hypot(...p.deviation)));
  const gain = roundGain((radius * 0.15) / largest);
  context.lineWidth = 1.5;
  for (const point of overlay.points) {
    const size = Math.hypot(...point.deviation) / largest;
    const [x, y] = toScreen(point.at);
    const tip = inWorld(point.deviation).map((v, k) => point.at[k] + v * gain);
    const [tx, ty] = toScreen(tip);
    context.strokeStyle = `hsl(${Math.round(120 * (1 - size))}, 75%, 40%)`;
    context.beginPath();
    context.moveTo(x, y);
    context.lineTo(tx, ty);
    context.stroke();
    context.fillStyle = '#5b6775';
    context.beginPath();
    context.arc(x, y, 2, 0, 2 * Math.PI);
    context.fill();
  }
  // The instrument (the measurement frame's origin) and its stations: a
  // tripod's triangle with its name.
  const places = [overlay.instrument, ...overlay.stations];
  let ellipses = 0;
  for (const place of places) {
    const [x, y] = toScreen(place.at);
    // A station's uncertainty: its 3σ ellipsoid, magnified as the vectors are.
    if (place.covariance) {
      const shape = screenEllipse(place.covariance, 3, pixels * gain);
      context.strokeStyle = 'rgba(138, 63, 252, 0.8)';
      context.lineWidth = 1.5;
      context.beginPath();
      context.ellipse(x, y, Math.max(shape.major, 1), Math.max(shape.minor, 1), shape.angle, 0, 2 * Math.PI);
      context.stroke();
      ellipses += 1;
    }
    tripod(context, [x, y], '#8a3ffc', place.name);
  }
  return { vectors: overlay.points.length, stations: overlay.stations.length, ellipses, gain };
}

/** Centre and radius of what is drawn: the world origin, every frame and the overlay. */
function viewBounds(origins) {
  const points = [[0, 0, 0], ...origins, ...overlayPlaces()];
  const low = [0, 1, 2].map((k) => Math.min(...points.map((p) => p[k])));
  const high = [0, 1, 2].map((k) => Math.max(...points.map((p) => p[k])));
  const centre = low.map((l, k) => (l + high[k]) / 2);
  const radius = Math.max(0.1, Math.hypot(...high.map((h_, k) => h_ - low[k])) / 2);
  return { centre, radius };
}

export function drawView(message) {
  const canvas = $('robot-view');
  const ratio = window.devicePixelRatio || 1;
  const width = canvas.clientWidth;
  const height = canvas.clientHeight;
  if (canvas.width !== width * ratio) {
    canvas.width = width * ratio;
    canvas.height = height * ratio;
  }
  const context = canvas.getContext('2d');
  context.setTransform(ratio, 0, 0, ratio, 0, 0);
  context.clearRect(0, 0, width, height);
  if (!state.pose) {
    context.fillStyle = '#5b6775';
    context.font = '14px system-ui, sans-serif';
    context.fillText(message || 'No valid robot to draw.', 16, 28);
    return;
  }
  const origins = state.pose.map((f) => f.origin);
  if (!state.view.bounds) state.view.bounds = viewBounds(origins);
  const { centre, radius } = state.view.bounds;
  const scale = (Math.min(width, height) * 0.46 * state.view.zoom) / radius;
  const [cx, cy] = project(centre);
  const toScreen = (point) => {
    const [x, y] = project(point);
    return [width / 2 + (x - cx) * scale, height / 2 - (y - cy) * scale];
  };
  const line = (a, b, color, widthPx, dash) => {
    const [ax, ay] = toScreen(a);
    const [bx, by] = toScreen(b);
    context.strokeStyle = color;
    context.lineWidth = widthPx;
    context.setLineDash(dash || []);
    context.beginPath();
    context.moveTo(ax, ay);
    context.lineTo(bx, by);
    context.stroke();
    context.setLineDash([]);
  };
  // Floor grid (the world's xy plane) around the robot.
  const step = niceStep(radius / 4);
  const extent = Math.ceil((radius * 1.2) / step) * step;
  const [gx, gy] = [Math.round(centre[0] / step) * step, Math.round(centre[1] / step) * step];
  for (let v = -extent; v <= extent + 1e-9; v += step) {
    line([gx + v, gy - extent, 0], [gx + v, gy + extent, 0], '#e3e8ee', 1);
    line([gx - extent, gy + v, 0], [gx + extent, gy + v, 0], '#e3e8ee', 1);
  }
  // The current method's plane (plane methods) and the points of its
  // generated data (methods that measure a point), in the world frame.
  // What is drawn, on the canvas for whoever checks it (the browser tests).
  const drawn = { plane: false, points: 0, floor: false, tracker: false };
  const method = state.info && methodInfo(state.method);
  if (method && method.uses_plane) {
    try {
      const normal = parseVector($(`${state.method}-identify-normal`).value, 'normal');
      const point = parseVector($(`${state.method}-identify-point`).value, 'point');
      const length = Math.hypot(...normal);
      const n = normal.map((v) => v / length);
      const helper = Math.abs(n[2]) < 0.9 ? [0, 0, 1] : [1, 0, 0];
      const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
      const u = cross(n, helper);
      const ul = Math.hypot(...u);
      const e1 = u.map((v) => v / ul);
      const e2 = cross(n, e1);
      const half = radius * 0.6;
      const corner = (a, b) => point.map((p, k) => p + (a * e1[k] + b * e2[k]) * half);
      const corners = [corner(-1, -1), corner(1, -1), corner(1, 1), corner(-1, 1)].map(toScreen);
      polygon(context, corners, 'rgba(31, 111, 235, 0.10)', 'rgba(31, 111, 235, 0.6)', 1.5);
      drawn.plane = true;
    } catch (error) {
      // No valid plane in the fields yet: nothing to draw.
    }
  }
  // The real robot's terminal points where the generated data were measured
  // (on the plane for the plane methods, on the fixed points for the links).
  const generated = state.generated[state.method];
  if (generated && generated.points) {
    context.fillStyle = 'rgba(214, 39, 40, 0.75)';
    for (const point of generated.points) {
      const [x, y] = toScreen(point);
      context.beginPath();
      context.arc(x, y, 2.5, 0, 2 * Math.PI);
      context.fill();
      drawn.points += 1;
    }
  }
  // The cell the shown method's fields state: its floor and its tracker.
  const cell = statedCell(state.method);
  if (cell.floor !== null) {
    const corners = [[-1, -1], [1, -1], [1, 1], [-1, 1]].map(([a, b]) => toScreen([gx + a * extent, gy + b * extent, cell.floor]));
    polygon(context, corners, 'rgba(160, 120, 60, 0.12)', 'rgba(160, 120, 60, 0.7)', 1);
    drawn.floor = true;
  }
  if (cell.station) {
    tripod(context, toScreen(cell.station), '#b35c00', 'tracker (cell)');
    drawn.tracker = true;
  }
  // The calibrated robot at the same joints, its frames placed on the
  // table's by frame 0 (a tracker's calibration is drawn on the robot, not
  // 2.5 m away), its differences magnified: orange, dashed.
  const ghost = calibratedGhost(radius);
  if (ghost) {
    for (let i = 0; i + 1 < ghost.origins.length; i += 1) line(ghost.origins[i], ghost.origins[i + 1], '#e67e00', 2.5, [6, 4]);
    drawn.calibrated = ghost.gain;
  }
  // The last plan's poses (their tool points), blue rings.
  const planned = state.plannedPoints[state.method] || [];
  context.strokeStyle = 'rgba(31, 111, 235, 0.9)';
  context.lineWidth = 1.5;
  for (const point of planned) {
    const [x, y] = toScreen(point);
    context.beginPath();
    context.arc(x, y, 3.5, 0, 2 * Math.PI);
    context.stroke();
  }
  drawn.planned = planned.length;
  const overlaid = drawOverlay(context, toScreen, radius, scale);
  // World axes.
  const axis = radius * 0.12;
  line([0, 0, 0], [axis, 0, 0], '#e8a3a3', 1.5);
  line([0, 0, 0], [0, axis, 0], '#9fd09f', 1.5);
  line([0, 0, 0], [0, 0, axis], '#9dbfe0', 1.5);
  line([0, 0, 0], origins[0], '#9aa6b2', 2, [5, 4]);
  // Links between successive frame origins.
  context.lineCap = 'round';
  for (let i = 0; i + 1 < origins.length; i += 1) line(origins[i], origins[i + 1], '#3b4a5a', 7);
  context.lineCap = 'butt';
  // Frame axes: x red, y green, z blue; the tool's larger.
  state.pose.forEach((frame, j) => {
    const size = j === state.pose.length - 1 ? axis * 1.6 : axis;
    const tip = (v) => frame.origin.map((o, k) => o + v[k] * size);
    line(frame.origin, tip(frame.x), '#d62728', 2);
    line(frame.origin, tip(frame.y), '#2ca02c', 2);
    line(frame.origin, tip(frame.z), '#1f77b4', 2.5);
  });
  // Origins, with the numbers of the frames that share a point.
  const spots = [];
  state.pose.forEach((frame, j) => {
    const [x, y] = toScreen(frame.origin);
    const spot = spots.find((s) => Math.hypot(s.x - x, s.y - y) < 4);
    if (spot) spot.frames.push(j); else spots.push({ x, y, frames: [j] });
  });
  context.font = '12px system-ui, sans-serif';
  const last = state.pose.length - 1;
  for (const spot of spots) {
    const joint = spot.frames.some((j) => j !== 0 && j !== last);
    context.fillStyle = '#ffffff';
    context.strokeStyle = '#14202e';
    context.lineWidth = 2;
    context.beginPath();
    context.arc(spot.x, spot.y, joint ? 6 : 4, 0, 2 * Math.PI);
    context.fill();
    context.stroke();
    context.fillStyle = '#14202e';
    context.fillText(spot.frames.join(','), spot.x + 9, spot.y - 8);
  }
  context.fillStyle = '#5b6775';
  context.fillText(`floor grid ${fmt(step)} m`, 10, height - 10);
  canvas.dataset.plane = String(drawn.plane);
  canvas.dataset.points = String(drawn.points);
  canvas.dataset.vectors = String(overlaid.vectors);
  canvas.dataset.stations = String(overlaid.stations);
  canvas.dataset.ellipses = String(overlaid.ellipses);
  canvas.dataset.floor = String(drawn.floor);
  canvas.dataset.planned = String(drawn.planned || 0);
  canvas.dataset.calibrated = String(drawn.calibrated || 0);
  canvas.dataset.tracker = String(drawn.tracker);
  const caption = $('view-overlay');
  if (caption) {
    const ghostText = drawn.calibrated ? `Orange, dashed: the calibrated robot at the same joints, its differences from the table’s magnified ×${fmt(drawn.calibrated)}. ` : '';
    caption.replaceChildren(ghostText, ...(state.overlay ? [
      `Error vectors of ${state.overlay.source}, magnified ×${fmt(overlaid.gain)} (green small, red the largest); ▲ the instrument${state.overlay.stations.length ? ' and its stations, each ringed by its 3σ uncertainty magnified alike' : ''}. `,
      h('button', { type: 'button', class: 'link', id: 'view-overlay-hide', text: 'Hide', onclick: () => { state.overlay = null; state.view.bounds = null; drawView(); } }),
    ] : []));
  }
}

export function installViewControls() {
  const canvas = $('robot-view');
  let dragging = null;
  canvas.addEventListener('pointerdown', (event) => {
    dragging = { x: event.clientX, y: event.clientY };
    canvas.setPointerCapture(event.pointerId);
  });
  canvas.addEventListener('pointermove', (event) => {
    if (!dragging) return;
    state.view.azimuth -= (event.clientX - dragging.x) * 0.01;
    state.view.elevation = Math.max(-1.5, Math.min(1.5, state.view.elevation + (event.clientY - dragging.y) * 0.01));
    dragging = { x: event.clientX, y: event.clientY };
    drawView();
  });
  canvas.addEventListener('pointerup', () => { dragging = null; });
  canvas.addEventListener('wheel', (event) => {
    event.preventDefault();
    state.view.zoom = Math.max(0.2, Math.min(8, state.view.zoom * Math.exp(-event.deltaY * 0.001)));
    drawView();
  }, { passive: false });
}
