// Headless check (Debian's Chromium, puppeteer-core) of the viewer's error paths that no good file
// reaches: a PLY cut short is refused in the status line, naming the file and that it is cut
// short, through view.py and through the picker, and no pane of its part is shown (it opened as
// a partial mesh); a pane whose first draw throws (a failure injected into three.js's
// Object3D.onBeforeRender) is named with the error in the status line, the page ready and not left
// on "making its meshes", and the next file opens; an attribute of doubles (injected into
// OBJLoader's result: the loaders convert every file's) is named before the draw, not reported
// with three.js's message. An STL of upper-case keywords is refused with the keyword named, and a PLY
// whose header runs past 64 KiB offers its field; one of a thousand comments names a few of them in
// its colour note.
// Usage: node viewer/tests/viewer_errors_test.mjs --mesh ico2.off [--chromium PATH]
import { writeFileSync } from 'node:fs';
import { check, finish, parseArgs, readOff, startViewer, workFolder } from './test_support.mjs';

const args = parseArgs('viewer_errors_test.mjs --mesh MESH.off [--chromium PATH]', ['mesh']);
const work = workFolder('shellcontract-viewer-errors-');
const file = work.file;

const { vertices, faces } = readOff(args.mesh);
const ply = 'ply\nformat ascii 1.0\n' + `element vertex ${vertices.length}\nproperty float x\nproperty float y\nproperty float z\n` +
  `element face ${faces.length}\nproperty list uchar int vertex_indices\nend_header\n` +
  vertices.map((v) => v.join(' ')).join('\n') + '\n' + faces.map((f) => `3 ${f.join(' ')}`).join('\n') + '\n';
writeFileSync(file('whole.ply'), ply);
// Cut within the faces: the part read has every vertex and most faces (it opened as a mesh with a hole).
writeFileSync(file('cut.ply'), ply.slice(0, Math.floor(ply.length * 0.8)));
// An ASCII STL of upper-case keywords, as some CAD exporters write it (the CLI refuses it): it was
// named as a binary STL cut short. A PLY whose header, of comments, runs past 64 KiB (the CLI
// reads it): it opened without its field.
writeFileSync(file('upper.stl'), `SOLID S\n${faces.map((f) => 'FACET NORMAL 0 0 0\nOUTER LOOP\n' +
  f.map((i) => `VERTEX ${vertices[i].join(' ')}\n`).join('') + 'ENDLOOP\nENDFACET\n').join('')}ENDSOLID S\n`);
writeFileSync(file('long_header.ply'), 'ply\nformat ascii 1.0\n' + `comment ${'c'.repeat(90)}\n`.repeat(800) +
  `element vertex ${vertices.length}\nproperty float x\nproperty float y\nproperty float z\nproperty float height\n` +
  `element face ${faces.length}\nproperty list uchar int vertex_indices\nend_header\n` +
  vertices.map((v) => `${v.join(' ')} ${v[2]}`).join('\n') + '\n' + faces.map((f) => `3 ${f.join(' ')}`).join('\n') + '\n');
// A coloured PLY that keeps a thousand comments (a result keeps its input's): its colour note
// listed every one of them.
writeFileSync(file('many_comments.ply'), 'ply\nformat ascii 1.0\n' +
  Array.from({ length: 1000 }, (_, i) => `comment note ${i} ${'x'.repeat(200)}\n`).join('') +
  `element vertex ${vertices.length}\nproperty float x\nproperty float y\nproperty float z\n` +
  'property uchar red\nproperty uchar green\nproperty uchar blue\n' +
  `element face ${faces.length}\nproperty list uchar int vertex_indices\nend_header\n` +
  vertices.map((v) => `${v.join(' ')} 200 30 30`).join('\n') + '\n' + faces.map((f) => `3 ${f.join(' ')}`).join('\n') + '\n');
