// Whether a file is whole and well formed, checked before three.js's loaders read it: they read
// what is there and say nothing of the rest (a PLY cut short opened as the part read; an OBJ's
// face of two corners, or of a vertex it does not have, drew with NaN positions), or fail with a
// bare RangeError ("Offset is outside the bounds of the DataView" for a binary PLY or STL cut short,
// "Invalid typed array length: 11" for a .glb). Each check throws an Error naming the file and what
// is wrong, as parseOff (mesh_files.js) does for an OFF. A format that holds its counts (PLY, binary
// STL, .glb) is checked against them; an ASCII STL for its closing keywords; an OBJ, which holds no
// counts, for its lines: a file cut at the end of a line is a smaller OBJ, which no check can tell.

/** The sizes of a PLY's property types, and the DataView getter of each. */
const PLY_TYPES = {
  char: [1, 'getInt8'], int8: [1, 'getInt8'], uchar: [1, 'getUint8'], uint8: [1, 'getUint8'],
  short: [2, 'getInt16'], int16: [2, 'getInt16'], ushort: [2, 'getUint16'], uint16: [2, 'getUint16'],
  int: [4, 'getInt32'], int32: [4, 'getInt32'], uint: [4, 'getUint32'], uint32: [4, 'getUint32'],
  float: [4, 'getFloat32'], float32: [4, 'getFloat32'], double: [8, 'getFloat64'], float64: [8, 'getFloat64'],
};
const INTEGER_TYPES = new Set(['char', 'int8', 'uchar', 'uint8', 'short', 'int16', 'ushort', 'uint16', 'int', 'int32', 'uint', 'uint32']);

/** The text of the bytes, one character per byte (so an index in it is a byte offset). */
const bytesText = (buffer, start = 0, end = buffer.byteLength) =>
  new TextDecoder('latin1').decode(new Uint8Array(buffer, start, Math.max(0, Math.min(end, buffer.byteLength) - start)));

/** The 1-based line of the text at index `at`. */
const lineAt = (text, at) => text.slice(0, at).split(/\r\n|\n|\r/).length;

/**
 * The most bytes a PLY's header is read in. The CLI reads a header of any length and writes its
 * input's header back with the result (comments included); past this the file is refused as no
 * PLY the viewer reads, rather than decoded whole in search of an 'end_header' it may not have (a
 * binary file of hundreds of MB).
 */
export const PLY_HEADER_LIMIT = 16 * 1024 * 1024;

/**
 * The header's lines in the bytes [from, to): each line's tokens (split at blanks and tabs, as
 * the CLI splits them), its byte offset and that of the next line; `end`: the 'end_header' line's
 * index, or -1 when none ends within them. A line ends at "\n", "\r\n" or a lone "\r", or at the
 * file's end; one cut by `to` short of the file's end is not read (it may go on).
 */
function headerLines(buffer, from, to) {
  const text = bytesText(buffer, from, to), whole = to >= buffer.byteLength;
  const line = /([^\r\n]*)(\r\n|\n|\r|$)/y, lines = [];
  for (let m; line.lastIndex < text.length && (m = line.exec(text));) {
    if (!whole && (m[2] === '' || line.lastIndex >= text.length)) break;
    const tokens = m[1].split(/[ \t]+/).filter((t) => t !== '');
    lines.push({ tokens, at: from + m.index, next: from + line.lastIndex });
    if (tokens[0] === 'end_header') return { lines, end: lines.length - 1 };
  }
  return { lines, end: -1 };
}

/**
 * A PLY's header, read up to its 'end_header' line as the CLI reads it (a UTF-8 byte-order mark
 * skipped): its format, elements ({name, count, properties: {name, type} or {name, list:
 * [countType, itemType]}}), comments ({at, next}: the line's bytes), the lines three.js's
 * PLYLoader needs (`lines`: format, element and property, as tokens), the byte offset of its data
 * and the data's first line. Throws for a header cut short, one longer than PLY_HEADER_LIMIT, or
 * one the viewer cannot read.
 */
