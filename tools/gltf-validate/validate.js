// Validates GLB files with the Khronos glTF validator; prints a JSON summary per file
// and exits non-zero if any file has an error.
const validator = require('gltf-validator');
const fs = require('fs');
(async () => {
  let failed = 0;
  for (const file of process.argv.slice(2)) {
    const result = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)));
    const issues = result.issues;
    const errors = issues.messages.filter((m) => m.severity === 0).map((m) => `${m.code} ${m.pointer || ''} ${m.message}`);
    console.log(JSON.stringify({ file, errors: issues.numErrors, warnings: issues.numWarnings, messages: errors }));
    if (issues.numErrors > 0) failed++;
  }
  process.exit(failed ? 1 : 0);
})();
