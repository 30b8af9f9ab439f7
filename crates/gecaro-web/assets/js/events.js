/**
 * The page's events: how a lower module tells the ones above it that
 * something happened, so that imports run one way (a module never imports
 * the modules that use it). `main.js` wires the listeners.
 *
 * - `server-back`: the server answers again after it was lost.
 * - `files-changed`: the folder's file lists (`state.files`) were read again.
 * - `overlay`: the 3D view has something else to draw: a result's (`state.overlay`),
 *   or the cell's floor and tracker as typed.
 */
const bus = new EventTarget();

/** Tells the listeners of `name` (with `detail`, if any). */
export function emit(name, detail) {
  bus.dispatchEvent(new CustomEvent(name, { detail }));
}

/** Calls `listener(detail)` each time `name` is emitted. */
export function on(name, listener) {
  bus.addEventListener(name, (event) => listener(event.detail));
}
