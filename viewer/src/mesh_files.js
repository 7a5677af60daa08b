// Result meshes (issue 56): OFF (parsed here: three.js has no OFF loader), OBJ, PLY and STL
// (three.js's loaders from node_modules) as one THREE.Object3D each, with the per-vertex scalar
// fields a PLY carries (e.g. the --fields files' mean_curvature) and its own colours. A file cut
// short or malformed is refused with what is wrong (file_checks.js), never opened as the part read.
import * as THREE from 'three';
import { OBJLoader } from 'three/addons/loaders/OBJLoader.js';
import { PLYLoader } from 'three/addons/loaders/PLYLoader.js';
import { STLLoader } from 'three/addons/loaders/STLLoader.js';
import { checkAsciiStl, checkBinaryStl, checkObj, checkPly } from './file_checks.js';
import { withUnnamedFirstMaterial } from './obj_materials.js';

export const MESH_EXTENSIONS = ['off', 'obj', 'ply', 'stl'];
/** The glTF files the viewer shows (panes.js): a run's animated .glb, a .glb or .gltf mesh. */
export const GLTF_EXTENSIONS = ['glb', 'gltf'];

export function extensionOf(name) {
  const m = /\.([^./\\]+)$/.exec(name);
  return m ? m[1].toLowerCase() : '';
}

/** Whether the viewer shows the file named so, as a pane: a glTF or a mesh. */
export function isViewerFile(name) {
  const ext = extensionOf(name);
  return GLTF_EXTENSIONS.includes(ext) || MESH_EXTENSIONS.includes(ext);
}

/**
 * Positions (x, y, z after one another, numbers in double) as float32 relative to their bounding
 * box's centre, subtracted in double: float32 keeps about 7 digits of a coordinate, so a mesh far
 * from the origin (a statue in UTM metres, northing 5e6: float spacing 0.5) stored absolute lost
 * its shape. The mesh's object is placed at the centre (three.js composes its matrices in double).
 * @returns {{position: Float32Array, centre: number[]}}
 */
export function recentred(values) {
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < values.length; i++) {
    lo[i % 3] = Math.min(lo[i % 3], values[i]);
    hi[i % 3] = Math.max(hi[i % 3], values[i]);
  }
  // Halves summed, as the CLI's glTF centre (gltf_centre): no overflow near the double range's end.
  const centre = values.length ? lo.map((l, k) => l / 2 + hi[k] / 2) : [0, 0, 0];
  const position = new Float32Array(values.length);
  for (let i = 0; i < values.length; i++) position[i] = values[i] - centre[i % 3];
  return { position, centre };
}

/**
 * The OBJ with its vertex, texture coordinate and normal lines before every other line, its
 * faces' negative (relative) indices made absolute: the same mesh, for OBJLoader, which looks a
 * face's vertices up as it reads the face (a vertex defined after it gave NaN positions; the CLI
 * reads such a file). A file whose definitions all come first is returned as it is.
 */
export function verticesFirst(text) {
  const raw = text.split(/\r\n|\n|\r/), lines = [];
  for (let i = 0, joined = ''; i < raw.length; i++) {  // '\' continues a line (as checkObj reads it)
    if (raw[i].endsWith('\\') && i + 1 < raw.length) { joined += raw[i].slice(0, -1); continue; }
    lines.push(joined + raw[i]);
    joined = '';
  }
  const key = (line) => line.trimStart().split(/\s/, 1)[0];
  const defines = (line) => ['v', 'vt', 'vn'].includes(key(line));
  const firstOther = lines.findIndex((l) => !defines(l) && ['f', 'l', 'p'].includes(key(l)));
  if (firstOther < 0 || !lines.slice(firstOther).some(defines)) return text;
  const counts = { v: 0, vt: 0, vn: 0 }, head = [], body = [];
  for (const line of lines) {
    const k = key(line);
    if (k in counts) {
      counts[k]++;
      head.push(line);
    } else if (['f', 'l', 'p'].includes(k)) {
      const kinds = ['v', 'vt', 'vn'];
      body.push(line.replace(/(\s)(-?\d+)((?:\/-?\d*){0,2})/g, (m, space, v, rest) => {
        const parts = [v, ...rest.split('/').slice(1)].map((x, j) => {
          const n = Number(x);
          return x === '' || !(n < 0) ? x : String(counts[kinds[j]] + n + 1);
        });
        return space + parts.join('/');
      }));
    } else {
      body.push(line);
    }
  }
  return head.concat(body).join('\n');
}

