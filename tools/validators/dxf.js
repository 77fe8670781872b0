#!/usr/bin/env node
// Read DXF files with dxf-parser (a second DXF reader, independent of ezdxf).
//
//   node dxf.js FILE.dxf [...]
//
// Prints a JSON array, one verdict per file: {file, errors, warnings, messages, units
// ($INSUNITS), header: {extmin, extmax} ($EXTMIN / $EXTMAX), entities: {"LAYER/TYPE": count},
// geometry: {min, max} (bounding box of every LWPOLYLINE vertex and LINE end point),
// text: {min, max} (TEXT insertion points), closed: {"LAYER": closed polylines}}.
// Errors: $EXTMIN / $EXTMAX missing or left at the +-1e20 placeholders, or not containing the
// geometry; no entities. Exit status 0 when every file was read, 1 otherwise.
"use strict";
const fs = require("fs");
const DxfParser = require("dxf-parser");

function box() {
  return { min: [Infinity, Infinity], max: [-Infinity, -Infinity] };
}

function grow(b, p) {
  b.min = [Math.min(b.min[0], p.x), Math.min(b.min[1], p.y)];
  b.max = [Math.max(b.max[0], p.x), Math.max(b.max[1], p.y)];
}

function finite(b) {
  return Number.isFinite(b.min[0]) ? b : null;
}

function check(file) {
  const messages = [];
  const say = (severity, message) => messages.push({ severity, message });
  const dxf = new DxfParser().parseSync(fs.readFileSync(file, "utf8"));
  const entities = {};
  const closed = {};
  const geometry = box();
  const text = box();
  for (const e of dxf.entities) {
    const key = `${e.layer}/${e.type}`;
    entities[key] = (entities[key] || 0) + 1;
    if (e.type === "LWPOLYLINE" || e.type === "POLYLINE" || e.type === "LINE") {
      for (const v of e.vertices) grow(geometry, v);
      if (e.shape) closed[e.layer] = (closed[e.layer] || 0) + 1;
    } else if (e.type === "TEXT" || e.type === "MTEXT") {
      grow(text, e.startPoint || e.position);
    } else {
      say("warning", `entity ${e.type} on ${e.layer} is not measured`);
    }
  }
  if (!dxf.entities.length) say("error", "no entities");
  const h = dxf.header || {};
  const extmin = h.$EXTMIN ? [h.$EXTMIN.x, h.$EXTMIN.y, h.$EXTMIN.z] : null;
  const extmax = h.$EXTMAX ? [h.$EXTMAX.x, h.$EXTMAX.y, h.$EXTMAX.z] : null;
  if (!extmin || !extmax) {
    say("error", "$EXTMIN / $EXTMAX missing");
  } else if ([...extmin, ...extmax].some((v) => !Number.isFinite(v) || Math.abs(v) >= 1e20)) {
    say("error", `$EXTMIN / $EXTMAX left at placeholders: ${extmin} / ${extmax}`);
  } else {
    for (const b of [geometry, text]) {
      if (!finite(b)) continue;
      const eps = 1e-9 * (1 + Math.max(...b.max.map(Math.abs), ...b.min.map(Math.abs)));
      const inside =
        extmin[0] <= b.min[0] + eps && extmin[1] <= b.min[1] + eps &&
        extmax[0] >= b.max[0] - eps && extmax[1] >= b.max[1] - eps;
      if (!inside) say("error", `$EXTMIN / $EXTMAX ${extmin} / ${extmax} do not contain ${JSON.stringify(b)}`);
    }
  }
  if (h.$INSUNITS === undefined) say("warning", "$INSUNITS missing");
  return {
    file,
    errors: messages.filter((m) => m.severity === "error").length,
    warnings: messages.filter((m) => m.severity === "warning").length,
    messages,
    units: h.$INSUNITS === undefined ? null : h.$INSUNITS,
    header: { extmin, extmax },
    entities,
    closed,
    geometry: finite(geometry),
    text: finite(text),
  };
}

function main(files) {
  const out = [];
  let status = 0;
  for (const file of files) {
    try {
      out.push(check(file));
    } catch (err) {
      status = 1;
      out.push({ file, errors: 1, warnings: 0, messages: [{ severity: "error", message: String(err) }] });
    }
  }
  process.stdout.write(JSON.stringify(out) + "\n");
  process.exitCode = status;
}

main(process.argv.slice(2));
