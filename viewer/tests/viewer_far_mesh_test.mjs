// The viewer's own mesh loaders keep a mesh far from the origin (review14 D1): an OFF, a PLY and an
// OBJ of doubles are recentred in double before they become float32 (mesh_files.js, recentred), and the
// mesh is placed at its centre, so its positions plus the object's position give the file's to
// float precision relative to the mesh's size. Before, a 2-unit sphere at northing 5e6 (float
// spacing 0.5) became a cloud of a few hundred points. Each loader's bounding sphere and box are
// those of the positions as drawn (review18 H2: PLYLoader's, computed before the recentring, sat
// at twice the centre, and three.js culled the mesh: a PLY a few radii from the origin was blank),
// and an ASCII STL, which the CLI writes with 17 digits, is recentred in double too (review18 M1:
// it was read into float32 first, slabs 0.5 apart). Node only, no browser.
// Usage: node viewer/tests/viewer_far_mesh_test.mjs
import { loadMeshFile, parseOff } from '../src/mesh_files.js';

const failures = [];
const check = (ok, what) => {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failures.push(what);
};

// An icosahedron subdivided twice, on the unit sphere, at UTM-like coordinates.
const FAR = [500000, 5000000, 100];
function sphere() {
  const t = (1 + Math.sqrt(5)) / 2;
  let v = [[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t], [0, -1, -t], [0, 1, -t],
           [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]];
  let f = [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4], [11, 10, 2],
           [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5],
           [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]];
  const unit = (p) => { const n = Math.hypot(...p); return p.map((c) => c / n); };
  v = v.map(unit);
  for (let level = 0; level < 2; level++) {
    const mid = new Map(), next = [];
    const m = (a, b) => {
      const key = a < b ? `${a},${b}` : `${b},${a}`;
      if (!mid.has(key)) { v.push(unit(v[a].map((c, k) => (c + v[b][k]) / 2))); mid.set(key, v.length - 1); }
      return mid.get(key);
    };
    for (const [a, b, c] of f) {
      const ab = m(a, b), bc = m(b, c), ca = m(c, a);
      next.push([a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]);
    }
    f = next;
  }
  return { v: v.map((p) => p.map((c, k) => c + FAR[k])), f };
}

const { v, f } = sphere();
const size = 2 * Math.sqrt(3);  // at most the bounding box's diagonal
const tol = 8 * size * 2 ** -23;

/**
 * Whether the mesh's bounding sphere and box, placed with the object, hold every position the
 * file has and sit on the mesh (three.js culls against the sphere): the check of what is drawn.
 */
function boundsHold(what, object, geometry) {
  // Those three.js uses: the geometry's, or, where it has none yet, computed from the positions
  // as they are now (as three.js computes them on the first draw).
  if (!geometry.boundingSphere) geometry.computeBoundingSphere();
  if (!geometry.boundingBox) geometry.computeBoundingBox();
  const s = geometry.boundingSphere, b = geometry.boundingBox;
  const o = object.position.toArray();
  const centre = s.center.toArray().map((c, k) => c + o[k]);
  let far = 0;
  for (const p of v) far = Math.max(far, Math.hypot(...p.map((c, k) => c - centre[k])));
  check(far <= s.radius * (1 + 1e-6) + tol && s.radius <= size, `${what}: the bounding sphere (centre ${centre}, radius ${s.radius}) holds the mesh (farthest vertex ${far})`);
  const lo = b.min.toArray().map((c, k) => c + o[k]), hi = b.max.toArray().map((c, k) => c + o[k]);
  check(lo.every((c, k) => Math.abs(c - (FAR[k] - 1)) < 1e-3) && hi.every((c, k) => Math.abs(c - (FAR[k] + 1)) < 1e-3),
        `${what}: the bounding box is the mesh's (${lo} to ${hi})`);
}

/** The largest difference between the object's placed positions and the file's, and the count of
 * distinct stored positions. */
function compare(object, geometry) {
  const p = geometry.getAttribute('position').array;
  let err = 0;
  const distinct = new Set();
  for (let i = 0; i < v.length; i++) {
    for (let k = 0; k < 3; k++) err = Math.max(err, Math.abs(p[3 * i + k] + object.position.getComponent(k) - v[i][k]));
    distinct.add(`${p[3 * i]},${p[3 * i + 1]},${p[3 * i + 2]}`);
  }
  return { err, distinct: distinct.size };
}

