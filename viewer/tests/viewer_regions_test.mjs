// Headless check (Debian's Chromium, puppeteer-core) that a regions run's .glb shows its regions:
// the colour menu offers 'region', which draws each region id in a colour of its own (every corner
// of a face listed on a line of the --regions file in that line's colour, the faces of no region
// in another), with a legend of the ids instead of the ramp; a run without regions offers none.
// Usage: node viewer/tests/viewer_regions_test.mjs --cli SHELLCONTRACT --mesh bumpy_sphere.off
//        --regions bumpy_sphere.bumps.txt [--chromium PATH]
import { readFileSync } from 'node:fs';
import { check, finish, parseArgs, readOff, runCli, startViewer, workFolder } from './test_support.mjs';

const args = parseArgs('viewer_regions_test.mjs --cli SHELLCONTRACT --mesh MESH.off --regions FACES.txt [--chromium PATH]',
  ['cli', 'mesh', 'regions']);
const work = workFolder('shellcontract-viewer-regions-');
const file = work.file;
runCli(args.cli, 'run', args.mesh, '-o', file('regions.off'), '-n', '8', '-q', '--regions', args.regions, '--gltf', file('regions.glb'));
runCli(args.cli, 'run', args.mesh, '-o', file('plain.off'), '-n', '8', '-q', '--gltf', file('plain.glb'));

// Each face's region from the file's lines (0, 1, ... in order; -1 for a face on none).
const faces = readOff(args.mesh).faces.length;
const regionOf = new Array(faces).fill(-1);
readFileSync(args.regions, 'utf8').split(/\r?\n/).map((l) => l.replace(/^.*:/, '').trim()).filter(Boolean)
  .forEach((line, r) => line.split(/\s+/).forEach((f) => { regionOf[Number(f)] = r; }));
const ids = [...new Set(regionOf.filter((r) => r >= 0))].sort((a, b) => a - b);

const { page, consoleErrors, open, shot, pixels, close } = await startViewer(args.chromium);
try {
  let s = await open(file('regions.glb'));
  const options = await page.$$eval('#colour option', (o) => o.map((x) => [x.textContent, x.value]));
  const region = options.find((o) => o[0] === 'region');
  check(!s.error && region !== undefined, `the regions run's .glb offers 'region' (${options.map((o) => o[0]).join(', ')})`);
  await page.select('#colour', region?.[1] ?? '-1');
  const state = await page.evaluate(() => ({ shown: window.viewer.shown, legend: window.viewer.legend }));
  check(state.shown[0] === 'region' && state.legend?.name === 'region' && state.legend.categorical === true &&
        JSON.stringify(state.legend.ids) === JSON.stringify(ids),
        `'region' is shown, with a categorical legend of the file's ids ${JSON.stringify(ids)} (${JSON.stringify(state)})`);

  // Every corner of a face is its region's colour: one colour per id, each apart from the others.
  const [mesh] = (await page.evaluate(() => window.viewer.vertexColours()))[0];
  const colourOf = new Map();
  let mixed = 0;
  for (let f = 0; f < faces; f++) {
    for (let k = 0; k < 3; k++) {
      const v = mesh.index[3 * f + k];
      const c = mesh.rgb.slice(3 * v, 3 * v + 3);
      const had = colourOf.get(regionOf[f]);
      if (!had) colourOf.set(regionOf[f], c);
      else if (had.some((x, i) => Math.abs(x - c[i]) > 1e-6)) mixed++;
    }
  }
  check(mesh.index.length === 3 * faces && mixed === 0, `each face's corners are its region's colour, one colour per id (${mixed} corners differ)`);
  const all = [...colourOf.entries()];
  let closest = Infinity;
  for (let i = 0; i < all.length; i++) {
    for (let j = i + 1; j < all.length; j++) closest = Math.min(closest, Math.max(...all[i][1].map((x, k) => Math.abs(x - all[j][1][k]))));
  }
  check(all.length === ids.length + 1 && closest > 0.1,
        `${ids.length} regions and none in ${all.length} colours, each pair apart (closest channel difference ${closest.toFixed(3)})`);

  // The legend: a swatch per id and one for none, each in its id's colour; the ramp and its
  // ticks (a field's ends) not drawn.
  const bar = await page.evaluate(() => {
    const b = document.querySelector('#colour-bar');
    const shown = (e) => getComputedStyle(e).display !== 'none';
    return { hidden: b.hidden, ramp: !shown(b.querySelector('.ramp')) && !shown(b.querySelector('.ticks')),
             swatches: [...b.querySelectorAll('.swatch')].map((e) => [e.textContent, getComputedStyle(e).backgroundColor]),
             note: document.querySelector('#colour-note').textContent };
  });
  const labels = bar.swatches.map((x) => x[0]);
  check(!bar.hidden && bar.ramp && JSON.stringify(labels) === JSON.stringify(['none', ...ids.map(String)]) &&
        new Set(bar.swatches.map((x) => x[1])).size === labels.length && /^region: \d+ ids?/.test(bar.note),
        `the legend shows the ids, each in a colour of its own (${JSON.stringify(bar)})`);
  const p = await pixels(await shot());
  check(p.covered > 0.05, `the mesh is drawn (${(100 * p.covered).toFixed(1)} % of the pixels)`);

  // Back to a field: its ramp again, the swatches gone.
  await page.select('#colour', '0');
  const back = await page.evaluate(() => {
    const shown = (s) => getComputedStyle(document.querySelector(`#colour-bar ${s}`)).display !== 'none';
    return { ramp: shown('.ramp'), ticks: shown('.ticks'), swatches: shown('.swatches') };
  });
  check(back.ramp && back.ticks && !back.swatches, `a field's ramp and ticks come back, the swatches go (${JSON.stringify(back)})`);

  // A run without regions offers none.
  s = await open(file('plain.glb'));
  const plain = await page.$$eval('#colour option', (o) => o.map((x) => x.textContent));
  check(!s.error && !plain.includes('region'), `a run without regions offers no 'region' (${plain.join(', ')})`);
  check(consoleErrors.length === 0, `no console errors${consoleErrors.length ? ': ' + consoleErrors.slice(0, 3).join(' | ') : ''}`);
} finally {
  await close();
  work.remove();
}
finish('all viewer region checks passed');
