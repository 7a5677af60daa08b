// Headless check (Debian's Chromium, puppeteer-core) of what issue 56 asked of the viewer: it
// opens result meshes (OFF, OBJ, PLY, STL), shows two files side by side (and a .glb's first
// frame beside its current one), colours each pane and each frame with its own values (a glTF
// field of one frame only on that frame), and jumps to a frame; a .glb of several primitives (an
// OBJ with two materials) plays and colours every one; the two panes of "before | after" wear each
// its own frame's colours (materials: viewer_materials_test.mjs); switching colours and frames
// makes no new WebGL buffers, and closing a pane frees its own. The files come from real runs of
// the CLI on a small mesh, made here in a temporary folder.
// Usage: node viewer/tests/viewer_meshes_test.mjs --cli SHELLCONTRACT --mesh ico2.off [--chromium PATH]
import { readFileSync, writeFileSync } from 'node:fs';
import { check, finish, linear, parseArgs, readOff, runCli, startViewer, workFolder } from './test_support.mjs';

const args = parseArgs('viewer_meshes_test.mjs --cli SHELLCONTRACT --mesh MESH.off [--chromium PATH]', ['cli', 'mesh']);

// ---------------------------------------------------------------- the files
const work = workFolder('shellcontract-viewer-meshes-');
const file = work.file;
const cli = (...a) => runCli(args.cli, ...a);
const runOptions = ['--frames', '20', '--target-volume', '0.7', '-q'];
cli('run', args.mesh, '-o', file('out.off'), ...runOptions, '--fields', file('fields'), '--gltf', file('run.glb'), '--export-every', '5');
for (const ext of ['obj', 'ply', 'stl']) cli('run', args.mesh, '-o', file(`out.${ext}`), ...runOptions);
const { vertices: v, faces } = readOff(args.mesh);
const nv = v.length, nf = faces.length;
// The same mesh as an OBJ whose faces use two materials (by the side of z = 0 their centroid
// is on), and the runs of both with the same options: the .glb of the OBJ has two primitives.
{
  let obj = 'mtllib two.mtl\n' + v.map((c) => `v ${c[0]} ${c[1]} ${c[2]}\n`).join('');
  for (const f of faces) {
    const z = f.reduce((s, i) => s + Number(v[i][2]), 0);
    obj += `usemtl ${z > 0 ? 'top' : 'bottom'}\nf ${f.map((i) => i + 1).join(' ')}\n`;
  }
  writeFileSync(file('two.obj'), obj);
  writeFileSync(file('two.mtl'), 'newmtl top\nKd 0.9 0.1 0.1\nnewmtl bottom\nKd 0.1 0.1 0.9\n');
  cli('run', file('two.obj'), '-o', file('two_out.obj'), ...runOptions, '--gltf', file('two.glb'), '--export-every', '5');
  cli('run', args.mesh, '-o', file('one_out.off'), ...runOptions, '--gltf', file('one.glb'), '--export-every', '5');
}

/** A vertex property of an ascii PLY as numbers, read here, not by the page. */
function plyColumn(plyPath, name) {
  const text = readFileSync(plyPath, 'utf8');
  const [head, body] = text.split('end_header');
  const props = [...head.matchAll(/^property (\S+) (\S+)$/gm)].map((m) => m[2]);
  const count = Number(/element vertex (\d+)/.exec(head)[1]);
  const rows = body.trim().split(/\r?\n/).slice(0, count).map((l) => l.trim().split(/\s+/).map(Number));
  return rows.map((r) => r[props.indexOf(name)]);
}
/** Mean linear red of an ascii PLY's vertices (PLYLoader stores the linear value of a uchar colour
 * back as a byte: Math.round(linear * 255)). */
const meanRed = (plyPath) => {
  const red = plyColumn(plyPath, 'red');
  return red.reduce((s, r) => s + Math.round(linear(r) * 255) / 255, 0) / red.length;
};
/** Whether the page's values are the PLY's float column, exactly. */
const sameFloats = (page, ply) => page && page.length === ply.length && ply.every((v, i) => Math.fround(v) === page[i]);

