// Runs the Khronos glTF validator (npm gltf-validator) on each .glb or self-contained .gltf (its
// buffers as data URIs) given; fails on any error.
// Usage: node viewer/tests/validate_gltf.mjs FILE.glb|FILE.gltf [...]
import { readFile } from 'node:fs/promises';
import validator from 'gltf-validator';

const files = process.argv.slice(2);
if (files.length === 0) {
  console.error('usage: validate_gltf.mjs FILE.glb|FILE.gltf [...]');
  process.exit(2);
}
let failed = false;
for (const file of files) {
  const bytes = new Uint8Array(await readFile(file));
  const report = await validator.validateBytes(bytes, {
    uri: file,
    maxIssues: 0,  // no limit
    externalResourceFunction: (uri) => Promise.reject(new Error(`external resource ${uri}: the file must stand alone`)),
  });
  const { numErrors, numWarnings, numInfos, numHints } = report.issues;
  console.log(`${file}: ${numErrors} errors, ${numWarnings} warnings, ${numInfos} infos, ${numHints} hints` +
              ` (validator ${report.validatorVersion})`);
  for (const m of report.issues.messages) {
    if (m.severity <= 1) console.log(`  ${m.severity === 0 ? 'error' : 'warning'} ${m.code} ${m.pointer ?? ''}: ${m.message}`);
  }
  if (numErrors > 0) failed = true;
}
process.exit(failed ? 1 : 0);
