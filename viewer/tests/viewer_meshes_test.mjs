// Headless check (Debian's Chromium, puppeteer-core) of what issue 56 asked of the viewer: it
// opens result meshes (OFF, OBJ, PLY, STL), shows two files side by side (and a .glb's first
// frame beside its current one), colours each pane and each frame with its own values (a glTF
// field of one frame only on that frame), and jumps to a frame; a .glb of several primitives (an
// OBJ with two materials) plays and colours every one; the two panes of "before | after" wear each
// its own frame's colours; with no field chosen a .glb's primitives wear their materials (base
// colour, texture). The files come from real runs of the CLI on a small mesh, made here in a
// temporary folder.
// Usage: node viewer/tests/viewer_meshes_test.mjs --cli SHELLCONTRACT --mesh ico2.off [--chromium PATH]
import { spawn, spawnSync } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { deflateSync } from 'node:zlib';
import puppeteer from 'puppeteer-core';

const args = Object.fromEntries(process.argv.slice(2).reduce((acc, a, i, all) => {
  if (a.startsWith('--')) acc.push([a.slice(2), all[i + 1]]);
  return acc;
}, []));
const repo = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..', '..');
if (!args.cli || !args.mesh) {
  console.error('usage: viewer_meshes_test.mjs --cli SHELLCONTRACT --mesh MESH.off [--chromium PATH]');
  process.exit(2);
}
const failures = [];
function check(ok, what) {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failures.push(what);
}

// ---------------------------------------------------------------- the files
const work = mkdtempSync(path.join(tmpdir(), 'shellcontract-viewer-meshes-'));
const file = (n) => path.join(work, n);
function cli(...a) {
  const r = spawnSync(args.cli, a, { encoding: 'utf8' });
  if (r.status !== 0 && r.status !== 5) throw new Error(`${args.cli} ${a.join(' ')}: exit ${r.status}\n${r.stderr}`);
}
const runOptions = ['--frames', '20', '--target-volume', '0.7', '-q'];
cli('run', args.mesh, '-o', file('out.off'), ...runOptions, '--fields', file('fields'), '--gltf', file('run.glb'), '--export-every', '5');
for (const ext of ['obj', 'ply', 'stl']) cli('run', args.mesh, '-o', file(`out.${ext}`), ...runOptions);
// The counts of the OFF input: the first line that is not the keyword or a comment.
const countLine = readFileSync(args.mesh, 'utf8').split(/\r?\n/).map((l) => l.split('#')[0].trim())
  .filter((l) => l && l !== 'OFF')[0].split(/\s+/);
const nv = Number(countLine[0]), nf = Number(countLine[1]);
// The same mesh as an OBJ whose faces use two materials (by the side of z = 0 their centroid
// is on), and the runs of both with the same options: the .glb of the OBJ has two primitives.
{
  const lines = readFileSync(args.mesh, 'utf8').split(/\r?\n/).map((l) => l.split('#')[0].trim())
    .filter((l) => l && l !== 'OFF').slice(1);
  const v = lines.slice(0, nv).map((l) => l.split(/\s+/));
  let obj = 'mtllib two.mtl\n' + v.map((c) => `v ${c[0]} ${c[1]} ${c[2]}\n`).join('');
  for (const l of lines.slice(nv, nv + nf)) {
    const f = l.split(/\s+/).slice(1, 4).map(Number);
    const z = f.reduce((s, i) => s + Number(v[i][2]), 0);
    obj += `usemtl ${z > 0 ? 'top' : 'bottom'}\nf ${f.map((i) => i + 1).join(' ')}\n`;
  }
  writeFileSync(file('two.obj'), obj);
  writeFileSync(file('two.mtl'), 'newmtl top\nKd 0.9 0.1 0.1\nnewmtl bottom\nKd 0.1 0.1 0.9\n');
  cli('run', file('two.obj'), '-o', file('two_out.obj'), ...runOptions, '--gltf', file('two.glb'), '--export-every', '5');
  cli('run', args.mesh, '-o', file('one_out.off'), ...runOptions, '--gltf', file('one.glb'), '--export-every', '5');
  // Three materials by the side of x = 0 the face is on: red and blue base colours, and a white
  // one with a green texture in the band between; the first faces have none. Every vertex has a
  // texture coordinate (its x and y), as the exporter writes TEXCOORD_0 for all or none.
  let three = 'mtllib three.mtl\n' + v.map((c) => `v ${c[0]} ${c[1]} ${c[2]}\n`).join('') +
    v.map((c) => `vt ${0.5 + Number(c[0])} ${0.5 + Number(c[1])}\n`).join('');
  lines.slice(nv, nv + nf).forEach((l, k) => {
    const f = l.split(/\s+/).slice(1, 4).map(Number);
    const x = f.reduce((s, i) => s + Number(v[i][0]), 0) / 3;
    if (k >= 3) three += `usemtl ${x > 0.15 ? 'red' : x < -0.15 ? 'blue' : 'skin'}\n`;
    three += `f ${f.map((i) => `${i + 1}/${i + 1}`).join(' ')}\n`;
  });
  writeFileSync(file('three.obj'), three);
  writeFileSync(file('three.mtl'), 'newmtl red\nKd 0.9 0.1 0.1\nnewmtl blue\nKd 0.1 0.1 0.9\nnewmtl skin\nKd 1 1 1\nmap_Kd green.png\n');
  writeFileSync(file('green.png'), solidPng(4, 4, [40, 190, 60]));
  cli('run', file('three.obj'), '-o', file('three_out.obj'), ...runOptions, '--gltf', file('three.glb'), '--export-every', '5');
}

