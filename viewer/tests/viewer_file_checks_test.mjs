// The viewer refuses a file cut short or malformed, naming the file and the problem, instead of
// showing the part three.js's loader read (review: a PLY cut short opened as a partial mesh, with
// no error; an OBJ's face of a vertex it lacks drew with NaN positions; a binary STL, a binary PLY
// or a .glb cut short failed with a bare RangeError). Each format is written whole here (a whole
// file opens) and cut at every tenth of its length, and at one byte short; a file that holds its
// counts (PLY, binary STL, .glb) must then be refused as cut short, an ASCII STL too (it ends
// before 'endsolid'). An OBJ holds no counts: one cut at the end of a line is a smaller OBJ, so
// its check is of the lines, and an OBJ cut within a vertex or face line is refused. WebGL takes
// no doubles: a loader that left a Float64Array attribute (none of the files does: injected here
// into OBJLoader) is named by makePane before the first draw would throw with the array's values.
// Headers and keywords as the CLI reads them: a PLY's header however long (up to the viewer's
// limit, which is named) and however its 'end_header' is written; an STL's keywords in upper case
// refused, named, as the CLI refuses them.
// Node only, no browser.
// Usage: node viewer/tests/viewer_file_checks_test.mjs
import * as THREE from 'three';
import { OBJLoader } from 'three/addons/loaders/OBJLoader.js';
import { PLY_HEADER_LIMIT, checkPly } from '../src/file_checks.js';
import { loadMeshFile, plyForLoader } from '../src/mesh_files.js';
import { makePane } from '../src/panes.js';

// three's FileLoader reports its progress with the browser's ProgressEvent, which node lacks:
// a .gltf's embedded buffer (a data: URI) is fetched through it.
globalThis.ProgressEvent ??= class extends Event {
  constructor(type, init = {}) {
    super(type);
    Object.assign(this, init);
  }
};

const failures = [];
const check = (ok, what) => {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failures.push(what);
};
const text = (s) => new TextEncoder().encode(s);
const ab = (u8) => u8.buffer.slice(u8.byteOffset, u8.byteOffset + u8.byteLength);

// An octahedron: every format below holds it.
const V = [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]];
const F = [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]];

const plyHead = (format, index = 'int', comments = '') => `ply\nformat ${format} 1.0\ncomment an octahedron\n${comments}element vertex ${V.length}\n` +
  'property double x\nproperty double y\nproperty double z\nproperty float mean_curvature\n' +
  `element face ${F.length}\nproperty list uchar ${index} vertex_indices\nend_header\n`;
function binaryPly(little, comments = '') {
  const head = text(plyHead(little ? 'binary_little_endian' : 'binary_big_endian', 'int', comments));
  const body = new DataView(new ArrayBuffer(V.length * 28 + F.length * 13));
  V.forEach((p, i) => { p.forEach((c, k) => body.setFloat64(28 * i + 8 * k, c, little)); body.setFloat32(28 * i + 24, 1, little); });
  F.forEach((t, j) => {
    const at = 28 * V.length + 13 * j;
    body.setUint8(at, 3);
    t.forEach((x, k) => body.setInt32(at + 1 + 4 * k, x, little));
  });
  const out = new Uint8Array(head.length + body.byteLength);
  out.set(head);
  out.set(new Uint8Array(body.buffer), head.length);
  return out;
}
/** An ASCII STL of the octahedron, its solid called `solid`. */
const asciiStl = (solid) => text(`solid ${solid}\n` + F.map((t) => 'facet normal 0 0 0\n outer loop\n' +
  t.map((i) => `  vertex ${V[i].join(' ')}\n`).join('') + ' endloop\nendfacet\n').join('') + `endsolid ${solid}\n`);
