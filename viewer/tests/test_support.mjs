// What the headless viewer tests share (viewer_test.mjs, viewer_meshes_test.mjs,
// viewer_materials_test.mjs): their arguments and checks, the CLI's runs in a temporary folder,
// small files written here (an ico2 OBJ with materials, a PNG), Debian's Chromium through
// puppeteer-core, and the page served by scripts/view.py with its pictures.
import { spawn, spawnSync } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { deflateSync } from 'node:zlib';
import puppeteer from 'puppeteer-core';

export const repo = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..', '..');

/** --name value pairs of the command line; exits with the usage when one of `required` is missing. */
export function parseArgs(usage, required) {
  const args = Object.fromEntries(process.argv.slice(2).reduce((acc, a, i, all) => {
    if (a.startsWith('--')) acc.push([a.slice(2), all[i + 1]]);
    return acc;
  }, []));
  if (required.some((k) => !args[k])) {
    console.error(`usage: ${usage}`);
    process.exit(2);
  }
  return args;
}

export const failures = [];
export function check(ok, what) {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failures.push(what);
}
/** Ends the test: exit 1 naming the count of failed checks, else the success line. */
export function finish(success) {
  if (failures.length) {
    console.error(`${failures.length} check(s) failed`);
    process.exit(1);
  }
  console.log(success);
}

/** A temporary folder for the test's files; `file(name)` is a path in it. */
export function workFolder(prefix) {
  const dir = mkdtempSync(path.join(tmpdir(), prefix));
  return { dir, file: (n) => path.join(dir, n), remove: () => rmSync(dir, { recursive: true, force: true }) };
}

/** Runs the CLI; exit 5 (a run that missed its target) is a run that wrote its files. */
export function runCli(cli, ...a) {
  const r = spawnSync(cli, a, { encoding: 'utf8' });
  if (r.status !== 0 && r.status !== 5) throw new Error(`${cli} ${a.join(' ')}: exit ${r.status}\n${r.stderr}`);
}

/** An OFF file's vertices (each three coordinate strings) and triangles (vertex indices). */
export function readOff(offPath) {
  const lines = readFileSync(offPath, 'utf8').split(/\r?\n/).map((l) => l.split('#')[0].trim())
    .filter((l) => l && l !== 'OFF');
  const [nv, nf] = lines[0].split(/\s+/).map(Number);
  const vertices = lines.slice(1, 1 + nv).map((l) => l.split(/\s+/).slice(0, 3));
  const faces = lines.slice(1 + nv, 1 + nv + nf).map((l) => l.split(/\s+/).slice(1, 4).map(Number));
  return { vertices, faces };
}

/**
 * The OFF mesh as an OBJ with three materials by the side of x = 0 each face is on: red and blue
 * base colours, and a white one with a green 4 x 4 texture in the band between; the first faces
 * have none. Every vertex has a texture coordinate (its x and y), as the exporter writes
 * TEXCOORD_0 for all or none. Writes NAME.obj, NAME.mtl and green.png into the folder.
 */
export function writeThreeMaterialObj(offPath, file, name) {
  const { vertices: v, faces } = readOff(offPath);
  let obj = `mtllib ${name}.mtl\n` + v.map((c) => `v ${c[0]} ${c[1]} ${c[2]}\n`).join('') +
    v.map((c) => `vt ${0.5 + Number(c[0])} ${0.5 + Number(c[1])}\n`).join('');
  faces.forEach((f, k) => {
    const x = f.reduce((s, i) => s + Number(v[i][0]), 0) / 3;
    if (k >= 3) obj += `usemtl ${x > 0.15 ? 'red' : x < -0.15 ? 'blue' : 'skin'}\n`;
    obj += `f ${f.map((i) => `${i + 1}/${i + 1}`).join(' ')}\n`;
  });
  writeFileSync(file(`${name}.obj`), obj);
  writeFileSync(file(`${name}.mtl`), 'newmtl red\nKd 0.9 0.1 0.1\nnewmtl blue\nKd 0.1 0.1 0.9\nnewmtl skin\nKd 1 1 1\nmap_Kd green.png\n');
  writeFileSync(file('green.png'), solidPng(4, 4, [40, 190, 60]));
}