const { page, consoleErrors, open, pick, settle, shot, differing, pixels, close } = await startViewer(args.chromium);
try {
  // The WebGL buffers the page creates and deletes are counted, for the checks of the colour
  // buffers below.
  await page.evaluateOnNewDocument(() => {
    window.buffers = { created: 0, deleted: 0 };
    for (const C of [WebGLRenderingContext, WebGL2RenderingContext]) {
      const { createBuffer, deleteBuffer } = C.prototype;
      C.prototype.createBuffer = function (...a) { window.buffers.created++; return createBuffer.apply(this, a); };
      C.prototype.deleteBuffer = function (...a) { window.buffers.deleted++; return deleteBuffer.apply(this, a); };
    }
  });
  // Every mesh format opens, with the file's vertices (OBJ and STL too, whose loaders make three
  // corners per face: the count is the file's, not the corners').
  const pictures = {};
  for (const [ext, count] of [['off', nv], ['obj', nv], ['ply', nv], ['stl', nv]]) {
    const s = await open(file(`out.${ext}`));
    check(!s.error && s.panes.length === 1 && s.panes[0].vertices === count,
          `out.${ext} opens (${s.error ?? `${s.panes[0]?.vertices} vertices, expected ${count}`})`);
    pictures[ext] = await shot();
    const c = (await pixels(pictures[ext])).covered;
    check(c > 0.02, `out.${ext} is drawn (${(100 * c).toFixed(1)} % of the pixels)`);
  }
  // OFF and PLY hold the same indexed mesh: the same picture.
  const dPly = await differing(pictures.off, pictures.ply);
  check(dPly < 0.002, `out.off and out.ply look the same (${(100 * dPly).toFixed(2)} % differ)`);

  // Before and after side by side: the input and the result differ; the same file twice does not.
  let s = await open(args.mesh, file('out.off'));
  check(s.panes.length === 2, `two files open side by side (${s.panes.map((p) => p.name).join(', ')})`);
  const dBeforeAfter = await differing(await shot('left'), await shot('right'));
  check(dBeforeAfter > 0.01, `before and after differ (${(100 * dBeforeAfter).toFixed(1)} % of the pixels)`);
  s = await open(file('out.off'), file('out.ply'));
  const dSame = await differing(await shot('left'), await shot('right'));
  check(dSame < 0.002, `the same mesh in both panes looks the same (${(100 * dSame).toFixed(2)} % differ)`);

  // More than two meshes chosen: two panes, and the status names the files not opened.
  const status = () => page.$eval('#status', (e) => ({ text: e.textContent, error: e.classList.contains('error') }));
  s = await pick(file('out.off'), file('out.ply'), file('out.stl'), file('out.obj'));
  let line = await status();
  check(s.panes.length === 2 && /out\.stl/.test(line.text) && /out\.obj/.test(line.text) && /not opened/.test(line.text),
        `of four meshes chosen two open and the status names the other two (${s.panes.map((p) => p.name).join(', ')}; "${line.text}")`);
  // A file that fails beside one that opens: the error stays in the status line, with the summary.
  writeFileSync(file('broken.off'), 'OFF\n3 1 0\n0 0 0\n');
  s = await pick(file('out.off'), file('broken.off'));
  line = await status();
  check(s.panes.length === 1 && /broken\.off/.test(s.error ?? '') && line.error && /broken\.off: /.test(line.text) &&
        /out\.off: \d+ vertices/.test(line.text), `the error of broken.off stays in the status beside out.off's summary ("${line.text}")`);
  // Its console error is the one expected here, not one for the final check.
  consoleErrors.splice(0, consoleErrors.length, ...consoleErrors.filter((m) => !m.includes('broken.off')));

  // The fields PLYs side by side open on their first field, on one range over both (each file's
  // baked colours are on its own range, so the same colour would mean two values), with a colour
  // bar; "file colours" shows each pane its own file's colours, and the note says so.
  s = await open(file('fields_start.ply'), file('fields_end.ply'));
  const legend = await page.evaluate(() => ({ legend: window.viewer.legend, bar: !document.getElementById('colour-bar').hidden }));
  check(JSON.stringify(s.shown) === '["mean_curvature","mean_curvature"]' && legend.bar && legend.legend?.name === 'mean_curvature',
        `the pair opens on mean curvature, one range, with a colour bar (${JSON.stringify(s.shown)}, ${JSON.stringify(legend)})`);
  await page.select('#colour', 'file');
  s.shown = await page.evaluate(() => window.viewer.shown);
  const fileNote = await page.$eval('#colour-note', (e) => e.textContent);
  check(JSON.stringify(s.shown) === '["file colours","file colours"]' && /fields_start\.ply: its own colours/.test(fileNote),
        `both panes show their file's colours, and the note says whose ("${fileNote}")`);
  const means = await page.evaluate(() => window.viewer.colourMeans());
  const expected = [meanRed(file('fields_start.ply')), meanRed(file('fields_end.ply'))];
  check(means && means[0] !== null && means[1] !== null && Math.abs(means[0] - expected[0]) < 1e-4 && Math.abs(means[1] - expected[1]) < 1e-4,
        `each pane's colours are its file's (mean red ${means?.map((m) => m?.toFixed(4))} vs ${expected.map((m) => m.toFixed(4))})`);
  check(Math.abs(expected[0] - expected[1]) > 1e-3, 'the start and end colours differ (else the check above proves nothing)');
  await page.select('#colour', 'field:mean_curvature');
  s = await page.evaluate(() => window.viewer.shown);
  check(JSON.stringify(s) === '["mean_curvature","mean_curvature"]', `a scalar field of the files colours both panes (${JSON.stringify(s)})`);

  // The CLI's .glb: mean curvature has each frame's own values (those of the --fields PLYs of
  // the same run, frame 0 and the last); the other fields are the last frame's only, so frame 0
  // is not coloured by them.
  s = await open(file('run.glb'));
  const frames = await page.evaluate(() => window.viewer.frameNumbers);
  check(JSON.stringify(frames) === '[0,5,10,15,20]', `the run's frames (${JSON.stringify(frames)})`);
  const pageValues = () => page.evaluate(() => (window.viewer.colourValues[0] ? Array.from(window.viewer.colourValues[0]) : null));
  check(s.shown[0] === 'mean_curvature', `frame 0 is coloured by mean curvature (shown: ${s.shown[0]})`);
  check(sameFloats(await pageValues(), plyColumn(file('fields_start.ply'), 'mean_curvature')),
        "frame 0's colours are frame 0's mean curvature (the --fields start PLY's)");
  const frame0Mean = (await page.evaluate(() => window.viewer.colourMeans()))[0];
  await page.select('#colour', '1');
  s.shown = await page.evaluate(() => window.viewer.shown);
  check(s.shown[0] === 'none', `frame 0 does not wear the last frame's gaussian curvature (shown: ${s.shown[0]})`);
  const frame0Coloured = await shot();
  await page.select('#colour', '-1');
  const frame0Plain = await shot();
  check(await differing(frame0Coloured, frame0Plain) < 0.001, 'frame 0 looks the same with that field chosen as with none');
  await page.select('#colour', '0');
  await page.focus('#scrubber');
  await page.keyboard.press('End');
  check(sameFloats(await pageValues(), plyColumn(file('fields_end.ply'), 'mean_curvature')),
        "the last frame's colours are its own mean curvature (the --fields end PLY's)");
  const lastMean = (await page.evaluate(() => window.viewer.colourMeans()))[0];
  check(Math.abs(lastMean - frame0Mean) > 1e-3, `frame 0 and the last frame have different colours (mean red ${frame0Mean?.toFixed(4)}, ${lastMean?.toFixed(4)})`);
  await page.select('#colour', '1');
  const lastShown = await page.evaluate(() => window.viewer.shown[0]);
  check(lastShown === 'gaussian_curvature', `the last frame wears its gaussian curvature (shown: ${lastShown})`);
  check(sameFloats(await pageValues(), plyColumn(file('fields_end.ply'), 'gaussian_curvature')),
        "its colours are the last frame's gaussian curvature (the --fields end PLY's), from the file's _GAUSSIAN_CURVATURE");
  const lastColoured = await shot();
  await page.select('#colour', '-1');
  check(await differing(lastColoured, await shot()) > 0.01, 'on the last frame the field changes the picture');

  // Jump to a frame: an exported one, and one between two exported frames (the one before it).
  for (const [typed, k] of [[10, 2], [12, 2], [20, 4], [0, 0]]) {
    await page.$eval('#goto', (e, v) => { e.value = String(v); e.dispatchEvent(new Event('change')); }, typed);
    const got = await page.evaluate(() => ({ k: window.viewer.keyframe, label: document.getElementById('frame-label').textContent }));
    check(got.k === k && got.label.startsWith(`frame ${frames[k]} `), `go to frame ${typed} shows keyframe ${k} (${got.k}, "${got.label}")`);
  }

  // A .glb's first frame beside its current one: equal on frame 0, different on the last.
  await page.click('#side-by-side');
  const sb = await page.evaluate(() => ({ on: window.viewer.sideBySide, panes: window.viewer.panes.length }));
  check(sb.on && sb.panes === 2, `before | after shows two panes (${JSON.stringify(sb)})`);
  const d0 = await differing(await shot('left'), await shot('right'));
  check(d0 < 0.002, `on frame 0 both panes show frame 0 (${(100 * d0).toFixed(2)} % differ)`);
  await page.focus('#scrubber');
  await page.keyboard.press('End');
  const dEnd = await differing(await shot('left'), await shot('right'));
  check(dEnd > 0.01, `on the last frame the panes differ (${(100 * dEnd).toFixed(1)} % of the pixels)`);
  // Each pane wears its own frame's colours: the colours read back from each pane's geometry are
  // those of frame 0 (left) and of the last frame (right), as seen one pane at a time above.
  await page.select('#colour', '0');
  const sbMeans = await page.evaluate(() => window.viewer.colourMeans());
  check(sbMeans[0] !== null && sbMeans[1] !== null && Math.abs(sbMeans[0] - frame0Mean) < 1e-6 && Math.abs(sbMeans[1] - lastMean) < 1e-6,
        `side by side, the left pane wears frame 0's colours and the right the last frame's (mean red ${sbMeans.map((m) => m?.toFixed(4))}, expected ${frame0Mean?.toFixed(4)}, ${lastMean?.toFixed(4)})`);
  const sbInf = await page.evaluate(() => window.viewer.influences());
  check(sbInf[0][0].every((x) => x === 0) && sbInf[1][0].at(-1) === 1 && sbInf[1][0].slice(0, -1).every((x) => x === 0),
        `side by side, the left pane is at frame 0 and the right at the last frame (influences ${JSON.stringify(sbInf)})`);
  await page.select('#colour', '1');
  const sbShown = await page.evaluate(() => ({ shown: window.viewer.shown, means: window.viewer.colourMeans() }));
  check(JSON.stringify(sbShown.shown) === '["none","gaussian_curvature"]' && sbShown.means[0] === null && sbShown.means[1] !== null,
        `a field of the last frame only colours the right pane only (${JSON.stringify(sbShown)})`);
  await page.select('#colour', '0');
  await page.focus('#scrubber');
  await page.keyboard.press('Home');
  const sbHome = await page.evaluate(() => window.viewer.colourMeans());
  check(Math.abs(sbHome[0] - frame0Mean) < 1e-6 && Math.abs(sbHome[1] - frame0Mean) < 1e-6,
        `back on frame 0 both panes wear frame 0's colours (mean red ${sbHome.map((m) => m?.toFixed(4))})`);

  // Two materials, two primitives (three.js: two meshes): each plays the frames and wears the
  // colour field, so the picture is the one-primitive file's, frame for frame. (The file opens
  // showing its materials: viewer_materials_test.mjs; here its first field is chosen.)
  s = await open(file('two.glb'));
  check(!s.error && s.panes[0]?.meshes === 2, `two.glb opens as two meshes (${s.error ?? s.panes[0]?.meshes})`);
  await page.select('#colour', '0');
  s.shown = await page.evaluate(() => window.viewer.shown);
  const both = await page.evaluate(() => window.viewer.colourMeans()[0]);
  check(both !== null && s.shown[0] === 'mean_curvature', `every primitive wears the colour field (shown: ${s.shown[0]}, mean red ${both})`);
  await page.focus('#scrubber');
  await page.keyboard.press('End');
  const inf = await page.evaluate(() => window.viewer.influences()[0]);
  check(inf.length === 2 && inf.every((a) => a.length === 4 && a[3] === 1 && a.slice(0, 3).every((x) => x === 0)),
        `on the last frame every primitive shows the last morph target (${JSON.stringify(inf)})`);
  const twoLast = await shot();
  s = await open(file('one.glb'));
  check(s.panes[0]?.meshes === 1, `one.glb (the OFF's run) opens as one mesh (${s.panes[0]?.meshes})`);
  await page.focus('#scrubber');
  await page.keyboard.press('End');
  const dTwo = await differing(twoLast, await shot());
  check(dTwo < 0.002, `the two-primitive file's last frame looks as the one-primitive file's (${(100 * dTwo).toFixed(2)} % differ)`);

  // Colours on the GPU: a choice of colours or a frame writes the colours into the mesh's one
  // colour buffer, not into a new buffer each time (three.js frees the buffers of a geometry's
  // current attributes only, so each one swapped out would stay until garbage collection). After
  // the first picture with a field shown, stepping through the frames and switching the choices
  // makes no buffer: before | after of the run (a per-frame field, so every frame has new colours).
  const buffers = () => page.evaluate(() => window.buffers.created);
  const live = () => page.evaluate(() => window.buffers.created - window.buffers.deleted);
  const choices = () => page.$$eval('#colour option', (os) => os.map((o) => o.value));
  /** Steps through every frame under every colour choice, `rounds` times. */
  const cycle = async (rounds, frameCount) => {
    for (let r = 0; r < rounds; r++) {
      for (const c of [...await choices(), ...(await choices()).reverse()]) {
        await page.select('#colour', c);
        await page.focus('#scrubber');
        await page.keyboard.press('Home');
        for (let k = 1; k < frameCount; k++) await page.keyboard.press('ArrowRight');
        await settle();
      }
    }
  };
  s = await open(file('run.glb'));
  await settle();
  const glbLive = await live();
  await page.click('#side-by-side');
  await settle();
  const glbBefore = await buffers();
  await cycle(3, frames.length);
  const glbMade = (await buffers()) - glbBefore;
  check(s.shown[0] === 'mean_curvature' && glbMade === 0,
        `switching colours and frames of the .glb side by side makes no WebGL buffer (${glbMade} made; first shown: ${s.shown[0]})`);
  // Back to one pane: the first frame's pane frees its own colour buffers, not the shared ones.
  await page.click('#side-by-side');
  await settle();
  const glbAfter = { live: await live(), made: (await buffers()) - glbBefore };
  check(glbAfter.live === glbLive && glbAfter.made === 0,
        `before | after off frees the buffers it made and keeps the others (${glbAfter.live} live, ${glbLive} before; ${glbAfter.made} made)`);
  // A mesh file opens on its first field (the mesh's one buffer of field colours, which later
  // choices rewrite); the first choice of the file's own colours uploads them, once: so at most
  // one buffer per mesh shown, however many switches follow.
  s = await open(file('fields_start.ply'), file('fields_end.ply'));
  await settle();
  const meshLive = await live();
  const meshBefore = await buffers();
  await cycle(1, 1);
  const firstRound = (await buffers()) - meshBefore;
  await cycle(3, 1);
  const laterRounds = (await buffers()) - meshBefore - firstRound;
  check(JSON.stringify(s.shown) === '["mean_curvature","mean_curvature"]' && (await choices()).length > 3 && firstRound <= 2 && laterRounds === 0,
        `switching the colours of two meshes makes at most one WebGL buffer per mesh, once (${firstRound} in the first round of switches, ${laterRounds} in three more)`);
  // The same files again: the old panes' buffers are freed, also the colour buffers off their
  // geometries' 'color' (the switches end on the file's colours, then none).
  await pick(file('fields_start.ply'), file('fields_end.ply'));
  await settle();
  const reopened = await live();
  check(reopened === meshLive, `opening the files again frees the buffers of the panes they replace (${reopened} live, ${meshLive} before)`);

  check(consoleErrors.length === 0, `no console errors${consoleErrors.length ? ': ' + consoleErrors.join(' | ') : ''}`);
} finally {
  await close();
  work.remove();
}
finish('all viewer mesh checks passed');