/** A binary STL; `header`: the text its 80-byte header begins with (STLLoader's test of ASCII: 'solid' first). */
function binaryStl(header = '') {
  const d = new DataView(new ArrayBuffer(84 + 50 * F.length));
  new Uint8Array(d.buffer).set(text(header));
  d.setUint32(80, F.length, true);
  F.forEach((t, j) => t.forEach((i, c) => V[i].forEach((x, k) => d.setFloat32(84 + 50 * j + 12 + 12 * c + 4 * k, x, true))));
  return new Uint8Array(d.buffer);
}
/** A .glb of the octahedron (POSITION and indices), as small as glTF allows. */
function glb() {
  const bin = new Uint8Array(V.length * 12 + F.length * 6 + 4);
  const d = new DataView(bin.buffer);
  V.forEach((p, i) => p.forEach((c, k) => d.setFloat32(12 * i + 4 * k, c, true)));
  F.flat().forEach((x, k) => d.setUint16(12 * V.length + 2 * k, x, true));
  const json = {
    asset: { version: '2.0' }, scene: 0, scenes: [{ nodes: [0] }], nodes: [{ mesh: 0 }],
    meshes: [{ primitives: [{ attributes: { POSITION: 0 }, indices: 1 }] }],
    buffers: [{ byteLength: bin.length }],
    bufferViews: [{ buffer: 0, byteOffset: 0, byteLength: 12 * V.length }, { buffer: 0, byteOffset: 12 * V.length, byteLength: 6 * F.length }],
    accessors: [{ bufferView: 0, componentType: 5126, count: V.length, type: 'VEC3', min: [-1, -1, -1], max: [1, 1, 1] },
                { bufferView: 1, componentType: 5123, count: 3 * F.length, type: 'SCALAR' }],
  };
  let js = JSON.stringify(json);
  js += ' '.repeat((4 - (js.length % 4)) % 4);
  const jsonBytes = text(js);
  const out = new Uint8Array(12 + 8 + jsonBytes.length + 8 + bin.length);
  const o = new DataView(out.buffer);
  out.set(text('glTF'), 0);
  o.setUint32(4, 2, true);
  o.setUint32(8, out.length, true);
  o.setUint32(12, jsonBytes.length, true);
  out.set(text('JSON'), 16);
  out.set(jsonBytes, 20);
  o.setUint32(20 + jsonBytes.length, bin.length, true);
  out.set(text('BIN\0'), 24 + jsonBytes.length);
  out.set(bin, 28 + jsonBytes.length);
  return out;
}
/** A .gltf of the octahedron, its buffer embedded as run and repair write it (`uri`: another). */
function gltf(uri) {
  const bin = new Uint8Array(V.length * 12 + F.length * 6 + 4);
  const d = new DataView(bin.buffer);
  V.forEach((p, i) => p.forEach((c, k) => d.setFloat32(12 * i + 4 * k, c, true)));
  F.flat().forEach((x, k) => d.setUint16(12 * V.length + 2 * k, x, true));
  const json = {
    asset: { version: '2.0' }, scene: 0, scenes: [{ nodes: [0] }], nodes: [{ mesh: 0 }],
    meshes: [{ primitives: [{ attributes: { POSITION: 0 }, indices: 1 }] }],
    buffers: [{ byteLength: bin.length, uri: uri ?? `data:application/octet-stream;base64,${Buffer.from(bin).toString('base64')}` }],
    bufferViews: [{ buffer: 0, byteOffset: 0, byteLength: 12 * V.length }, { buffer: 0, byteOffset: 12 * V.length, byteLength: 6 * F.length }],
    accessors: [{ bufferView: 0, componentType: 5126, count: V.length, type: 'VEC3', min: [-1, -1, -1], max: [1, 1, 1] },
                { bufferView: 1, componentType: 5123, count: 3 * F.length, type: 'SCALAR' }],
  };
  return text(JSON.stringify(json));
}

