// Runs the Khronos glTF-Validator over files and prints one summary line per file.
//
// Usage: node tests/gltf_validate.mjs VALIDATOR_DIR FILE...
//
// VALIDATOR_DIR is the folder of the npm package `gltf-validator` (the one holding its
// package.json), or a folder whose node_modules holds it. Each file's line reads
// `PATH: errors E, warnings W, infos I, hints H`, followed by its messages. The exit code
// is 0 when no file has an error, a warning or an info, 1 otherwise, 2 on bad usage or a
// validator that cannot be loaded. Hints are printed but do not fail.
import { createRequire } from "node:module";
import { existsSync, readFileSync } from "node:fs";
import { basename, dirname, join, resolve } from "node:path";

const [dir, ...files] = process.argv.slice(2);
if (!dir || files.length === 0) {
  console.error("usage: node gltf_validate.mjs VALIDATOR_DIR FILE...");
  process.exit(2);
}

let packageDir = resolve(dir);
if (!existsSync(join(packageDir, "package.json")) ||
    JSON.parse(readFileSync(join(packageDir, "package.json"), "utf8")).name !== "gltf-validator") {
  packageDir = join(packageDir, "node_modules", "gltf-validator");
}
let validator;
try {
  validator = createRequire(join(packageDir, "package.json"))(packageDir);
} catch (error) {
  console.error(`cannot load gltf-validator from ${packageDir}: ${error.message}`);
  process.exit(2);
}

let failed = false;
for (const file of files) {
  const path = resolve(file);
  const report = await validator.validateBytes(new Uint8Array(readFileSync(path)), {
    uri: basename(path),
    maxIssues: 0,
    writeTimestamp: false,
    externalResourceFunction: (uri) =>
      Promise.resolve(new Uint8Array(readFileSync(join(dirname(path), decodeURIComponent(uri))))),
  });
  const i = report.issues;
  console.log(
    `${file}: errors ${i.numErrors}, warnings ${i.numWarnings}, infos ${i.numInfos}, hints ${i.numHints}`,
  );
  for (const m of i.messages) {
    const severity = ["error", "warning", "info", "hint"][m.severity] ?? m.severity;
    console.log(`  ${severity} ${m.code} at ${m.pointer ?? ""}: ${m.message}`);
  }
  if (i.numErrors > 0 || i.numWarnings > 0 || i.numInfos > 0) {
    failed = true;
  }
}
console.log(`validator ${validator.version()}: ${failed ? "FAILED" : "ok"}`);
process.exit(failed ? 1 : 0);
