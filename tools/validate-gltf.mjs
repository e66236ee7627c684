#!/usr/bin/env node
// Runs the Khronos glTF validator on each .glb/.gltf given and prints a JSON summary per file
// (one JSON object per line). Exit code: 0 if no file has errors, 1 if any has, 2 for bad usage
// or a file that cannot be read. Set-up: `cd tools && npm ci` (or scripts/install-deps.sh).
//
//   node tools/validate-gltf.mjs avatar.glb [more.glb ...] [--full]
//
// --full prints the validator's complete report instead of the summary.
import { readFile } from 'node:fs/promises';
import { basename } from 'node:path';
import { createRequire } from 'node:module';

const require = createRequire(import.meta.url);
let validator;
try {
  validator = require('gltf-validator');
} catch {
  console.error('validate-gltf: the gltf-validator package is missing; run `cd tools && npm ci` ' +
                '(or scripts/install-deps.sh)');
  process.exit(2);
}

const args = process.argv.slice(2);
const full = args.includes('--full');
const files = args.filter((a) => a !== '--full');
if (files.length === 0) {
  console.error('usage: node validate-gltf.mjs FILE.glb [FILE.glb ...] [--full]');
  process.exit(2);
}

let failed = false;
for (const file of files) {
  let bytes;
  try {
    bytes = await readFile(file);
  } catch (e) {
    console.error(`validate-gltf: cannot read ${file}: ${e.message}`);
    process.exit(2);
  }
  let report;
  try {
    report = await validator.validateBytes(new Uint8Array(bytes), {
      uri: basename(file),
      maxIssues: 0,
      writeTimestamp: false,
    });
  } catch (e) {
    // The validator rejects only when it cannot even tell the format: count it as an error.
    console.log(JSON.stringify({ file, fatal: String(e), numErrors: 1 }));
    failed = true;
    continue;
  }
  const { issues, info } = report;
  if (issues.numErrors > 0) failed = true;
  if (full) {
    console.log(JSON.stringify({ file, ...report }, null, 2));
    continue;
  }
  console.log(JSON.stringify({
    file,
    validatorVersion: report.validatorVersion,
    numErrors: issues.numErrors,
    numWarnings: issues.numWarnings,
    numInfos: issues.numInfos,
    numHints: issues.numHints,
    // Every issue above the hint level, so a failure says why without --full.
    messages: issues.messages
      .filter((m) => m.severity <= 2)
      .map((m) => ({ code: m.code, severity: m.severity, pointer: m.pointer, message: m.message })),
    info: info && {
      generator: info.generator,
      drawCallCount: info.drawCallCount,
      totalVertexCount: info.totalVertexCount,
      totalTriangleCount: info.totalTriangleCount,
      maxAttributes: info.maxAttributes,
      maxInfluences: info.maxInfluences,
      hasSkins: info.hasSkins,
      materialCount: info.materialCount,
    },
  }));
}
process.exit(failed ? 1 : 0);
