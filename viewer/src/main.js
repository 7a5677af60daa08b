// ShellContract viewer: plays the morph-target animation of a run's .glb (one target per exported
// frame, STEP keyframes), scrubs it and jumps to a frame, plots V/V0 from the run's CSV log or JSON
// summary, switches the colour fields, and opens result meshes (OFF, OBJ, PLY, STL; an OBJ with
// the .mtl and textures chosen with it). Two files are shown side by side (before and after, one
// camera; of more chosen, the status line names those not opened); a single .glb can show its
// first frame beside the current one. Each frame is coloured with its own values where the file
// has them (the glTF's extras.frame_fields); a field of one frame only (extras 'frame') is shown on
// that frame and never on the others; a mesh file is coloured with its own values. With no field shown, a file's primitives (or an OBJ's groups)
// wear its materials (base colour, texture), and a file with materials opens so.
// Two runs' .glb side by side step by run frame. A field is drawn on a diverging map about 0 or a
// sequential one (colour_map.js), with a colour bar (legend.js). An error names its file, briefly.
// URL parameters: ?file=A&compare=B&log=RUN.csv (or a .json summary); A and B: .glb or meshes.
// While a file loads, the status line says so: its name and the bytes read (state.loading).
// For tests, window.viewer exposes the state: {ready, loading, keyframe, frameNumbers, panes (with their
// meshes: a .glb's primitives), shown, colourValues (per pane, the values its colours show),
// looks() (per pane and mesh, the material drawn), ...}.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { colourScale, fieldColourAttribute, range } from './colour_map.js';
import { drawLegend, legendNote } from './legend.js';
import { loadingText, mb, nextPaint, readFile, readResponse } from './loading.js';
import { extensionOf, MESH_EXTENSIONS } from './mesh_files.js';
import { disposePane, firstFramePane, makePane } from './panes.js';
import { drawPlot } from './plot.js';
import { parseCsvLog, parseJsonSummary, ratioAt } from './run_log.js';

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

/**
 * An error's message for the status line: naming the file, and short. A three.js message may hold
 * a whole array's values (megabytes, which pushed the page's controls off the window).
 */
function errorText(name, e) {
  let m = String(e?.message ?? e);
  if (!m.startsWith(name)) m = `${name}: ${m}`;
  return m.length > 240 ? `${m.slice(0, 240)}…` : m;
}

/** Shows the text in the status line; `error` (a message within it) marks the line as an error. */
function setStatus(text, error = null) {
  state.loading = null;  // the panes' summary or an error ends the loading line
  el('status').textContent = text;
  el('status').classList.toggle('error', !!error);
  if (error) { state.error = error; console.error(error); }
}

// ---------------------------------------------------------------- loading
/**
 * The status line while `name` loads (state.loading: {name, loaded, total, building}): the bytes
 * read so far, then, with `building`, that its meshes are being made (a large .glb's frames take
 * seconds more). Updated at most every 100 ms: a large file arrives in thousands of pieces.
 */
