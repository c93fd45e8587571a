#!/usr/bin/env node
// Converts a mesh package from npm that exports `{ positions, cells }` (CommonJS), such as
// `bunny` or `teapot`, into a Wavefront OBJ file with `v` and 1-based `f` lines.
//
// Usage:
//   npm install --prefix /tmp/npm-meshes --no-save bunny@1.0.1 teapot@1.0.0
//   node scenes/tools/npm_to_obj.mjs /tmp/npm-meshes bunny  scenes/bunny.obj
//   node scenes/tools/npm_to_obj.mjs /tmp/npm-meshes teapot scenes/teapot.obj
//
// The first argument is the folder given to `npm install --prefix` (the one holding
// `node_modules`). The output is deterministic: coordinates are written exactly as the package
// has them, so running the conversion again gives the same file byte for byte.
//
// Checks: every position must be three finite numbers and every cell a list of valid integer
// indices. Cells with more than three corners are split into triangle fans; cells with fewer
// than three distinct corners are dropped (and counted in the header); the script fails if
// anything else is wrong.

import { createRequire } from "node:module";
import { writeFileSync } from "node:fs";
import { join, resolve } from "node:path";

function fail(message) {
  console.error(`npm_to_obj: ${message}`);
  process.exit(1);
}

const [prefix, name, output] = process.argv.slice(2);
if (!prefix || !name || !output) {
  fail("usage: node npm_to_obj.mjs <npm-prefix-folder> <package-name> <output.obj>");
}

const require = createRequire(join(resolve(prefix), "package.json"));
let mesh, pkg;
try {
  mesh = require(name);
  pkg = require(`${name}/package.json`);
} catch (e) {
  fail(`cannot load package "${name}" from ${prefix}/node_modules: ${e.message}`);
}
const { positions, cells } = mesh;
if (!Array.isArray(positions) || !Array.isArray(cells)) {
  fail(`package "${name}" does not export { positions, cells } arrays`);
}

positions.forEach((p, i) => {
  if (!Array.isArray(p) || p.length !== 3 || !p.every((x) => typeof x === "number" && Number.isFinite(x))) {
    fail(`position ${i} is not three finite numbers: ${JSON.stringify(p)}`);
  }
});

const triangles = [];
let dropped = 0;
let fanned = 0;
cells.forEach((cell, i) => {
  if (!Array.isArray(cell) || !cell.every((k) => Number.isInteger(k) && k >= 0 && k < positions.length)) {
    fail(`cell ${i} has an invalid index: ${JSON.stringify(cell)}`);
  }
  if (new Set(cell).size < 3) {
    dropped += 1;
    return;
  }
  if (cell.length > 3) fanned += 1;
  for (let k = 1; k + 1 < cell.length; k++) triangles.push([cell[0], cell[k], cell[k + 1]]);
});
if (triangles.length === 0) fail(`package "${name}" has no triangles`);

const lo = [Infinity, Infinity, Infinity];
const hi = [-Infinity, -Infinity, -Infinity];
for (const p of positions) {
  for (let k = 0; k < 3; k++) {
    lo[k] = Math.min(lo[k], p[k]);
    hi[k] = Math.max(hi[k], p[k]);
  }
}

const lines = [
  `# ${pkg.description ?? name}`,
  `# Converted from the npm package ${pkg.name}@${pkg.version} (licence: ${pkg.license ?? "not stated"})`,
  `# by scenes/tools/npm_to_obj.mjs; see scenes/README.md.`,
  `# Package repository: ${pkg.repository?.url ?? pkg.repository ?? "not stated"}; author: ${pkg.author ?? "not stated"}`,
  `# ${positions.length} vertices, ${triangles.length} triangles` +
    (fanned ? `, ${fanned} polygons split into fans` : "") +
    (dropped ? `, ${dropped} degenerate cells dropped` : ""),
  `# bounds: min [${lo.join(", ")}], max [${hi.join(", ")}]`,
  `o ${name}`,
];
for (const p of positions) lines.push(`v ${p[0]} ${p[1]} ${p[2]}`);
for (const t of triangles) lines.push(`f ${t[0] + 1} ${t[1] + 1} ${t[2] + 1}`);
writeFileSync(output, lines.join("\n") + "\n");
console.log(`${output}: ${positions.length} vertices, ${triangles.length} triangles from ${pkg.name}@${pkg.version}`);
