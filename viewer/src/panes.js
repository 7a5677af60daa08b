// The panes of the view: one per file shown (a run's .glb or a result mesh), each with its own
// scene; a single .glb's first frame is a second pane on the same data ("before | after").
import * as THREE from 'three';
import {GLTFLoader} from 'three/addons/loaders/GLTFLoader.js';

import {fieldColoursOf} from './colour_map.js';
import {checkGlb, checkGltf} from './file_checks.js';
import {extensionOf, GLTF_EXTENSIONS, isViewerFile, loadMeshFile} from './mesh_files.js';
import {loadObjMaterials} from './obj_materials.js';

/** A scene with the viewer's background and lights; `sun` follows the camera (main.js render). */
export function makeScene() {
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0xf4f4f2);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x808080, 1.6));
  const sun = new THREE.DirectionalLight(0xffffff, 1.8);
  scene.add(sun);
  return { scene, sun };
}

/** A glTF's pane: a run's animated .glb, or a .glb or .gltf mesh (run's result of a glTF input). */
async function glbPane(arrayBuffer, name) {
  // A .glb cut short failed in GLTFLoader with a bare RangeError ("Invalid typed array length");
  // a .gltf cut short with JSON's error, naming no file.
  if (extensionOf(name) === 'gltf')
    checkGltf(arrayBuffer, name);
  else
    checkGlb(arrayBuffer, name);
  const gltf = await new GLTFLoader().parseAsync(arrayBuffer, '');
  // three makes one mesh per glTF primitive: an OBJ with several materials has one primitive per
  // material, all on the same vertices and morph targets, so every one is moved and coloured
  // alike. Those of the first glTF mesh are the shell (another file may hold other meshes).
  const meshes = [];
  const meshOf = (o) => gltf.parser.associations.get(o)?.meshes;
  gltf.scene.traverse((o) => { if (o.isMesh && (!meshes.length || meshOf(o) === meshOf(meshes[0]))) meshes.push(o); });
  if (!meshes.length) throw new Error(`${name}: no mesh`);
  const shell = meshes[0];
  // The glTF mesh's extras: three puts them on each primitive's mesh; a loader that puts them on
  // the group of a multi-primitive mesh instead is looked up through the parents.
  let extras = {};
  for (let o = shell; o; o = o.parent) {
    if (o.userData && (o.userData.frame_numbers || o.userData.colour_fields)) { extras = o.userData; break; }
  }
  const targets = shell.morphTargetInfluences ? shell.morphTargetInfluences.length : 0;
  const frameNumbers = Array.isArray(extras.frame_numbers) ? extras.frame_numbers : Array.from({ length: targets + 1 }, (_, k) => k);
  const track = gltf.animations[0]?.tracks[0];
  // Colour fields: the values of each, a custom attribute the loader names in lower case
  // ('_MEAN_CURVATURE' is '_mean_curvature'); colours.js maps them to colours over the extras' low
  // and high. (The file has no COLOR_n: glTF multiplies COLOR_0 with the base colour.)
  // Categorical fields (the run's region ids: extras.categorical_fields) follow them in the
  // menu, marked `categorical`: their values are ids, coloured one apart from another
  // (colours.js), not over a range.
  const colourInfo = Array.isArray(extras.colour_fields) ? [...extras.colour_fields] : [];
  for (const f of Array.isArray(extras.categorical_fields) ? extras.categorical_fields : []) {
    if (typeof f?.name !== 'string' || colourInfo.some((c) => c.name === f.name)) continue;
    colourInfo.push({ ...f, categorical: true, ids: Array.isArray(f.ids) ? f.ids.map(Number) : [] });
  }
  const geometry = shell.geometry;
  const fieldValues = meshes.map((m) => colourInfo.map((f) => (
    typeof f.values_attribute === 'string' ? m.geometry.getAttribute(f.values_attribute.toLowerCase())?.array ?? null : null)));
  // Fields with each frame's own values (extras.frame_fields: one accessor per frame), by name.
  const frameFields = {};
  for (const f of Array.isArray(extras.frame_fields) ? extras.frame_fields : []) {
    if (!Array.isArray(f.accessors) || f.accessors.length !== frameNumbers.length) continue;
    const values = await Promise.all(f.accessors.map((i) => gltf.parser.getDependency('accessor', i)));
    frameFields[f.name] = { values: values.map((a) => a.array), low: Number(f.low), high: Number(f.high) };
  }
  // Per mesh two materials: the viewer's, for a field's colours (or the plain colour), and the
  // file's own (an OBJ's material: base colour, texture on TEXCOORD_0), drawn when no field is.
  // A primitive without a glTF material keeps the plain colour: glTF's default material is a
  // white metal, near black under these lights.
  const looks = meshes.map((m) => {
    const field = new THREE.MeshStandardMaterial({ color: 0xffffff, roughness: 0.6, metalness: 0.0, side: THREE.DoubleSide });
    if (gltf.parser.associations.get(m.material)?.materials === undefined) return { field, file: null };
    const file = m.material.clone();
    file.vertexColors = false;  // a field's colours are the viewer's, never the file material's
    file.side = THREE.DoubleSide;  // as the viewer's: a folded shell shows its back faces
    return { field, file };
  });
  for (const [j, m] of meshes.entries()) m.material = looks[j].field;
  const { scene, sun } = makeScene();
  scene.add(gltf.scene);
  return { name, kind: 'glb', scene, sun, object: gltf.scene, meshes, vertices: geometry.getAttribute('position').count,
           frameNumbers, times: track ? Array.from(track.times) : frameNumbers.map((_, k) => k / 24), colourInfo, fieldValues,
           frameFields, looks };
}

