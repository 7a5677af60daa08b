// ShellContract viewer: plays the morph-target animation of a run's .glb (one target per exported
// frame, STEP keyframes), scrubs it, plots V/V0 from the run's CSV log or JSON summary and switches
// the colour fields (COLOR_n attributes named in the mesh's extras).
// URL parameters: ?file=RUN.glb&log=RUN.csv (or a .json summary).
// For tests, window.viewer exposes the state: {ready, keyframe, frameNumbers, log, summary, ...}.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { drawPlot } from './plot.js';
import { parseCsvLog, parseJsonSummary, ratioAt } from './run_log.js';

const el = (id) => document.getElementById(id);
const view = el('view');
const state = {
  ready: false, error: null, keyframe: 0, frameNumbers: [], times: [], log: null, summary: null,
  colourFields: [], colour: -1, playing: false,
};
window.viewer = state;

// ---------------------------------------------------------------- scene
const renderer = new THREE.WebGLRenderer({ antialias: true });
renderer.setPixelRatio(window.devicePixelRatio);
view.appendChild(renderer.domElement);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0xf4f4f2);
const camera = new THREE.PerspectiveCamera(35, 1, 0.01, 100);
scene.add(camera);
scene.add(new THREE.HemisphereLight(0xffffff, 0x808080, 1.6));
const sun = new THREE.DirectionalLight(0xffffff, 1.8);
sun.position.set(1, 2, 3);
camera.add(sun);  // the light follows the view
const controls = new OrbitControls(camera, renderer.domElement);
controls.addEventListener('change', render);
let root = null;   // the loaded glTF scene
let shell = null;  // the THREE.Mesh with the morph targets
let colourAttributes = [];

function resize() {
  const w = view.clientWidth, h = view.clientHeight;
  renderer.setSize(w, h);
  camera.aspect = w / Math.max(h, 1);
  camera.updateProjectionMatrix();
  render();
}
function render() { renderer.render(scene, camera); }
window.addEventListener('resize', resize);

function setStatus(text, isError = false) {
  el('status').textContent = text;
  el('status').classList.toggle('error', isError);
  if (isError) { state.error = text; console.error(text); }
}

// ---------------------------------------------------------------- loading
async function loadGlb(arrayBuffer, name) {
  const gltf = await new GLTFLoader().parseAsync(arrayBuffer, '');
  if (root) scene.remove(root);
  root = gltf.scene;
  shell = null;
  gltf.scene.traverse((o) => { if (!shell && o.isMesh) shell = o; });
  if (!shell) throw new Error(`${name}: no mesh`);
  scene.add(gltf.scene);
  const extras = shell.userData ?? {};
  const targets = shell.morphTargetInfluences ? shell.morphTargetInfluences.length : 0;
  state.frameNumbers = Array.isArray(extras.frame_numbers) ? extras.frame_numbers
    : Array.from({ length: targets + 1 }, (_, k) => k);
  const track = gltf.animations[0]?.tracks[0];
  state.times = track ? Array.from(track.times) : state.frameNumbers.map((_, k) => k / 24);

  // Colour fields: COLOR_0 is three's 'color', COLOR_n its 'color_n'.
  const geometry = shell.geometry;
  state.colourFields = Array.isArray(extras.colour_fields) ? extras.colour_fields : [];
  colourAttributes = state.colourFields.map((f, i) => geometry.getAttribute(i === 0 ? 'color' : `color_${i}`));
  const select = el('colour');
  select.replaceChildren(new Option('none', '-1'));
  state.colourFields.forEach((f, i) => select.add(new Option(f.name, String(i))));
  shell.material = new THREE.MeshStandardMaterial({ color: 0xffffff, roughness: 0.6, metalness: 0.0,
                                                    side: THREE.DoubleSide });
  setColour(state.colourFields.length > 0 ? 0 : -1);

  // Camera on frame 0's bounding box.
  const box = new THREE.Box3().setFromObject(shell);
  const centre = box.getCenter(new THREE.Vector3());
  const radius = box.getSize(new THREE.Vector3()).length() / 2;
  camera.near = radius / 100;
  camera.far = radius * 100;
  camera.position.copy(centre).add(new THREE.Vector3(0.6, 0.5, 1.6).normalize().multiplyScalar(radius * 3.2));
  controls.target.copy(centre);
  controls.update();

  const scrubber = el('scrubber');
  scrubber.max = String(state.frameNumbers.length - 1);
  scrubber.disabled = false;
  el('play').disabled = state.frameNumbers.length < 2;
  setKeyframe(0);
  setStatus(`${name}: ${geometry.getAttribute('position').count} vertices, ${state.frameNumbers.length} frames`);
  state.ready = true;
}

