// ShellContract viewer: plays the morph-target animation of a run's .glb (one target per exported
// frame, STEP keyframes), scrubs it and jumps to a frame, plots V/V0 from the run's CSV log or JSON
// summary, switches the colour fields, and opens result meshes (OFF, OBJ, PLY, STL, a .glb or .gltf
// mesh, such as run's result of a glTF input; an OBJ with
// the .mtl and textures chosen with it). Two files are shown side by side (before and after, one
// camera; of more chosen, the status line names those not opened); a single .glb can show its
// first frame beside the current one. Each frame is coloured with its own values where the file
// has them (the glTF's extras.frame_fields); a field of one frame only (extras 'frame') is shown on
// that frame and never on the others; a mesh file is coloured with its own values. With no field
// shown, a file's primitives (or an OBJ's groups) wear its materials (base colour, texture), and a
// file with materials opens so. Two runs' .glb side by side step by run frame. An error names its
// file, briefly.
// This file holds the page: its state, the scene and camera, the opening of files and the
// controls. The rest is in modules of one job each: panes.js (a file's pane), mesh_files.js and
// file_checks.js (reading a mesh file), colours.js (the colour menu and a choice applied;
// colour_map.js, legend.js), frames.js (frames, jumps, playback), status_line.js, loading.js,
// plot.js, run_log.js, test_hooks.js.
// URL parameters: ?file=A&compare=B&log=RUN.csv (or a .json summary); A and B: .glb, .gltf or
// meshes. While a file loads, the status line says so: its name and the bytes read (state.loading).
// For tests, window.viewer exposes the state: {ready, loading, keyframe, frameNumbers, panes (with
// their meshes: a .glb's primitives), shown, colourValues (per pane, the values its colours show),
// looks() (per pane and mesh, the material drawn), ...}.
import * as THREE from 'three';
import {OrbitControls} from 'three/addons/controls/OrbitControls.js';

import {applyColours as colourPanes, colourChoices} from './colours.js';
import {frameSteps, lastAtOrBefore, player, showFrame} from './frames.js';
import {drawLegend} from './legend.js';
import {nextPaint, readFile, readResponse} from './loading.js';
import {extensionOf, isViewerFile} from './mesh_files.js';
import {disposePane, firstFramePane, makePane} from './panes.js';
import {drawPlot} from './plot.js';
import {parseCsvLog, parseJsonSummary, ratioAt} from './run_log.js';
import {errorText, statusLine} from './status_line.js';
import {exposeForTests} from './test_hooks.js';

const el = (id) => document.getElementById(id);
const view = el('view');
const state = {
  ready: false, error: null, loading: null, keyframe: 0, frameNumbers: [], times: [], log: null, summary: null,
  colourFields: [], colour: '-1', playing: false, sideBySide: false,
  panes: [],   // per pane: {name, kind: 'glb' | 'mesh', vertices, frame (glb: shown run frame)}
  shown: [],   // per pane: the colours it shows ('none', a field's name, 'file colours' or 'file materials')
};
window.viewer = state;

// ---------------------------------------------------------------- scene
const renderer = new THREE.WebGLRenderer({ antialias: true });
renderer.setPixelRatio(window.devicePixelRatio);
renderer.setScissorTest(true);
view.appendChild(renderer.domElement);
const camera = new THREE.PerspectiveCamera(35, 1, 0.01, 100);
const controls = new OrbitControls(camera, renderer.domElement);
controls.addEventListener('change', render);
/** @type {{name, kind, scene, sun, object, meshes, vertices, frameNumbers?, colourInfo?, fieldValues?, looks?, fixed?, fields?, fileColours?}[]} */
let panes = [];

