// Headless check (Debian's Chromium, puppeteer-core) of the viewer and the materials of the files
// it opens: a .glb of an OBJ with materials (base colour, alpha, texture) opens showing them and
// wears them where no colour field is shown, a field's colours replace them, and the colour note
// says what is shown (also for a file with materials and no colour fields). The files come from a run of the CLI
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

const { page, consoleErrors, shot, open, pixels, close } = await startViewer(args.chromium);
try {
  // The file's materials: three.glb has a primitive per material (red, blue, white with a green
  // texture) and one without. It opens showing them ("none" chosen), as the .glb's JSON says, and
  // the picture has red, blue and green in it; its colour fields are still offered, and a field's
  // colours replace the materials.
  let s = await open(file('three.glb'));
  const json = glbJson(file('three.glb'));
  const prims = json.meshes[0].primitives;
  const defs = prims.map((p) => (p.material === undefined ? null : json.materials[p.material]));
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

  check(consoleErrors.length === 0, `no console errors${consoleErrors.length ? ': ' + consoleErrors.join(' | ') : ''}`);
} finally {
  await close();
  work.remove();
}
finish('all viewer material checks passed');
