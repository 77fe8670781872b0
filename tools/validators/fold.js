#!/usr/bin/env node
// Check FOLD files with the FOLD reference library (npm fold, E. Demaine) and Rabbit Ear.
//
//   node fold.js [--tolerance DEG] FILE.fold [...]
//
// For every frame (the key frame and each of file_frames, which must not inherit):
// * Rabbit Ear's graph validation (duplicate / circular edges, isolated vertices, references)
//   and its vertex / edge / face counts;
// * edges_faces recomputed by the fold library (convert.edges_vertices_to_edges_faces_edges)
//   from edges_vertices and faces_vertices, compared with the file's (a boundary edge's missing
//   face is null; FOLD 1.2 or later only);
// * 3D frames: every edge's fold angle recomputed from vertices_coords (face normals from
//   fold's geom.polygonNormal, the signed angle about the edge, valley positive, as the FOLD
//   spec) and compared with edges_foldAngle; the sign of every angle checked against
//   edges_assignment (M < 0, V > 0, B / F / U = 0). Where |angle| > 1 degree the valley /
//   mountain side is also checked by where the right face's centroid lies (above or below the
//   left face's plane).
// Prints a JSON array, one verdict per file: {file, spec, errors, warnings, messages, frames:
// [{title, dimension, vertices, edges, faces, assignments, maxFoldAngleDifference,
// maxFoldAngle}]}. Exit status 0 when every file was read, 1 otherwise.
"use strict";
const fs = require("fs");
const FOLD = require("fold");
const ear = require("rabbit-ear");

const g = FOLD.geom;

function frames(doc) {
  const key = {};
  for (const k of Object.keys(doc)) if (k !== "file_frames") key[k] = doc[k];
  return [key, ...(doc.file_frames || [])];
}