function loadLog(text, name) {
  if (name.toLowerCase().endsWith('.json')) {
    state.summary = parseJsonSummary(text);
    el('plot-note').textContent = `${name}: final V/V0 ${state.summary.finalVolumeRatio}, minimum ${state.summary.minVolumeRatio}`;
  } else {
    state.log = parseCsvLog(text);
    el('plot-note').textContent = `${name}: ${state.log.frame.length} rows`;
  }
  updatePlot();
}

async function fetchChecked(url) {
  const r = await fetch(url);
  if (!r.ok) throw new Error(`${url}: HTTP ${r.status}`);
  return r;
}

async function openFiles(files) {
  for (const f of files) {
    try {
      if (f.name.toLowerCase().endsWith('.glb')) await loadGlb(await f.arrayBuffer(), f.name);
      else loadLog(await f.text(), f.name);
    } catch (e) { setStatus(`${f.name}: ${e.message}`, true); }
  }
}

// ---------------------------------------------------------------- frames, colours, plot
function setKeyframe(k) {
  if (!shell) return;
  k = Math.max(0, Math.min(state.frameNumbers.length - 1, k));
  state.keyframe = k;
  const influences = shell.morphTargetInfluences ?? [];
  influences.fill(0);
  if (k > 0) influences[k - 1] = 1;  // the glTF's STEP keyframe k
  el('scrubber').value = String(k);
  const frame = state.frameNumbers[k];
  const ratio = ratioAt(state.log, frame);
  el('frame-label').textContent = `frame ${frame} (${k + 1}/${state.frameNumbers.length})` +
    (ratio !== undefined ? `  V/V0 ${ratio.toFixed(4)}` : '');
  updatePlot();
  render();
}

function setColour(i) {
  state.colour = i;
  el('colour').value = String(i);
  if (!shell) return;
  const m = shell.material;
  if (i >= 0 && colourAttributes[i]) {
    shell.geometry.setAttribute('color', colourAttributes[i]);
    m.vertexColors = true;
    const f = state.colourFields[i];
    el('colour-note').textContent = `${f.name}: blue ${Number(f.low).toPrecision(3)}, red ${Number(f.high).toPrecision(3)} (its 2nd to 98th percentile)`;
  } else {
    m.vertexColors = false;
    m.color.set(0xd8c8b0);
    el('colour-note').textContent = state.colourFields.length ? '' : 'this file has no colour fields';
  }
  if (i >= 0) m.color.set(0xffffff);
  m.needsUpdate = true;
  render();
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
el('colour').addEventListener('change', (e) => setColour(Number(e.target.value)));
el('file-input').addEventListener('change', (e) => openFiles(Array.from(e.target.files)));
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

resize();
updatePlot();
const params = new URLSearchParams(window.location.search);
(async () => {
  try {
    const log = params.get('log');
    if (log) loadLog(await (await fetchChecked(log)).text(), log);
    const file = params.get('file');
    if (file) await loadGlb(await (await fetchChecked(file)).arrayBuffer(), file);
    else state.ready = true;
  } catch (e) {
    setStatus(e.message, true);
  }
})();