function plyHeader(buffer, name) {
  const u8 = new Uint8Array(buffer);
  const bom = u8[0] === 0xef && u8[1] === 0xbb && u8[2] === 0xbf ? 3 : 0;
  // Most headers end in the first 64 KiB: a longer one (comments) is read again, up to the limit.
  let read;
  for (const size of [65536, PLY_HEADER_LIMIT]) {
    read = headerLines(buffer, bom, Math.min(buffer.byteLength, bom + size));
    if (read.end >= 0 || buffer.byteLength <= bom + size || (read.lines.length && read.lines[0].tokens.join(' ') !== 'ply')) break;
  }
  const { lines, end } = read;
  if (lines[0]?.tokens.join(' ') !== 'ply') throw new Error(`${name}: not a PLY file (it does not begin with 'ply')`);
  if (end < 0 && buffer.byteLength > bom + PLY_HEADER_LIMIT) {
    throw new Error(`${name}: no 'end_header' line in the file's first ${PLY_HEADER_LIMIT / 1048576} MiB: ` +
                    `the viewer reads a PLY header of up to ${PLY_HEADER_LIMIT / 1048576} MiB`);
  }
  if (end < 0) throw new Error(`${name}: the header has no 'end_header' line: the file is cut short in its header`);
  const out = { format: '', elements: [], comments: [], lines: [], dataStart: lines[end].next, dataLine: end + 2 };
  lines.slice(1, end).forEach(({ tokens: t, at, next }, k) => {
    const where = `${name}: line ${k + 2}`;
    if (t[0] === 'comment') out.comments.push({ at, next });
    if (['format', 'element', 'property'].includes(t[0])) out.lines.push(t);
    if (t[0] === 'format') {
      out.format = t[1];
      if (!['ascii', 'binary_little_endian', 'binary_big_endian'].includes(t[1])) throw new Error(`${where}: unknown format '${t[1]}'`);
    } else if (t[0] === 'element') {
      const count = Number(t[2]);
      if (!Number.isInteger(count) || count < 0) throw new Error(`${where}: element '${t[1]}' has no count ('${t[2] ?? ''}')`);
      out.elements.push({name: t[1], count, properties: [], line: k + 2});
    } else if (t[0] === 'property') {
      const element = out.elements.at(-1);
      if (!element) throw new Error(`${where}: a property before any element`);
      const list = t[1] === 'list';
      const types = list ? [t[2], t[3]] : [t[1]];
      const bad = types.find((x) => !PLY_TYPES[x]);
      if (bad !== undefined) throw new Error(`${where}: unknown property type '${bad}'`);
      if (list && !INTEGER_TYPES.has(t[2])) throw new Error(`${where}: a list's count of type '${t[2]}', not an integer type`);
      element.properties.push(list ? { name: t[4], list: types } : { name: t[2], type: t[1] });
    }
  });
  if (!out.format) throw new Error(`${name}: the header has no 'format' line`);
  // An element without properties takes no bytes, so no body bounds its count, and every loop over
  // its instances (checkPly's, PLYLoader's) runs for as long as it says. No file declares more
  // instances than it has bytes: refused, as the CLI refuses it.
  for (const e of out.elements) {
    if (e.properties.length === 0 && e.count > buffer.byteLength) {
      throw new Error(
          `${name}: line ${e.line}: element '${e.name}' has no properties but declares ${
              e.count} instances, ` +
          `more than the file's ${buffer.byteLength} bytes`);
    }
  }
  return out;
}

/**
 * Checks that a PLY holds every element its header counts (ASCII: numbers, integers where the type
 * is; binary: the bytes) and that its faces refer to vertices it has. @returns its header (plyHeader)
 */
