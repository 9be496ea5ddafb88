// Validates one GLB with Khronos glTF-Validator and prints its report as JSON on stdout.
// Usage: node validate.js FILE.glb
const fs = require('fs');
const validator = require('gltf-validator');

const path = process.argv[2];
const bytes = new Uint8Array(fs.readFileSync(path));
validator.validateBytes(bytes, {uri: path, maxIssues: 100})
  .then((report) => {
    console.log(JSON.stringify(report.issues));
  })
  .catch((error) => {
    console.error(`validation failed: ${error}`);
    process.exit(2);
  });