function resize() {
  renderer.setSize(view.clientWidth, view.clientHeight);
  render();
}
function render() {
  const w = view.clientWidth, h = view.clientHeight, n = Math.max(1, panes.length);
  camera.aspect = w / n / Math.max(h, 1);
  camera.updateProjectionMatrix();
  if (!panes.length) {
    renderer.setViewport(0, 0, w, h);
    renderer.setScissor(0, 0, w, h);
    renderer.setClearColor(0xf4f4f2);
    renderer.clear();
  }
  panes.forEach((p, i) => {
    const x = Math.round((i * w) / n), pw = Math.round(((i + 1) * w) / n) - x;
    renderer.setViewport(x, 0, pw, h);
    renderer.setScissor(x, 0, pw, h);
    // The light follows the view: from the camera, a little above and to the right.
    p.sun.position.copy(camera.position).add(new THREE.Vector3(1, 2, 3).applyQuaternion(camera.quaternion));
    renderer.render(p.scene, camera);
  });
  el('pane-labels').replaceChildren(...panes.map((p, i) => {
    const s = document.createElement('span');
    s.textContent = p.fixed !== undefined ? `${p.name}, frame ${p.frameNumbers[p.fixed]}` : p.name;
    s.style.left = `${(100 * i) / n}%`;
    return s;
  }));
}
window.addEventListener('resize', resize);

const status = statusLine(el('status'), state);
const setStatus = status.set, showLoading = status.loading;

// ---------------------------------------------------------------- loading
/** A pane of the bytes of `name` (read by `read`, given the progress callback), the status line showing the load. */
async function loadPane(name, read, companions) {
  const bytes = await read((loaded, total) => showLoading(name, loaded, total));
  showLoading(name, bytes.byteLength, bytes.byteLength, true);
  await nextPaint();
  return makePane(bytes, name, companions);
}
/**
 * Shows the panes made of the files (one, or two side by side) and resets the frame and colours.
 * The status line gives each pane's summary after `errors` (the files that failed to open: the
 * summary must not hide them) and before `notes`.
 */
function showPanes(newPanes, errors = [], notes = []) {
  for (const p of panes) if (!newPanes.includes(p)) disposePane(p);
  panes = newPanes;
  const glb = panes.find((p) => p.kind === 'glb');
  const glbs = panes.filter((p) => p.kind === 'glb');
  // Two runs side by side step by run frame, each pane at its last kept frame at or before it
  // (so the shorter run holds its last frame).
  ({ frameNumbers: state.frameNumbers, times: state.times } = frameSteps(glbs));
  state.sideBySide = false;
  el('side-by-side').checked = false;
  el('side-by-side').disabled = !(panes.length === 1 && glb && glb.frameNumbers.length > 1);

  // Colour choices: the glTF's fields by index; a mesh file's own colours and scalar fields.
  const choices = colourChoices(panes);
  el('colour').replaceChildren(...choices.options.map(([label, value]) => new Option(label, value)));
  state.colourFields = choices.colourFields;
  const first = choices.first;

  // The colours before anything is drawn (moving the camera below draws): a file's own colours
  // drawn once and at once replaced by a field's would hold GPU memory until the pane closes.
  state.keyframe = 0;
  state.colour = first;
  applyColours();

  // Camera on the first frame's bounding box of every pane.
  const box = new THREE.Box3();
  for (const p of panes) box.expandByObject(p.object);
  const centre = box.getCenter(new THREE.Vector3());
  const radius = Math.max(box.getSize(new THREE.Vector3()).length() / 2, 1e-9);
  camera.near = radius / 100;
  camera.far = radius * 100;
  camera.position.copy(centre).add(new THREE.Vector3(0.6, 0.5, 1.6).normalize().multiplyScalar(radius * 3.2));
  controls.target.copy(centre);
  controls.update();

  const scrubber = el('scrubber');
  scrubber.max = String(state.frameNumbers.length - 1);
  scrubber.disabled = !glb;
  el('play').disabled = !glb || state.frameNumbers.length < 2;
  el('goto').disabled = !glb;
  state.panes = panes.map((p) => ({ name: p.name, kind: p.kind, vertices: p.vertices, meshes: p.meshes.length }));
  setColour(first);
  setKeyframe(0);
  const summary = panes.map((p) => `${p.name}: ${p.vertices} vertices` +
    (p.kind === 'glb' ? `, ${p.frameNumbers.length} frames` : '') +
    (p.notes?.length ? ` (${p.notes.join('; ')})` : ''));
  if (glbs.length === 2 && glbs[0].frameNumbers.join() !== glbs[1].frameNumbers.join()) {
    notes = [...notes, 'the two runs kept different frames: each pane shows its last kept frame at or before the frame shown'];
  }
  setStatus([...errors, ...summary, ...notes].join('  |  '), errors.length ? errors.join('; ') : null);
}

