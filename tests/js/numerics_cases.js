// Runs the page's numerics (src/resonant/views/explore_assets/numerics.js) outside the
// browser: reads golden cases as JSON on stdin, prints what the page computes for each as
// JSON on stdout.  The module is loaded with require (no eval, no new Function).
"use strict";
const path = require("path");
const N = require(path.join(__dirname, "..", "..", "src", "resonant", "views",
                            "explore_assets", "numerics.js"));

function read() {
  return new Promise(resolve => {
    let text = "";
    process.stdin.setEncoding("utf8");
    process.stdin.on("data", chunk => { text += chunk; });
    process.stdin.on("end", () => resolve(JSON.parse(text)));
  });
}

function run(c) {
  const n = c.n;
  const m = Float64Array.from(c.M), k = Float64Array.from(c.K), d = Float64Array.from(c.C);
  const eig = N.undampedEigen(n, m, k);
  const values = Array.from(eig.values);
  const frequencies = N.frequenciesFromEigenvalues(values);
  const shapes = [];
  for (let col = 0; col < values.length; col++) shapes.push(N.unitShape(n, eig.vectors, col));
  const state = N.stateEigenvalues(n, m, d, k);
  const out = { name: c.name, lambdas: values, frequencies, shapes };
  if (state !== null) {
    out.state = { re: Array.from(state.re), im: Array.from(state.im) };
    out.stability = N.classify(state);
    const ratios = N.dampingRatios(state);
    out.damping_ratios = ratios.ratios;
    out.damped_frequencies = ratios.damped;
  }
  return out;
}

read().then(cases => { process.stdout.write(JSON.stringify(cases.map(run))); });
