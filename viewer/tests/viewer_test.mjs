// Headless check of the viewer in Debian's Chromium (puppeteer-core; no browser is downloaded):
// serves a run with scripts/view.py, then checks that the page loads with no console errors, that
// the first and last frames look different, that the scrubber moves the mesh, that the plot holds
// the CSV's V/V0 series (and, with --json, the summary's final and minimum V/V0), and that
// switching the colour field changes the picture.
// Usage: node viewer/tests/viewer_test.mjs --glb RUN.glb --csv RUN.csv [--json RUN.json]
//        [--chromium PATH] [--screenshot OUT.png]
import { readFileSync } from 'node:fs';
import { check, finish, parseArgs, startViewer } from './test_support.mjs';

const args = parseArgs('viewer_test.mjs --glb RUN.glb --csv RUN.csv [--chromium PATH] [--screenshot OUT.png]',
  ['glb', 'csv']);

const { page, consoleErrors, open, showLabels, pick, settle, shot, differing, close } = await startViewer(args.chromium);
try {
  page.on('requestfailed', (r) => consoleErrors.push(`request failed: ${r.url()}`));
  const opened = await open(args.glb, '--log', args.csv);
  console.log(`viewer at ${page.url()}`);
  const state0 = { error: opened.error, frames: await page.evaluate(() => window.viewer.frameNumbers) };
  check(!state0.error, `the run loads (${state0.error ?? 'no error'})`);
  check(state0.frames.length > 2, `the file has several frames (${state0.frames.length})`);

  // First frame against last frame, moved with the scrubber (keyboard on the range input).
  const first = await shot();
  const plotFirst = await shot('#plot');
  await page.focus('#scrubber');
  await page.keyboard.press('End');
  const kLast = await page.evaluate(() => window.viewer.keyframe);
  check(kLast === state0.frames.length - 1, `End on the scrubber shows the last frame (keyframe ${kLast})`);
  const last = await shot();
  const dLast = await differing(first, last);
  check(dLast > 0.01, `first and last frame differ (${(100 * dLast).toFixed(1)} % of the pixels)`);

  // The scrubber moves the mesh step by step: Home, then two steps right.
  await page.keyboard.press('Home');
  const home = await shot();
  check(await differing(first, home) < 0.001, 'Home on the scrubber brings back the first frame');
  await page.keyboard.press('ArrowRight');
  await page.keyboard.press('ArrowRight');
  const k2 = await page.evaluate(() => window.viewer.keyframe);
  const label = await page.$eval('#frame-label', (e) => e.textContent);
  check(k2 === 2, `two steps right show keyframe 2 (${k2}; label "${label}")`);
  check(label.startsWith(`frame ${state0.frames[2]} `), `the label names the frame (${label})`);
  const d2 = await differing(home, await shot());
  check(d2 > 0.001, `the mesh moved (${(100 * d2).toFixed(2)} % of the pixels)`);

  // The plot: the page's series is the CSV's, and the marker follows the frame.
  const lines = readFileSync(args.csv, 'utf8').trim().split('\n');
  const header = lines[0].split(',');
  const rows = lines.slice(1).map((l) => l.split(','));
  const expectFrame = rows.map((r) => Number(r[header.indexOf('frame')]));
  const expectRatio = rows.map((r) => Number(r[header.indexOf('volume_ratio')]));
  const log = await page.evaluate(() => window.viewer.log);
  check(log && JSON.stringify(log.frame) === JSON.stringify(expectFrame), `the plot's frames are the CSV's (${log?.frame.length} rows)`);
  check(log && JSON.stringify(log.volumeRatio) === JSON.stringify(expectRatio), "the plot's V/V0 are the CSV's");
  check(Math.min(...expectRatio) < 0.99, `the run's V/V0 goes down (to ${Math.min(...expectRatio).toFixed(3)})`);
  const dPlot = await differing(plotFirst, await shot('#plot'));
  check(dPlot > 0.0005, `the plot's marker follows the frame (${(100 * dPlot).toFixed(2)} % of its pixels changed)`);

  // Colour fields: switching changes the picture.
  const fields = await page.evaluate(() => window.viewer.colourFields.map((f) => f.name));
  check(fields.length >= 1, `the file's colour fields are offered (${fields.join(', ')})`);
  const c0 = await shot();
  if (fields.length >= 2) {
    await page.select('#colour', '1');
    check(await differing(c0, await shot()) > 0.01, 'switching to the second colour field changes the colours');
  }
  await page.select('#colour', '-1');
  check(await differing(c0, await shot()) > 0.01, 'switching the colours off changes the picture');

  if (args.screenshot) {
    await showLabels();  // the README's picture: the page as a user sees it
    await page.select('#colour', '0');
    await page.focus('#scrubber');
    await page.keyboard.press('End');
    await settle();
    await page.screenshot({ path: args.screenshot });
    console.log(`screenshot: ${args.screenshot}`);
  }
  // The file picker: the same run opened through the page's <input type=file>.
  await page.evaluate(() => { window.viewer.log = null; });
  await pick(args.glb, args.csv);
  const picked = await page.evaluate(() => ({
    frames: window.viewer.frameNumbers.length, rows: window.viewer.log?.frame.length }));
  check(picked.frames === state0.frames.length && picked.rows === expectFrame.length,
        `the file picker opens the .glb and the CSV (${picked.frames} frames, ${picked.rows} rows)`);

  // The JSON summary instead of the CSV: its final and minimum V/V0.
  if (args.json) {
    await open(args.glb, '--log', args.json);
    const expected = JSON.parse(readFileSync(args.json, 'utf8'));
    const summary = await page.evaluate(() => window.viewer.summary);
    check(summary && summary.finalVolumeRatio === expected.final_volume_ratio &&
          summary.minVolumeRatio === expected.min_volume_ratio,
          `the summary's final and minimum V/V0 are the JSON's (${summary?.finalVolumeRatio}, ${summary?.minVolumeRatio})`);
  }
  check(consoleErrors.length === 0, `no console errors${consoleErrors.length ? ': ' + consoleErrors.join(' | ') : ''}`);
} finally {
  await close();
}
finish('all viewer checks passed');
