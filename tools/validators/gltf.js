#!/usr/bin/env node
// Validate binary glTF files with the Khronos glTF-Validator (npm gltf-validator).
//
//   node gltf.js FILE.glb [...]
//
// Prints one JSON verdict per file, as a JSON array: {file, errors, warnings, infos, hints,
// messages (the first 50 issues: code, severity, pointer, message), bounds (min / max of every
// mesh's POSITION accessor, from the file's JSON chunk), nodes, nodesWithTransform, meshes,
// vertices, triangles}. Exit status 0 when every file was read (whatever the issues), 1 if one
// could not be read at all.
"use strict";
const fs = require("fs");
const validator = require("gltf-validator");

const SEVERITY = ["error", "warning", "info", "hint"];

function glbJson(bytes) {
  // GLB: 12-byte header, then chunks (length, type); the first chunk is JSON ("JSON" = 0x4e4f534a)
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  if (view.getUint32(0, true) !== 0x46546c67) throw new Error("not a GLB file (magic)");
  const length = view.getUint32(12, true);
  if (view.getUint32(16, true) !== 0x4e4f534a) throw new Error("first GLB chunk is not JSON");
  return JSON.parse(new TextDecoder("utf-8").decode(bytes.subarray(20, 20 + length)));
}

function bounds(gltf) {
  let min = [Infinity, Infinity, Infinity];
  let max = [-Infinity, -Infinity, -Infinity];
  for (const mesh of gltf.meshes || []) {
    for (const prim of mesh.primitives || []) {
      const acc = gltf.accessors[prim.attributes.POSITION];
      if (!acc || !acc.min || !acc.max) continue;
      min = min.map((v, i) => Math.min(v, acc.min[i]));
      max = max.map((v, i) => Math.max(v, acc.max[i]));
    }
  }
  return { min, max };
}

async function check(file) {
  const bytes = new Uint8Array(fs.readFileSync(file));
  const report = await validator.validateBytes(bytes, { maxIssues: 1000 });
  const issues = report.issues;
  const gltf = glbJson(bytes);
  const transformed = (gltf.nodes || []).filter(
    (n) => n.matrix || n.rotation || n.translation || n.scale
  ).length;
  return {
    file,
    validator: report.validatorVersion,
    errors: issues.numErrors,
    warnings: issues.numWarnings,
    infos: issues.numInfos,
    hints: issues.numHints,
    messages: issues.messages.slice(0, 50).map((m) => ({
      code: m.code,
      severity: SEVERITY[m.severity] || String(m.severity),
      pointer: m.pointer,
      message: m.message,
    })),
    bounds: bounds(gltf),
    nodes: (gltf.nodes || []).length,
    nodesWithTransform: transformed,
    meshes: (gltf.meshes || []).length,
    vertices: report.info ? report.info.totalVertexCount : null,
    triangles: report.info ? report.info.totalTriangleCount : null,
  };
}

async function main(files) {
  const out = [];
  let status = 0;
  for (const file of files) {
    try {
      out.push(await check(file));
    } catch (err) {
      status = 1;
      out.push({ file, errors: 1, warnings: 0, messages: [{ code: "READ", message: String(err) }] });
    }
  }
  process.stdout.write(JSON.stringify(out) + "\n");
  process.exitCode = status;
}

main(process.argv.slice(2));
