// Headless check that the viewer says a file is loading (Debian's Chromium, puppeteer-core): the
// test's own server serves the viewer and a run's .glb in two halves, holding the second until
// the page's status line has been read, so no timing decides what is seen. While the file loads
// the status line names it and the bytes read (window.viewer.loading too); once loaded the line is
// the file's summary and `loading` is null; a file that fails ends the loading line with its error.
// Usage: node viewer/tests/viewer_loading_test.mjs --glb RUN.glb [--chromium PATH]
import { createServer } from 'node:http';
import { readFileSync } from 'node:fs';
import path from 'node:path';
import { check, finish, parseArgs, repo, startViewer } from './test_support.mjs';

const args = parseArgs('viewer_loading_test.mjs --glb RUN.glb [--chromium PATH]', ['glb']);
const glb = readFileSync(args.glb);
const viewerDir = path.join(repo, 'viewer');
const types = { '.html': 'text/html', '.js': 'text/javascript', '.mjs': 'text/javascript', '.css': 'text/css' };

// /held/NAME: the bytes of NAME (run.glb: the .glb; bad.glb: not a .glb), the first half at once
// and the rest when the test releases it.
let release = null;
const released = () => new Promise((r) => { release = r; });
const server = createServer(async (req, res) => {
  const url = new URL(req.url, 'http://localhost');
  if (url.pathname.startsWith('/held/')) {
    const body = url.pathname === '/held/run.glb' ? glb : Buffer.alloc(glb.length, 'x');
    const wait = released();
    res.writeHead(200, { 'Content-Type': 'model/gltf-binary', 'Content-Length': body.length });
    res.write(body.subarray(0, body.length >> 1));
    await wait;
    res.end(body.subarray(body.length >> 1));
    return;
  }
  const file = path.join(viewerDir, path.normalize(url.pathname));
  try {
    const bytes = readFileSync(file);
    res.writeHead(200, { 'Content-Type': types[path.extname(file)] ?? 'application/octet-stream' });
    res.end(bytes);
  } catch {
    res.writeHead(404);
    res.end();
  }
});
await new Promise((r) => server.listen(0, '127.0.0.1', r));
const base = `http://127.0.0.1:${server.address().port}`;

const { page, consoleErrors, close } = await startViewer(args.chromium);
const status = () => page.$eval('#status', (e) => e.textContent);
try {
  await page.goto(`${base}/index.html?file=/held/run.glb`, { waitUntil: 'load' });
  // Half the file is there: the line says so (its 100 ms updates catch up with the bytes).
  await page.waitForFunction(() => window.viewer.loading?.loaded > 0, { timeout: 30000 });
  await page.waitForFunction(() => /\((\d+) %\)/.exec(document.getElementById('status').textContent)?.[1] > 0,
    { timeout: 5000 }).catch(() => {});
  const during = await status();
  const loading = await page.evaluate(() => window.viewer.loading);
  check(during.startsWith('Loading run.glb: '), `while it loads the status line names the file ("${during}")`);
  const percent = Number(/\((\d+) %\)/.exec(during)?.[1]);
  check(percent > 0 && percent < 100, `it gives the part read, between 0 and 100 % (${percent} %)`);
  check(!during.includes('Drop'), 'it no longer invites a drop');
  check(loading?.name === 'run.glb' && loading.total === glb.length && loading.loaded < glb.length,
    `window.viewer.loading: ${JSON.stringify(loading)} of ${glb.length} bytes`);
  check(!(await page.evaluate(() => window.viewer.ready)), 'the viewer is not ready yet');
  release();
  await page.waitForFunction(() => window.viewer.ready || window.viewer.error, { timeout: 60000 });
  const after = await status();
  check(await page.evaluate(() => window.viewer.loading === null), 'once loaded, window.viewer.loading is null');
  check(after.startsWith('run.glb: ') && after.includes('vertices') && !after.includes('Loading'),
    `once loaded the status line is the file's summary ("${after}")`);

  // A file that fails: the loading line gives way to the error.
  await page.goto(`${base}/index.html?file=/held/bad.glb`, { waitUntil: 'load' });
  await page.waitForFunction(() => window.viewer.loading?.loaded > 0, { timeout: 30000 });
  release();
  await page.waitForFunction(() => window.viewer.error, { timeout: 60000 });
  const failed = await status();
  check(await page.evaluate(() => window.viewer.loading === null), 'after an error, window.viewer.loading is null');
  check(!failed.startsWith('Loading'), `after an error the status line is the error ("${failed}")`);
  consoleErrors.splice(0);  // the bad file's own error, expected
} finally {
  await close();
  server.close();
}
check(consoleErrors.length === 0, `no console errors (${consoleErrors.join('; ')})`);
finish('viewer loading test passed');