let loadingShownAt = 0, loadingTimer = null;
function showLoading(name, loaded, total, building = false) {
  state.loading = { name, loaded, total, building };
  const wait = 100 - (performance.now() - loadingShownAt);
  if (!building && loaded > 0 && loaded < total && wait > 0) {
    // The latest state is shown when the interval is over (a stalled transfer shows where it is).
    loadingTimer ??= setTimeout(() => { loadingTimer = null; drawLoading(); }, wait);
    return;
  }
  drawLoading();
}
function drawLoading() {
  const l = state.loading;
  if (!l) return;  // the load ended (setStatus) before this update's turn
  loadingShownAt = performance.now();
  el('status').classList.remove('error');
  el('status').textContent = l.building ? `Opening ${l.name} (${mb(l.loaded)}): making its meshes…` : loadingText(l.name, l.loaded, l.total);
}

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
  if (glbs.length === 2) {
    // Two runs side by side step by run frame: every frame either kept, each pane at its last
    // kept frame at or before it (so the shorter run holds its last frame), one keyframe a tick.
    state.frameNumbers = [...new Set(glbs.flatMap((p) => p.frameNumbers))].sort((a, b) => a - b);
    state.times = state.frameNumbers.map((_, k) => k / 24);
  } else {
    state.frameNumbers = glb ? glb.frameNumbers : [0];
    state.times = glb ? glb.times : [0];
  }
  state.sideBySide = false;
  el('side-by-side').checked = false;
  el('side-by-side').disabled = !(panes.length === 1 && glb && glb.frameNumbers.length > 1);

  // Colour choices: the glTF's fields by index; a mesh file's own colours and scalar fields.
  // With none chosen, a file with materials wears them.
  const materials = panes.some((p) => p.looks?.some((l) => l.file));
  const select = el('colour');
  select.replaceChildren(new Option(materials ? 'none (file materials)' : 'none', '-1'));
  // The glTF fields by name (two runs may hold different ones), by index in this list.
  state.colourFields = [...new Map(glbs.flatMap((p) => p.colourInfo).map((f) => [f.name, f])).values()];
  state.colourFields.forEach((f, i) => select.add(new Option(f.name, String(i))));
  if (panes.some((p) => p.kind === 'mesh' && p.fileColours)) select.add(new Option('file colours', 'file'));
  const names = [...new Set(panes.flatMap((p) => (p.kind === 'mesh' ? p.fields.map((f) => f.name) : [])))];
  names.forEach((n) => select.add(new Option(n, `field:${n}`)));
  // First choice: the files' materials where they have some (how the file says it looks; the
  // fields stay in the menu), else the glTF's first field, else the face colours of a file that
  // has them (a regions file: one colour a region), else the files' first field (one range over
  // the panes, so a --fields start and end pair compare: each file's baked colours are on its own
  // range), else the files' own colours.
  const values = [...select.options].map((o) => o.value);
  const faceColours = panes.some((p) => p.kind === 'mesh' && p.faceColours);
  const firstField = values.find((v) => v.startsWith('field:'));
  const first = materials ? '-1' : values.includes('0') ? '0' : faceColours && values.includes('file') ? 'file'
    : firstField ?? (values.includes('file') ? 'file' : '-1');

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
      const ext = extensionOf(f.name);
      if (ext === 'glb' || MESH_EXTENSIONS.includes(ext)) {
        // Two panes at most: the first two files that open; the others are named, not read, so
        // a file that fails does not take a pane from the next.
        if (models.length === 2) notOpened.push(f.name);
        else models.push(await loadPane(f.name, (progress) => readFile(f, progress), companions));
      } else if (!companions.includes(f)) loadLog(await f.text(), f.name);
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
  for (const p of panes) {
    if (p.kind !== 'glb') continue;
    const kp = paneKeyframe(p);
    for (const m of p.meshes) {
      const influences = m.morphTargetInfluences ?? [];
      influences.fill(0);
      if (kp > 0 && kp <= influences.length) influences[kp - 1] = 1;  // the glTF's STEP keyframe kp
    }
  }
  el('scrubber').value = String(k);
  const frame = state.frameNumbers[k];
  // The box shows the frame shown, not a number typed before the scrubber moved.
  if (document.activeElement !== el('goto') && !el('goto').disabled) el('goto').value = String(frame);
  const ratio = ratioAt(state.log, frame);
  el('frame-label').textContent = !panes.some((p) => p.kind === 'glb') ? 'no frames: meshes only'
    : `frame ${frame} (${k + 1}/${state.frameNumbers.length})` + (ratio !== undefined ? `  V/V0 ${ratio.toFixed(4)}` : '');
  applyColours();
  updatePlot();
  render();
}

/**
 * The keyframe a .glb pane shows: its fixed one ("before | after"), else its last kept frame at
 * or before the run frame shown (the same index when the page steps through this file's frames).
 */