writeFileSync(file('tri.obj'), 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n');
writeFileSync(file('doubles.obj'), 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n');  // another name: the picker fires no change for the same file

const { page, consoleErrors, open, pick, close } = await startViewer(args.chromium);
const status = () => page.$eval('#status', (e) => ({ text: e.textContent, error: e.classList.contains('error') }));
const viewer = () => page.evaluate(() => ({ ready: window.viewer.ready, error: window.viewer.error, loading: window.viewer.loading,
                                            panes: window.viewer.panes.map((p) => p.name) }));
try {
  // A PLY cut short: refused, named, no pane.
  let s = await open(file('cut.ply'));
  let line = await status();
  check(line.error && /^cut\.ply: the file ends after \d+ of the \d+ 'face' elements its header gives: it is cut short$/.test(line.text),
        `through view.py, a PLY cut short is refused in the status line, named ("${line.text}")`);
  check(s.panes.length === 0, `through view.py, no pane of its part is shown (${JSON.stringify(s.panes)})`);
  s = await open(file('whole.ply'));
  check(!s.error && s.panes.length === 1, `the whole PLY opens (${s.error ?? s.panes[0]?.name})`);
  s = await pick(file('cut.ply'));
  line = await status();
  check(line.error && /^cut\.ply: the file ends after .*: it is cut short$/.test(line.text),
        `through the picker, the PLY cut short is refused in the status line, named ("${line.text}")`);

  s = await open(file('upper.stl'));
  line = await status();
  check(line.error && /^upper\.stl: line 1: the keyword 'SOLID' is not in lower case/.test(line.text) && s.panes.length === 0,
        `an STL of upper-case keywords is refused in the status line, the keyword named ("${line.text}")`);
  s = await open(file('long_header.ply'));
  const menu = await page.$eval('#colour', (e) => [...e.options].map((o) => o.textContent));
  check(!s.error && menu.some((o) => /height/.test(o)), `a PLY of a header past 64 KiB opens with its field in the menu (${s.error ?? JSON.stringify(menu)})`);

  s = await open(file('many_comments.ply'));
  const note = await page.$eval('#colour-note', (e) => e.textContent);
  check(!s.error && /note 0 x+\u2026; note 1 .*; note 2 .*; and 997 more comments/.test(note) && note.length < 600,
        `a PLY of a thousand comments names three, cut, and counts the rest (${note.length} characters: "${note.slice(0, 80)}...")`);

  // A first draw that throws: injected into three.js (the page's own module, through its import map).
  await page.evaluate(async () => {
    const THREE = await import('three');
    const before = THREE.Object3D.prototype.onBeforeRender;
    THREE.Object3D.prototype.onBeforeRender = function (...a) {
      if (window.failDraws && this.isMesh) throw new Error('injected draw failure');
      return before.apply(this, a);
    };
    window.failDraws = true;
  });
  // A page left unready (the error not caught) fails the wait: named here, not as puppeteer's timeout.
  s = await pick(file('whole.ply')).catch((e) => ({ error: `never ready: ${e.message}` }));
  line = await status();
  const v = await viewer();
  check(line.error && line.text === 'whole.ply: injected draw failure' && v.error === line.text,
        `a pane whose first draw throws is named with the error in the status line ("${line.text}")`);
  check(v.ready && v.loading === null && !/making its meshes/.test(line.text), `the page is ready, not left loading (${JSON.stringify(v)})`);
  await page.evaluate(() => { window.failDraws = false; });
  s = await pick(file('tri.obj'));
  line = await status();
  check(!s.error && !line.error && /^tri\.obj: 3 vertices/.test(line.text), `after it, the next file opens ("${line.text}")`);

  // An attribute of doubles: injected into OBJLoader's result (the page's module); named before the draw.
  await page.evaluate(async () => {
    const THREE = await import('three');
    const { OBJLoader } = await import('three/addons/loaders/OBJLoader.js');
    const parse = OBJLoader.prototype.parse;
    OBJLoader.prototype.parse = function (...a) {
      const object = parse.apply(this, a);
      object.traverse((o) => {
        if (o.isMesh) o.geometry.setAttribute('uv', new THREE.BufferAttribute(new Float64Array(2 * o.geometry.getAttribute('position').count), 2));
      });
      return object;
    };
  });
  s = await pick(file('doubles.obj'));
  line = await status();
  check(line.error && line.text === "doubles.obj: its 'uv' values are doubles, which WebGL cannot draw",
        `an attribute of doubles is named in the status line ("${line.text}")`);

  const expected = /cut\.ply|upper\.stl|injected draw failure|doubles/;
  const others = consoleErrors.filter((m) => !expected.test(m));
  check(others.length === 0, `no other console errors${others.length ? ': ' + others.slice(0, 3).join(' | ') : ''}`);
} finally {
  await close();
  work.remove();
}
finish('all viewer error checks passed');