const files = {
  'octa.off': text(`OFF\n${V.length} ${F.length} 0\n${V.map((p) => p.join(' ')).join('\n')}\n${F.map((t) => `3 ${t.join(' ')}`).join('\n')}\n`),
  'octa.ply': text(plyHead('ascii') + V.map((p) => `${p.join(' ')} 1`).join('\n') + '\n' + F.map((t) => `3 ${t.join(' ')}`).join('\n') + '\n'),
  'octa_le.ply': binaryPly(true),
  'octa_be.ply': binaryPly(false),
  'octa.stl': asciiStl('octa'),
  // A solid's name is free text: longer than the first KiB, or of the format's keywords.
  'octa_long_name.stl': asciiStl('n'.repeat(1100)),
  'octa_keywords.stl': asciiStl('vertex facet endfacet'),
  'octa_binary.stl': binaryStl(),
  // A binary STL whose header begins with 'solid', as some writers' do: cut short, it is no
  // longer the size of its count, so STLLoader's test takes it for ASCII.
  'octa_binary_solid.stl': binaryStl('solid octa, binary'),
  'octa_crlf.ply': text((plyHead('ascii') + V.map((p) => `${p.join(' ')} 1`).join('\n') + '\n' + F.map((t) => `3 ${t.join(' ')}`).join('\n') + '\n').replace(/\n/g, '\r\n')),
  'octa.glb': glb(),
  'octa.gltf': gltf(),
};
/** Opens the bytes as the viewer does (makePane: a .glb or a mesh file): null, or the error's message. */
async function refusal(bytes, name) {
  try {
    await makePane(ab(bytes), name);
    return null;
  } catch (e) {
    return String(e.message ?? e);
  }
}

for (const [name, whole] of Object.entries(files)) {
  const opened = await refusal(whole, name);
  check(opened === null, `${name}: the whole file opens (${opened ?? 'opened'})`);
  // Cuts: every tenth of the length, and one byte short (OFF: its own parser, the reference).
  const cuts = [...new Set([...Array.from({ length: 9 }, (_, k) => Math.floor(((k + 1) * whole.length) / 10)), whole.length - 1])];
  const silent = [], unnamed = [];
  for (const n of cuts) {
    // A text file cut after its last line's end (its final newline) is whole: not a cut.
    if (n === whole.length - 1 && whole[n] === 10 && !/_le|_be|_binary|\.glb$/.test(name)) continue;
    // Nor an ASCII STL cut after its 'endsolid': what follows is the solid's name, free text.
    if (/\.stl$/.test(name) && !/_binary/.test(name) && /\bendsolid\b/.test(new TextDecoder().decode(whole.subarray(0, n)))) continue;
    const cutName = name.replace('.', '_cut.');
    const m = await refusal(whole.subarray(0, n), cutName);
    if (m === null) silent.push(n);
    else if (!m.startsWith(`${cutName}: `) || !(/cut short|ends before/.test(m))) unnamed.push(`${n}: ${m}`);
  }
  check(silent.length === 0, `${name}: cut at ${cuts.join(', ')} of ${whole.length} bytes, never opened (opened: ${silent.join(', ') || 'none'})`);
  check(unnamed.length === 0, `${name}: each cut's error names the file and that it ends early (${unnamed.slice(0, 2).join(' | ') || 'all do'})`);
}

// Cut within an OBJ's vertex or face line: refused, the line named; at a line's end it is a smaller OBJ.
{
  const obj = V.map((p) => `v ${p.join(' ')}`).join('\n') + '\n' + F.map((t) => `f ${t.map((i) => i + 1).join(' ')}`).join('\n') + '\n';
  check(await refusal(text(obj), 'octa.obj') === null, 'octa.obj: the whole file opens');
  for (const [cut, what] of [[obj.indexOf('v 0 0 1') + 5, 'a vertex line'], [obj.lastIndexOf('f ') + 5, 'a face line']]) {
    const m = await refusal(text(obj.slice(0, cut)), 'octa_cut.obj');
    check(m !== null && /^octa_cut\.obj: line \d+: .*the file may be cut short$/.test(m), `an OBJ cut within ${what} is refused, naming the line ("${m}")`);
  }
}