function paneKeyframe(p) {
  if (p.fixed !== undefined) return p.fixed;
  const frame = state.frameNumbers[state.keyframe];
  let kp = 0;
  p.frameNumbers.forEach((n, i) => { if (n <= frame) kp = i; });
  return kp;
}

/** Jumps to run frame f: its keyframe, or the last one before it when f was not exported. */
function jumpToFrame(f) {
  let k = 0;
  state.frameNumbers.forEach((n, i) => { if (n <= f) k = i; });
  setPlaying(false);
  setKeyframe(k);
}

function setColour(choice) {
  state.colour = String(choice);
  el('colour').value = state.colour;
  applyColours();
  render();
}

/** Colours every pane by the choice, each with its own values, or leaves it plain. */
function applyColours() {
  const choice = state.colour;
  const notes = [];
  // A scalar field of mesh files: one range over every pane that has it, so colours compare.
  const legends = [];  // {name, scale, of}: the colour bar's
  let scale = null;
  if (choice.startsWith('field:')) {
    const name = choice.slice(6);
    const arrays = panes.flatMap((p) => (p.kind === 'mesh' ? p.meshes.map((m) => m.geometry.userData.fields?.[name]).filter(Boolean) : []));
    const r = range(arrays);
    scale = colourScale(r.low, r.high);
    legends.push({ name, scale, of: `2nd to 98th percentile of ${panes.length > 1 ? 'both files: one range' : 'the file'}` });
  }
  const values = panes.map(() => null);  // per pane: the values its colours show, if any
  state.shown = panes.map((p, pi) => {
    let shown = 'none', fileMaterials = false;
    p.meshes.forEach((m, j) => {
      let attr = null;
      if (p.kind === 'glb' && /^\d+$/.test(choice)) {
        const wanted = state.colourFields[Number(choice)];
        const i = p.colourInfo.findIndex((f) => f.name === wanted?.name), info = p.colourInfo[i];
        const k = paneKeyframe(p), frame = p.frameNumbers[k];
        const perFrame = info && p.frameFields[info.name];
        if (perFrame) {
          // Each frame's own values, on one scale over all frames (so frames compare).
          const scale = colourScale(perFrame.low, perFrame.high);
          attr = fieldColourAttribute(m.geometry, perFrame.values[k], scale);
          values[pi] = perFrame.values[k];
          if (j === 0) legends.push({ name: info.name, scale, of: "each frame's own values; 2nd to 98th percentile over all frames" });
        } else if (info && (info.frame === undefined || info.frame === frame) && p.fieldValues[j][i]) {
          // A field of one frame ('frame' in the extras) is shown on that frame only; without
          // 'frame', on any.
          attr = fieldColourAttribute(m.geometry, p.fieldValues[j][i], colourScale(Number(info.low), Number(info.high)));
          values[pi] = p.fieldValues[j][i];
        }
        if (info && !perFrame && j === 0) {
          legends.push({ name: info.name, scale: colourScale(Number(info.low), Number(info.high)),
                         of: 'its 2nd to 98th percentile' + (info.frame !== undefined ? `; values of frame ${info.frame}, shown on that frame only` : '') });
        }
        if (attr) shown = info.name;
      } else if (p.kind === 'mesh' && choice === 'file' && p.fileColourAttributes[j]) {
        attr = p.fileColourAttributes[j];
        shown = 'file colours';
        // What the file's colours are: its header's comments say it where the CLI wrote them.
        if (j === 0) {
          notes.push(`${p.name}: its own ${p.faceColours ? 'face ' : ''}colours` +
                     (p.comments?.length ? ` (${p.comments.join('; ')})` : '') +
                     (p.fields.length && !p.faceColours ? `, on its own scale; a field from the menu puts ${panes.length > 1 ? 'both files' : 'it'} on one` : ''));
        }
      } else if (p.kind === 'mesh' && scale) {
        const v = m.geometry.userData.fields?.[choice.slice(6)];
        if (v) {
          attr = fieldColourAttribute(m.geometry, v, scale);
          values[pi] = v;
          shown = choice.slice(6);
        }
      }
      // 'color' is the file's own attribute (on the GPU since the file opened) or the geometry's
      // one attribute of field colours (colour_map.js), rewritten there: a switch makes no buffer.
      if (attr) m.geometry.setAttribute('color', attr);
      // A field's colours when one is shown, else the file's material where it has one.
      const file = attr ? null : p.looks[j].file;
      m.material = file ?? p.looks[j].field;
      if (file) { fileMaterials = true; return; }
      const mat = m.material;
      mat.vertexColors = !!attr;
      mat.color.set(attr ? 0xffffff : 0xd8c8b0);
      mat.needsUpdate = true;
    });
    return shown === 'none' && fileMaterials ? 'file materials' : shown;
  });
  state.colourValues = values;
  drawLegend(el('colour-bar'), legends[0] ?? null);
  state.legend = legends[0] ? { name: legends[0].name, ...legends[0].scale } : null;
  notes.push(...legends.map(legendNote));
  // The note says what is shown: a file with materials and no colour fields is not plain.
  const withMaterials = panes.filter((p, i) => state.shown[i] === 'file materials').map((p) => p.name);
  if (withMaterials.length) notes.push(`the materials of ${[...new Set(withMaterials)].join(' and ')} are shown`);
  if (el('colour').options.length === 1) notes.unshift(`no colour fields in ${panes.length > 1 ? 'these files' : 'this file'}`);
  el('colour-note').textContent = [...new Set(notes)].join('; ');
}

