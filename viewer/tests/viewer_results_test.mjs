// Headless check (Debian's Chromium, puppeteer-core) that the viewer shows every result the CLI
// writes, or says plainly why not (review18): the PLY of `regions -o` (double properties, face
// colours: it broke the page) is drawn in its regions' colours, opened through view.py and through
// the picker; a result PLY a few radii from the origin is drawn (its stale bounding sphere culled
// it); a file that fails is named with a short error, and a --log that is not a log leaves the mesh
// drawn; two runs' .glb side by side step by run frame, the shorter holding its last frame; file
// names are shown as written (not percent-encoded), two of one name with their folders; a .gltf
// (repair's, run's of a .gltf input) opens and is drawn.
// Usage: node viewer/tests/viewer_results_test.mjs --cli SHELLCONTRACT --mesh bumpy_sphere.off [--chromium PATH]
import { mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { check, finish, parseArgs, runCli, startViewer, workFolder } from './test_support.mjs';

const args = parseArgs('viewer_results_test.mjs --cli SHELLCONTRACT --mesh MESH.off [--chromium PATH]', ['cli', 'mesh']);
const work = workFolder('shellcontract-viewer-results-');
const file = work.file;
const cli = (...a) => runCli(args.cli, ...a);

cli('regions', args.mesh, '-o', file('regions.ply'));
// The mesh moved 3 of its sizes along x, and its run's PLY result.
{
  const lines = readFileSync(args.mesh, 'utf8').split(/\r?\n/);
  let at = 0;
  while (!/^\s*\d/.test(lines[at])) at++;
  const nv = Number(lines[at].trim().split(/\s+/)[0]);
  let x0 = Infinity, x1 = -Infinity;
  for (let i = at + 1; i <= at + nv; i++) { const x = Number(lines[i].trim().split(/\s+/)[0]); x0 = Math.min(x0, x); x1 = Math.max(x1, x); }
  for (let i = at + 1; i <= at + nv; i++) {
    const c = lines[i].trim().split(/\s+/);
    lines[i] = [Number(c[0]) + 3 * (x1 - x0), c[1], c[2]].join(' ');
  }
  writeFileSync(file('moved.off'), lines.join('\n'));
}
cli('run', file('moved.off'), '-o', file('moved_out.ply'), '-n', '5', '-q');
// Two runs of different lengths and kept frames: frames 0 to 20 (every one), and 0 to 40 (every 5th).
cli('run', args.mesh, '-o', file('short.off'), '-n', '20', '-q', '--gltf', file('short.glb'), '--summary', file('short.json'));
cli('run', args.mesh, '-o', file('long.off'), '-n', '40', '-q', '--gltf', file('long.glb'), '--export-every', '5');
writeFileSync(file('notalog.csv'), 'a,b\n1,2\n');
writeFileSync(file('other.json'), '{"name": "not a summary"}');
writeFileSync(file('my run #2 (50%) é.off'), readFileSync(args.mesh));
for (const d of ['before', 'after']) {
  mkdirSync(file(d));
  writeFileSync(file(`${d}/out.off`), readFileSync(d === 'before' ? args.mesh : file('short.off')));
}
writeFileSync(file('cut.glb'), readFileSync(file('short.glb')).subarray(0, 4000));
// A .gltf, as repair writes it on request (and run for a .gltf input): its buffers embedded.
cli('repair', args.mesh, '-o', file('repaired.gltf'));

const { page, consoleErrors, open, pick, shot, pixels, close } = await startViewer(args.chromium);
const status = () => page.$eval('#status', (e) => ({ text: e.textContent, error: e.classList.contains('error'), height: e.getBoundingClientRect().height }));
try {
  // The regions PLY: opens, is drawn, shows its face colours (regions) and says what they are.
  for (const how of ['view.py', 'the picker']) {
    const s = how === 'view.py' ? await open(file('regions.ply')) : await pick(file('regions.ply'));
    const line = await status();
    check(!s.error && s.panes.length === 1 && !line.error && /^regions\.ply: \d+ vertices/.test(line.text),
          `through ${how}, regions.ply opens (${s.error ?? line.text})`);
    const note = await page.$eval('#colour-note', (e) => e.textContent);
    check(s.shown[0] === 'file colours' && /face colours/.test(note) && /region/.test(note),
          `through ${how}, its face colours (its regions) are shown, and the note says so (${s.shown[0]}; "${note}")`);
    const p = await pixels(await shot());
    check(p.covered > 0.02, `through ${how}, regions.ply is drawn (${(100 * p.covered).toFixed(1)} % of the pixels)`);
  }
  // Its curvature, a double property, colours it too.
  await page.select('#colour', 'field:mean_curvature');
  const field = await page.evaluate(() => ({ shown: window.viewer.shown[0], legend: window.viewer.legend }));
  check(field.shown === 'mean_curvature' && field.legend?.name === 'mean_curvature', `its mean curvature (doubles) colours it (${JSON.stringify(field)})`);

  // A result a few radii from the origin is drawn, alone and beside its input.
  let s = await open(file('moved_out.ply'));
  let c = (await pixels(await shot())).covered;
  check(!s.error && c > 0.02, `moved_out.ply, 3 sizes from the origin, is drawn (${(100 * c).toFixed(1)} % of the pixels)`);
  s = await open(file('moved.off'), file('moved_out.ply'));
  c = (await pixels(await shot('right'))).covered;
  check(!s.error && c > 0.02, `beside moved.off, moved_out.ply is drawn (${(100 * c).toFixed(1)} % of the right half)`);

  // The .gltf opens and is drawn, through view.py and the picker (both had refused it).
  for (const how of ['view.py', 'the picker']) {
    s = how === 'view.py' ? await open(file('repaired.gltf')) : await pick(file('repaired.gltf'));
    const line = await status();
    c = (await pixels(await shot())).covered;
    check(!s.error && s.panes.length === 1 && !line.error && /^repaired\.gltf: \d+ vertices/.test(line.text) && c > 0.02,
          `through ${how}, repaired.gltf opens and is drawn (${s.error ?? line.text}; ${(100 * c).toFixed(1)} % of the pixels)`);
  }

  // A .glb cut short: the error names the file and is short; the status line stays one or two lines.
  s = await open(file('cut.glb'));
  let line = await status();
  check(line.error && /^cut\.glb: /.test(line.text) && line.text.length < 300 && line.height < 60,
        `a cut .glb's error names it, briefly ("${line.text}", ${line.height} px high)`);
  // A --log that is not a log: its error is named, and the mesh is drawn all the same.
  s = await open(file('moved.off'), '--log', file('notalog.csv'));
  line = await status();
  c = (await pixels(await shot())).covered;
  check(s.panes.length === 1 && /notalog\.csv: /.test(line.text) && /moved\.off: \d+ vertices/.test(line.text) && c > 0.02,
        `a bad --log is named and the mesh still drawn ("${line.text}", ${(100 * c).toFixed(1)} % drawn)`);
  // A JSON that is not a run's summary is named, not read as "final V/V0 undefined".
  s = await open(file('moved.off'), '--log', file('other.json'));
  line = await status();
  check(/other\.json: not a run summary/.test(line.text), `a JSON that is not a summary is named ("${line.text}")`);
  consoleErrors.splice(0, consoleErrors.length, ...consoleErrors.filter((m) => !/cut\.glb|notalog\.csv|other\.json/.test(m)));
  // A summary's values are shown to four decimals.
  s = await open(file('short.glb'), '--log', file('short.json'));
  const plotNote = await page.$eval('#plot-note', (e) => e.textContent);
  check(/^short\.json: final V\/V0 \d\.\d{4}(, minimum \d\.\d{4})?$/.test(plotNote), `the summary's values, to four decimals ("${plotNote}")`);
  // A file name as the user wrote it, not percent-encoded.
  s = await open(file('my run #2 (50%) é.off'));
  line = await status();
  check(!s.error && line.text.startsWith('my run #2 (50%) é.off: ') && s.panes[0]?.name === 'my run #2 (50%) é.off',
        `a file name with spaces, '#', '%' and 'é' is shown as written ("${line.text}")`);
  // Two files of one name: each named with its folder, as the user knows them.
  s = await open(file('before/out.off'), file('after/out.off'));
  check(JSON.stringify(s.panes.map((p) => p.name)) === '["before/out.off","after/out.off"]',
        `two out.off are named by their folders (${s.panes.map((p) => p.name).join(', ')})`);

  // Two runs side by side: stepped by run frame; each pane at its last kept frame at or before it.
  for (const order of [['short', 'long'], ['long', 'short']]) {
    s = await open(...order.map((n) => file(`${n}.glb`)));
    const frames = await page.evaluate(() => window.viewer.frameNumbers);
    check(frames.length === 25 && frames[0] === 0 && frames.at(-1) === 40 && frames.includes(13) && frames.includes(35),
          `${order.join(' | ')}: the frames of both runs (${frames.length}: ${frames[0]} to ${frames.at(-1)})`);
    const at = async (f) => {
      await page.evaluate((f) => window.viewer.jumpToFrame(f), f);
      const inf = await page.evaluate(() => window.viewer.influences());
      // The keyframe each pane shows: 0, or 1 + the index of its morph target at 1.
      return Object.fromEntries(order.map((n, i) => [n, inf[i][0].indexOf(1) + 1]));
    };
    const lengths = async () => (await page.evaluate(() => window.viewer.influences())).map((p) => p[0].length);
    const before = await lengths();
    let k = await at(10);
    check(k.short === 10 && k.long === 2, `${order.join(' | ')}: at frame 10, short shows its frame 10 and long its frame 10 (keyframes ${JSON.stringify(k)})`);
    k = await at(13);
    check(k.short === 13 && k.long === 2, `${order.join(' | ')}: at frame 13, long holds its frame 10 (keyframes ${JSON.stringify(k)})`);
    k = await at(40);
    check(k.short === 20 && k.long === 8, `${order.join(' | ')}: at frame 40, short holds its last frame (keyframes ${JSON.stringify(k)})`);
    await page.select('#colour', '0');
    k = await at(35);
    const shown = await page.evaluate(() => window.viewer.shown);
    check(JSON.stringify(await lengths()) === JSON.stringify(before) && shown.every((x) => x === 'mean_curvature'),
          `${order.join(' | ')}: no influence written past the end, both coloured (${JSON.stringify(await lengths())}, ${JSON.stringify(shown)})`);
  }
  check(consoleErrors.length === 0, `no console errors${consoleErrors.length ? ': ' + consoleErrors.slice(0, 3).join(' | ') : ''}`);
} finally {
  await close();
  work.remove();
}
finish('all viewer result checks passed');
