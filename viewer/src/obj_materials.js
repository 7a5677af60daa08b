// An OBJ's materials from the .mtl files and textures opened with it (one selection or drop of
// several files): three.js's MTLLoader reads the .mtl and loads the textures, and a LoadingManager
// URL modifier turns the names the OBJ and the .mtl give into the chosen files. The materials are
// those the CLI's .glb of the same OBJ has (src/export/gltf_material.cpp reads newmtl, Kd, d, Tr
// and map_Kd), so an OBJ beside its run's .glb looks the same: Kd is the base colour as given
// (MTLLoader would take it as sRGB; the exporter writes it unconverted), clamped to 1, on a
// metalness 0, roughness 1 material.
import * as THREE from 'three';
import { MTLLoader } from 'three/addons/loaders/MTLLoader.js';

/** The file name of a path an OBJ or .mtl gives (either slash). */
const baseName = (p) => p.split(/[\\/]/).pop();

/** The MTL keys the .glb carries; the rest (Ks, bump maps, ...) is left out, as the exporter does. */
const KEPT_KEYS = ['name', 'kd', 'd', 'tr', 'map_kd'];

/**
 * The OBJ's text with an unnamed `usemtl` before its first face when that face comes before any
 * `usemtl`: such faces have no material (the .glb gives them a primitive without one), but
 * OBJLoader would put them in the first named material's group.
 */
export function withUnnamedFirstMaterial(text) {
  const face = /^[ \t]*f\s/m.exec(text), use = /^[ \t]*usemtl\s/m.exec(text);
  if (!face || !use || use.index < face.index) return text;
  return `${text.slice(0, face.index)}usemtl \n${text.slice(face.index)}`;
}

/**
 * Loads the materials of the OBJ's mtllib lines from the files chosen with it.
 * @param {string} objName the OBJ's file name, for the notes
 * @param {string[]} libraries the mtllib lines' names (OBJLoader's materialLibraries)
 * @param {File[]} files the other files of the selection (.mtl, textures)
 * @returns {Promise<{materials: Map<string, THREE.MeshStandardMaterial>, notes: string[]}>}
 *   the materials by name; the notes name each .mtl or texture that is missing or unreadable
 *   (the OBJ is drawn without it: not an error)
 */
export async function loadObjMaterials(objName, libraries, files) {
  const notes = [];
  const materials = new Map();
  const find = (name) => {
    const n = baseName(name);
    return files.find((f) => f.name === n) ?? files.find((f) => f.name.toLowerCase() === n.toLowerCase());
  };
  const urls = new Map();  // File -> its object URL, revoked once everything has loaded
  const urlOf = (name) => {
    const f = find(name);
    if (!f) return name;
    if (!urls.has(f)) urls.set(f, URL.createObjectURL(f));
    return urls.get(f);
  };
  const manager = new THREE.LoadingManager();
  manager.setURLModifier(urlOf);
  try {
    // One mtllib line may name several libraries (spaces between), or one whose name has spaces.
    const libs = libraries.flatMap((l) => (find(l) ? [l] : l.split(/\s+/).filter(Boolean)));
    let creator = null;
    const info = {};  // by material name; the first definition in the order of the mtllib lines
    for (const lib of libs) {
      if (!find(lib)) {
        notes.push(`${lib} (named by ${objName}) was not opened with it: open the .obj, its .mtl and textures together`);
        continue;
      }
      let c;
      try {
        c = await new MTLLoader(manager).loadAsync(lib);
      } catch {
        notes.push(`${lib} cannot be read`);
        continue;
      }
      creator ??= c;
      for (const [name, m] of Object.entries(c.materialsInfo)) {
        if (name in info) continue;
        info[name] = Object.fromEntries(Object.entries(m).filter(([k]) => KEPT_KEYS.includes(k)));
        const texture = info[name].map_kd && c.getTextureParams(info[name].map_kd, {}).url;
        if (texture && !find(texture)) {
          notes.push(`${texture} (the texture of ${name} in ${lib}) was not opened with ${objName}: ${name} has no texture`);
          delete info[name].map_kd;
        }
      }
    }
    if (!creator) return { materials, notes };
    creator.setMaterials(info);
    // The textures load through a manager of their own, idle until they start (the .mtl's may
    // not have ended yet when loadAsync resolves): its onLoad comes when the last one has.
    const textures = new THREE.LoadingManager();
    textures.setURLModifier(urlOf);
    creator.setManager(textures);
    let loading = false;
    const loaded = new Promise((resolve) => { textures.onLoad = resolve; });
    textures.onStart = () => { loading = true; };
    const phong = Object.keys(info).map((name) => creator.create(name));
    if (loading) await loaded;
    for (const p of phong) {
      const kd = info[p.name].kd;
      const map = p.map?.image ? p.map : null;  // a texture that failed to load has no image
      if (p.map && !map) {
        notes.push(`the texture of ${p.name} cannot be read: ${p.name} has no texture`);
        p.map.dispose();
      }
      const colour = Array.isArray(kd) && kd.every((x) => Number.isFinite(x) && x >= 0)
        ? new THREE.Color(...kd.map((x) => Math.min(x, 1))) : new THREE.Color(1, 1, 1);
      materials.set(p.name, new THREE.MeshStandardMaterial({
        name: p.name, color: colour, map, opacity: p.opacity, transparent: p.transparent, depthWrite: !p.transparent,
        metalness: 0, roughness: 1, side: THREE.DoubleSide,
      }));
      p.dispose();
    }
    return { materials, notes };
  } finally {
    for (const u of urls.values()) URL.revokeObjectURL(u);
  }
}
