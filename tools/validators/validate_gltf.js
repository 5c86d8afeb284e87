// Runs the Khronos glTF-Validator (npm `gltf-validator`) on one .glb/.gltf and prints a one-line
// summary plus the messages with severity Error. Exit 0 if the file has no errors, 1 if it has,
// 2 on usage or I/O problems.  Usage: node validate_gltf.js FILE [NODE_MODULES_DIR]
const fs = require('fs');
const path = require('path');
if (process.argv.length < 3) {
  console.error('usage: node validate_gltf.js FILE [NODE_MODULES_DIR]');
  process.exit(2);
}
const file = process.argv[2];
const modules = process.argv[3];
const validator = require(modules ? path.resolve(modules, 'gltf-validator') : 'gltf-validator');
let bytes;
try {
  bytes = new Uint8Array(fs.readFileSync(file));
} catch (e) {
  console.error(`${file}: error: cannot read: ${e.message}`);
  process.exit(2);
}
validator.validateBytes(bytes, {
  uri: path.basename(file),
  maxIssues: 0,
  externalResourceFunction: (uri) => new Promise((resolve, reject) => {
    fs.readFile(path.join(path.dirname(file), decodeURIComponent(uri)),
                (err, data) => err ? reject(err.toString()) : resolve(new Uint8Array(data)));
  }),
}).then((report) => {
  const i = report.issues;
  console.log(`${file}: errors=${i.numErrors} warnings=${i.numWarnings} infos=${i.numInfos} hints=${i.numHints}`);
  for (const m of i.messages) {
    if (m.severity === 0) console.log(`  ${m.code} ${m.pointer || ''} ${m.message}`);
  }
  process.exit(i.numErrors === 0 ? 0 : 1);
}, (err) => {
  console.error(`${file}: error: validator failed: ${err}`);
  process.exit(2);
});