/**
 * An OBJ's text with its vertices ('v x y z ...') relative to their bounding box's centre,
 * subtracted in double before OBJLoader reads them into float32 (recentred's reason). JavaScript's
 * shortest round-trip form writes each difference, so OBJLoader reads the same double back. A
 * 'v' line this does not read as three finite numbers leaves the text as it was (centre 0), for
 * OBJLoader to judge.
 * @returns {{text: string, centre: number[]}}
 */
export function recentredObj(text) {
  const lines = text.split(/\r\n|\n|\r/);
  const vertex = /^(\s*v\s+)(\S+)\s+(\S+)\s+(\S+)(.*)$/;
  const rows = [];
  for (let i = 0; i < lines.length; i++) {
    if (!/^\s*v\s/.test(lines[i])) continue;
    const m = vertex.exec(lines[i]);
    const xyz = m ? [m[2], m[3], m[4]].map(Number) : [];
    if (!m || !xyz.every(Number.isFinite)) return { text, centre: [0, 0, 0] };
    rows.push([i, m[1], xyz, m[5]]);
  }
  const values = rows.flatMap((r) => r[2]);
  if (!values.length) return { text, centre: [0, 0, 0] };
  const { centre } = recentred(values);
  for (const [i, head, xyz, rest] of rows) lines[i] = head + xyz.map((c, k) => String(c - centre[k])).join(' ') + rest;
  return { text: lines.join('\n'), centre };
}

/**
 * Parses an OFF file (ascii; the "OFF" keyword optional; comments after '#'); polygons are
 * fan-triangulated for display. Throws an Error naming the line for anything else.
 * @returns {THREE.BufferGeometry} indexed, with normals; its positions relative to its bounding
 *   box's centre, which is userData.centre (recentred: place the mesh there)
 */
export function parseOff(text, name) {
  const tokens = [];  // [value, line]
  text.split(/\r\n|\n|\r/).forEach((line, i) => {
    const body = line.split('#')[0].trim();
    if (body) for (const t of body.split(/\s+/)) tokens.push([t, i + 1]);
  });
  let at = 0;
  const next = (what) => {
    if (at >= tokens.length) throw new Error(`${name}: the file ends before ${what}`);
    return tokens[at++];
  };
  const number = (what, integer = false) => {
    const [t, line] = next(what);
    const v = Number(t);
    if (!Number.isFinite(v) || (integer && !Number.isInteger(v))) throw new Error(`${name}: line ${line}: ${what} '${t}' is not ${integer ? 'an integer' : 'a number'}`);
    return v;
  };
  if (tokens.length && /^[CN4]*OFF$/.test(tokens[0][0])) {
    if (tokens[0][0] !== 'OFF') throw new Error(`${name}: line ${tokens[0][1]}: only plain ascii OFF is shown (not ${tokens[0][0]})`);
    at = 1;
  }
  const nv = number('the vertex count', true), nf = number('the face count', true);
  number('the edge count', true);
  const coordinates = new Float64Array(3 * nv);
  for (let i = 0; i < 3 * nv; i++) coordinates[i] = number(`coordinate ${i % 3} of vertex ${Math.floor(i / 3)}`);
  const index = [];
  for (let f = 0; f < nf; f++) {
    const n = number(`the corner count of face ${f}`, true);
    const c = [];
    for (let k = 0; k < n; k++) {
      const v = number(`corner ${k} of face ${f}`, true);
      if (v < 0 || v >= nv) throw new Error(`${name}: face ${f} refers to vertex ${v}, but the file has ${nv}`);
      c.push(v);
    }
    for (let k = 1; k + 1 < n; k++) index.push(c[0], c[k], c[k + 1]);
    // Anything after the corners on the face's line (a colour) is skipped.
    const line = tokens[at - 1][1];
    while (at < tokens.length && tokens[at][1] === line) at++;
  }
  const g = new THREE.BufferGeometry();
  const { position, centre } = recentred(coordinates);
  g.setAttribute('position', new THREE.BufferAttribute(position, 3));
  g.userData.centre = centre;
  g.setIndex(index);
  g.computeVertexNormals();
  return g;
}