/**
 * A result mesh's pane; an OBJ's materials come from the .mtl files and textures among
 * `companions` (the other files of the selection). `notes` names what could not be used.
 */
async function meshPane(arrayBuffer, name, companions) {
  const m = loadMeshFile(arrayBuffer, name);
  const { scene, sun } = makeScene();
  scene.add(m.object);
  // The file's own colours, kept aside: the colour choice may replace them.
  const fileColourAttributes = m.meshes.map((s) => s.geometry.getAttribute('color'));
  // As a .glb's: the viewer's material for a field's colours (or the plain colour), and the
  // file's materials, one per group of an OBJ's faces, drawn when no field is.
  let looks = m.meshes.map((s) => ({ field: s.material, file: null }));
  let notes = [];
  if (m.materialLibraries.length) {
    const loaded = await loadObjMaterials(name, m.materialLibraries, companions);
    notes = loaded.notes;
    if (loaded.materials.size) {
      // Faces without a material (or of one no .mtl defines) are the plain colour, as in the .glb.
      const plain = new THREE.MeshStandardMaterial({ color: 0xd8c8b0, roughness: 0.6, metalness: 0.0, side: THREE.DoubleSide });
      const fileMaterial = (n) => loaded.materials.get(n) ?? plain;
      looks = m.meshes.map((s, j) => {
        const names = m.materialNames[j];
        const used = [names].flat().some((n) => loaded.materials.has(n));
        return { field: s.material, file: used ? (Array.isArray(names) ? names.map(fileMaterial) : fileMaterial(names)) : null };
      });
    }
  }
  return { name, kind: 'mesh', scene, sun, object: m.object, meshes: m.meshes, vertices: m.vertices, fields: m.fields,
           fileColours: m.fileColours, faceColours: m.faceColours, comments: m.comments, fileColourAttributes, looks, notes };
}

/**
 * A pane of the file: a .glb or .gltf, or a result mesh (`companions`: the other files opened
 * with it).
 */
export async function makePane(arrayBuffer, name, companions = []) {
  const ext = extensionOf(name);
  if (!isViewerFile(name))
    throw new Error(`${name}: not a .glb, a .gltf or a mesh (.off, .obj, .ply, .stl)`);
  const pane = GLTF_EXTENSIONS.includes(ext) ? await glbPane(arrayBuffer, name) :
                                               await meshPane(arrayBuffer, name, companions);
  // WebGL takes no doubles: a Float64Array attribute would throw on the first draw, with every
  // value in three.js's message. Named here, while the file is still the one being opened.
  for (const m of pane.meshes) {
    for (const [k, a] of Object.entries(m.geometry.attributes)) {
      if (a.array instanceof Float64Array) throw new Error(`${name}: its '${k}' values are doubles, which WebGL cannot draw`);
    }
  }
  return pane;
}

