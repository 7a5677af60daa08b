// Headless check (Debian's Chromium, puppeteer-core) of the viewer and the materials of the files
// it opens: a .glb of an OBJ with materials (base colour, alpha, texture) opens showing them and
// wears them where no colour field is shown, a field's colours replace them, and the colour note
// says what is shown (also for a file with materials and no colour fields); an OBJ opened with
// its .mtl and textures in one selection wears its materials as its .glb does, and one opened
// without them is drawn plain with a note naming what is missing; turning "before | after" off
// (or opening other files) frees the GPU memory of the panes that go. The files come from a run of the CLI
// on a small mesh written as an OBJ with three materials, made here in a temporary folder.
// Usage: node viewer/tests/viewer_materials_test.mjs --cli SHELLCONTRACT --mesh ico2.off [--chromium PATH]
import {
  check, finish, glbJson, linear, parseArgs, runCli, startViewer, workFolder, writeEditedGlb, writeThreeMaterialObj,
} from './test_support.mjs';

const args = parseArgs('viewer_materials_test.mjs --cli SHELLCONTRACT --mesh MESH.off [--chromium PATH]', ['cli', 'mesh']);

// ---------------------------------------------------------------- the files
const work = workFolder('shellcontract-viewer-materials-');
const file = work.file;
// three.obj: red, blue and a white material with a green texture (green.png), and faces without.
writeThreeMaterialObj(args.mesh, file, 'three');
runCli(args.cli, 'run', file('three.obj'), '-o', file('three_out.obj'), '--frames', '20', '--target-volume', '0.7', '-q',
       '--gltf', file('three.glb'), '--export-every', '5');
// The same .glb without colour fields: materials and nothing to colour by.
writeEditedGlb(file('three.glb'), file('three_no_fields.glb'), (json) => {
  for (const m of json.meshes) {
    delete m.extras?.colour_fields;
    delete m.extras?.frame_fields;
  }
  return json;
});

