// The page's status line: the panes' summary, an error naming its file (short), and while a file
// loads its name and the bytes read (state.loading).
import { loadingText, mb } from './loading.js';

/**
 * An error's message for the status line: naming the file, and short. A three.js message may hold
 * a whole array's values (megabytes, which pushed the page's controls off the window).
 */
export function errorText(name, e) {
  let m = String(e?.message ?? e);
  if (!m.startsWith(name)) m = `${name}: ${m}`;
  return m.length > 240 ? `${m.slice(0, 240)}…` : m;
}

/**
 * The status line in `line` (an element) for the page's state ({loading, error}). @returns
 * {{set(text, error?), loading(name, loaded, total, building?)}}: `set` shows the text, `error` (a
 * message within it) marking the line as an error; `loading` shows a file's load.
 */
export function statusLine(line, state) {
  function set(text, error = null) {
    state.loading = null;  // the panes' summary or an error ends the loading line
    line.textContent = text;
    line.classList.toggle('error', !!error);
    if (error) { state.error = error; console.error(error); }
  }

  /**
   * The line while `name` loads (state.loading: {name, loaded, total, building}): the bytes read
   * so far, then, with `building`, that its meshes are being made (a large .glb's frames take
   * seconds more). Updated at most every 100 ms: a large file arrives in thousands of pieces.
   */
  let shownAt = 0, timer = null;
  function loading(name, loaded, total, building = false) {
    state.loading = { name, loaded, total, building };
    const wait = 100 - (performance.now() - shownAt);
    if (!building && loaded > 0 && loaded < total && wait > 0) {
      // The latest state is shown when the interval is over (a stalled transfer shows where it is).
      timer ??= setTimeout(() => { timer = null; draw(); }, wait);
      return;
    }
    draw();
  }
  function draw() {
    const l = state.loading;
    if (!l) return;  // the load ended (set) before this update's turn
    shownAt = performance.now();
    line.classList.remove('error');
    line.textContent = l.building ? `Opening ${l.name} (${mb(l.loaded)}): making its meshes…` : loadingText(l.name, l.loaded, l.total);
  }
  return { set, loading };
}