export function checkPly(buffer, name) {
  const header = plyHeader(buffer, name);
  const vertices = header.elements.find((e) => e.name === 'vertex')?.count ?? 0;
  const isIndex = (e, p) => e.name === 'face' && p.list && ['vertex_indices', 'vertex_index'].includes(p.name);
  const badIndex = (f, v) => new Error(`${name}: face ${f} refers to vertex ${v}, but the file has ${vertices}`);
  const cut = (e, i) => new Error(`${name}: the file ends after ${i} of the ${e.count} '${e.name}' elements its header gives: it is cut short`);
  if (header.format === 'ascii') {
    const text = bytesText(buffer, header.dataStart);
    const token = /\S+/g;
    const next = (e, i) => {
      const m = token.exec(text);
      if (!m) throw cut(e, i);
      return m;
    };
    const number = (e, i, type) => {
      const m = next(e, i), v = Number(m[0]);
      const ok = INTEGER_TYPES.has(type) ? Number.isInteger(v) : !Number.isNaN(v) || /^[-+]?(nan|inf(inity)?)$/i.test(m[0]);
      if (!ok) {
        throw new Error(`${name}: line ${lineAt(text, m.index) + header.dataLine - 1}: ` +
                        `${e.name} ${i}: '${m[0]}' is not ${INTEGER_TYPES.has(type) ? 'an integer' : 'a number'}`);
      }
      return v;
    };
    for (const e of header.elements) {
      // An element without properties has nothing to read (plyHeader bounded its count).
      if (e.properties.length === 0) continue;
      for (let i = 0; i < e.count; i++) {
        for (const p of e.properties) {
          if (!p.list) { number(e, i, p.type); continue; }
          const n = number(e, i, p.list[0]);
          for (let k = 0; k < n; k++) {
            const v = number(e, i, p.list[1]);
            if (isIndex(e, p) && (v < 0 || v >= vertices)) throw badIndex(i, v);
          }
        }
      }
    }
    return header;
  }
  const data = new DataView(buffer, Math.min(header.dataStart, buffer.byteLength));
  const little = header.format === 'binary_little_endian';
  let at = 0;
  const read = (e, i, type) => {
    const [size, get] = PLY_TYPES[type];
    if (at + size > data.byteLength) throw cut(e, i);
    const v = data[get](at, little);
    at += size;
    return v;
  };
  for (const e of header.elements) {
    // Elements of fixed size (every property a scalar) are checked by their total alone.
    if (e.properties.every((p) => !p.list)) {
      const size = e.properties.reduce((s, p) => s + PLY_TYPES[p.type][0], 0);
      if (at + size * e.count > data.byteLength) throw cut(e, Math.floor((data.byteLength - at) / size));
      at += size * e.count;
      continue;
    }
    for (let i = 0; i < e.count; i++) {
      for (const p of e.properties) {
        if (!p.list) { read(e, i, p.type); continue; }
        const n = read(e, i, p.list[0]);
        if (!isIndex(e, p)) {
          if (at + n * PLY_TYPES[p.list[1]][0] > data.byteLength) throw cut(e, i);
          at += n * PLY_TYPES[p.list[1]][0];
          continue;
        }
        for (let k = 0; k < n; k++) {
          const v = read(e, i, p.list[1]);
          if (v < 0 || v >= vertices) throw badIndex(i, v);
        }
      }
    }
  }
  return header;
}

/** Checks that a binary STL holds the triangles its header counts. */
export function checkBinaryStl(buffer, name) {
  if (buffer.byteLength < 84) throw new Error(`${name}: the file ends in a binary STL's 84-byte header: it is cut short (or an ASCII STL that does not begin with 'solid')`);
  const n = new DataView(buffer).getUint32(80, true), size = 84 + 50 * n;
  if (buffer.byteLength < size) {
    throw new Error(`${name}: the file ends after ${Math.floor((buffer.byteLength - 84) / 50)} of the ${n} triangles its header gives ` +
                    `(${buffer.byteLength} of ${size} bytes): it is cut short`);
  }
}

/** The keywords an ASCII STL's reading rests on, which the CLI (CGAL) reads in lower case only. */
const STL_KEYWORDS = ['solid', 'facet', 'vertex', 'endfacet', 'endsolid'];

/**
 * Checks an ASCII STL's keywords: each facet of three vertices of three numbers, closed by
 * 'endfacet', and the solid closed by 'endsolid' (STLLoader reads only what lies between 'solid'
 * and 'endsolid': a file cut short had no faces). A keyword in upper or mixed case ('SOLID',
 * 'Facet', as some CAD exporters write) is refused, named: the CLI does not read it as one (a
 * file beginning 'SOLID' is neither ASCII nor binary to it, a 'VERTEX' leaves its facet without
 * vertices, a 'FACET' is skipped with its vertices), and so neither do three.js's loaders.
 * ('normal', 'outer loop' and 'endloop' are skipped by both in any case.)
 */