const off = `OFF\n${v.length} ${f.length} 0\n` + v.map((p) => p.join(' ')).join('\n') + '\n' +
            f.map((t) => `3 ${t.join(' ')}`).join('\n') + '\n';
{
  const g = parseOff(off, 'far.off');
  const centre = g.userData.centre ?? [0, 0, 0];
  check(centre.every((c, k) => Math.abs(c - FAR[k]) < 1e-9), `OFF: the centre is kept, ${centre}`);
  const { object, meshes } = loadMeshFile(new TextEncoder().encode(off).buffer, 'far.off');
  const { err, distinct } = compare(object, meshes[0].geometry);
  check(distinct === v.length, `OFF: ${distinct} distinct positions of ${v.length}`);
  check(err <= tol, `OFF: placed positions within ${err} of the file's (tolerance ${tol})`);
  boundsHold('OFF', object, meshes[0].geometry);
}
{
  const ply = `ply\nformat ascii 1.0\nelement vertex ${v.length}\nproperty double x\nproperty double y\nproperty double z\n` +
              `element face ${f.length}\nproperty list uchar int vertex_indices\nend_header\n` +
              v.map((p) => p.join(' ')).join('\n') + '\n' + f.map((t) => `3 ${t.join(' ')}`).join('\n') + '\n';
  const { object, meshes } = loadMeshFile(new TextEncoder().encode(ply).buffer, 'far.ply');
  const { err, distinct } = compare(object, meshes[0].geometry);
  check(meshes[0].geometry.getAttribute('position').array instanceof Float32Array, 'PLY: float32 positions for the GPU');
  check(distinct === v.length, `PLY: ${distinct} distinct positions of ${v.length}`);
  check(err <= tol, `PLY: placed positions within ${err} of the file's (tolerance ${tol})`);
  boundsHold('PLY', object, meshes[0].geometry);
}
{
  // An OBJ: OBJLoader reads its text into float32 directly, so its vertices are recentred in the
  // text first (recentredObj); OBJLoader splits indexed faces into triangle corners.
  const obj = v.map((p) => `v ${p.join(' ')}`).join('\n') + '\n' + f.map((t) => `f ${t.map((i) => i + 1).join(' ')}`).join('\n') + '\n';
  const { object, meshes } = loadMeshFile(new TextEncoder().encode(obj).buffer, 'far.obj');
  const p = meshes[0].geometry.getAttribute('position').array;
  let err = 0;
  f.forEach((t, j) => t.forEach((i, c) => {
    for (let k = 0; k < 3; k++) err = Math.max(err, Math.abs(p[9 * j + 3 * c + k] + object.position.getComponent(k) - v[i][k]));
  }));
  check(err <= tol, `OBJ: placed positions within ${err} of the file's (tolerance ${tol})`);
  boundsHold('OBJ', object, meshes[0].geometry);
}
{
  // An ASCII STL as the CLI writes it (17 digits): recentred in double before float32, so the
  // sphere keeps its vertices apart.
  const stl = 'solid far\n' + f.map((t) => 'facet normal 0 0 0\nouter loop\n' +
    t.map((i) => `vertex ${v[i].map((c) => c.toPrecision(17)).join(' ')}\n`).join('') + 'endloop\nendfacet\n').join('') + 'endsolid far\n';
  const { object, meshes, vertices } = loadMeshFile(new TextEncoder().encode(stl).buffer, 'far_ascii.stl');
  const p = meshes[0].geometry.getAttribute('position').array;
  let err = 0;
  const distinct = new Set();
  f.forEach((t, j) => t.forEach((i, c) => {
    for (let k = 0; k < 3; k++) err = Math.max(err, Math.abs(p[9 * j + 3 * c + k] + object.position.getComponent(k) - v[i][k]));
    distinct.add(`${p[9 * j + 3 * c]},${p[9 * j + 3 * c + 1]},${p[9 * j + 3 * c + 2]}`);
  }));
  check(distinct.size === v.length, `ASCII STL: ${distinct.size} distinct positions of ${v.length}`);
  check(err <= tol, `ASCII STL: placed positions within ${err} of the file's (tolerance ${tol})`);
  check(vertices === v.length, `ASCII STL: the file's ${v.length} vertices counted, not its corners (${vertices})`);
  boundsHold('ASCII STL', object, meshes[0].geometry);
}
{
  // A binary STL holds float32 already: recentred, the placed positions are the file's floats.
  const data = new DataView(new ArrayBuffer(84 + 50 * f.length));
  data.setUint32(80, f.length, true);
  const stored = [];
  f.forEach((t, j) => t.forEach((i, c) => {
    for (let k = 0; k < 3; k++) {
      data.setFloat32(84 + 50 * j + 12 + 12 * c + 4 * k, v[i][k], true);
      stored.push(data.getFloat32(84 + 50 * j + 12 + 12 * c + 4 * k, true));
    }
  }));
  const { object, meshes } = loadMeshFile(data.buffer, 'far.stl');
  const p = meshes[0].geometry.getAttribute('position').array;
  let err = 0, span = 0;
  for (let i = 0; i < stored.length; i++) {
    err = Math.max(err, Math.abs(p[i] + object.position.getComponent(i % 3) - stored[i]));
    span = Math.max(span, Math.abs(p[i]));
  }
  check(err <= tol, `STL: placed positions within ${err} of the file's floats (tolerance ${tol})`);
  check(span <= size, `STL: stored positions relative to the mesh's centre (largest ${span})`);
  boundsHold('binary STL', object, meshes[0].geometry);
}
{
  // A mesh at the origin stays there: nothing moves for the usual files.
  const near = `OFF\n3 1 0\n-1 0 0\n1 0 0\n0 1 0\n3 0 1 2\n`;
  const { object } = loadMeshFile(new TextEncoder().encode(near).buffer, 'near.off');
  check(object.position.x === 0 && object.position.y === 0.5 && object.position.z === 0,
        `a mesh near the origin is placed at its own centre, (${object.position.toArray()})`);
}
if (failures.length) {
  console.error(`${failures.length} check(s) failed`);
  process.exit(1);
}
console.log('viewer_far_mesh: ok');