// A .gltf (run's result of a .gltf input, repair -o x.gltf) opens as a glTF pane with the
// octahedron's vertices; one whose buffer is a separate file is refused, naming it (the viewer
// reads the file alone, and view.py serves only the files named to it).
{
  const pane = await makePane(ab(gltf()), 'octa.gltf');
  check(pane.kind === 'glb' && pane.vertices === V.length, `octa.gltf opens as a glTF pane of ${V.length} vertices (${pane.kind}, ${pane.vertices})`);
  const m = await refusal(gltf('octa.bin'), 'octa_bin.gltf');
  check(m !== null && m.startsWith("octa_bin.gltf: buffer 0 is the file 'octa.bin'"), `a .gltf with a buffer file is refused, naming it ("${m}")`);
  const other = await refusal(text('{}'), 'notes.txt');
  check(other === 'notes.txt: not a .glb, a .gltf or a mesh (.off, .obj, .ply, .stl)', `another file is refused, naming what opens ("${other}")`);
}

// Whole files that three.js's loaders misread, opened with the octahedron's eight faces: a
// binary STL with a header beginning 'solid' and bytes after its triangles (STLLoader took it for
// ASCII: 'no faces'), and an OBJ with comments after its elements (OBJLoader read '#' and 'note'
// as corners: NaN positions).
{
  const padded = new Uint8Array(binaryStl('solid octa, binary').length + 2);
  padded.set(binaryStl('solid octa, binary'));
  const obj = V.map((p) => `v ${p.join(' ')} # a vertex`).join('\n') + '\n' +
              F.map((t) => `f ${t.map((i) => i + 1).join(' ')} # note`).join('\n') + '\n';
  for (const [name, bytes] of [['padded.stl', padded], ['commented.obj', text(obj)]]) {
    let r = null, m = null;
    try {
      r = loadMeshFile(ab(bytes), name);
    } catch (e) {
      m = e.message;
    }
    const positions = r ? r.meshes.flatMap((mesh) => Array.from(mesh.geometry.getAttribute('position').array)) : [];
    check(r !== null && positions.length === 9 * F.length && positions.every(Number.isFinite),
          `${name} opens with ${F.length} faces of finite positions (${m ?? positions.length / 9 + ' faces'})`);
  }
}

// A face before the vertices it names (the CLI reads such an OBJ, and writes its result in the
// input's order): drawn with those vertices, a relative index counted from its own line.
{
  const obj = 'v 0 0 0\nv 1 0 0\nf 1 3 2\nf 1 4 3\nv 0 1 0\nv 0 0 1\nf 1 -3 -1\nf 2 3 4\n';
  const P = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]];
  const faces = [[1, 3, 2], [1, 4, 3], [1, 2, 4], [2, 3, 4]];
  let got = null, m = null;
  try {
    const r = loadMeshFile(ab(text(obj)), 'ahead.obj');
    const at = r.object.position.toArray();
    got = r.meshes.flatMap((mesh) => Array.from(mesh.geometry.getAttribute('position').array)).map((x, i) => x + at[i % 3]);
  } catch (e) {
    m = e.message;
  }
  const expected = faces.flat().flatMap((v) => P[v - 1]);
  check(got !== null && got.length === expected.length && got.every((x, i) => Math.abs(x - expected[i]) < 1e-6),
        `ahead.obj opens with each face's own vertices (${m ?? got.length / 9 + ' faces'})`);
}

