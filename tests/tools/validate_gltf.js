// Runs the Khronos glTF-Validator (npm package gltf-validator) on one .glb/.gltf file and prints
// a one-line JSON summary on stdout:
//   {"file": ..., "errors": N, "warnings": N, "infos": N, "hints": N, "messages": [first 20]}
// Usage: NODE_PATH=<repo>/.tools/node_modules node tests/tools/validate_gltf.js FILE
// Exit status: 0 when the file was validated (whatever it found), 2 on usage or I/O problems.
'use strict';
const fs = require('fs');
const path = require('path');
const validator = require('gltf-validator');

const file = process.argv[2];
if (!file) {
  process.stderr.write('usage: node validate_gltf.js FILE\n');
  process.exit(2);
}

let bytes;
try {
  bytes = new Uint8Array(fs.readFileSync(file));
} catch (error) {
  process.stderr.write(`validate_gltf: cannot read ${file}: ${error.message}\n`);
  process.exit(2);
}

validator
    .validateBytes(bytes, {
      uri: path.basename(file),
      maxIssues: 0,
      writeTimestamp: false,
      externalResourceFunction: (uri) => new Promise((resolve, reject) => {
        fs.readFile(path.resolve(path.dirname(file), decodeURIComponent(uri)),
                    (error, data) => error ? reject(error.toString()) : resolve(new Uint8Array(data)));
      }),
    })
    .then((report) => {
      const issues = report.issues;
      const summary = {
        file,
        errors: issues.numErrors,
        warnings: issues.numWarnings,
        infos: issues.numInfos,
        hints: issues.numHints,
        messages: issues.messages.slice(0, 20).map(
            (m) => `${['error', 'warning', 'info', 'hint'][m.severity]} ${m.code} ${m.pointer || ''}: ${m.message}`),
      };
      process.stdout.write(JSON.stringify(summary) + '\n');
    })
    .catch((error) => {
      process.stderr.write(`validate_gltf: validator failed on ${file}: ${error}\n`);
      process.exit(2);
    });