export function checkAsciiStl(text, name) {
  const token = /\S+/g;
  let m, facets = 0, inFacet = false, corners = 0, closed = false;
  const where = (at) => `${name}: line ${lineAt(text, at)}`;
  const caseOf = (word, at) => {
    if (word.length < 5 || word.length > 8) return;  // not a keyword's length (most words: numbers)
    const lower = word.toLowerCase();
    if (word === lower || !STL_KEYWORDS.includes(lower)) return;
    throw new Error(`${where(at)}: the keyword '${word}' is not in lower case: an ASCII STL's keywords ` +
                    `(${STL_KEYWORDS.map((k) => `'${k}'`).join(', ')}) are read in lower case only, as the CLI reads them`);
  };
  // The rest of a 'solid' or 'endsolid' line is the solid's name, free text ('solid vertex'):
  // not keywords.
  const skipLine = () => {
    const end = text.slice(token.lastIndex).search(/\r|\n/);
    token.lastIndex = end < 0 ? text.length : token.lastIndex + end;
  };
  while ((m = token.exec(text))) {
    const word = m[0];
    caseOf(word, m.index);
    if (word === 'facet') {
      if (inFacet) throw new Error(`${where(m.index)}: facet ${facets} has no 'endfacet'`);
      inFacet = true;
      corners = 0;
      closed = false;
    } else if (word === 'vertex') {
      if (!inFacet) throw new Error(`${where(m.index)}: a vertex outside a facet`);
      for (let k = 0; k < 3; k++) {
        const c = token.exec(text);
        if (!c) throw new Error(`${name}: the file ends after ${facets} facets, within the next: it is cut short`);
        if (!Number.isFinite(Number(c[0]))) throw new Error(`${where(c.index)}: coordinate ${k} of a vertex of facet ${facets}, '${c[0]}', is not a number`);
      }
      corners++;
    } else if (word === 'endfacet') {
      if (!inFacet) throw new Error(`${where(m.index)}: 'endfacet' without its facet`);
      if (corners !== 3) throw new Error(`${where(m.index)}: facet ${facets} has ${corners} vertices, not 3`);
      inFacet = false;
      facets++;
    } else if (word === 'endsolid') {
      if (inFacet) throw new Error(`${where(m.index)}: facet ${facets} has no 'endfacet'`);
      closed = true;
      skipLine();
    } else if (word === 'solid' && !inFacet) {
      closed = false;  // a file of several solids: each closed by its own 'endsolid'
      skipLine();
    }
  }
  if (inFacet) throw new Error(`${name}: the file ends after ${facets} facets, within the next: it is cut short`);
  if (!closed) throw new Error(`${name}: the file ends before 'endsolid' (after ${facets} facets): it is cut short`);
}

/**
 * Checks an OBJ's lines that three.js's OBJLoader reads into positions: a vertex ('v') of three
 * numbers at least, a texture coordinate ('vt') of one, a normal ('vn') of three, and each face
 * ('f') of three corners or more, each referring to a vertex (and texture coordinate and normal)
 * the file defines: a positive index anywhere in the file, as the CLI reads it (OBJLoader looks
 * them up as it reads the face: loadMeshFile moves the definitions first, verticesFirst), a
 * negative one among those before the face.
 */
