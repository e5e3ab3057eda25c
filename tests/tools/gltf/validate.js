#!/usr/bin/env node
// Validates one .glb or .gltf with the Khronos glTF validator (the pinned npm package in this
// folder, installed by scripts/setup.sh with `npm ci`). External resources (the .bin of a .gltf)
// are read from the file's own folder; a missing one is reported by the validator as an error.
//
//   node validate.js FILE          prints a summary line per severity, every issue, then the report
//                                  as JSON; exit 0 when there are no errors and no warnings,
//                                  1 when there are, 2 when the file could not be validated at all.
"use strict";
const fs = require("fs");
const path = require("path");
const validator = require("gltf-validator");

const file = process.argv[2];
if (!file) {
  console.error("usage: node validate.js FILE.glb|FILE.gltf");
  process.exit(2);
}
const full = path.resolve(file);
let bytes;
try {
  bytes = fs.readFileSync(full);
} catch (e) {
  console.error(`validate.js: cannot read ${full}: ${e.message}`);
  process.exit(2);
}

const loaded = [];
validator
  .validateBytes(new Uint8Array(bytes), {
    uri: path.basename(full),
    maxIssues: 0,
    writeTimestamp: false,
    externalResourceFunction: (uri) =>
      new Promise((resolve, reject) => {
        const p = path.resolve(path.dirname(full), decodeURIComponent(uri));
        fs.readFile(p, (err, data) => {
          if (err) {
            reject(err.toString());
            return;
          }
          loaded.push(path.basename(p));
          resolve(new Uint8Array(data));
        });
      }),
  })
  .then(
    (report) => {
      const i = report.issues;
      console.log(`validator ${report.validatorVersion}: ${report.uri} (${report.mimeType})`);
      console.log(`errors ${i.numErrors} warnings ${i.numWarnings} infos ${i.numInfos} hints ${i.numHints}`);
      if (loaded.length) console.log(`external resources: ${loaded.join(", ")}`);
      const names = ["error", "warning", "info", "hint"];
      for (const m of i.messages) {
        console.log(`${names[m.severity] || m.severity}: ${m.code} ${m.pointer || ""} ${m.message}`);
      }
      console.log(JSON.stringify(report, null, 2));
      process.exit(i.numErrors === 0 && i.numWarnings === 0 ? 0 : 1);
    },
    (err) => {
      console.error(`validate.js: ${full} could not be validated: ${err}`);
      process.exit(2);
    }
  );