/** A single .glb's first frame beside its current frame (or back to one pane). */
function setSideBySide(on) {
  const glb = panes.find((p) => p.kind === 'glb' && p.fixed === undefined);
  if (!glb) return;
  if (on && panes.length === 1) {
    panes = [firstFramePane(glb), glb];
  } else if (!on) {
    for (const p of panes) if (p !== glb) disposePane(p, glb);
    panes = [glb];
  }
  state.sideBySide = panes.length === 2;
  state.panes = panes.map((p) => ({ name: p.name, kind: p.kind, vertices: p.vertices, meshes: p.meshes.length }));
  setColour(state.colour);
  setKeyframe(state.keyframe);
}

function loadLog(text, name) {
  if (name.toLowerCase().endsWith('.json')) {
    state.summary = parseJsonSummary(text);
    const { finalVolumeRatio: last, minVolumeRatio: min } = state.summary;
    if (!Number.isFinite(last)) throw new Error('not a run summary (no final_volume_ratio)');
    el('plot-note').textContent = `${name}: final V/V0 ${last.toFixed(4)}` + (Number.isFinite(min) ? `, minimum ${min.toFixed(4)}` : '');
  } else {
    state.log = parseCsvLog(text);
    el('plot-note').textContent = `${name}: ${state.log.frame.length} rows`;
  }
  updatePlot();
}

async function fetchChecked(url) {
  const r = await fetch(url);
  if (r.status === 404) throw new Error('not served (HTTP 404): view.py serves only the files it was started with, while it runs');
  if (!r.ok) throw new Error(`HTTP ${r.status}`);
  return r;
}

/** What an OBJ may name (mtllib, map_Kd): opened with it, not on their own. */
const COMPANION_EXTENSIONS = ['mtl', 'png', 'jpg', 'jpeg', 'gif', 'webp', 'bmp'];

async function openFiles(files) {
  const models = [], errors = [], notOpened = [];
  const companions = files.filter((f) => COMPANION_EXTENSIONS.includes(extensionOf(f.name)));
  for (const f of files) {
    try {
      if (isViewerFile(f.name)) {
        // Two panes at most: the first two files that open; the others are named, not read, so
        // a file that fails does not take a pane from the next.
        if (models.length === 2) notOpened.push(f.name);
        else models.push(await loadPane(f.name, (progress) => readFile(f, progress), companions));
      } else if (!companions.includes(f))
        loadLog(await f.text(), f.name);
    } catch (e) { errors.push(errorText(f.name, e)); }
  }
  const notes = notOpened.length
    ? [`not opened: ${notOpened.join(', ')} (the viewer shows at most two files side by side)`] : [];
  finishOpening(models, errors, notes);
}

/**
 * Shows the panes that opened with the errors of those that did not; a pane that cannot be drawn
 * (its first draw throws) is named in the status line, never left on "making its meshes".
 */
function finishOpening(models, errors, notes = []) {
  try {
    if (models.length) showPanes(models, errors, notes);
    else if (errors.length) setStatus(errors.join('  |  '), errors.join('; '));
  } catch (e) {
    const text = errorText(models.map((p) => p.name).join(', '), e);
    setStatus([...errors, text].join('  |  '), text);
  }
  state.ready = true;
}

// ---------------------------------------------------------------- frames, colours, plot
function setKeyframe(k) {
  if (!panes.length) return;
  k = Math.max(0, Math.min(state.frameNumbers.length - 1, k));
  state.keyframe = k;
  const frame = state.frameNumbers[k];
  showFrame(panes, frame);
  el('scrubber').value = String(k);
  // The box shows the frame shown, not a number typed before the scrubber moved.
  if (document.activeElement !== el('goto') && !el('goto').disabled) el('goto').value = String(frame);
  const ratio = ratioAt(state.log, frame);
  el('frame-label').textContent = !panes.some((p) => p.kind === 'glb') ? 'no frames: meshes only'
    : `frame ${frame} (${k + 1}/${state.frameNumbers.length})` + (ratio !== undefined ? `  V/V0 ${ratio.toFixed(4)}` : '');
  applyColours();
  updatePlot();
  render();
}