/** A PNG of w x h pixels of one RGB colour (8 bits, no alpha). */
function solidPng(w, h, rgb) {
  const table = Array.from({ length: 256 }, (_, n) => {
    let c = n;
    for (let k = 0; k < 8; k++) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
    return c >>> 0;
  });
  const crc = (buf) => {
    let c = 0xffffffff;
    for (const x of buf) c = table[(c ^ x) & 0xff] ^ (c >>> 8);
    return (c ^ 0xffffffff) >>> 0;
  };
  const chunk = (type, data) => {
    const body = Buffer.concat([Buffer.from(type, 'ascii'), data]);
    const head = Buffer.alloc(4), tail = Buffer.alloc(4);
    head.writeUInt32BE(data.length);
    tail.writeUInt32BE(crc(body));
    return Buffer.concat([head, body, tail]);
  };
  const ihdr = Buffer.alloc(13);
  ihdr.writeUInt32BE(w, 0);
  ihdr.writeUInt32BE(h, 4);
  ihdr[8] = 8;  // bits per channel
  ihdr[9] = 2;  // RGB
  const row = [0, ...Array.from({ length: w }, () => rgb).flat()];  // filter byte 0, then the pixels
  const pixels = Buffer.from(Array.from({ length: h }, () => row).flat());
  return Buffer.concat([Buffer.from([137, 80, 78, 71, 13, 10, 26, 10]), chunk('IHDR', ihdr),
    chunk('IDAT', deflateSync(pixels)), chunk('IEND', Buffer.alloc(0))]);
}

/** The JSON chunk of a .glb, read here, not by the page. */
function glbJson(glbPath) {
  const b = readFileSync(glbPath);
  return JSON.parse(b.subarray(20, 20 + b.readUInt32LE(12)).toString('utf8'));
}

/** Starts scripts/view.py with the files; resolves to {server, url}. */
function serve(...files) {
  return new Promise((resolve, reject) => {
    const server = spawn('/usr/bin/python3', [path.join(repo, 'scripts', 'view.py'), ...files, '--port', '0'],
      { stdio: ['ignore', 'pipe', 'inherit'] });
    let out = '';
    server.stdout.on('data', (d) => {
      out += d;
      if (out.includes('\n')) resolve({ server, url: out.split('\n')[0].trim() });
    });
    server.on('exit', (code) => reject(new Error(`view.py exited with ${code}`)));
  });
}

/** sRGB byte to linear, as three.js's Color.setRGB(..., SRGBColorSpace); PLYLoader stores the
 * result of a uchar colour back as a byte (Math.round(linear * 255)). */