const { page, consoleErrors, differing, shot, open, pick, pixels, close } = await startViewer(args.chromium);
try {
  // The file's materials: three.glb has a primitive per material (red, blue, white with a green
  // texture) and one without. It opens showing them ("none" chosen), as the .glb's JSON says, and
  // the picture has red, blue and green in it; its colour fields are still offered, and a field's
  // colours replace the materials.
  let s = await open(file('three.glb'));
  const json = glbJson(file('three.glb'));
  const prims = json.meshes[0].primitives;
  const defs = prims.map((p) => (p.material === undefined ? null : json.materials[p.material]));
  // The fields are custom attributes, never COLOR_n: glTF multiplies COLOR_0 with the base
  // colour, so Blender and three.js would tint the materials with a field's colours.
  const colorAttributes = prims.flatMap((p) => Object.keys(p.attributes).filter((a) => a.startsWith('COLOR_')));
  const fieldAttributes = (json.meshes[0].extras?.colour_fields ?? []).map((f) => f.values_attribute);
  check(colorAttributes.length === 0 && fieldAttributes.length === 4 &&
        prims.every((p) => fieldAttributes.every((a) => typeof a === 'string' && a.startsWith('_') && p.attributes[a] !== undefined)),
        `three.glb's fields are custom attributes on every primitive, with no COLOR_n (${fieldAttributes.join(', ')}; COLOR_n: ${colorAttributes.join(', ') || 'none'})`);
  check(!s.error && prims.length === 4 && s.panes[0]?.meshes === 4 && defs.filter((d) => d).length === 3,
        `three.glb opens as four meshes, three with a material (${s.error ?? `${s.panes[0]?.meshes} meshes, ${prims.length} primitives`})`);
  const menu = await page.$eval('#colour', (e) => ({ value: e.value, options: [...e.options].map((o) => o.value) }));
  check(s.shown[0] === 'file materials' && menu.value === '-1',
        `a file with materials opens showing them (shown: ${s.shown[0]}; colour menu on ${menu.value})`);
  check(menu.options.includes('0'), `its colour fields are still offered (${JSON.stringify(menu.options)})`);
  const pageLooks = async () => (await page.evaluate(() => window.viewer.looks?.()))?.[0] ?? [];
  const looks = await pageLooks();
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
  s.shown = await page.evaluate(() => window.viewer.shown);
  const fieldLooks = await pageLooks();
  check(s.shown[0] === 'mean_curvature' && fieldLooks.length === 4 &&
        fieldLooks.every((l) => l.vertexColors && !l.texture && l.colour.every((c) => c === 1)),
        `choosing a field replaces the materials with the field's colours (shown ${s.shown[0]}; ${JSON.stringify(fieldLooks)})`);
  let note = await page.$eval('#colour-note', (e) => e.textContent);
  check(note.startsWith('mean_curvature: '), `the note describes the field shown ("${note}")`);
  await page.select('#colour', '-1');
  s.shown = await page.evaluate(() => window.viewer.shown);
  note = await page.$eval('#colour-note', (e) => e.textContent);
  check(s.shown[0] === 'file materials' && /materials/.test(note), `back to "none", the materials again, and the note says so (shown ${s.shown[0]}; "${note}")`);

  // The same file without its colour fields (the mesh's extras colour_fields and frame_fields
  // removed): only "none" is offered, the materials are shown, and the note says that there are
  // no colour fields and that the materials are shown (not that the file has no colours).
  s = await open(file('three_no_fields.glb'));
  const plainMenu = await page.$eval('#colour', (e) => [...e.options].map((o) => o.value));
  note = await page.$eval('#colour-note', (e) => e.textContent);
  check(!s.error && JSON.stringify(plainMenu) === '["-1"]' && s.shown[0] === 'file materials',
        `three_no_fields.glb offers no colour field and shows its materials (${s.error ?? `menu ${JSON.stringify(plainMenu)}, shown ${s.shown[0]}`})`);
  check(/no colour fields/.test(note) && /materials/.test(note) && !/no colours/.test(note),
        `the note says there are no colour fields and the materials are shown ("${note}")`);

  // An OBJ opened with its .mtl and texture in one selection (the file picker; a drop is the same
  // path), beside its run's .glb: the OBJ opens showing its materials, each group of faces wearing
  // the material the .glb's primitive of the same name wears (base colour, opacity, texture; the
  // faces before the first usemtl the plain colour, as the .glb's primitive without material).
  s = await pick(file('three.obj'), file('three.mtl'), file('green.png'), file('three.glb'));
  const status = () => page.$eval('#status', (e) => e.textContent);
  let text = await status();
  check(!s.error && s.panes.length === 2 && s.panes[0].name === 'three.obj' && s.panes[1].name === 'three.glb',
        `three.obj with three.mtl and green.png opens beside three.glb (${s.error ?? s.panes.map((p) => p.name).join(', ')}; "${text}")`);
  check(JSON.stringify(s.shown) === '["file materials","file materials"]', `both panes open showing their materials (${JSON.stringify(s.shown)})`);
  /** A pane's looks by material name (an OBJ's mesh has one per group of faces). */
  const byName = (paneLooks) => {
    const m = new Map();
    for (const l of paneLooks.flat()) if (!m.has(l.name)) m.set(l.name, l);
    return m;
  };
  const both = await page.evaluate(() => window.viewer.looks());
  const [objLooks, glbLooks] = both.map(byName);
  check([...glbLooks.keys()].sort().join() === [...objLooks.keys()].sort().join(),
        `the OBJ's groups have the .glb's materials (${[...objLooks.keys()].map((n) => JSON.stringify(n)).join(', ')})`);
  for (const [n, g] of glbLooks) {
    const o = objLooks.get(n);
    check(o && !o.vertexColors && near(o.colour, g.colour) && Math.abs(o.opacity - g.opacity) < 1e-6 && JSON.stringify(o.texture) === JSON.stringify(g.texture),
          `the OBJ's material ${JSON.stringify(n)} looks as the .glb's (${JSON.stringify(o)} vs ${JSON.stringify(g)})`);
  }
  const objRgb = (await pixels(await shot('left'))).hues;
  check(objRgb.every((f) => f > 0.005), `the OBJ's picture has red, the texture's green and blue (${objRgb.map((f) => (100 * f).toFixed(1)).join(', ')} % of the pixels)`);
  check(!/not opened|cannot be read/.test(text), `nothing is missing ("${text}")`);

  // The OBJ alone: drawn plain, and the status names the .mtl it did not get (not an error).
  s = await pick(file('three.obj'));
  text = await status();
  check(!s.error && s.panes.length === 1 && s.shown[0] === 'none', `three.obj alone opens plain (${s.error ?? `shown ${s.shown[0]}`})`);
  check(/three\.mtl \(named by three\.obj\) was not opened with it/.test(text), `the status names the missing .mtl ("${text}")`);
  // The same through view.py (a URL: only the OBJ is served).
  s = await open(file('three.obj'));
  text = await status();
  check(!s.error && /three\.mtl \(named by three\.obj\) was not opened with it/.test(text), `served alone, the same note ("${s.error ?? text}")`);

  // The OBJ and its .mtl without the texture: the materials, the textured one without its
  // texture, and the status names the missing texture.
  s = await pick(file('three.obj'), file('three.mtl'));
  text = await status();
  const noTexture = byName((await page.evaluate(() => window.viewer.looks()))[0]);
  check(!s.error && s.shown[0] === 'file materials' && noTexture.get('skin')?.texture === null && near(noTexture.get('skin')?.colour ?? [], [1, 1, 1]) &&
        near(noTexture.get('red')?.colour ?? [], [0.9, 0.1, 0.1]),
        `without green.png the OBJ wears its materials, skin untextured (${s.error ?? JSON.stringify([...noTexture.values()])})`);
  check(/green\.png \(the texture of skin in three\.mtl\) was not opened with three\.obj/.test(text), `the status names the missing texture ("${text}")`);

  // "before | after" on and off frees the first-frame pane's GPU memory (renderer.info): its
  // geometries and their morph-target textures; what it shares with the pane that stays (the
  // attributes, the index, the file's texture) stays, so that pane looks as before. Opening other
  // files frees the panes shown before.
  s = await open(file('three.glb'));
  const memory = () => page.evaluate(() => window.viewer.memory());
  const toggle = async () => { await page.click('#side-by-side'); return shot(); };
  const single = await shot();
  const m0 = await memory();
  await toggle();
  const m1 = await memory();
  check(m1.geometries > m0.geometries && m1.textures > m0.textures,
        `side by side, the second pane's geometries and textures are on the GPU (${JSON.stringify(m0)}, then ${JSON.stringify(m1)})`);
  const back = await toggle();
  const m2 = await memory();
  check(m2.geometries === m0.geometries && m2.textures === m0.textures,
        `turned off, they are freed (${JSON.stringify(m2)}; one pane: ${JSON.stringify(m0)})`);
  const dBack = await differing(single, back);
  check(dBack < 0.002, `the pane left looks as before, materials and texture included (${(100 * dBack).toFixed(2)} % differ)`);
  await page.select('#colour', '0');
  await page.focus('#scrubber');
  await page.keyboard.press('End');
  const lastColoured = await shot();
  const m3 = await memory();
  await toggle();
  const lastBack = await toggle();
  const m4 = await memory();
  check(m4.geometries === m3.geometries && m4.textures === m3.textures && m3.geometries === m0.geometries,
        `on the last frame with a field, on and off again frees them too (${JSON.stringify(m3)}, then ${JSON.stringify(m4)})`);
  const dLast = await differing(lastColoured, lastBack);
  check(dLast < 0.002, `and the pane left still shows the field on the last frame (${(100 * dLast).toFixed(2)} % differ)`);
  s = await pick(file('three.glb'));
  await shot();
  const m5 = await memory();
  check(!s.error && m5.geometries === m0.geometries && m5.textures === m0.textures,
        `opening the file again frees the pane it replaces (${JSON.stringify(m5)}; one pane: ${JSON.stringify(m0)})`);

  check(consoleErrors.length === 0, `no console errors${consoleErrors.length ? ': ' + consoleErrors.join(' | ') : ''}`);
} finally {
  await close();
  work.remove();
}
finish('all viewer material checks passed');