// PLY headers the CLI reads (its result keeps its input's header, comments and all): one longer
// than 64 KiB (the viewer read its fields, comments and colours from the first 64 KiB only: none),
// an 'end_header' with a blank after it, a comment holding the word 'end_header', a UTF-8
// byte-order mark (three.js's PLYLoader read no vertices, or NaN positions, from the last three).
// Each opens with the octahedron: every drawn vertex at the position of the vertex whose field
// value it carries (the field is the vertex's index), and its field, comments and colours kept.
{
  const long = Array.from({ length: 1200 }, (_, i) => `comment provenance ${i}: ${'p'.repeat(60)}\n`).join('');
  const regions = 'comment shellcontract regions: face colour = region, grey = none\n';
  const coloured = (comments) => text(`ply\nformat ascii 1.0\n${comments}element vertex ${V.length}\nproperty double x\nproperty double y\n` +
    `property double z\nproperty float mean_curvature\nelement face ${F.length}\nproperty list uchar int vertex_indices\n` +
    'property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n' + V.map((p, i) => `${p.join(' ')} ${i}`).join('\n') + '\n' +
    F.map((t) => `3 ${t.join(' ')} 230 25 75`).join('\n') + '\n');
  const ascii = (head) => text(head + V.map((p, i) => `${p.join(' ')} ${i}`).join('\n') + '\n' + F.map((t) => `3 ${t.join(' ')}`).join('\n') + '\n');
  // binaryPly's field is 1 for every vertex: here its index, as the others have it.
  const indexed = (bytes) => {
    const at = bytes.length - (V.length * 28 + F.length * 13);
    V.forEach((_, i) => new DataView(bytes.buffer).setFloat32(at + 28 * i + 24, i, true));
    return bytes;
  };
  const bom = new Uint8Array([0xef, 0xbb, 0xbf, ...ascii(plyHead('ascii'))]);
  const le = indexed(binaryPly(true)), end = plyHead('binary_little_endian').length - 1;  // the 'end_header' line's '\n'
  const blankAfterEnd = new Uint8Array([...le.subarray(0, end), 0x09, ...le.subarray(end)]);
  const cases = [
    ['long_header.ply', coloured(long + regions), { faceColours: true, comment: /regions: face colour/ }],
    ['long_header_le.ply', indexed(binaryPly(true, long)), {}],
    ['blank_after_end.ply', ascii(plyHead('ascii').replace('end_header\n', 'end_header \n')), {}],
    ['blank_after_end_le.ply', blankAfterEnd, {}],
    ['comment_end_header.ply', ascii(plyHead('ascii', 'int', 'comment the data follows end_header and this\n')), { comment: /follows end_header/ }],
    ['bom.ply', bom, {}],
  ];
  for (const [name, bytes, expect] of cases) {
    let r = null, m = null;
    try {
      r = loadMeshFile(ab(bytes), name);
    } catch (e) {
      m = e.message;
    }
    const bad = [];
    if (r) {
      const g = r.meshes[0].geometry, position = g.getAttribute('position'), field = g.userData.fields?.mean_curvature;
      const o = r.object.position.toArray(), triangles = (g.index ? g.index.count : position.count) / 3;
      if (triangles !== F.length) bad.push(`${triangles} faces`);
      if (!field || field.length !== position.count) bad.push(`field of ${field?.length} values`);
      for (let k = 0; field && k < position.count && bad.length < 3; k++) {
        const p = V[field[k]];
        if (!p || p.some((c, j) => Math.abs(position.array[3 * k + j] + o[j] - c) > 1e-6)) bad.push(`vertex ${k} not at its value's position`);
      }
      if (r.vertices !== V.length) bad.push(`${r.vertices} vertices counted`);
      if (expect.faceColours && !r.faceColours) bad.push('no face colours');
      if (expect.comment && !r.comments.some((c) => expect.comment.test(c))) bad.push(`comments ${JSON.stringify(r.comments.slice(-2))}`);
    }
    check(r !== null && bad.length === 0, `${name} opens as the octahedron with its field (${m ?? (bad.join('; ') || 'it does')})`);
  }
  // The headers PLYLoader misreads are rewritten in a copy of the file; one it reads as it is (the
  // CLI writes such: comments, '\n' line ends) is passed on uncopied, so that a large mesh is not
  // held twice (review: every PLY was copied).
  const asIs = ['octa.ply', 'octa_le.ply', 'octa_be.ply', 'long_header.ply', 'long_header_le.ply'];
  const rewritten = ['octa_crlf.ply', 'blank_after_end.ply', 'blank_after_end_le.ply', 'comment_end_header.ply', 'bom.ply'];
  const bytesOf = Object.fromEntries([...Object.entries(files), ...cases.map(([n, b]) => [n, b])]);
  for (const name of [...asIs, ...rewritten]) {
    const buffer = ab(bytesOf[name]);
    const passed = plyForLoader(buffer, checkPly(buffer, name)) === buffer;
    check(passed === asIs.includes(name), `${name}: ${asIs.includes(name) ? 'read as it is, not copied' : 'its header rewritten for PLYLoader'} (${passed ? 'passed as it came' : 'copied'})`);
  }
  // A header of no 'end_header' in PLY_HEADER_LIMIT (of comments, or a binary file that is no PLY
  // past its first line) is refused, named as that, not read on through the whole file.
  const absurd = 'ply\nformat ascii 1.0\n' + `comment ${'c'.repeat(90)}\n`.repeat(Math.ceil(PLY_HEADER_LIMIT / 99) + 10);
  for (const [name, bytes] of [['absurd.ply', text(absurd)], ['absurd_late_end.ply', ascii(absurd + plyHead('ascii').slice(4))]]) {
    const m = await refusal(bytes, name);
    check(m !== null && m.startsWith(`${name}: no 'end_header' line in the file's first ${PLY_HEADER_LIMIT / 1048576} MiB`),
          `${name}, a header past ${PLY_HEADER_LIMIT} bytes, is refused with the limit named ("${m}")`);
  }
}

