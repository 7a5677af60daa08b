// Result meshes (issue 56): OFF (parsed here: three.js has no OFF loader), OBJ, PLY and STL
// (three.js's loaders from node_modules) as one THREE.Object3D each, with the per-vertex scalar
// fields a PLY carries (e.g. the --fields files' mean_curvature) and its own colours.
import * as THREE from 'three';
import { OBJLoader } from 'three/addons/loaders/OBJLoader.js';
import { PLYLoader } from 'three/addons/loaders/PLYLoader.js';
import { STLLoader } from 'three/addons/loaders/STLLoader.js';
import { withUnnamedFirstMaterial } from './obj_materials.js';

export const MESH_EXTENSIONS = ['off', 'obj', 'ply', 'stl'];

export function extensionOf(name) {
  const m = /\.([^./\\]+)$/.exec(name);
  return m ? m[1].toLowerCase() : '';
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

/** The vertex element's scalar properties of a PLY header that are not geometry or colour. */
function plyScalarFields(buffer) {
  const head = new TextDecoder().decode(new Uint8Array(buffer, 0, Math.min(buffer.byteLength, 65536)));
  const end = head.indexOf('end_header');
  if (end < 0) return [];
  const fields = [];
  let element = '';
  for (const line of head.slice(0, end).split(/\r\n|\n|\r/)) {
    const t = line.trim().split(/\s+/);
    if (t[0] === 'element') element = t[1];
    else if (t[0] === 'property' && element === 'vertex' && t[1] !== 'list' &&
             !['x', 'y', 'z', 'nx', 'ny', 'nz', 'red', 'green', 'blue', 'alpha', 's', 't', 'u', 'v'].includes(t[2])) fields.push(t[2]);
  }
  return fields;
}

/**
 * Loads a result mesh. @returns {{object: THREE.Object3D, meshes: THREE.Mesh[], vertices: number,
 * fields: {name: string, attribute: string}[], fileColours: boolean, materialLibraries: string[],
 * materialNames: (string | string[])[]}} (the last two: an OBJ's mtllib names and, per mesh, the
 * usemtl names of its groups; the meshes wear the viewer's material)
 */
export function loadMeshFile(buffer, name) {
  const ext = extensionOf(name);
  let object, fields = [], materialLibraries = [];
  if (ext === 'off') {
    const g = parseOff(new TextDecoder().decode(buffer), name);
    object = new THREE.Mesh(g);
    object.position.fromArray(g.userData.centre);
  } else if (ext === 'obj') {
    const { text, centre } = recentredObj(new TextDecoder().decode(buffer));
    object = new OBJLoader().parse(withUnnamedFirstMaterial(text));
    materialLibraries = object.materialLibraries;
    object.position.fromArray(centre);
  } else if (ext === 'ply') {
    const loader = new PLYLoader();
    fields = plyScalarFields(buffer).map((f) => ({ name: f, attribute: `field_${f}` }));
    loader.setCustomPropertyNameMapping(Object.fromEntries(fields.map((f) => [f.attribute, [f.name]])));
    const g = loader.parse(buffer);
    // PLYLoader keeps a double property as a Float64Array, which WebGL cannot draw (the CLI
    // writes doubles: 17 digits): floats for the GPU. Custom fields stay as read.
    // Double positions recentred before they become floats, as an OFF's (recentred).
    let centre = [0, 0, 0];
    for (const [key, a] of Object.entries(g.attributes)) {
      if (a.array instanceof Float64Array && !key.startsWith('field_')) {
        let floats = Float32Array.from(a.array);
        if (key === 'position') ({ position: floats, centre } = recentred(a.array));
        g.setAttribute(key, new THREE.Float32BufferAttribute(floats, a.itemSize, a.normalized));
      }
    }
    if (!g.getAttribute('normal')) g.computeVertexNormals();
    object = new THREE.Mesh(g);
    object.position.fromArray(centre);
  } else if (ext === 'stl') {
    const g = new STLLoader().parse(buffer);
    // STLLoader reads straight into float32 (a binary STL holds no more); recentred all the same,
    // so that the GPU's float arithmetic works on coordinates the size of the mesh, as for the
    // other formats.
    const { position, centre } = recentred(Float64Array.from(g.getAttribute('position').array));
    g.setAttribute('position', new THREE.Float32BufferAttribute(position, 3));
    g.computeVertexNormals();
    object = new THREE.Mesh(g);
    object.position.fromArray(centre);
  } else {
    throw new Error(`${name}: unknown mesh format '.${ext}' (expected .off, .obj, .ply, .stl or .glb)`);
  }
  const meshes = [];
  object.traverse((o) => { if (o.isMesh) meshes.push(o); });
  if (!meshes.length) throw new Error(`${name}: no faces`);
  // The materials' names of each mesh, kept for the .mtl (obj_materials.js): an OBJ of several has
  // an array, one per geometry group.
  const materialNames = meshes.map((m) => (Array.isArray(m.material) ? m.material.map((x) => x.name) : m.material?.name ?? ''));
  for (const m of meshes) {
    if (!m.geometry.getAttribute('normal')) m.geometry.computeVertexNormals();
    m.material = new THREE.MeshStandardMaterial({ color: 0xd8c8b0, roughness: 0.6, metalness: 0.0, side: THREE.DoubleSide });
  }
  const vertices = meshes.reduce((n, m) => n + m.geometry.getAttribute('position').count, 0);
  const fileColours = meshes.every((m) => m.geometry.getAttribute('color'));
  return { object, meshes, vertices, fields, fileColours, materialLibraries, materialNames };
}