/**
 * What a PLY's header (checkPly's, read up to its 'end_header' however long) says beyond the
 * geometry: the vertex element's scalar properties that are not geometry or colour (`fields`), its
 * comments (the CLI's name what the colours are: "face colour = region, grey = none"), its vertex
 * count and whether its faces carry colours.
 */
function plyExtras(buffer, header) {
  const out = { fields: [], comments: [], vertices: 0, faceColours: false };
  for (const { at, next } of header.comments) {
    const words = new TextDecoder().decode(new Uint8Array(buffer, at, next - at)).trim().split(/\s+/).slice(1).join(' ');
    if (!/^Generated by/i.test(words)) out.comments.push(words);
  }
  for (const e of header.elements) {
    if (e.name === 'vertex') out.vertices = e.count;
    for (const p of e.properties) {
      if (e.name === 'face' && ['red', 'diffuse_red'].includes(p.name)) out.faceColours = true;
      else if (e.name === 'vertex' && !p.list &&
               !['x', 'y', 'z', 'nx', 'ny', 'nz', 'red', 'green', 'blue', 'alpha', 's', 't', 'u', 'v'].includes(p.name)) out.fields.push(p.name);
    }
  }
  return out;
}

/**
 * The PLY as three.js's PLYLoader reads it right. Of headers the CLI reads, PLYLoader read no
 * vertices where the 'end_header' line has a blank after it (it ends the header only at a line
 * that is 'end_header' exactly) or the file begins with a UTF-8 byte-order mark, and NaN positions
 * where a comment holds the word 'end_header' (it reads an ASCII body from the text's first
 * 'end_header'); line ends other than '\n' throughout, and blanks it does not split alike, are
 * other ways to mislead it. Such a header is rewritten: its format, element and property lines
 * alone, one blank between words and '\n' after each, then the file's data, in a copy of the
 * file. A header PLYLoader reads as it is (the CLI writes such) is not copied: the file is passed
 * as it came, so a large mesh is not held twice.
 */
export function plyForLoader(buffer, header) {
  const canonical = header.lines.map((t) => t.join(' '));
  if (loaderReadsAsIs(buffer, header, canonical)) return buffer;
  const head = new TextEncoder().encode(['ply', ...canonical, 'end_header', ''].join('\n'));
  const out = new Uint8Array(head.length + buffer.byteLength - header.dataStart);
  out.set(head);
  out.set(new Uint8Array(buffer, header.dataStart), head.length);
  return out.buffer;
}

/**
 * Whether the header is what plyForLoader would write but for comment lines: 'ply', each line
 * ended by '\n' alone, its format, element and property lines single-blanked in their order,
 * comments that do not hold 'end_header', and 'end_header' last, exactly.
 */
function loaderReadsAsIs(buffer, header, canonical) {
  const text = new TextDecoder('latin1').decode(new Uint8Array(buffer, 0, header.dataStart));
  const lines = text.split('\n');
  if (lines[0] !== 'ply' || text.includes('\r') || lines.pop() !== '' || lines.pop() !== 'end_header') return false;
  const rest = [];
  for (const line of lines.slice(1)) {
    if (/^comment(\s|$)/.test(line)) {
      if (line.includes('end_header')) return false;
    } else {
      rest.push(line);
    }
  }
  return rest.length === canonical.length && rest.every((line, i) => line === canonical[i]);
}

/**
 * An ASCII STL's text with its vertices ('vertex x y z') relative to their bounding box's centre,
 * subtracted in double before STLLoader reads them into float32 (recentredObj's reason: the CLI
 * writes 17 digits, and at northing 5e6 float32 keeps a spacing of 0.5). Text that is not an ASCII
 * STL, or a vertex this does not read as three finite numbers, is left as it was (centre 0).
 * @returns {{text: string, centre: number[]}}
 */
export function recentredAsciiStl(text) {
  const vertex = /^(\s*vertex\s+)(\S+)\s+(\S+)\s+(\S+)(.*)$/;
  const lines = text.split(/\r\n|\n|\r/);
  const rows = [];
  for (let i = 0; i < lines.length; i++) {
    if (!/^\s*vertex\s/.test(lines[i])) continue;
    const m = vertex.exec(lines[i]);
    const xyz = m ? [m[2], m[3], m[4]].map(Number) : [];
    if (!m || !xyz.every(Number.isFinite)) return { text, centre: [0, 0, 0] };
    rows.push([i, m[1], xyz, m[5]]);
  }
  if (!rows.length) return { text, centre: [0, 0, 0] };
  const { centre } = recentred(rows.flatMap((r) => r[2]));
  for (const [i, head, xyz, rest] of rows) lines[i] = head + xyz.map((c, k) => String(c - centre[k])).join(' ') + rest;
  return { text: lines.join('\n'), centre };
}