const linear = (b) => { const c = b / 255; return c < 0.04045 ? c * 0.0773993808 : Math.pow(c * 0.9478672986 + 0.0521327014, 2.4); };
/** A vertex property of an ascii PLY as numbers, read here, not by the page. */
function plyColumn(plyPath, name) {
  const text = readFileSync(plyPath, 'utf8');
  const [head, body] = text.split('end_header');
  const props = [...head.matchAll(/^property (\S+) (\S+)$/gm)].map((m) => m[2]);
  const count = Number(/element vertex (\d+)/.exec(head)[1]);
  const rows = body.trim().split(/\r?\n/).slice(0, count).map((l) => l.trim().split(/\s+/).map(Number));
  return rows.map((r) => r[props.indexOf(name)]);
}
/** Mean linear red of an ascii PLY's vertices. */
const meanRed = (plyPath) => {
  const red = plyColumn(plyPath, 'red');
  return red.reduce((s, r) => s + Math.round(linear(r) * 255) / 255, 0) / red.length;
};
/** Whether the page's values are the PLY's float column, exactly. */
const sameFloats = (page, ply) => page && page.length === ply.length && ply.every((v, i) => Math.fround(v) === page[i]);

const profile = mkdtempSync(path.join(tmpdir(), 'shellcontract-chromium-'));
const browser = await puppeteer.launch({
  executablePath: args.chromium ?? '/usr/bin/chromium', headless: true, userDataDir: profile,
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
    '--disable-background-networking', '--disable-component-update', '--disable-sync',
    '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
});
const servers = [];
try {
  const page = await browser.newPage();
  await page.setViewport({ width: 1100, height: 640 });
  const consoleErrors = [];
  page.on('console', (m) => { if (m.type() === 'error') consoleErrors.push(m.text()); });
  page.on('pageerror', (e) => consoleErrors.push(String(e)));
  const open = async (...files) => {
    const s = await serve(...files);
    servers.push(s.server);
    await page.goto(s.url, { waitUntil: 'load' });
    await page.waitForFunction(() => window.viewer && (window.viewer.ready || window.viewer.error), { timeout: 60000 });
    await page.addStyleTag({ content: '#pane-labels { display: none; }' });  // pictures of the meshes only
    return page.evaluate(() => ({ error: window.viewer.error, panes: window.viewer.panes, shown: window.viewer.shown }));
  };
  const settle = () => page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
  /** Screenshot of #view, or of its left or right half. */
  const shot = async (half) => {
    await settle();
    const b = await (await page.$('#view')).boundingBox();
    const w = Math.floor(b.width / 2);
    const clip = half === 'left' ? { x: b.x, y: b.y, width: w, height: b.height }
      : half === 'right' ? { x: b.x + w, y: b.y, width: w, height: b.height } : b;
    return page.screenshot({ clip, encoding: 'base64' });
  };
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
  /**
   * What a screenshot shows, from one decode of its PNG: `covered`, the fraction of the pixels
   * that are not the background (0xf4f4f2), and `hues`, the fractions that are mostly red, mostly
   * green and mostly blue.
   */
  const pixels = (a) => page.evaluate(async (a) => {
    const img = new Image();
    img.src = `data:image/png;base64,${a}`;
    await img.decode();
    const c = new OffscreenCanvas(img.width, img.height);
    const ctx = c.getContext('2d');
    ctx.drawImage(img, 0, 0);
    const p = ctx.getImageData(0, 0, img.width, img.height).data;
    let covered = 0;
    const hues = [0, 0, 0];
    for (let i = 0; i < p.length; i += 4) {
      if (Math.abs(p[i] - 0xf4) + Math.abs(p[i + 1] - 0xf4) + Math.abs(p[i + 2] - 0xf2) > 24) covered++;
      for (let k = 0; k < 3; k++) if (p[i + k] > p[i + (k + 1) % 3] + 40 && p[i + k] > p[i + (k + 2) % 3] + 40) hues[k]++;
    }
    const n = p.length / 4;
    return { covered: covered / n, hues: hues.map((x) => x / n) };
  }, a);

  // Every mesh format opens, with the file's vertices (OBJ and STL: three corners per face).
  const pictures = {};
  for (const [ext, count] of [['off', nv], ['obj', 3 * nf], ['ply', nv], ['stl', 3 * nf]]) {
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

  // The fields PLYs side by side: each pane wears its own file's colours.
  s = await open(file('fields_start.ply'), file('fields_end.ply'));
  check(JSON.stringify(s.shown) === '["file colours","file colours"]', `both panes show their file's colours (${JSON.stringify(s.shown)})`);
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
  // colour field, so the picture is the one-primitive file's, frame for frame.
  s = await open(file('two.glb'));
  check(!s.error && s.panes[0]?.meshes === 2, `two.glb opens as two meshes (${s.error ?? s.panes[0]?.meshes})`);
  const both = await page.evaluate(() => window.viewer.colourMeans()[0]);
  check(both !== null && s.shown[0] !== 'none', `every primitive wears the colour field (shown: ${s.shown[0]}, mean red ${both})`);
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

  // The file's materials: three.glb has a primitive per material (red, blue, white with a green
  // texture) and one without. A field's colours replace them; with none chosen each primitive
  // wears its own material's base colour and texture (as the .glb's JSON says), and the picture
  // has red, blue and green in it.
  s = await open(file('three.glb'));
  const json = glbJson(file('three.glb'));
  const prims = json.meshes[0].primitives;
  const defs = prims.map((p) => (p.material === undefined ? null : json.materials[p.material]));
  check(!s.error && prims.length === 4 && s.panes[0]?.meshes === 4 && defs.filter((d) => d).length === 3,
        `three.glb opens as four meshes, three with a material (${s.error ?? `${s.panes[0]?.meshes} meshes, ${prims.length} primitives`})`);
  const pageLooks = async () => (await page.evaluate(() => window.viewer.looks?.()))?.[0] ?? [];
  let looks = await pageLooks();
  check(s.shown[0] === 'mean_curvature' && looks.length === 4 && looks.every((l) => l.vertexColors && !l.texture && l.colour.every((c) => c === 1)),
        `with a field chosen every primitive wears the field's colours (shown ${s.shown[0]}; ${JSON.stringify(looks)})`);
  await page.select('#colour', '-1');
  looks = await pageLooks();
  const shownNone = await page.evaluate(() => window.viewer.shown[0]);
  check(shownNone === 'file materials', `with no field chosen the pane shows the file's materials (shown: ${shownNone})`);
  const plain = [0xd8, 0xc8, 0xb0].map(linear);
  const near = (a, b) => a.length === b.length && a.every((x, i) => Math.abs(x - b[i]) < 1e-6);
  defs.forEach((d, i) => {
    const l = looks[i];
    if (!d) {
      check(l && !l.vertexColors && !l.texture && near(l.colour, plain),
            `primitive ${i}, without material, is the plain colour (${JSON.stringify(l)})`);
      return;
    }
    const factor = d.pbrMetallicRoughness?.baseColorFactor ?? [1, 1, 1, 1];
    const textured = d.pbrMetallicRoughness?.baseColorTexture !== undefined;
    check(l && l.name === d.name && !l.vertexColors && near(l.colour, factor.slice(0, 3)) && Math.abs(l.opacity - factor[3]) < 1e-6 &&
          (textured ? JSON.stringify(l.texture) === '[4,4]' : l.texture === null),
          `primitive ${i} wears material ${d.name}: base colour ${factor.join(' ')}${textured ? ', the 4 x 4 texture' : ''} (${JSON.stringify(l)})`);
  });
  const factors = defs.filter((d) => d).map((d) => JSON.stringify(d.pbrMetallicRoughness?.baseColorFactor ?? [1, 1, 1, 1]));
  check(new Set(factors).size === 3, `the three materials have different base colours (${factors.join(', ')})`);
  const rgb = (await pixels(await shot())).hues;
  check(rgb.every((f) => f > 0.005), `the picture has the materials' red, the texture's green and blue (${rgb.map((f) => (100 * f).toFixed(1)).join(', ')} % of the pixels)`);
  await page.select('#colour', '0');
  const fieldLooks = await pageLooks();
  check(fieldLooks.length === 4 && fieldLooks.every((l) => l.vertexColors && !l.texture), 'choosing a field again replaces the materials');

  check(consoleErrors.length === 0, `no console errors${consoleErrors.length ? ': ' + consoleErrors.join(' | ') : ''}`);
} finally {
  await browser.close();
  for (const s of servers) s.kill();
  rmSync(profile, { recursive: true, force: true });
  rmSync(work, { recursive: true, force: true });
}
if (failures.length) {
  console.error(`${failures.length} check(s) failed`);
  process.exit(1);
}
console.log('all viewer mesh checks passed');
