// Runs the Khronos glTF validator on one .gltf/.glb and prints one JSON line:
// {"errors": N, "warnings": N, "codes": {"CODE": count, ...}} (errors only in codes).
// Usage: node tools/validate.mjs FILE
import fs from 'node:fs';
import path from 'node:path';
import { createRequire } from 'node:module';

const require = createRequire(import.meta.url);
const validator = require('gltf-validator');

const file = process.argv[2];
if (!file) {
  console.error('usage: node tools/validate.mjs FILE');
  process.exit(2);
}
const dir = path.dirname(file);
try {
  const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
    uri: path.basename(file),
    maxIssues: 10000,
    externalResourceFunction: (uri) =>
      new Promise((resolve, reject) => {
        try {
          resolve(new Uint8Array(fs.readFileSync(path.resolve(dir, decodeURIComponent(uri)))));
        } catch (e) {
          reject(e.toString());
        }
      }),
  });
  const codes = {};
  for (const m of report.issues.messages) {
    if (m.severity === 0) codes[m.code] = (codes[m.code] || 0) + 1;
  }
  console.log(JSON.stringify({ errors: report.issues.numErrors, warnings: report.issues.numWarnings, codes }));
} catch (e) {
  console.log(JSON.stringify({ errors: -1, fatal: String(e) }));
  process.exit(1);
}