/** A PNG of w x h pixels of one RGB colour (8 bits, no alpha). */
export function solidPng(w, h, rgb) {
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
export function glbJson(glbPath) {
  const b = readFileSync(glbPath);
  return JSON.parse(b.subarray(20, 20 + b.readUInt32LE(12)).toString('utf8'));
}

/** A copy of a .glb with its JSON chunk replaced by `edit(json)`'s result (the binary chunk kept). */
export function writeEditedGlb(glbPath, outPath, edit) {
  const b = readFileSync(glbPath);
  const jsonLength = b.readUInt32LE(12);
  let text = JSON.stringify(edit(JSON.parse(b.subarray(20, 20 + jsonLength).toString('utf8'))));
  text += ' '.repeat((4 - (Buffer.byteLength(text) % 4)) % 4);  // chunks are 4-byte aligned, JSON padded with spaces
  const json = Buffer.from(text, 'utf8');
  const rest = b.subarray(20 + jsonLength);  // the BIN chunk, as it was
  const head = Buffer.alloc(20);
  head.write('glTF', 0, 'ascii');
  head.writeUInt32LE(2, 4);
  head.writeUInt32LE(20 + json.length + rest.length, 8);
  head.writeUInt32LE(json.length, 12);
  head.write('JSON', 16, 'ascii');
  writeFileSync(outPath, Buffer.concat([head, json, rest]));
}

/** sRGB byte to linear, as three.js's Color.setRGB(..., SRGBColorSpace). */
export const linear = (b) => { const c = b / 255; return c < 0.04045 ? c * 0.0773993808 : Math.pow(c * 0.9478672986 + 0.0521327014, 2.4); };

/** Starts scripts/view.py with the files (and its options); resolves to {server, url}. */
export function serve(...files) {
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

/**
 * Debian's Chromium (software WebGL) with one page of 1100 x 640 and the page's tools; `close()`
 * ends the browser and the servers. Console errors and uncaught exceptions of the page are
 * collected in `consoleErrors`.
 */
export async function startViewer(chromium) {
  const profile = mkdtempSync(path.join(tmpdir(), 'shellcontract-chromium-'));
  const browser = await puppeteer.launch({
    executablePath: chromium ?? '/usr/bin/chromium', headless: true, userDataDir: profile,
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync',
      '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  });
  const servers = [];
  const close = async () => {
    await browser.close();
    for (const s of servers) s.kill();
    rmSync(profile, { recursive: true, force: true });
  };
  try {
    const page = await browser.newPage();
    await page.setViewport({ width: 1100, height: 640 });
    const consoleErrors = [];
    page.on('console', (m) => { if (m.type() === 'error') consoleErrors.push(m.text()); });
    page.on('pageerror', (e) => consoleErrors.push(String(e)));
    const viewerState = () => page.evaluate(() => ({ error: window.viewer.error, panes: window.viewer.panes, shown: window.viewer.shown }));
    let labelsHidden = null;
    /**
     * Serves the files with view.py (with its options: '--log', RUN.csv) and opens the page on
     * them; resolves to its state.
     */
    const open = async (...files) => {
      const s = await serve(...files);
      servers.push(s.server);
      await page.goto(s.url, { waitUntil: 'load' });
      await page.waitForFunction(() => window.viewer && (window.viewer.ready || window.viewer.error), { timeout: 60000 });
      labelsHidden = await page.addStyleTag({ content: '#pane-labels { display: none; }' });  // pictures of the meshes only
      return viewerState();
    };
    /** Shows the panes' labels again, which `open` hides (a picture of the page as a user sees it). */
    const showLabels = () => labelsHidden?.evaluate((e) => e.remove());
    /** Opens the files through the page's file picker (<input type=file multiple>), as a user would. */
    const pick = async (...files) => {
      await page.evaluate(() => { window.viewer.ready = false; window.viewer.error = null; });
      await (await page.$('#file-input')).uploadFile(...files);
      await page.waitForFunction(() => window.viewer.ready, { timeout: 60000 });
      return viewerState();
    };
    const settle = () => page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
    /** Screenshot of #view, of its left or right half ('left', 'right'), or of another element ('#plot'). */
    const shot = async (part = '#view') => {
      await settle();
      const half = part === 'left' || part === 'right';
      const b = await (await page.$(half ? '#view' : part)).boundingBox();
      const w = Math.floor(b.width / 2);
      const clip = part === 'left' ? { x: b.x, y: b.y, width: w, height: b.height }
        : part === 'right' ? { x: b.x + w, y: b.y, width: w, height: b.height } : b;
      return page.screenshot({ clip, encoding: 'base64' });
    };
    /** Fraction of the pixels that differ between two screenshots. */
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
     * that are not the background (0xf4f4f2), and `hues`, the fractions that are mostly red,
     * mostly green and mostly blue.
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
    return { page, consoleErrors, open, showLabels, pick, settle, shot, differing, pixels, close };
  } catch (e) {
    await close();
    throw e;
  }
}
