// Headless check of the viewer in Debian's Chromium (puppeteer-core; no browser is downloaded):
// serves a run with scripts/view.py, then checks that the page loads with no console errors, that
// the first and last frames look different, that the scrubber moves the mesh, that the plot holds
// the CSV's V/V0 series (and, with --json, the summary's final and minimum V/V0), and that
// switching the colour field changes the picture.
// Usage: node viewer/tests/viewer_test.mjs --glb RUN.glb --csv RUN.csv [--json RUN.json]
//        [--chromium PATH] [--screenshot OUT.png]
import { mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import puppeteer from 'puppeteer-core';
import { check, finish, parseArgs, serve } from './test_support.mjs';

const args = parseArgs('viewer_test.mjs --glb RUN.glb --csv RUN.csv [--chromium PATH] [--screenshot OUT.png]',
  ['glb', 'csv']);
const chromium = args.chromium ?? '/usr/bin/chromium';

const { server, url } = await serve(args.glb, '--log', args.csv);
let jsonServer = null;
console.log(`viewer at ${url}`);
const profile = mkdtempSync(path.join(tmpdir(), 'shellcontract-chromium-'));
const browser = await puppeteer.launch({
  executablePath: chromium,
  headless: true,
  userDataDir: profile,
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
    '--disable-background-networking', '--disable-component-update', '--disable-sync',
    '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
});
try {
  const page = await browser.newPage();
  await page.setViewport({ width: 1100, height: 640 });
  const consoleErrors = [];
  page.on('console', (m) => { if (m.type() === 'error') consoleErrors.push(m.text()); });
  page.on('pageerror', (e) => consoleErrors.push(String(e)));
  page.on('requestfailed', (r) => consoleErrors.push(`request failed: ${r.url()}`));
  await page.goto(url, { waitUntil: 'load' });
  await page.waitForFunction(() => window.viewer && (window.viewer.ready || window.viewer.error), { timeout: 60000 });
  const state0 = await page.evaluate(() => ({ error: window.viewer.error, frames: window.viewer.frameNumbers }));
  check(!state0.error, `the run loads (${state0.error ?? 'no error'})`);
  check(state0.frames.length > 2, `the file has several frames (${state0.frames.length})`);

  const settle = () => page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
  const shot = async (selector) => { await settle(); return (await page.$(selector)).screenshot({ encoding: 'base64' }); };
  /** Fraction of pixels that differ between two PNG screenshots (decoded in the page). */
  const differing = (a, b) => page.evaluate(async (a, b) => {
    const load = async (s) => {
      const img = new Image();
      img.src = `data:image/png;base64,${s}`;
      await img.decode();
      const c = new OffscreenCanvas(img.width, img.height);
      const ctx = c.getContext('2d');
      ctx.drawImage(img, 0, 0);
      return ctx.getImageData(0, 0, img.width, img.height).data;
    };
    const [pa, pb] = [await load(a), await load(b)];
    if (pa.length !== pb.length) return 1;
    let n = 0;
    for (let i = 0; i < pa.length; i += 4)
      if (Math.abs(pa[i] - pb[i]) + Math.abs(pa[i + 1] - pb[i + 1]) + Math.abs(pa[i + 2] - pb[i + 2]) > 24) n++;
    return n / (pa.length / 4);
  }, a, b);

  // First frame against last frame, moved with the scrubber (keyboard on the range input).
  const first = await shot('#view');
  const plotFirst = await shot('#plot');
  await page.focus('#scrubber');
  await page.keyboard.press('End');
  const kLast = await page.evaluate(() => window.viewer.keyframe);
  check(kLast === state0.frames.length - 1, `End on the scrubber shows the last frame (keyframe ${kLast})`);
  const last = await shot('#view');
  const dLast = await differing(first, last);
  check(dLast > 0.01, `first and last frame differ (${(100 * dLast).toFixed(1)} % of the pixels)`);

  // The scrubber moves the mesh step by step: Home, then two steps right.
  await page.keyboard.press('Home');
  const home = await shot('#view');
  check(await differing(first, home) < 0.001, 'Home on the scrubber brings back the first frame');
  await page.keyboard.press('ArrowRight');
  await page.keyboard.press('ArrowRight');
  const k2 = await page.evaluate(() => window.viewer.keyframe);
  const label = await page.$eval('#frame-label', (e) => e.textContent);
  check(k2 === 2, `two steps right show keyframe 2 (${k2}; label "${label}")`);
  check(label.startsWith(`frame ${state0.frames[2]} `), `the label names the frame (${label})`);
  const d2 = await differing(home, await shot('#view'));
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
  const c0 = await shot('#view');
  if (fields.length >= 2) {
    await page.select('#colour', '1');
    check(await differing(c0, await shot('#view')) > 0.01, 'switching to the second colour field changes the colours');
  }
  await page.select('#colour', '-1');
  check(await differing(c0, await shot('#view')) > 0.01, 'switching the colours off changes the picture');

  if (args.screenshot) {
    await page.select('#colour', '0');
    await page.focus('#scrubber');
    await page.keyboard.press('End');
    await settle();
    await page.screenshot({ path: args.screenshot });
    console.log(`screenshot: ${args.screenshot}`);
  }
  // The file picker: the same run opened through the page's <input type=file>.
  await page.evaluate(() => { window.viewer.ready = false; window.viewer.log = null; });
  await (await page.$('#file-input')).uploadFile(args.glb, args.csv);
  await page.waitForFunction(() => window.viewer.ready && window.viewer.log, { timeout: 60000 });
  const picked = await page.evaluate(() => ({
    frames: window.viewer.frameNumbers.length, rows: window.viewer.log.frame.length }));
  check(picked.frames === state0.frames.length && picked.rows === expectFrame.length,
        `the file picker opens the .glb and the CSV (${picked.frames} frames, ${picked.rows} rows)`);

  // The JSON summary instead of the CSV: its final and minimum V/V0.
  if (args.json) {
    const served = await serve(args.glb, '--log', args.json);
    jsonServer = served.server;
    await page.goto(served.url, { waitUntil: 'load' });
    await page.waitForFunction(() => window.viewer && (window.viewer.ready || window.viewer.error), { timeout: 60000 });
    const expected = JSON.parse(readFileSync(args.json, 'utf8'));
    const summary = await page.evaluate(() => window.viewer.summary);
    check(summary && summary.finalVolumeRatio === expected.final_volume_ratio &&
          summary.minVolumeRatio === expected.min_volume_ratio,
          `the summary's final and minimum V/V0 are the JSON's (${summary?.finalVolumeRatio}, ${summary?.minVolumeRatio})`);
  }
  check(consoleErrors.length === 0, `no console errors${consoleErrors.length ? ': ' + consoleErrors.join(' | ') : ''}`);
} finally {
  await browser.close();
  server.kill();
  jsonServer?.kill();
  rmSync(profile, { recursive: true, force: true });
}
finish('all viewer checks passed');