// An ASCII STL's keywords in upper or mixed case (some CAD exporters' 'SOLID', 'FACET NORMAL',
// 'VERTEX'): the CLI reads them in lower case only (a file beginning 'SOLID' is neither ASCII nor
// binary to it; it skips a 'FACET' with its vertices), so each is refused with the keyword and its
// line named (the viewer took 'SOLID ...' for a binary STL cut short: "the file ends after 17 of
// the 807416096 triangles its header gives"). The words the CLI skips in any case ('normal',
// 'outer', 'loop', 'endloop') open in upper case.
{
  const stl = (kw) => `${kw('solid')} octa\n` + F.map((t) => ` ${kw('facet')} ${kw('normal')} 0 0 0\n  ${kw('outer')} ${kw('loop')}\n` +
    t.map((i) => `   ${kw('vertex')} ${V[i].join(' ')}\n`).join('') + `  ${kw('endloop')}\n ${kw('endfacet')}\n`).join('') + `${kw('endsolid')} octa\n`;
  const upper = (...words) => (w) => (words.includes(w) ? w.toUpperCase() : w);
  const cases = [
    ['upper.stl', (w) => w.toUpperCase(), 'SOLID'],
    ['capitalised.stl', (w) => w[0].toUpperCase() + w.slice(1), 'Solid'],
    ['upper_facets.stl', (w) => (['solid', 'endsolid'].includes(w) ? w : w.toUpperCase()), 'FACET'],
    ['upper_vertex.stl', upper('vertex'), 'VERTEX'],
    ['upper_endfacet.stl', upper('endfacet'), 'ENDFACET'],
    ['upper_endsolid.stl', upper('endsolid'), 'ENDSOLID'],
  ];
  for (const [name, kw, word] of cases) {
    const body = stl(kw), line = body.split('\n').findIndex((l) => l.split(/\s+/).includes(word)) + 1;
    const m = await refusal(text(body), name);
    check(m !== null && m.startsWith(`${name}: line ${line}: the keyword '${word}' is not in lower case`),
          `${name} is refused, its keyword '${word}' named on line ${line} ("${m}")`);
  }
  const r = loadMeshFile(ab(text(stl(upper('normal', 'outer', 'loop', 'endloop')))), 'upper_loops.stl');
  check(r.meshes[0].geometry.getAttribute('position').count === 3 * F.length, "an STL of upper-case 'NORMAL', 'OUTER LOOP', 'ENDLOOP' opens");
}