export function checkObj(text, name) {
  // Lines ending in '\' go on in the next, as OBJLoader joins them; each keeps its first line's number.
  const raw = text.split(/\r\n|\n|\r/), lines = [], numbers = [];
  for (let i = 0, start = 0, joined = ''; i < raw.length; i++) {
    if (raw[i].endsWith('\\') && i + 1 < raw.length) { joined += raw[i].slice(0, -1); continue; }
    lines.push(joined + raw[i]);
    numbers.push(start + 1);
    joined = '';
    start = i + 1;
  }
  const last = lines.findLastIndex((l) => l.trim() !== '');
  if (last >= 0 && lines[last].trimEnd().endsWith('\\')) {
    throw new Error(`${name}: line ${numbers[last]}: a line continuation ('\\') with no line after it: the file may be cut short`);
  }
  const counts = { v: 0, vt: 0, vn: 0 };
  const totals = { v: 0, vt: 0, vn: 0 };
  for (const line of lines) {
    const key = line.trimStart().split(/\s/, 1)[0];
    if (key in totals) totals[key]++;
  }
  const need = { v: 3, vt: 1, vn: 3 }, short = { v: 'is not three numbers', vt: 'has no number', vn: 'is not three numbers' };
  const what = { v: 'vertex', vt: 'texture coordinate', vn: 'normal' };
  lines.forEach((line, i) => {
    const t = line.split('#')[0].trim().split(/\s+/);
    const fail = (problem) => {
      const end = i === last ? ': the file may be cut short' : '';
      return new Error(`${name}: line ${numbers[i]}: ${problem}${end}`);
    };
    if (t[0] in need) {
      const values = t.slice(1, 1 + need[t[0]]);
      if (values.length < need[t[0]] || !values.every((x) => Number.isFinite(Number(x)))) {
        throw fail(`a ${what[t[0]]} '${t.join(' ')}' ${short[t[0]]}`);
      }
      counts[t[0]]++;
    } else if (t[0] === 'f') {
      const corners = t.slice(1);
      if (corners.length < 3) throw fail(`a face of ${corners.length} corner${corners.length === 1 ? '' : 's'} ('${t.join(' ')}')`);
      for (const c of corners) {
        c.split('/').forEach((x, k) => {
          const kind = ['v', 'vt', 'vn'][k];
          if (x === '' && k > 0) return;  // 'v//vn': no texture coordinate
          const n = Number(x);
          if (!kind || !Number.isInteger(n) || n === 0) throw fail(`a face's corner '${c}' is not of the form v, v/vt, v//vn or v/vt/vn`);
          if (n > 0 && n > totals[kind]) throw fail(`a face refers to ${what[kind]} ${n}, but the file has ${totals[kind]}`);
          if (n < 0 && counts[kind] + n + 1 < 1) {
            throw fail(`a face refers to ${what[kind]} ${n}, but the file has ${counts[kind]} before it`);
          }
        });
      }
    }
  });
}

/**
 * Checks a .glb's header and chunks against its length: the 12-byte header ('glTF', version,
 * length), then chunks of an 8-byte header and their data, within the length the header gives.
 */
export function checkGlb(buffer, name) {
  const data = new DataView(buffer);
  if (buffer.byteLength < 4 || bytesText(buffer, 0, 4) !== 'glTF') throw new Error(`${name}: not a binary glTF (it does not begin with 'glTF')`);
  if (buffer.byteLength < 12) throw new Error(`${name}: the file ends in its 12-byte header: it is cut short`);
  const length = data.getUint32(8, true);
  if (buffer.byteLength < length) {
    throw new Error(`${name}: the file ends at byte ${buffer.byteLength} of the ${length} its header gives: it is cut short`);
  }
  for (let at = 12, k = 0; at < length; k++) {
    if (at + 8 > length) throw new Error(`${name}: chunk ${k}'s header runs past the file's length (${length} bytes)`);
    const size = data.getUint32(at, true);
    if (at + 8 + size > length) {
      throw new Error(`${name}: chunk ${k} ('${bytesText(buffer, at + 4, at + 8)}', ${size} bytes) runs past the file's length (${length} bytes)`);
    }
    at += 8 + size;
  }
}

/**
 * Checks a .gltf (JSON, the format `run` writes for a .gltf input and `repair -o x.gltf` writes):
 * its text must be a JSON object (a file cut short is not), and every buffer must be embedded in
 * it (a data: URI, as those commands write them): the viewer reads the file alone, from the Open
 * button or from view.py, which serves only the files named to it. Its images, when they are
 * files, are not read: its materials show without their textures.
 */
export function checkGltf(buffer, name) {
  let json;
  try {
    json = JSON.parse(new TextDecoder().decode(buffer));
  } catch (e) {
    throw new Error(`${name}: not a glTF's JSON text (${e.message}): the file may be cut short`);
  }
  if (json === null || typeof json !== 'object' || Array.isArray(json))
    throw new Error(`${name}: not a glTF (its JSON is not an object)`);
  const buffers = Array.isArray(json.buffers) ? json.buffers : [];
  for (const [k, b] of buffers.entries()) {
    if (typeof b?.uri === 'string' && b.uri.startsWith('data:')) continue;
    throw new Error(
        `${name}: buffer ${k} is ${
            typeof b?.uri === 'string' ? `the file '${b.uri}'` : 'not embedded'}, which the ` +
        'viewer does not read (it reads a .gltf whose buffers are in it, as run and repair write them, or a .glb)');
  }
}