function updatePlot() {
  drawPlot(el('plot'), state.log, state.summary, state.frameNumbers[state.keyframe]);
}

// Playback follows the glTF's key times; it wraps at the end.
let playStart = 0, playFrom = 0;
function tick(now) {
  if (!state.playing) return;
  const t = state.times[playFrom] + (now - playStart) / 1000;
  let k = playFrom;
  while (k + 1 < state.times.length && state.times[k + 1] <= t) k++;
  if (k !== state.keyframe) setKeyframe(k);
  if (k === state.times.length - 1) { playFrom = 0; playStart = now + 500; }
  requestAnimationFrame(tick);
}
function setPlaying(on) {
  state.playing = on;
  el('play').textContent = on ? 'Pause' : 'Play';
  if (on) {
    playFrom = state.keyframe === state.frameNumbers.length - 1 ? 0 : state.keyframe;
    playStart = performance.now();
    requestAnimationFrame(tick);
  }
}

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
/** For tests: per pane, per mesh (a glTF primitive each), its morph target influences. */
state.influences = () => panes.map((p) => p.meshes.map((m) => Array.from(m.morphTargetInfluences ?? [])));
/** For tests: per pane, the mean red (linear) of the colours it shows; null for a plain pane. */
state.colourMeans = () => panes.map((p) => {
  let sum = 0, n = 0;
  for (const m of p.meshes) {
    const c = m.material.vertexColors ? m.geometry.getAttribute('color') : null;
    if (!c) return null;
    for (let i = 0; i < c.count; i++) sum += c.getX(i);
    n += c.count;
  }
  return n ? sum / n : null;
});
/** For tests: per pane, per mesh, the material drawn (an array for an OBJ's mesh of several, one
 * per group): its name, colour (linear RGB), opacity, the size of its texture (null without),
 * whether it shows vertex colours. */
/** For tests: three.js's count of the geometries and textures on the GPU (renderer.info.memory). */
state.memory = () => ({ ...renderer.info.memory });
const look = (material) => ({
  name: material.name, colour: material.color.toArray(), opacity: material.opacity,
  texture: material.map?.image ? [material.map.image.width, material.map.image.height] : null,
  vertexColors: material.vertexColors,
});
state.looks = () => panes.map((p) => p.meshes.map((m) => (Array.isArray(m.material) ? m.material.map(look) : look(m.material))));

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