/**
 * Whether an STL is ASCII, by STLLoader's own test: not the size a binary one of its count has, and
 * 'solid' first. A binary STL's 80-byte header may begin with 'solid' too: one cut short (not its
 * size) with neither 'facet' nor 'endsolid' near its start is binary, to be named as cut short.
 */
function isAsciiStl(buffer) {
  if (buffer.byteLength >= 84 && 84 + 50 * new DataView(buffer).getUint32(80, true) === buffer.byteLength) return false;
  // A binary STL whose header begins with 'solid' (some writers' do) is told by a zero byte: its
  // triangle count's last byte at offset 83 is one below 2^24 triangles, and text has none. (A
  // test for 'facet' near the start took an ASCII STL whose solid has a long name for binary.)
  const head = new Uint8Array(buffer, 0, Math.min(buffer.byteLength, 1024));
  // 'SOLID' too, for checkAsciiStl to name the keyword's case (the CLI does not read the file).
  return /^\s*solid/i.test(new TextDecoder().decode(head)) && (buffer.byteLength < 84 || !head.includes(0));
}

/** The count of distinct positions of a de-indexed geometry (an STL's triangle corners). */
function distinctPositions(values) {
  const seen = new Set();
  for (let i = 0; i < values.length; i += 3) seen.add(`${values[i]},${values[i + 1]},${values[i + 2]}`);
  return seen.size;
}

/**
 * Loads a result mesh. @returns {{object: THREE.Object3D, meshes: THREE.Mesh[], vertices: number,
 * fields: {name: string, attribute: string}[], fileColours: boolean, faceColours: boolean,
 * comments: string[], materialLibraries: string[], materialNames: (string | string[])[]}}
 * (vertices: the file's own count, not the corners of a de-indexed geometry; a field's values, as
 * read, are each mesh's geometry.userData.fields[name], not a GPU attribute; comments: a PLY's
 * header comments; the last two: an OBJ's mtllib names and, per mesh, the usemtl names of its
 * groups; the meshes wear the viewer's material)
 */
