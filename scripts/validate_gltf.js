#!/usr/bin/env node
// Validates glTF / GLB files with the Khronos glTF-Validator (npm gltf-validator, installed by
// scripts/install_deps.sh --with-colmap into scripts/node). Prints one line per file:
//   FILE: N errors, N warnings, N infos
// followed by each error's code and message; exits 1 when any file has an error, 2 when the
// validator is not installed or a file cannot be read.
'use strict';
const fs = require('fs');
const path = require('path');

let validator;
try {
  validator = require(path.join(__dirname, 'node', 'node_modules', 'gltf-validator'));
} catch (e) {
  console.error('validate_gltf: gltf-validator is not installed (scripts/install_deps.sh --with-colmap)');
  process.exit(2);
}

async function main(files) {
  if (files.length === 0) {
    console.error('usage: validate_gltf.js FILE.glb|FILE.gltf ...');
    return 2;
  }
  let failed = false;
  for (const file of files) {
    let bytes;
    try {
      bytes = new Uint8Array(fs.readFileSync(file));
    } catch (e) {
      console.error(`${file}: cannot read (${e.message})`);
      return 2;
    }
    // External resources (a .gltf's .bin and images) are read from beside the file.
    const report = await validator.validateBytes(bytes, {
      uri: path.basename(file),
      externalResourceFunction: (uri) =>
        Promise.resolve(new Uint8Array(fs.readFileSync(path.join(path.dirname(file), decodeURIComponent(uri))))),
    });
    const n = report.issues;
    console.log(`${file}: ${n.numErrors} errors, ${n.numWarnings} warnings, ${n.numInfos} infos`);
    for (const m of n.messages) {
      if (m.severity === 0) console.log(`  error ${m.code} at ${m.pointer || ''}: ${m.message}`);
    }
    failed = failed || n.numErrors > 0;
  }
  return failed ? 1 : 0;
}

main(process.argv.slice(2)).then((code) => process.exit(code), (e) => {
  console.error(`validate_gltf: ${e.message || e}`);
  process.exit(2);
});