/** Jumps to run frame f: its keyframe, or the last one before it when f was not exported. */
function jumpToFrame(f) {
  setPlaying(false);
  setKeyframe(lastAtOrBefore(state.frameNumbers, f));
}

function setColour(choice) {
  state.colour = String(choice);
  el('colour').value = state.colour;
  applyColours();
  render();
}

/** Colours every pane by the choice (colours.js), with the colour bar and the note of what is shown. */
function applyColours() {
  const r = colourPanes(panes, { choice: state.colour, colourFields: state.colourFields,
                                 frame: state.frameNumbers[state.keyframe], noFields: el('colour').options.length === 1 });
  state.shown = r.shown;
  state.colourValues = r.values;
  drawLegend(el('colour-bar'), r.legend);
  state.legend = r.legend ? { name: r.legend.name, ...r.legend.scale } : null;
  el('colour-note').textContent = r.notes.join('; ');
}

function updatePlot() {
  drawPlot(el('plot'), state.log, state.summary, state.frameNumbers[state.keyframe]);
}

// Playback follows the glTF's key times; it wraps at the end.
const setPlaying = player(state, setKeyframe, el('play'));

// ---------------------------------------------------------------- UI
el('scrubber').addEventListener('input', (e) => { setPlaying(false); setKeyframe(Number(e.target.value)); });
el('play').addEventListener('click', () => setPlaying(!state.playing));
el('colour').addEventListener('change', (e) => setColour(e.target.value));
el('side-by-side').addEventListener('change', (e) => setSideBySide(e.target.checked));
el('goto').addEventListener('change', (e) => { if (e.target.value !== '') jumpToFrame(Number(e.target.value)); });
el('file-input').addEventListener('change', (e) => { state.ready = false; openFiles(Array.from(e.target.files)); });
window.addEventListener('dragover', (e) => { e.preventDefault(); document.body.classList.add('dragging'); });
window.addEventListener('dragleave', () => document.body.classList.remove('dragging'));
window.addEventListener('drop', (e) => {
  e.preventDefault();
  document.body.classList.remove('dragging');
  openFiles(Array.from(e.dataTransfer.files));
});
window.addEventListener('keydown', (e) => {
  if (e.target !== document.body) return;
  if (e.key === ' ') { e.preventDefault(); setPlaying(!state.playing); }
  if (e.key === 'ArrowRight') setKeyframe(state.keyframe + 1);
  if (e.key === 'ArrowLeft') setKeyframe(state.keyframe - 1);
});
state.jumpToFrame = jumpToFrame;
exposeForTests(state, () => panes, renderer);

resize();
updatePlot();
const params = new URLSearchParams(window.location.search);
/** The file name of a served URL, as the user wrote it (view.py's URLs are percent-encoded). */
const fileName = (url) => {
  const last = url.split('/').pop();
  try { return decodeURIComponent(last); } catch { return last; }
};
(async () => {
  // Each file on its own: one that fails (a log that is not one, a mesh that cannot be drawn) is
  // named with its error, and the others still open.
  const models = [], errors = [];
  const log = params.get('log');
  if (log) {
    try { loadLog(await (await fetchChecked(log)).text(), fileName(log)); } catch (e) { errors.push(errorText(fileName(log), e)); }
  }
  for (const key of ['file', 'compare']) {
    const url = params.get(key);
    if (!url) continue;
    const name = fileName(url);
    try {
      showLoading(name, 0, 0);  // before the first byte: the request itself may wait
      models.push(await loadPane(name, async (progress) => readResponse(await fetchChecked(url), progress)));
    } catch (e) { errors.push(errorText(name, e)); }
  }
  finishOpening(models, errors);
})();