export function loadMeshFile(buffer, name) {
  const ext = extensionOf(name);
  let object, fields = [], materialLibraries = [], vertices = null, comments = [], faceColours = false;
  if (ext === 'off') {
    const g = parseOff(new TextDecoder().decode(buffer), name);
    object = new THREE.Mesh(g);
    object.position.fromArray(g.userData.centre);
  } else if (ext === 'obj') {
    const original = new TextDecoder().decode(buffer);
    checkObj(original, name);
    // A comment after an element ('f 1 2 3 # note'), which checkObj allows as the CLI does:
    // OBJLoader would read its words as corners (NaN positions).
    const uncommented = original.replace(/^(\s*(?:v|vt|vn|f|l|p)\s[^#\r\n]*)#.*$/gm, '$1');
    const { text, centre } = recentredObj(verticesFirst(uncommented));
    object = new OBJLoader().parse(withUnnamedFirstMaterial(text));
    materialLibraries = object.materialLibraries;
    object.position.fromArray(centre);
    // OBJLoader makes three corners per face: the file's vertices are its 'v' lines.
    vertices = (text.match(/^\s*v\s/gm) ?? []).length;
  } else if (ext === 'ply') {
    const checked = checkPly(buffer, name);
    const loader = new PLYLoader();
    const header = plyExtras(buffer, checked);
    ({ comments, faceColours } = header);
    fields = header.fields.map((f) => ({ name: f, attribute: `field_${f}` }));
    loader.setCustomPropertyNameMapping(Object.fromEntries(fields.map((f) => [f.attribute, [f.name]])));
    const g = loader.parse(plyForLoader(buffer, checked));
    // The fields' values are coloured here (colour_map.js), never read by a shader: kept as read
    // (a double property, as the CLI's regions -o writes, is a Float64Array, which WebGL cannot
    // take: it threw on the first draw) in userData, off the GPU.
    g.userData.fields = {};
    for (const f of fields) {
      const a = g.getAttribute(f.attribute);
      if (a) g.userData.fields[f.name] = a.array;
      g.deleteAttribute(f.attribute);
    }
    // Other doubles become floats for the GPU; double positions are recentred first, as an OFF's
    // (recentred).
    let centre = [0, 0, 0];
    for (const [key, a] of Object.entries(g.attributes)) {
      if (a.array instanceof Float64Array) {
        let floats = Float32Array.from(a.array);
        if (key === 'position') ({ position: floats, centre } = recentred(a.array));
        g.setAttribute(key, new THREE.Float32BufferAttribute(floats, a.itemSize, a.normalized));
      }
    }
    if (!g.getAttribute('normal')) g.computeVertexNormals();
    object = new THREE.Mesh(g);
    object.position.fromArray(centre);
    // Face colours make PLYLoader de-index the mesh (three corners per face).
    vertices = header.vertices || null;
  } else if (ext === 'stl') {
    // An ASCII STL's text is recentred in double first (recentredAsciiStl); a binary STL holds
    // float32 already. Either is recentred after reading all the same, so that the GPU's float
    // arithmetic works on coordinates the size of the mesh, as for the other formats.
    let first = [0, 0, 0], bytes = buffer;
    if (isAsciiStl(buffer)) {
      const original = new TextDecoder().decode(buffer);
      checkAsciiStl(original, name);
      const r = recentredAsciiStl(original);
      // STLLoader reads past the end of a text shorter than a binary header (an empty solid).
      if (!/^\s*vertex\s/m.test(r.text)) throw new Error(`${name}: no faces`);
      first = r.centre;
      bytes = new TextEncoder().encode(r.text).buffer;
    } else {
      checkBinaryStl(buffer, name);
      // Its triangles only: STLLoader's own test takes a binary STL whose header begins with
      // 'solid' for ASCII unless its length is exactly that of its count.
      bytes = buffer.slice(0, 84 + 50 * new DataView(buffer).getUint32(80, true));
    }
    const g = new STLLoader().parse(bytes);
    const { position, centre } = recentred(Float64Array.from(g.getAttribute('position').array));
    g.setAttribute('position', new THREE.Float32BufferAttribute(position, 3));
    g.computeVertexNormals();
    object = new THREE.Mesh(g);
    object.position.fromArray(centre.map((c, k) => c + first[k]));
    // STLLoader makes three corners per face: the file's vertices are its distinct positions.
    vertices = distinctPositions(g.getAttribute('position').array);
  } else {
    throw new Error(
        `${name}: unknown mesh format '.${ext}' (expected .off, .obj, .ply, .stl, .glb or .gltf)`);
  }
  const meshes = [];
  object.traverse((o) => { if (o.isMesh) meshes.push(o); });
  // A mesh with no triangles (an OFF of 0 faces, an STL cut short) would open as a blank view.
  const triangles = (g) => Math.floor((g.index ? g.index.count : g.getAttribute('position')?.count ?? 0) / 3);
  if (!meshes.some((m) => triangles(m.geometry) > 0)) throw new Error(`${name}: no faces`);
  // The materials' names of each mesh, kept for the .mtl (obj_materials.js): an OBJ of several has
  // an array, one per geometry group.
  const materialNames = meshes.map((m) => (Array.isArray(m.material) ? m.material.map((x) => x.name) : m.material?.name ?? ''));
  for (const m of meshes) {
    if (!m.geometry.getAttribute('normal')) m.geometry.computeVertexNormals();
    // The bounds of the positions as drawn: a loader that computed them before the positions were
    // recentred (PLYLoader) left them where the file's mesh was, and three.js culls the mesh
    // against its bounding sphere, so a mesh a few radii from the origin was never drawn.
    m.geometry.computeBoundingBox();
    m.geometry.computeBoundingSphere();
    m.material = new THREE.MeshStandardMaterial({ color: 0xd8c8b0, roughness: 0.6, metalness: 0.0, side: THREE.DoubleSide });
  }
  vertices ??= meshes.reduce((n, m) => n + m.geometry.getAttribute('position').count, 0);
  const fileColours = meshes.every((m) => m.geometry.getAttribute('color'));
  return { object, meshes, vertices, fields, fileColours, faceColours: fileColours && faceColours, comments, materialLibraries, materialNames };
}