// Malformed, not cut: each refused with the problem, naming the file.
const malformed = [
  ['faces.ply', text(plyHead('ascii') + V.map((p) => `${p.join(' ')} 1`).join('\n') + '\n' + F.map((t, j) => `3 ${j === 5 ? '0 1 6' : t.join(' ')}`).join('\n') + '\n'),
   /^faces\.ply: face 5 refers to vertex 6, but the file has 6$/],
  ['words.ply', text(plyHead('ascii') + V.map((p, i) => `${i === 2 ? 'x' : p[0]} ${p[1]} ${p[2]} 1`).join('\n') + '\n' + F.map((t) => `3 ${t.join(' ')}`).join('\n') + '\n'),
   /^words\.ply: line 14: vertex 2: 'x' is not a number$/],
  ['beyond.obj', text('v 0 0 0\nv 1 0 0\nf 1 2 3\ng end\n'), /^beyond\.obj: line 3: a face refers to vertex 3, but the file has 2$/],
  ['before.obj', text('v 0 0 0\nv 1 0 0\nf 1 2 -3\nv 0 1 0\n'), /^before\.obj: line 3: a face refers to vertex -3, but the file has 2 before it$/],
  ['two.obj', text('v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\nf 1 2 3\n'), /^two\.obj: line 4: a face of 2 corners/],
  ['nan.obj', text('v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n'), /^nan\.obj: line 2: a vertex 'v 1 nan 0' is not three numbers$/],
  ['two.stl', text('solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid t\n'),
   /^two\.stl: line 7: facet 0 has 2 vertices, not 3$/],
  ['notglb.glb', text('{"asset": {"version": "2.0"}}'), /^notglb\.glb: not a binary glTF/],
];
for (const [name, bytes, expected] of malformed) {
  const m = await refusal(bytes, name);
  check(m !== null && expected.test(m), `${name} is refused with its problem ("${m}")`);
}

// An element without properties holds no bytes: one of 100 instances changes nothing (the
// octahedron opens), one of 2^53 - 1 in a file of a few hundred bytes is refused, naming the
// element and its line, as the CLI refuses it (checkPly and PLYLoader walked every instance: months).
{
  const marked = (count) => text(plyHead('ascii').replace('element vertex', `element marker ${count}\nelement vertex`) +
    V.map((p) => `${p.join(' ')} 1`).join('\n') + '\n' + F.map((t) => `3 ${t.join(' ')}`).join('\n') + '\n');
  const small = await refusal(marked(100), 'marker.ply');
  check(small === null, `a PLY with an element of no properties and 100 instances opens (${small ?? 'opened'})`);
  const huge = marked(Number.MAX_SAFE_INTEGER);
  const m = await refusal(huge, 'marker_huge.ply');
  check(m === `marker_huge.ply: line 4: element 'marker' has no properties but declares ${Number.MAX_SAFE_INTEGER} instances, ` +
              `more than the file's ${huge.length} bytes`, `an element of no properties and 2^53 - 1 instances is refused, named ("${m}")`);
}

// The guard against doubles (panes.js makePane): no file gives a Float64Array attribute (the
// loaders' doubles become floats), so one is injected into OBJLoader's result; the pane is refused
// with the attribute named, before the first draw would throw.
{
  const parse = OBJLoader.prototype.parse;
  OBJLoader.prototype.parse = function (...a) {
    const object = parse.apply(this, a);
    object.traverse((o) => {
      if (o.isMesh) o.geometry.setAttribute('uv', new THREE.BufferAttribute(new Float64Array(2 * o.geometry.getAttribute('position').count), 2));
    });
    return object;
  };
  try {
    const m = await refusal(text('v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n'), 'doubles.obj');
    check(m === "doubles.obj: its 'uv' values are doubles, which WebGL cannot draw", `an attribute of doubles is refused, named ("${m}")`);
  } finally {
    OBJLoader.prototype.parse = parse;
  }
  const plain = await refusal(text('v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n'), 'plain.obj');
  check(plain === null, `without the injection the same OBJ opens (${plain ?? 'opened'})`);
}
// A PLY's double positions and fields still open (its doubles are the loader's to convert).
check(loadMeshFile(ab(files['octa_le.ply']), 'octa_le.ply').fields.length === 1, 'a binary PLY of doubles keeps its field');

if (failures.length) {
  console.error(`${failures.length} check(s) failed`);
  process.exit(1);
}
console.log('viewer_file_checks: ok');