/** The .glb pane `glb` at its first frame: a second pane on the same data, for "before | after". */
export function firstFramePane(glb) {
  const object = glb.object.clone(true);
  // The clone's meshes in the order of the pane's (the same traversal of the same tree).
  const original = [], copy = [];
  glb.object.traverse((o) => original.push(o));
  object.traverse((o) => copy.push(o));
  const meshes = glb.meshes.map((m) => copy[original.indexOf(m)]);
  // Object3D.clone shares the geometry, and a choice of colours sets the geometry's 'color':
  // each pane needs its own geometry, or both would show the colours written last (and so its
  // own attribute of field colours, which colour_map.js keeps per geometry).
  for (const m of meshes) m.geometry = paneGeometry(m.geometry);
  const looks = glb.looks.map((l) => ({ field: l.field.clone(), file: l.file ? l.file.clone() : null }));
  const { scene, sun } = makeScene();
  scene.add(object);
  return { ...glb, scene, sun, object, meshes, looks, fixed: 0 };
}

/**
 * A new geometry on the same index, attributes and morph targets: its own table of attributes,
 * so that setting its 'color' leaves the other pane's alone. The attributes themselves are only
 * read (the frames are chosen by each mesh's own morph influences), so they are shared, not
 * copied: a run's morph targets can be most of the file.
 */
function paneGeometry(g) {
  const c = new THREE.BufferGeometry();
  c.setIndex(g.index);
  for (const [k, a] of Object.entries(g.attributes)) c.setAttribute(k, a);
  for (const [k, list] of Object.entries(g.morphAttributes)) c.morphAttributes[k] = list.slice();
  c.morphTargetsRelative = g.morphTargetsRelative;
  for (const gr of g.groups) c.addGroup(gr.start, gr.count, gr.materialIndex);
  c.setDrawRange(g.drawRange.start, g.drawRange.count);
  c.boundingBox = g.boundingBox ? g.boundingBox.clone() : null;
  c.boundingSphere = g.boundingSphere ? g.boundingSphere.clone() : null;
  c.name = g.name;
  c.userData = g.userData;
  return c;
}

/**
 * Frees what the pane holds on the GPU, as three.js's "How to dispose of objects" says: its
 * geometries (their buffers and morph-target textures), materials and textures, except what the
 * pane `keep` still draws: the first-frame pane of "before | after" shares the index, attributes
 * and textures of the pane it was made from. (Both panes draw through the page's one renderer,
 * into two viewports: there is no renderer or render target of a pane to dispose.)
 */
export function disposePane(p, keep = null) {
  const kept = new Set();
  for (const [j, m] of (keep?.meshes ?? []).entries()) {
    kept.add(m.geometry).add(m.geometry.index);
    for (const a of attributesOf(keep, j)) kept.add(a);
  }
  for (const mat of (keep?.looks ?? []).flatMap(materialsOf)) {
    kept.add(mat);
    for (const t of texturesOf(mat)) kept.add(t);
  }
  for (const [j, m] of p.meshes.entries()) {
    const g = m.geometry;
    if (kept.has(g)) continue;
    // dispose() deletes the GPU buffers of the geometry's index and attributes, and only those:
    // the colours that a choice took off its 'color' (the file's, or the field colours) are put
    // back on it under spare names, and the kept pane's, which it may also draw, taken off.
    const current = new Set(Object.values(g.attributes));
    attributesOf(p, j).filter((a) => !current.has(a)).forEach((a, n) => g.setAttribute(`spare_colours_${n}`, a));
    if (kept.has(g.index)) g.setIndex(null);
    for (const [k, a] of Object.entries(g.attributes)) if (kept.has(a)) g.deleteAttribute(k);
    g.dispose();
  }
  const materials = new Set([...p.looks.flatMap(materialsOf), ...p.meshes.flatMap((m) => [m.material].flat())]);
  for (const mat of materials) {
    if (kept.has(mat)) continue;
    for (const t of texturesOf(mat)) if (!kept.has(t)) t.dispose();
    mat.dispose();
  }
}

/**
 * The attributes of the pane's mesh j: those of its geometry, and the colours that the colour
 * choice sets as its 'color' (colours.js applyColours), which may be off it now.
 */
const attributesOf = (p, j) => {
  const g = p.meshes[j].geometry;
  return [...new Set([...Object.values(g.attributes), p.fileColourAttributes?.[j],
                      fieldColoursOf(g)].filter(Boolean))];
};
/** The materials of a mesh's look: the viewer's and the file's (one, or one per group). */
const materialsOf = (look) => [look.field, look.file].flat().filter(Boolean);
/** The textures a material uses (map, normalMap, ...). */
const texturesOf = (material) => Object.values(material).filter((v) => v?.isTexture);