function checkFrame(frame, index, spec, tolerance, say) {
  const where = `frame ${index}`;
  const nv = frame.vertices_coords.length;
  const ne = frame.edges_vertices.length;
  const nf = frame.faces_vertices.length;
  if (frame.frame_inherit) say("warning", `${where}: frame_inherit is not checked`);
  for (const key of ["edges_assignment", "edges_foldAngle", "edges_faces"]) {
    if (frame[key] && frame[key].length !== ne) {
      say("error", `${where}: ${key} has ${frame[key].length} entries for ${ne} edges`);
    }
  }
  // Rabbit Ear: the graph's own consistency
  const graph = {
    vertices_coords: frame.vertices_coords,
    edges_vertices: frame.edges_vertices,
    faces_vertices: frame.faces_vertices,
  };
  const valid = ear.graph.validate(graph, 1e-12);
  if (valid.summary !== "valid") {
    say("error", `${where}: rabbit-ear validate: ${JSON.stringify(valid)}`.slice(0, 2000));
  }
  const counts = {
    vertices: ear.graph.count.vertices(graph),
    edges: ear.graph.count.edges(graph),
    faces: ear.graph.count.faces(graph),
  };
  // the fold library: edges_faces from edges_vertices and faces_vertices
  const copy = {
    edges_vertices: frame.edges_vertices.map((e) => e.slice()),
    faces_vertices: frame.faces_vertices.map((f) => f.slice()),
    faces_edges: [],
  };
  FOLD.convert.edges_vertices_to_edges_faces_edges(copy);
  const hasNull = (frame.edges_faces || []).some((ef) => ef.includes(null));
  if (hasNull && !(spec >= 1.2)) {
    say("error", `${where}: edges_faces has null entries, which need file_spec >= 1.2 (${spec})`);
  }
  let mismatch = 0;
  (frame.edges_faces || []).forEach((ef, e) => {
    const want = copy.edges_faces[e];
    const got = [ef[0] === undefined ? null : ef[0], ef.length > 1 ? ef[1] : null];
    if (got[0] !== want[0] || got[1] !== want[1]) mismatch += 1;
  });
  if (mismatch) say("error", `${where}: ${mismatch} edges_faces differ from fold's (left, right)`);

  const assignments = {};
  for (const a of frame.edges_assignment || []) assignments[a] = (assignments[a] || 0) + 1;
  const angles = frame.edges_foldAngle || [];
  let wrongSign = 0;
  angles.forEach((angle, e) => {
    const a = (frame.edges_assignment || [])[e];
    const bad =
      !Number.isFinite(angle) ||
      Math.abs(angle) > 180 ||
      (a === "M" && !(angle < 0)) ||
      (a === "V" && !(angle > 0)) ||
      (["B", "F", "U"].includes(a) && angle !== 0);
    if (bad && wrongSign === 0) say("error", `${where}: edge ${e} is ${a} with edges_foldAngle ${angle}`);
    if (bad) wrongSign += 1;
  });
  if (wrongSign > 1) say("error", `${where}: ${wrongSign} edges_foldAngle disagree with edges_assignment`);

  const dim = frame.vertices_coords[0] ? frame.vertices_coords[0].length : 0;
  let maxDiff = 0;
  let maxAngle = 0;
  let sideMismatch = 0;
  if (dim === 3) {
    const x = frame.vertices_coords;
    const normals = frame.faces_vertices.map((f) => g.polygonNormal(f.map((v) => x[v])));
    const centroids = frame.faces_vertices.map((f) =>
      g.mul(f.map((v) => x[v]).reduce(g.plus), 1 / f.length)
    );
    copy.edges_faces.forEach(([left, right], e) => {
      let angle = 0;
      if (left !== null && right !== null && left !== undefined && right !== undefined) {
        const [u, v] = frame.edges_vertices[e];
        const along = g.unit(g.sub(x[v], x[u]));
        const nl = normals[left];
        const nr = normals[right];
        const c = g.cross(nl, nr);
        angle = (Math.atan2(-g.dot(c, along), g.dot(nl, nr)) * 180) / Math.PI;
        if (Math.abs(angle) > 1) {
          const above = g.dot(nl, g.sub(centroids[right], x[u])) > 0; // valley: R above L
          if (above !== angle > 0) sideMismatch += 1;
        }
      }
      const written = angles[e] === undefined ? 0 : angles[e];
      const a = (frame.edges_assignment || [])[e];
      const diff = Math.abs(written - angle);
      // written 0 for coplanar faces ("F") and +-180 for faces folded onto each other
      const folded180 = Math.abs(Math.abs(written) - 180) < 1e-9 && Math.abs(Math.abs(angle) - 180) < 1e-6;
      if (!folded180 && !(a === "F" && Math.abs(angle) < 1e-6)) maxDiff = Math.max(maxDiff, diff);
      maxAngle = Math.max(maxAngle, Math.abs(written));
    });
    if (maxDiff > tolerance) {
      say("error", `${where}: edges_foldAngle differs from the coordinates by up to ${maxDiff} deg`);
    }
    if (sideMismatch) say("error", `${where}: ${sideMismatch} edges fold to the other side`);
  }
  return {
    title: frame.frame_title || null,
    classes: frame.frame_classes || [],
    dimension: dim,
    vertices: counts.vertices,
    edges: counts.edges,
    faces: counts.faces,
    arrays: { vertices: nv, edges: ne, faces: nf },
    assignments,
    maxFoldAngleDifference: maxDiff,
    maxFoldAngle: maxAngle,
  };
}

function check(file, tolerance) {
  const messages = [];
  const say = (severity, message) => messages.push({ severity, message });
  const doc = JSON.parse(fs.readFileSync(file, "utf8"));
  const spec = doc.file_spec;
  if (typeof spec !== "number") say("error", "file_spec is missing or not a number");
  else if (spec > 1.2) say("warning", `file_spec ${spec} is newer than the checker (1.2)`);
  const out = frames(doc).map((frame, i) => checkFrame(frame, i, spec, tolerance, say));
  return {
    file,
    spec,
    errors: messages.filter((m) => m.severity === "error").length,
    warnings: messages.filter((m) => m.severity === "warning").length,
    messages,
    frames: out,
  };
}

function main(argv) {
  let tolerance = 1e-6;
  const files = [];
  for (let i = 0; i < argv.length; i += 1) {
    if (argv[i] === "--tolerance") tolerance = Number(argv[++i]);
    else files.push(argv[i]);
  }
  const out = [];
  let status = 0;
  for (const file of files) {
    try {
      out.push(check(file, tolerance));
    } catch (err) {
      status = 1;
      out.push({ file, errors: 1, warnings: 0, messages: [{ severity: "error", message: String(err) }] });
    }
  }
  process.stdout.write(JSON.stringify(out) + "\n");
  process.exitCode = status;
}

main(process.argv.slice(2));
