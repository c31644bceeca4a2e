// resonant explore: the page.  Reads the model's data (JSON) and, for a live page, the
// functions printed from its equations (resonantParameters, resonantMatrices, resonantLoads, resonantMotion,
// resonantSignals); computes with ResonantNumerics; every text of the model is shown as text.
"use strict";
(() => {
  const NUM = ResonantNumerics;
  const D = JSON.parse(document.getElementById("resonant-data").textContent);
  const LIVE = D.live;
  const LAYOUT = D.layout;
  const COORDS = D.coordinates, OUTPUTS = D.outputs;
  const n = COORDS.length;
  const NAMES = [...COORDS, ...OUTPUTS];
  const UNIT = Object.fromEntries(NAMES.map(x => [x.name, x]));
  const PARAMS = D.parameters;
  const FREQ = PARAMS.findIndex(c => c.frequency);
  const CURVE_POINTS = 400;
  // twelve distinguishable colours (Okabe and Ito's eight first); past them, dashes
  const COLOURS = ["#0072b2", "#d55e00", "#009e73", "#cc79a7", "#e69f00", "#56b4e9", "#1d1d1f", "#8c564b",
    "#7a3fb0", "#9e9a00", "#b2182b", "#6b7f9e"];
  const DASHES = [[], [6, 3], [2, 2], [8, 2, 2, 2]];
  const NOW = "#1d1d1f";  // the current value (response) and the current instant (history)
  // the frequency response's axes and curve styles: the chart description resonant's plots
  // draw (resonant.views.charts, Chart.to_dict), one curve per name in the order of NAMES
  const CHART = D.response_chart;
  const STYLE = new Map(CHART ? NAMES.map((x, i) => [x.name, CHART.curves[i]]).filter(e => e[1]) : []);

  const $ = id => document.getElementById(id);
  function el(tag, attrs, text) {
    const e = document.createElement(tag);
    for (const [k, v] of Object.entries(attrs || {})) {
      if (v !== undefined && v !== null) e.setAttribute(k, v);
    }
    if (text !== undefined) e.textContent = text;
    return e;
  }
  function fmt(x, digits) {
    if (x === null || x === undefined || Number.isNaN(x)) return "–";
    if (!Number.isFinite(x)) return x > 0 ? "∞" : "−∞";
    if (x === 0) return "0";
    const a = Math.abs(x);
    const d = digits || 6;
    let s = (a >= 1e-4 && a < 1e7) ? Number(x.toPrecision(d)).toString() : x.toExponential(d - 1);
    return s.replace("-", "−");
  }
  // a number shown as text: its full value in data-value and the tooltip
  function number(x, digits, key) {
    const e = el("span", { "data-value": String(x), title: String(x) }, fmt(x, digits));
    if (key) e.setAttribute("data-key", key);
    return e;
  }

  // LaTeX of a name (x_{1}, \varphi, \mathrm{stroke}) as [base, subscript] in Unicode.  The
  // names come typeset from resonant (resonant.expressions.notation.name_latex: ks is
  // already k_{s}); this only reads LaTeX, it has no naming rule of its own
  const GREEK = { alpha: "α", beta: "β", gamma: "γ", delta: "δ", epsilon: "ε", varepsilon: "ε", zeta: "ζ", eta: "η", theta: "θ", vartheta: "ϑ", iota: "ι", kappa: "κ", lambda: "λ", mu: "μ", nu: "ν", xi: "ξ", pi: "π", rho: "ρ", sigma: "σ", tau: "τ", upsilon: "υ", phi: "ϕ", varphi: "φ", chi: "χ", psi: "ψ", omega: "ω", Gamma: "Γ", Delta: "Δ", Theta: "Θ", Lambda: "Λ", Xi: "Ξ", Pi: "Π", Sigma: "Σ", Phi: "Φ", Psi: "Ψ", Omega: "Ω" };
  function latexText(text) {
    const t = text.replace(/\\mathrm\{([^{}]*)\}/g, "$1").replace(/\\([A-Za-z]+)/g, (m, g) => GREEK[g] || g);
    const m = t.match(/^(.*?)_\{([^{}]*)\}(.*)$/);
    return m ? [m[1], m[2], m[3]] : [t, "", ""];
  }

  const SUB = { 0: "₀", 1: "₁", 2: "₂", 3: "₃", 4: "₄", 5: "₅", 6: "₆", 7: "₇", 8: "₈", 9: "₉", a: "ₐ", e: "ₑ", o: "ₒ", x: "ₓ", h: "ₕ", k: "ₖ", l: "ₗ", m: "ₘ", n: "ₙ", p: "ₚ", s: "ₛ", t: "ₜ", i: "ᵢ", j: "ⱼ", r: "ᵣ", u: "ᵤ", v: "ᵥ" };
  const SUP = { 0: "⁰", 1: "¹", 2: "²", 3: "³", 4: "⁴", 5: "⁵", 6: "⁶", 7: "⁷", 8: "⁸", 9: "⁹", "-": "⁻" };
  // a name as one line of text (canvas): ω, x₁, F₀ (a subscript without Unicode form: x_ab)
  function symbolText(x) {
    const [base, sub, rest] = latexText((x && x.symbol) || (x && x.name) || "");
    if (!sub) return base + rest;
    const all = [...sub].every(ch => SUB[ch]);
    return base + (all ? [...sub].map(ch => SUB[ch]).join("") : `_${sub}`) + rest;
  }
  // a name as HTML: italic base, subscript
  function symbolNode(x) {
    const [base, sub, rest] = latexText((x && x.symbol) || (x && x.name) || "");
    const e = el("span", { class: "sym" });
    e.append(el("i", {}, base));
    if (sub) e.append(el("sub", {}, sub));
    if (rest) e.append(document.createTextNode(rest));
    return e;
  }
  // a unit as printed: m/s², N·s/m, kg·m²
  function unitText(u) {
    return (u || "").replace(/\^\(?(-?\d+)\)?/g, (m, d) => [...d].map(ch => SUP[ch]).join("")).replace(/\*/g, "·");
  }
  function powerText(e) { return "10" + [...String(e)].map(ch => SUP[ch] || ch).join(""); }

  // -- the model's numbers ------------------------------------------------------------------
  function parameters(v, o) {
    return LIVE ? resonantParameters(v, o) : Float64Array.from(v);
  }

  function isClose(a, b) { return Math.abs(a - b) <= 1e-12 * Math.max(Math.abs(a), Math.abs(b)); }

  // M, C, K at p (checked finite)
  function matricesAt(p) {
    const f = resonantMatrices(p);
    const M = Float64Array.from(f.slice(0, n * n)), C = Float64Array.from(f.slice(n * n, 2 * n * n));
    const K = Float64Array.from(f.slice(2 * n * n));
    for (const a of [M, C, K]) {
      if (!a.every(Number.isFinite)) throw new Error("M, C or K is not finite for these parameter values");
    }
    return { M, C, K };
  }

  // M, C, K (given, or computed), the harmonics (grouped by frequency, ascending) and the
  // outputs at p
  function systemAt(p, matrices) {
    const { M, C, K } = matrices || matricesAt(p);
    const f = resonantLoads(p);
    let k = 0;
    const take = m => { const a = Float64Array.from(f.slice(k, k + m)); k += m; return a; };
    const V = LAYOUT.variables.length;
    const raw = [];
    for (let j = 0; j < LAYOUT.frequencies; j++) {
      const w = f[k++], FS = take(n), FC = take(n), sig = take(2 * V);
      const sign = w < 0 ? -1 : 1, still = w === 0;
      for (let i = 0; i < n; i++) FS[i] = still ? 0 : sign * FS[i];
      for (let v = 0; v < V; v++) sig[2 * v] = still ? 0 : sign * sig[2 * v];
      raw.push({ omega: Math.abs(w), FS, FC, sig });
    }
    const outputs = LAYOUT.outputs.map(o => ({ value: f[k++], coefs: o.terms.map(() => f[k++]) }));
    const groups = [];
    for (const h of raw) {
      const g = groups.find(x => isClose(x.omega, h.omega));
      if (g) {
        for (let i = 0; i < n; i++) { g.FS[i] += h.FS[i]; g.FC[i] += h.FC[i]; }
        for (let v = 0; v < 2 * V; v++) g.sig[v] += h.sig[v];
      } else groups.push(h);
    }
    groups.sort((a, b) => a.omega - b.omega);
    return { M, C, K, harmonics: groups, outputs };
  }

  // the stationary response (L, N) of every harmonic, and the pairs of every name
  function respond(sys, names) {
    const pairs = {};
    const responses = sys.harmonics.map(h => {
      const w = h.omega;
      const ar = new Float64Array(n * n), ai = new Float64Array(n * n);
      for (let i = 0; i < n * n; i++) { ar[i] = sys.K[i] - w * w * sys.M[i]; ai[i] = w * sys.C[i]; }
      const z = NUM.complexSolve(n, ar, ai, h.FC, h.FS.map(x => -x));
      return { omega: w, L: z.re, N: z.im.map(x => -x), singular: z.singular };
    });
    COORDS.forEach((c, i) => { if (!names || names.has(c.name)) pairs[c.name] = responses.map(r => [r.L[i], r.N[i]]); });
    LAYOUT.outputs.forEach((o, j) => {
      if (names && !names.has(o.name)) return;
      pairs[o.name] = responses.map((r, hi) => {
        let L = 0, N = 0;
        const w = r.omega, h = sys.harmonics[hi];
        o.terms.forEach(([, order, qi, vi], t) => {
          let lt, nt;
          if (qi >= 0) {
            lt = r.L[qi]; nt = r.N[qi];
            for (let d = 0; d < order; d++) [lt, nt] = [w * nt, -w * lt];
          } else if (vi >= 0) {
            lt = h.sig[2 * vi + 1]; nt = h.sig[2 * vi];
          } else { lt = 0; nt = 0; }
          L += sys.outputs[j].coefs[t] * lt; N += sys.outputs[j].coefs[t] * nt;
        });
        return [L, N];
      });
    });
    return { responses, pairs };
  }

  function amplitudesOf(omegas, pairs, fast) {
    const amplitudes = {}, phases = {};
    const moving = omegas.map((w, i) => (w > 0 ? i : -1)).filter(i => i >= 0);
    for (const [name, p] of Object.entries(pairs)) {
      amplitudes[name] = NUM.peak(omegas, p, fast);
      if (moving.length === 1) {
        const [L, N] = p[moving[0]];
        if (Math.hypot(L, N) > 0) phases[name] = NUM.phaseAngle(L, N);
      }
    }
    return { amplitudes, phases };
  }

  // a number as Python's {:.4g}
  function g4(x) {
    const a = Math.abs(x);
    if (x !== 0 && (a < 1e-4 || a >= 1e4)) return x.toExponential(3).replace(/\.?0+e/, "e").replace(/e([+-])(\d)$/, "e$10$2");
    return String(Number(x.toPrecision(4)));
  }

  // the mass matrix's diagnosis, in the words of resonant solve
  function massWarning(M) {
    if (!n || !NUM.isSymmetric(n, M)) return null;
    const ev = Array.from(NUM.jacobi(n, M).values).sort((a, b) => a - b);
    if (ev[0] >= 0) return null;
    const kind = ev[n - 1] < 0 ? "negative definite" : "indefinite (not positive definite)";
    return `the mass matrix M is ${kind} (eigenvalues from ${g4(ev[0])} to ${g4(ev[n - 1])}): a negative mass or inertia, so the kinetic energy is not positive; the natural frequencies and the results are not physical (check the signs in T or M)`;
  }

  // the warnings of resonant solve, in its order and words
  function warningsOf(lam, stability, omegas, harmonics, M) {
    const out = [];
    const mass = massWarning(M);
    if (mass) out.push(mass);
    let scale = 1;
    for (const v of lam) scale = Math.max(scale, Math.abs(v));
    if (lam.some(v => v < -1e-12 * scale)) {
      out.push(mass ? "omega^2 < 0 for some mode because M is not positive definite (see above), not necessarily because of K"
        : "K is not positive definite about this reference state: a statically unstable (buckling, inverted) mode exists");
    }
    if (stability === "unstable") out.push("the equilibrium is unstable: free vibrations grow, so the stationary solution is never reached in practice");
    for (const h of harmonics) {
      omegas.forEach((wn, i) => {
        if (h.omega > 0 && wn > 0 && Math.abs(h.omega - wn) <= 0.02 * wn) {
          out.push(`near resonance: the excitation frequency ${fmt(h.omega)} rad/s is within ${fmt(100 * Math.abs(h.omega - wn) / wn, 2)}% of natural frequency ${i + 1} (${fmt(wn)} rad/s); the amplitudes are sensitive to the data`);
        }
      });
    }
    return out;
  }

  // everything the page shows, computed at the parameters p
  function solveLive(p) {
    const sys = systemAt(p);
    if (NUM.realSolve(n, sys.M, new Float64Array(n), 1) === null) throw new Error("the mass matrix M is singular: every coordinate needs mass or inertia");
    const eig = NUM.undampedEigen(n, sys.M, sys.K);
    const omegas = NUM.frequenciesFromEigenvalues(eig.values);
    const modes = [];
    eig.values.forEach((lam, c) => { if (lam >= -1e-12 * Math.max(...eig.values.map(Math.abs), 1e-300)) modes.push(NUM.unitShape(n, eig.vectors, c)); });
    const state = NUM.stateEigenvalues(n, sys.M, sys.C, sys.K);
    const stability = NUM.classify(state);
    const damping = NUM.dampingRatios(state);
    const result = { p, M: sys.M, C: sys.C, K: sys.K, omegas, modes: modes.slice(0, omegas.length), eig: state, stability, damping, sys,
      harmonics: [], pairs: {}, amplitudes: {}, phases: {}, available: LAYOUT.harmonic, warnings: warningsOf(eig.values, stability, omegas, sys.harmonics, sys.M), error: null };
    if (!LAYOUT.harmonic) {
      result.warnings.push("the stationary solution needs signals that are sums of harmonics; the equation of motion is derived, use `resonant simulate` for other signals");
      return result;
    }
    const { responses, pairs } = respond(sys, null);
    const bad = responses.find(r => r.singular);
    if (bad) {
      result.error = bad.omega === 0 ? "a static load acts on a system with a zero-stiffness (rigid-body) mode: the static deflection is unbounded"
        : `resonance: the excitation frequency ${fmt(bad.omega)} rad/s and the system has no damping in that mode, so the stationary amplitude is unbounded`;
      return result;
    }
    result.harmonics = responses.map((r, i) => ({ omega: r.omega, F_S: Array.from(sys.harmonics[i].FS), F_C: Array.from(sys.harmonics[i].FC), L: Array.from(r.L), N: Array.from(r.N) }));
    result.pairs = pairs;
    Object.assign(result, amplitudesOf(responses.map(r => r.omega), pairs, false));
    return result;
  }

  // the response to the model's periodic load ([periodic]): per harmonic k of its series the
  // stationary response to the load's columns at k W (times the coefficient a_k - i b_k),
  // the mean from K z = a0 column, summed over one period (NUM.periodicHistory), as
  // resonant solve sums it; null without a periodic load
  const PER = D.periodic;
  function complexPower(w, p) {  // (i w)^p
    const m = Math.pow(w, p), a = p * Math.PI / 2;
    return [Math.abs(p % 2) === 1 ? 0 : m * Math.cos(a), Math.abs(p % 2) === 1 ? m * Math.sin(a) : 0];
  }
  function periodicLive(p, sys) {
    if (!PER || !PER.a || !LIVE) return null;
    const cols = resonantPeriodic(p), powers = LAYOUT.periodic_powers, H = PER.harmonics;
    const W = 2 * Math.PI / PER.period, name = PER.name, d = PER.derivative;
    const Z = {};
    NAMES.forEach(x => { Z[x.name] = { re: new Float64Array(H), im: new Float64Array(H), mean: 0 }; });
    const ar = new Float64Array(n * n), ai = new Float64Array(n * n);
    for (let k = 1; k <= H; k++) {
      const w = k * W, ca = PER.a[k - 1], cb = -PER.b[k - 1];
      if (ca === 0 && cb === 0) continue;
      for (let i = 0; i < n * n; i++) { ar[i] = sys.K[i] - w * w * sys.M[i]; ai[i] = w * sys.C[i]; }
      const br = new Float64Array(n), bi = new Float64Array(n);
      powers.forEach((pw, j) => {
        const [pr, pi] = complexPower(w, pw);
        for (let i = 0; i < n; i++) { br[i] += pr * cols[j * n + i]; bi[i] += pi * cols[j * n + i]; }
      });
      const z = NUM.complexSolve(n, ar, ai, br, bi);
      if (z.singular) throw new Error(`resonance: the periodic load's harmonic ${k} (${fmt(w)} rad/s) meets an undamped natural frequency, so its response is unbounded`);
      const put = (x, hr, hi) => { Z[x].re[k - 1] = hr * ca - hi * cb; Z[x].im[k - 1] = hr * cb + hi * ca; };
      COORDS.forEach((c, i) => put(c.name, z.re[i], z.im[i]));
      LAYOUT.outputs.forEach((o, j) => {
        let hr = 0, hi = 0;
        o.terms.forEach(([v, order, qi], t) => {
          const coef = sys.outputs[j].coefs[t];
          let tr = 0, ti = 0, pw = order;
          if (qi >= 0) { tr = z.re[qi]; ti = z.im[qi]; } else if (v === name) { tr = 1; pw = order - d; } else return;
          const [pr, pi] = complexPower(w, pw);
          hr += coef * (pr * tr - pi * ti); hi += coef * (pr * ti + pi * tr);
        });
        put(o.name, hr, hi);
      });
    }
    if (PER.a0 !== 0) {
      if (d > 0) throw new Error("the series of a derivative (a velocity or an acceleration) has a nonzero mean: the displacement would grow without bound");
      const rhs = new Float64Array(n);
      powers.forEach((pw, j) => { if (pw === 0) for (let i = 0; i < n; i++) rhs[i] += PER.a0 * cols[j * n + i]; });
      const z0 = NUM.realSolve(n, sys.K, rhs, 1);
      if (z0 === null) throw new Error("the periodic load has a mean, but the system has no static stiffness (a rigid-body mode): there is no stationary response");
      COORDS.forEach((c, i) => { Z[c.name].mean = z0[i]; });
      LAYOUT.outputs.forEach((o, j) => {
        let y = 0;
        o.terms.forEach(([v, order, qi], t) => {
          if (order !== 0) return;
          if (qi >= 0) y += sys.outputs[j].coefs[t] * z0[qi]; else if (v === name) y += sys.outputs[j].coefs[t] * PER.a0;
        });
        Z[o.name].mean = y;
      });
    }
    const history = {}, largest = {};
    for (const [x, zx] of Object.entries(Z)) {
      const h = NUM.periodicHistory(zx.re, zx.im, zx.mean);
      history[x] = h.values; largest[x] = h.largest;
    }
    return { period: PER.period, history, largest, load: loadHistory() };
  }

  // the load itself: its series summed (what the response answers)
  function loadHistory() {
    const h = NUM.periodicHistory(Float64Array.from(PER.a), Float64Array.from(PER.b, x => -x), PER.a0);
    return { values: h.values, largest: h.largest };
  }

  function periodicPrecomputed() {
    const pre = PER && PER.precomputed;
    if (!pre) return null;
    return { period: PER.period, history: pre.history, largest: pre.largest, time: pre.time,
      load: PER.a ? loadHistory() : null };
  }

  // the frequency response of the shown names over the frequency parameter's range
  function curveLive(v, o, shown) {
    if (FREQ < 0 || !LAYOUT.harmonic) return null;
    const c = PARAMS[FREQ];
    const values = [], curves = Object.fromEntries([...shown].map(s => [s, []]));
    const vv = Float64Array.from(v), oo = Uint8Array.from(o);
    oo[FREQ] = 1;
    // M, C, K stay as they are along the curve unless they depend on its parameter
    let fixed = null;
    if (!LAYOUT.matrix_parameters.includes(FREQ)) {
      try { fixed = matricesAt(parameters(vv, oo)); } catch (e) { fixed = null; }
    }
    for (let j = 0; j < CURVE_POINTS; j++) {
      const x = c.from + (c.to - c.from) * j / (CURVE_POINTS - 1);
      values.push(x);
      vv[FREQ] = x;
      let amps = null;
      try {
        const sys = systemAt(parameters(vv, oo), fixed);
        const { responses, pairs } = respond(sys, shown);
        if (!responses.some(r => r.singular)) amps = amplitudesOf(responses.map(r => r.omega), pairs, true).amplitudes;
      } catch (e) { amps = null; }
      for (const s of shown) curves[s].push(amps && Number.isFinite(amps[s]) ? amps[s] : NaN);
    }
    return { values, curves };
  }

  // -- a precomputed page -------------------------------------------------------------------
  const PRE = D.precomputed;
  function gridIndex(x) {
    const values = PRE.curve ? PRE.curve.values : [];
    let best = 0;
    values.forEach((v, j) => { if (Math.abs(v - x) < Math.abs(values[best] - x)) best = j; });
    return best;
  }
  function solvePrecomputed(v) {
    const s = PRE.solution, m = PRE.modes;
    const result = { p: Float64Array.from(v), M: s.M ? Float64Array.from(s.M.flat()) : null, C: s.C ? Float64Array.from(s.C.flat()) : null,
      K: s.K ? Float64Array.from(s.K.flat()) : null, omegas: m.natural_frequencies, modes: m.mode_shapes, stability: m.stability,
      damping: { ratios: m.damping_ratios, damped: [] }, eig: null, harmonics: s.harmonics, pairs: {}, amplitudes: { ...s.amplitudes },
      phases: { ...s.phases }, available: s.stationary_available, warnings: [...s.warnings], error: null };
    if (PRE.curve && FREQ >= 0) {
      const j = gridIndex(v[FREQ]);
      result.p[FREQ] = PRE.curve.values[j];
      result.amplitudes = {}; result.phases = {};
      const omegas = PRE.curve.omegas[j];
      for (const [name, c] of Object.entries(PRE.curve.names)) {
        result.pairs[name] = omegas.map((_, h) => [c.L[j][h], c.N[j][h]]);
        result.amplitudes[name] = c.amplitudes[j];
      }
      Object.assign(result.phases, amplitudesOf(omegas, result.pairs, false).phases);
      result.harmonics = omegas.map(w => ({ omega: w }));
    }
    return result;
  }
  function curvePrecomputed() {
    if (!PRE.curve) return null;
    return { values: PRE.curve.values, curves: Object.fromEntries(Object.entries(PRE.curve.names).map(([k, c]) => [k, c.amplitudes.map(a => (a === null ? NaN : a))])) };
  }

  // -- state ---------------------------------------------------------------------------------
  const S = {
    v: Float64Array.from(PARAMS.map(c => c.value)),
    o: new Uint8Array(PARAMS.length),
    shown: new Set(D.show),
    result: null, curve: null, plotted: null, mode: -1, playing: true, phase: 0, scale: 1, last: 0, timing: 0,
  };
  const P0 = Float64Array.from(PARAMS.map(c => c.value));

  function recompute() {
    const t0 = performance.now();
    try {
      if (LIVE) {
        S.result = solveLive(parameters(S.v, S.o));
        S.curve = curveLive(S.v, S.o, S.shown);
      } else {
        S.result = solvePrecomputed(S.v);
        S.curve = curvePrecomputed();
      }
      S.periodic = null;
      try {
        S.periodic = PER && PER.a && LIVE ? periodicLive(S.result.p, S.result.sys) : periodicPrecomputed();
      } catch (e) {
        S.periodic = { error: String(e.message || e) };
      }
      $("status").textContent = S.result.error || "";
    } catch (e) {
      S.result = null;
      $("status").textContent = String(e.message || e);
      if (!(e instanceof Error) || e.constructor !== Error) console.error(e);  // a bug, not the model
    }
    render();
    for (const listener of LISTENERS) listener();
    S.timing = performance.now() - t0;
  }
  // the panels of other scripts (rotor.js) that follow the sliders: called after each change
  const LISTENERS = [];

  // -- controls ------------------------------------------------------------------------------
  const controlsOf = [];
  function toSlider(c, x) {
    let t = c.log ? Math.log(x / c.from) / Math.log(c.to / c.from) : (x - c.from) / (c.to - c.from);
    // a value a log slider cannot show (0 or negative) sits at its lower end, not the middle
    if (Number.isNaN(t)) t = 0;
    return Math.round(1000 * Math.min(1, Math.max(0, t)));
  }
  // a typed value beyond the slider's range extends the range to it (a log slider that
  // must reach 0 or below becomes linear), so that the slider shows where the value is
  function extendRange(c, x) {
    const lo = Math.min(c.from, c.to), hi = Math.max(c.from, c.to);
    if (!(x < lo || x > hi)) return false;
    if (c.log && x <= 0) c.log = false;
    const up = c.from <= c.to;
    if ((x < lo) === up) c.from = x; else c.to = x;
    return true;
  }
  function fromSlider(c, pos) {
    const t = pos / 1000;
    const x = c.log ? c.from * Math.pow(c.to / c.from, t) : c.from + (c.to - c.from) * t;
    return x === 0 ? 0 : Number(x.toPrecision(4));
  }
  function shownValue(i) {
    const p = S.result ? S.result.p : S.v;
    return p[i];
  }

  function buildControls() {
    const box = $("sliders");
    const order = PARAMS.map((_, i) => i);
    if (FREQ >= 0) { order.splice(FREQ, 1); order.unshift(FREQ); }
    for (const i of order) {
      const c = PARAMS[i];
      const row = el("div", { class: "param" + (c.frequency ? " freq" : "") });
      const id = `param-${i}`;
      const label = el("label", { for: id });
      const left = el("span");
      if (c.frequency) left.append(el("span", {}, "excitation frequency "));
      const name = symbolNode(c);
      name.classList.add("name");
      name.setAttribute("title", c.name);
      left.append(name);
      label.append(left, el("span", { class: "unit" }, unitText(c.unit) || "(SI)"));
      const range = el("input", { type: "range", id, min: "0", max: "1000", step: "1", "data-name": c.name });
      // a text field (not type=number, which empties itself on "abc"): what was typed stays
      // visible with its message until it is corrected
      const field = el("input", { type: "text", inputmode: "decimal", class: "value", autocomplete: "off", spellcheck: "false",
        "aria-label": `${c.name} in ${c.unit || "SI units"}`, "data-name": c.name, "aria-describedby": `${id}-error` });
      const line = el("div", { class: "row" });
      line.append(range, field);
      const error = el("p", { class: "field-error", id: `${id}-error`, "data-name": c.name, "aria-live": "polite" });
      row.append(label, line, error);
      let follow = null;
      if (c.formula) {
        const f = el("div", { class: "formula" });
        f.append(el("span", {}, `= ${c.formula}`));
        follow = el("button", { type: "button", "aria-pressed": "true" }, "follows formula");
        follow.addEventListener("click", () => { S.o[i] = S.o[i] ? 0 : 1; S.v[i] = shownValue(i); recompute(); });
        f.append(follow);
        row.append(f);
      }
      if (!LIVE && !c.frequency) { range.disabled = true; field.disabled = true; }
      range.addEventListener("input", () => { fieldError(i, ""); setValue(i, fromSlider(c, Number(range.value)), false); });
      // typing: every valid number moves the slider and the results at once
      field.addEventListener("input", () => {
        const x = parseNumber(field.value);
        if (x === null) { fieldError(i, complaint(i, field.value, false)); return; }
        fieldError(i, "");
        // the frequency's range is also the response plot's band: it stays, with the arrow
        if (!c.frequency && extendRange(c, x * c.factor)) {
          range.setAttribute("aria-label", `${c.name}, range extended to ${fmt(Math.min(c.from, c.to) / c.factor)} … ${fmt(Math.max(c.from, c.to) / c.factor)}`);
        }
        setValue(i, x * c.factor, true);
      });
      // leaving the field (Enter, Tab): an invalid entry goes back to the last valid value,
      // and the message says so
      field.addEventListener("change", () => {
        const x = parseNumber(field.value);
        if (x === null) {
          fieldError(i, complaint(i, field.value, true));
          field.value = fieldText(i);
        }
      });
      // the arrow keys in the field step like the slider
      field.addEventListener("keydown", e => {
        if (e.key !== "ArrowUp" && e.key !== "ArrowDown") return;
        e.preventDefault();
        const step = (e.key === "ArrowUp" ? 1 : -1) * (e.shiftKey ? 50 : 10);
        const pos = Math.max(0, Math.min(1000, toSlider(c, shownValue(i)) + step));
        fieldError(i, "");
        setValue(i, fromSlider(c, pos), true);
        field.value = fieldText(i);
      });
      box.append(row);
      controlsOf[i] = { range, field, follow, error };
    }
  }

  // a number as typed (1.5, -2e3, "−4"), else null: no hexadecimal, no empty text, no NaN
  function parseNumber(text) {
    const s = String(text).trim().replace(/\u2212/g, "-");
    if (!/^[+-]?(\d+\.?\d*|\.\d+)(e[+-]?\d+)?$/i.test(s)) return null;
    const x = Number(s);
    return Number.isFinite(x) ? x : null;
  }
  function fieldText(i) { return String(Number((shownValue(i) / PARAMS[i].factor).toPrecision(10))); }
  function complaint(i, text, restored) {
    const c = PARAMS[i], what = String(text).trim() === "" ? "an empty field is not a number" : `“${String(text).trim().slice(0, 40)}” is not a number`;
    return `${what}; ${c.name} ${restored ? "is back at" : "stays"} ${fieldText(i)}${c.unit ? " " + unitText(c.unit) : ""}`;
  }
  function fieldError(i, text) {
    const ctl = controlsOf[i];
    if (!ctl) return;
    ctl.error.textContent = text;
    if (text) ctl.field.setAttribute("aria-invalid", "true"); else ctl.field.removeAttribute("aria-invalid");
  }

  // a new value of parameter i: the results, then every control (the slider and its spoken
  // value follow a typed number; the field follows the slider)
  function setValue(i, x, fromField) {
    S.v[i] = x;
    if (PARAMS[i].formula) S.o[i] = 1;
    recompute();
    syncControls(fromField ? -1 : i);
  }

  function syncControls(except) {
    PARAMS.forEach((c, i) => {
      const ctl = controlsOf[i];
      if (!ctl) return;
      const x = shownValue(i);
      // the slider's own position stays where the hand put it; its value is rounded to 4 digits
      if (i !== except) ctl.range.value = String(toSlider(c, x));
      ctl.range.setAttribute("aria-valuetext", `${fmt(x / c.factor)} ${unitText(c.unit)}`.trim());
      if (document.activeElement !== ctl.field) ctl.field.value = fieldText(i);
      if (ctl.follow) {
        ctl.follow.setAttribute("aria-pressed", S.o[i] ? "false" : "true");
        ctl.follow.textContent = S.o[i] ? "set (click to follow the formula)" : "follows formula";
      }
    });
  }

  // -- numbers -------------------------------------------------------------------------------
  function responseTable(r) {
    const t = $("response-table");
    t.replaceChildren();
    const head = el("tr");
    ["", "amplitude", "phase δ (rad)", "δ (°)"].forEach(h => head.append(el("th", { scope: "col" }, h)));
    const unstable = r.stability === "unstable";
    t.append(el("caption", { class: "hint" }, unstable ? "no stationary amplitudes: the equilibrium is unstable, free vibrations grow and the stationary solution is never reached" : excitationText(r)), head);
    for (const x of NAMES) {
      if (r.amplitudes[x.name] === undefined && !LIVE) continue;  // not precomputed
      const tr = el("tr", { "data-name": x.name });
      const th = el("th", { scope: "row" });
      th.append(symbolNode(x));
      tr.append(th);
      const amp = unstable ? undefined : r.amplitudes[x.name];
      const td = el("td");
      if (amp !== undefined) {
        const e = number(amp / x.factor, 6, `amplitudes.${x.name}`);
        e.setAttribute("data-si", String(amp));
        td.append(e, el("span", { class: "unit" }, x.unit ? ` ${unitText(x.unit)}` : ""));
      } else td.textContent = "–";
      const ph = unstable ? undefined : r.phases[x.name];
      const tdp = el("td"), tdd = el("td");
      if (ph !== undefined) { tdp.append(number(ph, 6, `phases.${x.name}`)); tdd.textContent = fmt(ph * 180 / Math.PI, 4); } else { tdp.textContent = "–"; tdd.textContent = "–"; }
      tr.append(td, tdp, tdd);
      t.append(tr);
    }
  }

  function excitationText(r) {
    if (!r.available) return "no stationary solution (a signal is not a sum of harmonics)";
    const ws = r.harmonics.map(h => h.omega);
    if (!ws.length) return "free vibration: no excitation";
    return "excitation at ω = " + ws.map(w => `${fmt(w)} rad/s`).join(", ");
  }

  function frequencyTable(r) {
    const t = $("frequency-table");
    t.replaceChildren();
    const head = el("tr");
    ["mode", "ω (rad/s)", "f (Hz)", "damping ratio ζ"].forEach(h => head.append(el("th", { scope: "col" }, h)));
    t.append(head);
    r.omegas.forEach((w, j) => {
      const tr = el("tr");
      tr.append(el("td", {}, String(j + 1)));
      const a = el("td"); a.append(number(w, 7, `natural_frequencies.${j}`));
      const b = el("td"); b.append(number(w / (2 * Math.PI), 6));
      const z = el("td");
      const zeta = r.damping.ratios[j];
      if (zeta !== undefined) z.append(number(zeta, 4, `damping_ratios.${j}`)); else z.textContent = "–";
      tr.append(a, b, z);
      t.append(tr);
    });
  }

  function matrixTable(label, a) {
    const t = el("table", { class: "matrix", "data-matrix": label });
    t.append(el("caption", {}, label));
    for (let i = 0; i < n; i++) {
      const tr = el("tr");
      for (let j = 0; j < n; j++) { const td = el("td"); td.append(number(a[i * n + j], 5, `${label}.${i}.${j}`)); tr.append(td); }
      t.append(tr);
    }
    const wrap = el("div", { class: "scroll" });
    wrap.append(t);
    return wrap;
  }

  function renderNumbers(r) {
    responseTable(r);
    frequencyTable(r);
    const st = $("stability");
    st.textContent = r.stability;
    const box = $("matrices");
    box.replaceChildren();
    if (r.M) {
      box.append(matrixTable("M", r.M), matrixTable("C", r.C), matrixTable("K", r.K));
    } else box.append(el("p", { class: "hint" }, `M, C, K are ${n} × ${n}: not shown.`));
    const w = $("warnings");
    w.replaceChildren(...r.warnings.map(x => el("p", {}, x)));
  }

  // the diagnosis next to the controls: the error (resonance, singular M) and every warning
  function renderDiagnosis(r) {
    const list = $("control-warnings");
    list.replaceChildren(...(r ? r.warnings : []).map(x => el("li", {}, x)));
  }

  // -- plots ---------------------------------------------------------------------------------
  function canvasContext(canvas) {
    const ratio = window.devicePixelRatio || 1;
    const w = canvas.clientWidth || 600, h = canvas.clientHeight || 260;
    if (canvas.width !== Math.round(w * ratio) || canvas.height !== Math.round(h * ratio)) {
      canvas.width = Math.round(w * ratio); canvas.height = Math.round(h * ratio);
    }
    const ctx = canvas.getContext("2d");
    ctx.setTransform(ratio, 0, 0, ratio, 0, 0);
    ctx.clearRect(0, 0, w, h);
    ctx.font = "12px system-ui, sans-serif";
    return { ctx, w, h };
  }

  function niceTicks(a, b, count) {
    const span = b - a, raw = span / count;
    const step = Math.pow(10, Math.floor(Math.log10(raw)));
    const mult = [1, 2, 5, 10].find(m => m * step >= raw) * step;
    const out = [];
    for (let x = Math.ceil(a / mult) * mult; x <= b + 1e-9 * span; x += mult) out.push(x);
    return out;
  }

  // the y range of a log axis that fits the values shown: from the smallest to the largest,
  // at most 8 decades (an antiresonance's near-zero would swamp the rest), with room above
  // the highest peak
  function logRange(values) {
    let lo = Infinity, hi = 0;
    for (const y of values) if (Number.isFinite(y) && y > 0) { lo = Math.min(lo, y); hi = Math.max(hi, y); }
    if (!(hi > 0)) return [-1, 1];
    lo = Math.max(lo, hi * 1e-8);
    let a = Math.log10(lo), b = Math.log10(hi);
    if (b - a < 1) { const m = (a + b) / 2; a = m - 0.5; b = m + 0.5; }
    const span = b - a;
    return [a - 0.04 * span, b + 0.08 * span];
  }

  function drawResponse() {
    const { ctx, w, h } = canvasContext($("response"));
    const r = S.result, curve = S.curve;
    if (!curve || !r) {
      ctx.fillStyle = "#5b5b60";
      ctx.fillText(FREQ < 0 ? "The excitation frequency is not a parameter of this model: no curve." : "No curve.", 12, 24);
      $("response-caption").textContent = "";
      return;
    }
    const c = PARAMS[FREQ];
    const names = [...S.shown].filter(s => curve.curves[s]);
    const factor = s => (UNIT[s] ? UNIT[s].factor : 1);
    const left = 62, right = 12, top = 30, bottom = 36;
    const xs = curve.values;
    const shownValues = [];
    for (const s of names) for (const y of curve.curves[s]) shownValues.push(y / factor(s));
    for (const s of names) if (r.amplitudes[s] > 0) shownValues.push(r.amplitudes[s] / factor(s));
    shownValues.push(...measuredValues(names, xs[0], xs[xs.length - 1], factor));
    const [la, lb] = logRange(shownValues);
    const units = [...new Set(names.map(s => unitText(UNIT[s] ? UNIT[s].unit : "") || (D.has_units ? "1" : "SI")))];
    const xText = CHART ? CHART.xtext : `${c.frequency ? "excitation frequency " : ""}${symbolText(c)} (${unitText(c.unit) || "SI"})`;
    const yText = CHART ? CHART.ytext : `amplitude (${units.join(", ")})`;
    S.plotted = { log_range: [la, lb], names, beyond: false, xlabel: xText, ylabel: yText,
      styles: names.map(s => ({ colour: colourOf(s), width: widthOf(s), dash: dashOf(s) })) };
    const X = x => left + (w - left - right) * (x - xs[0]) / (xs[xs.length - 1] - xs[0]);
    const Y = y => top + (h - top - bottom) * (1 - (Math.log10(y) - la) / (lb - la));
    const inside = y => Number.isFinite(y) && y > 0 && Math.log10(y) >= la;
    ctx.strokeStyle = "#e4e1da"; ctx.fillStyle = "#5b5b60"; ctx.lineWidth = 1;
    const decades = Math.floor(lb) - Math.ceil(la) + 1, every = Math.max(1, Math.ceil(decades / 6));
    for (let e = Math.ceil(la); e <= Math.floor(lb); e++) {
      const y = Y(Math.pow(10, e));
      ctx.beginPath(); ctx.moveTo(left, y); ctx.lineTo(w - right, y); ctx.stroke();
      if ((e - Math.ceil(la)) % every === 0) { ctx.textAlign = "right"; ctx.fillText(powerText(e), left - 4, y + 4); }
    }
    ctx.textAlign = "center";
    const ticks = niceTicks(xs[0] / c.factor, xs[xs.length - 1] / c.factor, Math.max(3, Math.min(6, Math.floor((w - left - right) / 60))));
    for (const x of ticks) {
      const px = X(x * c.factor);
      ctx.beginPath(); ctx.moveTo(px, top); ctx.lineTo(px, h - bottom); ctx.stroke();
      ctx.fillText(fmt(x, 4), px, h - bottom + 14);
    }
    // the axes' titles: the quantity, its symbol and its unit
    ctx.fillStyle = "#1d1d1f";
    ctx.fillText(xText, left + (w - left - right) / 2, h - 4);
    ctx.save();
    ctx.translate(13, top + (h - top - bottom) / 2); ctx.rotate(-Math.PI / 2);
    ctx.fillText(yText, 0, 0);
    ctx.restore();
    // natural frequencies: dashed lines, their labels above the plot (staggered when close)
    ctx.setLineDash([4, 3]); ctx.strokeStyle = "#8a8a8a"; ctx.fillStyle = "#5b5b60";
    let lastLabel = -Infinity, row = 0;
    r.omegas.forEach((wn, j) => {
      if (wn < xs[0] || wn > xs[xs.length - 1]) return;
      const px = X(wn);
      ctx.beginPath(); ctx.moveTo(px, top); ctx.lineTo(px, h - bottom); ctx.stroke();
      const text = `ω${[...String(j + 1)].map(ch => SUB[ch]).join("")}`;
      row = px - lastLabel < ctx.measureText(text).width + 6 ? 1 - row : 0;
      if (row === 1 && px - lastLabel < 8) return;  // two labels on one line: the first says it
      ctx.fillText(text, px, top - 5 - 12 * row);
      lastLabel = px;
    });
    ctx.setLineDash([]);
    names.forEach((s, k) => {
      const ys = curve.curves[s];
      const f = factor(s);
      ctx.strokeStyle = colourOf(s); ctx.lineWidth = widthOf(s);
      ctx.setLineDash(dashOf(s));
      ctx.beginPath();
      let pen = false;
      ys.forEach((y, j) => {
        if (!inside(y / f)) { pen = false; return; }  // below the axis
        const px = X(xs[j]), py = Math.max(top, Y(y / f));
        if (pen) ctx.lineTo(px, py); else ctx.moveTo(px, py);
        pen = true;
      });
      ctx.stroke();
    });
    ctx.setLineDash([]);
    S.plotted.measured = drawMeasured(ctx, names, X, Y, inside, factor, xs[0], xs[xs.length - 1], top);
    const now = r.p[FREQ], first = xs[0], last = xs[xs.length - 1];
    const beyond = !(now >= Math.min(first, last) && now <= Math.max(first, last));
    // the current value in black: the curves take the chart description's colours (orange
    // among them), the natural frequencies grey dashes
    ctx.strokeStyle = NOW; ctx.fillStyle = NOW; ctx.lineWidth = 2;
    if (!beyond) {
      ctx.beginPath(); ctx.moveTo(X(now), top); ctx.lineTo(X(now), h - bottom); ctx.stroke();
      for (const s of names) {
        const a = r.amplitudes[s];
        if (a === undefined || !inside(a / factor(s))) continue;
        ctx.fillStyle = colourOf(s);
        ctx.beginPath(); ctx.arc(X(now), Y(a / factor(s)), 3.5, 0, 2 * Math.PI); ctx.fill();
      }
    } else {
      // off the axis: an arrow at the edge it lies beyond, and the value
      const atRight = !(now < first), px = atRight ? w - right - 2 : left + 2, ym = top + (h - top - bottom) / 2, d = atRight ? 1 : -1;
      ctx.beginPath(); ctx.moveTo(px, ym); ctx.lineTo(px - d * 10, ym - 7); ctx.lineTo(px - d * 10, ym + 7); ctx.closePath(); ctx.fill();
      const note = `${atRight ? "" : "← "}${symbolText(c)} = ${fmt(now / c.factor, 4)} ${unitText(c.unit)}${atRight ? " →" : ""}`;
      const wide = ctx.measureText(note).width, x0 = atRight ? px - 14 - wide : px + 14;
      ctx.fillStyle = "rgba(255,255,255,.92)"; ctx.fillRect(x0 - 4, ym - 11, wide + 8, 18);
      ctx.strokeStyle = NOW; ctx.lineWidth = 1; ctx.strokeRect(x0 - 4, ym - 11, wide + 8, 18);
      ctx.fillStyle = NOW; ctx.textAlign = "left";
      ctx.fillText(note, x0, ym + 3);
    }
    S.plotted.beyond = beyond;
    const range = `${fmt(first / c.factor, 4)} to ${fmt(last / c.factor, 4)}${c.unit ? " " + unitText(c.unit) : ""}`;
    $("response-caption").textContent = `Peak amplitude (log scale, each in its unit) against ${symbolText(c)} from ${range}; the black line is the current value, dashed lines the natural frequencies ω₁, ω₂, … (rad/s)` + (FREQ >= 0 && c.unit && c.unit !== "rad/s" ? ` drawn where ${symbolText(c)} equals them` : "") + "." + (beyond ? ` The current value, ${fmt(now / c.factor, 6)}${c.unit ? " " + unitText(c.unit) : ""}, lies outside this range (the arrow).` : "") + measuredCaption();
  }

  // -- measured FRFs over the frequency response (resonant explore --test FILE) ---------------
  // D.measured: the parameter at each measured line (SI) and per name the measured amplitude
  // under the model's load at the file's values (SI; null where left out; none, with a note
  // the caption shows, where the model loads what no measured input makes); they stay as
  // the sliders move.  Drawn as open circles in the name's colour.
  const MEAS = D.measured;
  function measuredPoints(name, first, last) {
    if (!MEAS || !MEAS.curves[name]) return [];
    const lo = Math.min(first, last), hi = Math.max(first, last);
    return MEAS.values.map((x, j) => [x, MEAS.curves[name][j]])
      .filter(([x, y]) => x >= lo && x <= hi && y !== null && Number.isFinite(y) && y > 0);
  }
  function measuredValues(names, first, last, factor) {
    return names.flatMap(s => measuredPoints(s, first, last).map(([, y]) => y / factor(s)));
  }
  // draws the points; returns what was drawn (per name: [x (SI), value shown, px, py])
  function drawMeasured(ctx, names, X, Y, inside, factor, first, last, top) {
    if (!MEAS) return null;
    const drawn = {};
    ctx.lineWidth = 1.3;
    for (const s of names) {
      const points = measuredPoints(s, first, last).filter(([, y]) => inside(y / factor(s)));
      if (!points.length) continue;
      ctx.strokeStyle = colourOf(s);
      // as small as the points' spacing needs on a narrow plot (a phone), 2.6 px at most
      const radius = Math.max(1.3, Math.min(2.6, Math.abs(X(last) - X(first)) / points.length / 2.4));
      drawn[s] = points.map(([x, y]) => {
        const px = X(x), py = Math.max(top, Y(y / factor(s)));
        ctx.beginPath(); ctx.arc(px, py, radius, 0, 2 * Math.PI); ctx.stroke();
        return [x, y / factor(s), px, py];
      });
    }
    return drawn;
  }
  function measuredCaption() {
    if (!MEAS) return "";
    // a note with no curves: no points at all; with some: those it names are left out
    if (MEAS.note && !Object.keys(MEAS.curves).length) return ` Measured (${MEAS.source}): ${MEAS.note}.`;
    const shown = Object.keys(MEAS.curves).map(s => `${symbolText(UNIT[s] || { symbol: s })} (${MEAS.channels[s]})`);
    const inputs = MEAS.inputs.length > 1
      ? `the FRFs to ${MEAS.inputs.join(", ")}, each times the model's load at its input, summed (phases included),`
      : `the FRFs to ${MEAS.inputs[0]} times the model's load,`;
    return ` Open circles: measured (${MEAS.source}) ${shown.join(", ")}, ${inputs} at the file's values; they stay as the sliders move.` + (MEAS.note ? ` ${MEAS.note}.` : "");
  }

  // a curve's dash pattern in pixels: the description's is in line widths (as matplotlib's)
  function dashOf(name) {
    const style = STYLE.get(name);
    if (style) return style.dash ? style.dash.split(/[ ,]+/).map(v => Number(v) * style.width).filter(v => Number.isFinite(v) && v >= 0) : [];
    const i = NAMES.findIndex(x => x.name === name);
    return DASHES[Math.floor(Math.max(i, 0) / COLOURS.length) % DASHES.length];
  }

  function colourOf(name) {
    const style = STYLE.get(name);
    if (style && /^#[0-9a-fA-F]{6}$/.test(style.color || "")) return style.color;
    const i = NAMES.findIndex(x => x.name === name);
    return COLOURS[i % COLOURS.length];
  }

  function widthOf(name) {
    const style = STYLE.get(name);
    return style && style.width > 0 && style.width < 10 ? style.width : 1.6;
  }

  function periodOf(r) {
    const ws = r.harmonics.map(h => h.omega).filter(w => w > 0);
    if (!ws.length) return 1;
    return NUM.commonPeriod(ws) || 2 * Math.PI / Math.min(...ws);
  }

  function valueAt(r, name, t) {
    const p = r.pairs[name];
    if (!p) return 0;
    let y = 0;
    r.harmonics.forEach((h, i) => { y += p[i][0] * Math.cos(h.omega * t) + p[i][1] * Math.sin(h.omega * t); });
    return y;
  }

  function drawHistory() {
    const { ctx, w, h } = canvasContext($("history"));
    const r = S.result;
    const names = [...S.shown].filter(s => r && r.pairs[s]);
    if (!r || !names.length) { ctx.fillStyle = "#5b5b60"; ctx.fillText("No stationary response.", 12, 24); return; }
    if (names.every(s => !(r.amplitudes[s] > 0))) {  // free vibration: nothing to scale
      ctx.fillStyle = "#5b5b60";
      ctx.fillText("No excitation: the stationary response is zero.", 12, 24);
      $("history-caption").textContent = "";
      return;
    }
    const T = periodOf(r), left = 96, right = 10, rows = names.length;
    const rowH = (h - 8) / rows;
    names.forEach((s, k) => {
      const amp = Math.max(r.amplitudes[s] || 0, 1e-300), f = UNIT[s] ? UNIT[s].factor : 1;
      const mid = 4 + rowH * (k + 0.5);
      ctx.strokeStyle = "#e4e1da"; ctx.lineWidth = 1;
      ctx.beginPath(); ctx.moveTo(left, mid); ctx.lineTo(w - right, mid); ctx.stroke();
      ctx.fillStyle = colourOf(s); ctx.textAlign = "right";
      ctx.fillText(symbolText(UNIT[s] || { name: s }), left - 6, mid - 2);
      ctx.fillStyle = "#5b5b60";
      ctx.fillText(r.amplitudes[s] > 0 ? `±${fmt(amp / f, 3)} ${UNIT[s] ? unitText(UNIT[s].unit) : ""}` : "0",
                   left - 6, mid + 12);
      ctx.strokeStyle = colourOf(s); ctx.lineWidth = 1.5;
      ctx.beginPath();
      for (let j = 0; j <= 200; j++) {
        const t = T * j / 200, y = valueAt(r, s, t) / amp;
        const px = left + (w - left - right) * j / 200, py = mid - y * rowH * 0.42;
        if (j) ctx.lineTo(px, py); else ctx.moveTo(px, py);
      }
      ctx.stroke();
    });
    const px = left + (w - left - right) * S.phase;
    ctx.strokeStyle = NOW; ctx.lineWidth = 1.5;
    ctx.beginPath(); ctx.moveTo(px, 2); ctx.lineTo(px, h - 4); ctx.stroke();
    $("history-caption").textContent = `t from 0 to T = ${fmt(T, 4)} s (one period); each curve scaled to its amplitude.`;
  }

  function drawPeriodic() {
    if (!PER) return;
    $("periodic-panel").hidden = false;
    const { ctx, w, h } = canvasContext($("periodic"));
    const r = S.periodic;
    const names = [...S.shown].filter(s => r && r.history && r.history[s]);
    if (!r || r.error || !names.length) {
      ctx.fillStyle = "#5b5b60"; ctx.fillText(r && r.error ? r.error : "No periodic response.", 12, 24);
      return;
    }
    // the load first (grey), then every shown response, each row scaled to its largest |value|
    const rows = (r.load ? [{ key: null, ys: r.load.values, big: r.load.largest, colour: "#8a8a8f",
      label: `load on ${PER.name}`, value: PER.shape === "expression" ? `max ${fmt(r.load.largest, 4)} (SI)` : `amplitude ${fmt(PER.amplitude, 4)} (SI)` }] : []).concat(names.map(s => {
      const f = UNIT[s] ? UNIT[s].factor : 1;
      return { key: s, ys: r.history[s], big: r.largest[s], colour: colourOf(s), label: symbolText(UNIT[s] || { name: s }),
        value: `max ${fmt(r.largest[s] / f, 4)} ${UNIT[s] ? unitText(UNIT[s].unit) : ""}` };
    }));
    const left = Math.max(96, 12 + Math.max(...rows.map(q => Math.max(ctx.measureText(q.label).width, ctx.measureText(q.value).width))));
    const right = 10, rowH = (h - 8) / rows.length;
    rows.forEach((q, k) => {
      const ys = q.ys, big = Math.max(q.big, 1e-300);
      const mid = 4 + rowH * (k + 0.5), count = ys.length, step = Math.max(1, Math.floor(count / 800));
      ctx.strokeStyle = "#e4e1da"; ctx.lineWidth = 1;
      ctx.beginPath(); ctx.moveTo(left, mid); ctx.lineTo(w - right, mid); ctx.stroke();
      ctx.fillStyle = q.colour; ctx.textAlign = "right";
      ctx.fillText(q.label, left - 6, mid - 2);
      ctx.fillStyle = "#5b5b60";
      ctx.fillText(q.value, left - 6, mid + 12);
      ctx.strokeStyle = q.colour; ctx.lineWidth = 1.5;
      ctx.beginPath();
      for (let j = 0; j <= count; j += step) {
        const y = ys[j % count] / big, px = left + (w - left - right) * j / count, py = mid - y * rowH * 0.42;
        if (j) ctx.lineTo(px, py); else ctx.moveTo(px, py);
      }
      ctx.stroke();
    });
    const shape = PER.shape === "expression" ? "a signal given by its expression" : `a ${PER.shape} wave`;
    $("periodic-caption").textContent = `${shape} on ${PER.name}${PER.derivative ? ` (its derivative of order ${PER.derivative})` : ""}, period ${fmt(PER.period, 4)} s: ` +
      `${PER.harmonics} harmonics (remainder below ${fmt(100 * PER.tolerance, 3)} % RMS), each answered by the stationary response and summed; ` +
      `t from 0 to T, each curve scaled to its largest excursion (max).` + (LIVE && PER.a ? "" : " Computed by resonant at the file's parameter values.");
  }

  // -- motion --------------------------------------------------------------------------------
  const DR = D.drawing;
  const SIGNALS = LAYOUT && LAYOUT.signals ? LAYOUT.signals.length : 0;
  const REF = DR ? resonantMotion(P0, D.equilibrium, new Array(SIGNALS).fill(0)) : null;

  // q(t) and s(t) of what is shown (response or mode), at phase x of one cycle
  function displacement(x) {
    const r = S.result;
    const q = new Array(n).fill(0), s = new Array(SIGNALS).fill(0);
    if (!r) return { q, s };
    if (S.mode >= 0) {
      const shape = r.modes[S.mode] || [];
      const a = Math.sin(2 * Math.PI * x);
      for (let i = 0; i < n; i++) q[i] = a * (shape[i] || 0);
      return { q, s };
    }
    const t = periodOf(r) * x;
    COORDS.forEach((c, i) => { q[i] = valueAt(r, c.name, t); });
    if (DR && LIVE && SIGNALS) {
      const f = resonantSignals(r.p);
      for (let j = 0, k = 0; j < LAYOUT.signal_frequencies; j++) {
        const w = f[k++];
        for (let i = 0; i < SIGNALS; i++, k += 2) s[i] += f[k] * Math.sin(w * t) + f[k + 1] * Math.cos(w * t);
      }
    }
    return { q, s };
  }

  function transforms(q, s, scale) {
    const qa = q.map((v, i) => D.equilibrium[i] + scale * v), sa = s.map(v => scale * v);
    const g = resonantMotion(P0, qa, sa);
    return DR.owners.map((_, i) => ({
      dx: g[3 * i] - REF[3 * i], dy: g[3 * i + 1] - REF[3 * i + 1], da: g[3 * i + 2] - REF[3 * i + 2],
      px: REF[3 * i] + DR.shifts[i][0], py: REF[3 * i + 1] + DR.shifts[i][1],
    }));
  }

  function apply(T, owner, p) {
    const t = owner >= 0 ? T[owner] : null;
    if (!t || !Number.isFinite(t.dx + t.dy + t.da)) return p;
    const c = Math.cos(t.da), sn = Math.sin(t.da), rx = p[0] - t.px, ry = p[1] - t.py;
    return [t.px + t.dx + c * rx - sn * ry, t.py + t.dy + sn * rx + c * ry];
  }

  // the largest drawn displacement per unit of motion (to choose the automatic scale)
  function motionSize() {
    let big = 0;
    const eps = 1e-6;
    for (let k = 0; k < 8; k++) {
      const { q, s } = displacement(k / 8 + 1 / 16);
      if (DR) {
        const T = transforms(q, s, eps);
        for (const t of T) big = Math.max(big, (Math.hypot(t.dx, t.dy) + Math.abs(t.da) * DR.scale) / eps);
      } else for (const v of q) big = Math.max(big, Math.abs(v));
    }
    return big;
  }

  function autoScale() {
    const size = motionSize();
    const target = DR ? 0.12 * DR.scale : 1;
    return size > 0 && Number.isFinite(size) ? target / size : 1;
  }

  function drawMotion() {
    const canvas = $("mechanism");
    const { ctx, w, h } = canvasContext(canvas);
    const r = S.result;
    if (!r) return;
    const mult = Math.pow(10, Number($("scale").value) / 50);
    const scale = S.scale * mult;
    $("scale-out").textContent = fmt(scale, 3);
    const { q, s } = displacement(S.phase);
    if (DR && LIVE) drawMechanism(ctx, w, h, transforms(q, s, scale));
    else drawBars(ctx, w, h, q);
    drawHistory();
  }

  // the coordinates drawn as bars: all of a small model, else those of the curves
  const BARS = (n <= 12 ? COORDS : COORDS.filter(c => D.show.includes(c.name)).concat(COORDS).slice(0, 12))
    .filter((c, k, all) => all.indexOf(c) === k);

  function drawBars(ctx, w, h, q) {
    const r = S.result, left = 80, right = 20, rowH = Math.min(34, (h - 20) / Math.max(BARS.length, 1));
    const groups = {};
    const index = c => COORDS.indexOf(c);
    BARS.forEach(c => {
      const size = S.mode >= 0 ? 1 : Math.max(r.amplitudes[c.name] || 0, 0);
      groups[c.unit] = Math.max(groups[c.unit] || 0, size);
    });
    const mid = left + (w - left - right) / 2, half = (w - left - right) / 2 - 4;
    BARS.forEach((c, k) => {
      const y = 10 + rowH * k;
      const big = groups[c.unit] || 1;
      const v = big > 0 ? q[index(c)] / big : 0;
      ctx.fillStyle = "#f1efea"; ctx.fillRect(left, y + 4, w - left - right, rowH - 8);
      ctx.fillStyle = colourOf(c.name);
      const len = Math.max(-1, Math.min(1, v)) * half;
      ctx.fillRect(Math.min(mid, mid + len), y + 6, Math.abs(len), rowH - 12);
      ctx.fillStyle = "#1d1d1f"; ctx.textAlign = "right";
      ctx.fillText(`${symbolText(c)}${c.unit ? " (" + unitText(c.unit) + ")" : ""}`, left - 6, y + rowH / 2 + 4);
    });
    ctx.strokeStyle = "#1d1d1f";
    ctx.beginPath(); ctx.moveTo(mid, 6); ctx.lineTo(mid, 10 + rowH * BARS.length); ctx.stroke();
  }

  // -- the mechanism (as resonant draw draws it) ------------------------------------------
  const INK = "#1d1d1f", FILL = "#d9d6cf", FORCE = "#a8322d", COORD = "#1f4e9c";
  function view(w, h) {
    const [x0, x1, y0, y1] = DR.bounds, u = DR.scale, m = 0.12 * u;
    const ax = x0 - 2 * m, bx = x1 + 2 * m, ay = y0 - m, by = y1 + m;
    const k = Math.min(w / (bx - ax), h / (by - ay));
    const ox = (w - k * (bx - ax)) / 2, oy = (h - k * (by - ay)) / 2;
    return { k, X: x => ox + k * (x - ax), Y: y => h - oy - k * (y - ay) };
  }

  function along(a, b, t, side) {
    const dx = b[0] - a[0], dy = b[1] - a[1], len = Math.hypot(dx, dy) || 1;
    return [a[0] + t * dx - (side || 0) * dy / len, a[1] + t * dy + (side || 0) * dx / len];
  }

  function path(ctx, V, pts, close) {
    ctx.beginPath();
    pts.forEach((p, i) => (i ? ctx.lineTo(V.X(p[0]), V.Y(p[1])) : ctx.moveTo(V.X(p[0]), V.Y(p[1]))));
    if (close) ctx.closePath();
  }

  function label(ctx, V, lab, p, align, colour, size) {
    if (!lab || !lab.text) return;
    const [base, sub, rest] = lab.math ? latexText(lab.text) : [lab.text, "", ""];
    const fs = size || (lab.math ? 14 : 12);
    ctx.fillStyle = colour || INK;
    ctx.textBaseline = "middle";
    const font = (lab.math ? "italic " : "") + `${fs}px Georgia, serif`;
    ctx.font = font;
    const bw = ctx.measureText(base).width;
    ctx.font = `${Math.round(fs * 0.72)}px Georgia, serif`;
    const sw = ctx.measureText(sub).width;
    ctx.font = font;
    const rw = ctx.measureText(rest).width, total = bw + sw + rw;
    let x = V.X(p[0]);
    if (align === "center") x -= total / 2; else if (align === "right") x -= total;
    const y = V.Y(p[1]);
    ctx.textAlign = "left";
    ctx.fillText(base, x, y);
    if (sub) { ctx.font = `${Math.round(fs * 0.72)}px Georgia, serif`; ctx.fillText(sub, x + bw, y + fs * 0.3); ctx.font = font; }
    if (rest) ctx.fillText(rest, x + bw + sw, y);
    ctx.textBaseline = "alphabetic";
  }

  function arrowHead(ctx, V, tip, dir, size, colour) {
    const d = Math.hypot(dir[0], dir[1]) || 1, ux = dir[0] / d, uy = dir[1] / d;
    const X = V.X(tip[0]), Y = V.Y(tip[1]);
    ctx.fillStyle = colour;
    ctx.beginPath();
    ctx.moveTo(X, Y);
    ctx.lineTo(X - size * ux + 0.45 * size * uy, Y + size * uy + 0.45 * size * ux);
    ctx.lineTo(X - size * ux - 0.45 * size * uy, Y + size * uy - 0.45 * size * ux);
    ctx.closePath(); ctx.fill();
  }

  function drawLink(ctx, V, link, a, b, u) {
    ctx.strokeStyle = INK; ctx.lineWidth = 1.1;
    if (link.kind === "damper") {
      const wd = 0.05 * u;
      for (const seg of [[a, along(a, b, 0.35)], [along(a, b, 0.35, -wd), along(a, b, 0.35, wd)], [along(a, b, 0.35, -wd), along(a, b, 0.65, -wd)],
        [along(a, b, 0.35, wd), along(a, b, 0.65, wd)], [along(a, b, 0.55, -0.75 * wd), along(a, b, 0.55, 0.75 * wd)], [along(a, b, 0.55), b]]) {
        path(ctx, V, seg); ctx.stroke();
      }
      return;
    }
    const len = Math.hypot(b[0] - a[0], b[1] - a[1]);
    const lead = len ? Math.min(0.2, 0.06 * u / len) : 0.2, amp = 0.045 * u;
    if (link.torsion) {  // a torsion spring: the shaft and a coil about it (as resonant draw)
      ctx.save(); ctx.lineWidth = 0.7; ctx.setLineDash([6, 2, 1, 2]); path(ctx, V, [a, b]); ctx.stroke(); ctx.restore();
      const turns = 6, steps = 24, radius = 0.05 * u, pitch = (1 - 2 * lead) / turns, back = 0.4 * pitch, coil = [a];
      for (let k = 0; k <= turns * steps; k++) {
        const th = 2 * Math.PI * k / steps;
        coil.push(along(a, b, Math.max(0, lead + pitch * k / steps + back * (Math.cos(th) - 1)), radius * Math.sin(th)));
      }
      coil.push(along(a, b, 1 - lead), b);
      path(ctx, V, coil); ctx.stroke();
      return;
    }
    const pts = [a, along(a, b, lead)];
    for (let i = 0; i < 8; i++) pts.push(along(a, b, lead + (1 - 2 * lead) * (i + 0.5) / 8, amp * (i % 2 ? -1 : 1)));
    pts.push(along(a, b, 1 - lead), b);
    path(ctx, V, pts); ctx.stroke();
  }

  function drawSupport(ctx, V, sup, at, u) {
    const nrm = sup.normal, t = [-nrm[1], nrm[0]], half = sup.width / 2, depth = 0.06 * u;
    const a = [at[0] - half * t[0], at[1] - half * t[1]], b = [at[0] + half * t[0], at[1] + half * t[1]];
    if (sup.post) { ctx.strokeStyle = INK; ctx.lineWidth = 2.2; path(ctx, V, [sup.post, at]); ctx.stroke(); }
    ctx.fillStyle = "#ece9e3";
    path(ctx, V, [a, b, [b[0] - depth * nrm[0], b[1] - depth * nrm[1]], [a[0] - depth * nrm[0], a[1] - depth * nrm[1]]], true); ctx.fill();
    ctx.strokeStyle = INK; ctx.lineWidth = 1.4; path(ctx, V, [a, b]); ctx.stroke();
    const slant = 0.6 * depth, count = Math.max(4, Math.floor((sup.width - slant) / (0.045 * u)));
    ctx.lineWidth = 0.7;
    for (let i = 0; i <= count; i++) {
      const s = -half + slant + (sup.width - slant) * i / count;
      const p0 = [at[0] + s * t[0], at[1] + s * t[1]];
      path(ctx, V, [p0, [p0[0] - depth * nrm[0] - 0.6 * depth * t[0], p0[1] - depth * nrm[1] - 0.6 * depth * t[1]]]); ctx.stroke();
    }
    if (sup.signals && sup.signals.length) {
      const mo = sup.motion || t, c = [at[0] - 2.4 * depth * nrm[0], at[1] - 2.4 * depth * nrm[1]], ha = 0.09 * u;
      const s0 = [c[0] - ha * mo[0], c[1] - ha * mo[1]], e0 = [c[0] + ha * mo[0], c[1] + ha * mo[1]];
      ctx.strokeStyle = FORCE; ctx.lineWidth = 1; path(ctx, V, [s0, e0]); ctx.stroke();
      arrowHead(ctx, V, e0, mo, 7, FORCE); arrowHead(ctx, V, s0, [-mo[0], -mo[1]], 7, FORCE);
      let side = [-mo[1], mo[0]];
      if (side[1] < 0 || (side[1] === 0 && side[0] > 0)) side = [-side[0], -side[1]];
      label(ctx, V, sup.label, [c[0] + 0.07 * u * side[0], c[1] + 0.07 * u * side[1]], "center", FORCE);
    }
  }

  function circle(ctx, V, c, radius, fill, stroke, lw) {
    ctx.beginPath(); ctx.arc(V.X(c[0]), V.Y(c[1]), Math.max(radius * V.k, 1), 0, 2 * Math.PI);
    if (fill) { ctx.fillStyle = fill; ctx.fill(); }
    if (stroke) { ctx.strokeStyle = stroke; ctx.lineWidth = lw || 1; ctx.stroke(); }
  }

  function drawBody(ctx, V, b, T, owner, u) {
    const t = owner >= 0 ? T[owner] : null, da = t && Number.isFinite(t.da) ? t.da : 0;
    if (b.shape === "block") {
      const c = apply(T, owner, b.centre), ang = b.angle + da;
      const cs = Math.cos(ang), sn = Math.sin(ang), hw = b.width / 2, hh = b.height / 2;
      const corners = [[-hw, -hh], [hw, -hh], [hw, hh], [-hw, hh]].map(([x, y]) => [c[0] + cs * x - sn * y, c[1] + sn * x + cs * y]);
      ctx.fillStyle = FILL; ctx.strokeStyle = INK; ctx.lineWidth = 1.3;
      path(ctx, V, corners, true); ctx.fill(); ctx.stroke();
      // not on what sits at its middle (a pin): under its top edge
      const pinned = DR.pins.some(p => Math.hypot(p[0] - b.centre[0], p[1] - b.centre[1]) < 0.25 * b.height);
      label(ctx, V, b.label, pinned ? [c[0] - sn * (hh - 0.05 * u), c[1] + cs * (hh - 0.05 * u)] : c, "center", INK, 12);
    } else if (b.shape === "disc" || b.shape === "point") {
      let c = apply(T, owner, b.centre);
      if (b.path && b.path_centre) {
        const pc = apply(T, owner, b.path_centre);
        circle(ctx, V, pc, b.path, null, INK, 0.8);
        const off = unbalanceDirection(b, owner);
        c = [pc[0] + b.path * off[0], pc[1] + b.path * off[1]];
        ctx.strokeStyle = INK; ctx.lineWidth = 1; path(ctx, V, [pc, c]); ctx.stroke();
        circle(ctx, V, pc, 0.012 * u, INK);
      }
      circle(ctx, V, c, b.radius, b.shape === "disc" ? FILL : "#4a4a4a", INK, b.shape === "disc" ? 1.3 : 0.8);
      if (b.shape === "disc") {
        const ang = b.angle + da;
        ctx.strokeStyle = INK; ctx.lineWidth = 0.9;
        path(ctx, V, [c, [c[0] + b.radius * Math.cos(ang), c[1] + b.radius * Math.sin(ang)]]); ctx.stroke();
        circle(ctx, V, c, 0.012 * u, INK);
      }
      label(ctx, V, b.label, [c[0] + b.radius + 0.03 * u, c[1] + b.radius], "left", INK, 12);
    } else if (b.shape === "bar") {
      const a = apply(T, owner, b.start), e = apply(T, owner, b.end), hw = b.width / 2;
      ctx.fillStyle = "#bdb8ae"; ctx.strokeStyle = INK; ctx.lineWidth = 1;
      path(ctx, V, [along(a, e, 0, hw), along(a, e, 1, hw), along(a, e, 1, -hw), along(a, e, 0, -hw)], true); ctx.fill(); ctx.stroke();
      if (b.bob) circle(ctx, V, apply(T, owner, b.centre), b.bob, "#4a4a4a", INK, 0.8);
      if (b.gravity_centre) centreMark(ctx, V, apply(T, owner, b.gravity_centre), Math.max(0.022 * u, 0.7 * hw), da);
      const at = b.bob ? (([x, y]) => [x - b.bob - 0.03 * u, y + b.bob])(apply(T, owner, b.centre)) : along(a, e, 0.3, -(0.05 * u + hw));
      label(ctx, V, b.label, at, e[1] < a[1] ? "right" : "left", INK, 12);
    }
  }

  // the centre of gravity: a circle with two black quarters
  function centreMark(ctx, V, c, radius, turn) {
    circle(ctx, V, c, radius, "#fff", INK, 0.8);
    const X = V.X(c[0]), Y = V.Y(c[1]), r = Math.max(radius * V.k, 1);
    ctx.fillStyle = INK;
    for (const start of [0, Math.PI]) {
      ctx.beginPath(); ctx.moveTo(X, Y);
      ctx.arc(X, Y, r, -(start + turn) - Math.PI / 2, -(start + turn), false);
      ctx.closePath(); ctx.fill();
    }
  }

  // the direction of an unbalance from its circle's centre (its signals turn it)
  function unbalanceDirection(b, owner) {
    const ref = [b.centre[0] - b.path_centre[0], b.centre[1] - b.path_centre[1]];
    if (S.mode >= 0 || !SIGNALS) return norm(ref);
    const { s } = displacement(S.phase);
    const g = resonantMotion(P0, D.equilibrium, s.map(v => v * 1e-6));
    const d = [g[3 * owner] - REF[3 * owner], g[3 * owner + 1] - REF[3 * owner + 1]];
    return Math.hypot(d[0], d[1]) > 0 ? norm(d) : norm(ref);
  }
  function norm(v) { const d = Math.hypot(v[0], v[1]) || 1; return [v[0] / d, v[1] / d]; }

  function drawArrowItem(ctx, V, item, T, owner, u) {
    const colour = item.kind === "force" || item.kind === "torque" ? FORCE : COORD;
    const t = owner >= 0 ? T[owner] : null, da = t && Number.isFinite(t.da) ? t.da : 0;
    if (item.type === "Arrow") {
      const s = apply(T, owner, item.start), cs = Math.cos(da), sn = Math.sin(da);
      const v = [cs * item.vector[0] - sn * item.vector[1], sn * item.vector[0] + cs * item.vector[1]];
      const e = [s[0] + v[0], s[1] + v[1]];
      ctx.strokeStyle = colour; ctx.lineWidth = 1.4; path(ctx, V, [s, e]); ctx.stroke();
      arrowHead(ctx, V, e, v, 9, colour);
      const d = norm(v);
      if (item.kind === "coordinate") {
        const tick = 0.035 * u;
        path(ctx, V, [[s[0] - tick * d[1], s[1] + tick * d[0]], [s[0] + tick * d[1], s[1] - tick * d[0]]]); ctx.stroke();
      }
      label(ctx, V, item.label, [e[0] + 0.06 * u * d[0], e[1] + 0.06 * u * d[1]], d[0] > 0.3 ? "left" : d[0] < -0.3 ? "right" : "center", colour);
    } else {
      const c = apply(T, owner, item.centre), steps = 24, pts = [];
      for (let i = 0; i <= steps; i++) {
        const a = item.start + (item.stop - item.start) * i / steps + da;
        pts.push([c[0] + item.radius * Math.cos(a), c[1] + item.radius * Math.sin(a)]);
      }
      ctx.strokeStyle = colour; ctx.lineWidth = 1.3; path(ctx, V, pts); ctx.stroke();
      const last = pts[steps], prev = pts[steps - 1];
      arrowHead(ctx, V, last, [last[0] - prev[0], last[1] - prev[1]], 8, colour);
      const mid = (item.start + item.stop) / 2 + da;
      label(ctx, V, item.label, [c[0] + (item.radius + 0.06 * u) * Math.cos(mid), c[1] + (item.radius + 0.06 * u) * Math.sin(mid)], "center", colour);
    }
  }

  function drawMechanism(ctx, w, h, T) {
    const V = view(w, h), u = DR.scale, carry = DR.carriers;
    DR.supports.forEach((sup, i) => drawSupport(ctx, V, sup, apply(T, carry.supports[i], sup.position), u));
    DR.links.forEach((link, i) => {
      const [oa, ob] = carry.links[i] || [-1, -1];
      const a = apply(T, oa, link.start), b = apply(T, ob, link.end);
      drawLink(ctx, V, link, a, b, u);
      const shift = [(a[0] - link.start[0] + b[0] - link.end[0]) / 2, (a[1] - link.start[1] + b[1] - link.end[1]) / 2];
      label(ctx, V, link.label, [link.label_at[0] + shift[0], link.label_at[1] + shift[1]], "center", INK, 13);
    });
    DR.bodies.forEach((b, i) => drawBody(ctx, V, b, T, carry.bodies[i], u));
    DR.pins.forEach((pin, i) => circle(ctx, V, apply(T, carry.pins[i], pin), 0.022 * u, "#fff", INK, 1.1));
    for (const [name, x, y, owner] of DR.points) {
      if (DR.pins.some(p => Math.hypot(p[0] - x, p[1] - y) < 1e-9)) continue;
      const at = apply(T, owner, [x, y]);
      circle(ctx, V, at, 0.012 * u, INK);
      label(ctx, V, { text: name.split(".").slice(1).join("."), math: false }, [at[0] - 0.04 * u, at[1] - 0.03 * u], "right", INK, 11);
    }
    DR.forces.forEach((f, i) => drawArrowItem(ctx, V, f, T, carry.forces[i], u));
    DR.coordinates.forEach(c => drawArrowItem(ctx, V, c, T, -1, u));
  }

  // -- what moves: the response or a mode ---------------------------------------------------
  function buildModes() {
    const box = $("modes");
    box.replaceChildren();
    const r = S.result;
    const add = (j, text) => {
      const b = el("button", { type: "button", "data-mode": String(j), "aria-pressed": String(S.mode === j) }, text);
      b.addEventListener("click", () => showMode(j));
      box.append(b);
    };
    add(-1, "Stationary response");
    if (r) r.modes.slice(0, 12).forEach((_, j) => add(j, `Mode ${j + 1}: ${fmt(r.omegas[j], 4)} rad/s`));
  }

  function showMode(j) {
    S.mode = j;
    S.scale = autoScale();
    buildModes();
    captionMotion();
    drawMotion();
  }

  function captionMotion() {
    const r = S.result;
    let text;
    if (!r) text = "";
    else if (S.mode >= 0) text = `Mode ${S.mode + 1} (ω = ${fmt(r.omegas[S.mode], 5)} rad/s, f = ${fmt(r.omegas[S.mode] / (2 * Math.PI), 5)} Hz), largest component +1: ` + COORDS.map((c, i) => `${c.name} ${fmt((r.modes[S.mode] || [])[i], 4)}`).join(", ") + ".";
    else text = `The stationary response, one period in 2 s.` + (DR ? ` Displacements drawn ×${fmt(S.scale * Math.pow(10, Number($("scale").value) / 50), 3)}; the parts keep the file's dimensions.` : " Each bar is a coordinate, scaled by the largest amplitude of its unit.");
    $("motion-caption").textContent = text;
  }

  function buildShown() {
    const box = $("shown");
    for (const x of NAMES) {
      if (!LIVE && !(PRE.curve && PRE.curve.names[x.name])) continue;
      const id = `show-${x.name}`;
      const lab = el("label", { for: id });
      const box1 = el("input", { type: "checkbox", id });
      box1.checked = S.shown.has(x.name);
      box1.addEventListener("change", () => { if (box1.checked) S.shown.add(x.name); else S.shown.delete(x.name); recompute(); });
      const sw = el("span", { class: "swatch" });
      sw.style.background = colourOf(x.name);
      if (dashOf(x.name).length) sw.style.background = `repeating-linear-gradient(90deg, ${colourOf(x.name)} 0 4px, transparent 4px 6px)`;
      lab.append(box1, sw, symbolNode(x));
      box.append(lab);
    }
  }

  function render() {
    const r = S.result;
    if (r) renderNumbers(r);
    renderDiagnosis(r);
    drawResponse();
    drawPeriodic();
    if (r && S.mode >= r.modes.length) S.mode = -1;
    const before = $("modes").childElementCount;
    if (!r || before !== (r.modes.slice(0, 12).length + 1)) buildModes();
    else $("modes").querySelectorAll("button").forEach((b, j) => { if (j > 0) b.textContent = `Mode ${j}: ${fmt(r.omegas[j - 1], 4)} rad/s`; });
    S.scale = autoScale();
    captionMotion();
    drawMotion();
  }

  function frame(now) {
    if (S.playing) {
      const dt = S.last ? (now - S.last) / 1000 : 0;
      S.phase = (S.phase + dt / 2) % 1;
      drawMotion();
    }
    S.last = now;
    requestAnimationFrame(frame);
  }

  // the page's helpers for the panels of other scripts (the rotor panel, rotor.js)
  // parametersWith: the parameters p at the sliders' values, those named in `fixed` set to
  // theirs (a parameter defined by a formula then keeps the value given, as when typed)
  function parametersWith(fixed) {
    const v = Float64Array.from(S.v), o = Uint8Array.from(S.o);
    for (const [name, x] of Object.entries(fixed)) {
      const i = PARAMS.findIndex(c => c.name === name);
      if (i >= 0) { v[i] = x; o[i] = 1; }
    }
    return parameters(v, o);
  }
  window.resonantPage = Object.freeze({ el, fmt, number, canvasContext, niceTicks, logRange, COLOURS, NOW, PARAMS,
    LIVE, NUM, parametersWith, matricesAt, listen: f => { LISTENERS.push(f); } });

  // -- the script interface ------------------------------------------------------------------
  function jsonMatrix(a) {
    if (!a) return null;
    const out = [];
    for (let i = 0; i < n; i++) out.push(Array.from(a.slice(i * n, (i + 1) * n)));
    return out;
  }

  function state() {
    const r = S.result;
    const out = { title: D.title, coordinates: COORDS.map(c => c.name), parameters: Object.fromEntries(PARAMS.map((c, i) => [c.name, r ? r.p[i] : S.v[i]])),
      live: LIVE, error: r ? r.error : $("status").textContent, timing_ms: S.timing };
    if (PER) {
      const pr = S.periodic;
      out.periodic = pr && !pr.error ? { harmonics: PER.harmonics, period: PER.period, largest: pr.largest } : { error: pr ? pr.error : null };
    }
    if (!r) return out;
    Object.assign(out, { M: jsonMatrix(r.M), C: jsonMatrix(r.C), K: jsonMatrix(r.K), natural_frequencies: Array.from(r.omegas),
      harmonics: r.harmonics, amplitudes: r.amplitudes, phases: r.phases, stability: r.stability,
      eigenvalues: r.eig ? Array.from(r.eig.re).map((x, i) => [x, r.eig.im[i]]) : undefined,
      damping_ratios: r.damping.ratios, mode_shapes: r.modes, stationary_available: r.available, warnings: r.warnings,
      excitation: FREQ >= 0 ? { parameter: PARAMS[FREQ].name, value: r.p[FREQ] } : null,
      view: { mode: S.mode, phase: S.phase, playing: S.playing, scale: S.scale * Math.pow(10, Number($("scale").value) / 50) } });
    return JSON.parse(JSON.stringify(out));
  }

  function set(values) {
    const unknown = [];
    for (const [name, x] of Object.entries(values || {})) {
      const i = PARAMS.findIndex(c => c.name === name);
      if (i < 0 || typeof x !== "number" || !Number.isFinite(x) || (!LIVE && i !== FREQ)) { unknown.push(name); continue; }
      S.v[i] = x;
      if (PARAMS[i].formula) S.o[i] = 1;
    }
    recompute();
    syncControls();
    if (unknown.length) throw new Error(`not a parameter, not a finite number${LIVE ? "" : " or fixed on this precomputed page"}: ${unknown.join(", ")}`);
    return state();
  }

  window.resonant = Object.freeze({
    set, state,
    reset() { S.v = Float64Array.from(P0); S.o.fill(0); recompute(); syncControls(); return state(); },
    play() { S.playing = true; $("play").setAttribute("aria-pressed", "true"); $("play").textContent = "Pause"; },
    pause() { S.playing = false; $("play").setAttribute("aria-pressed", "false"); $("play").textContent = "Play"; },
    setPhase(x) { S.phase = ((Number(x) % 1) + 1) % 1; drawMotion(); return S.phase; },
    showMode(j) { showMode(Number(j)); return S.mode; },
    timeUpdate() { const t0 = performance.now(); recompute(); return performance.now() - t0; },
    // what the response plot shows: its y range (log10, in the units shown), the curves (SI)
    // and whether the current value lies beyond the plotted range
    response() {
      if (!S.curve || !S.plotted) return null;
      return JSON.parse(JSON.stringify({ ...S.plotted, values: S.curve.values,
        curves: Object.fromEntries(S.plotted.names.map(s => [s, S.curve.curves[s].map((y, j) => (Number.isFinite(y) ? y / (UNIT[s] ? UNIT[s].factor : 1) : null))])) }));
    },
  });

  // -- start ---------------------------------------------------------------------------------
  $("title").textContent = D.title || D.file;
  $("file").textContent = D.file;
  const badge = $("badge");
  badge.textContent = LIVE ? "computed live from the model's equations" : "precomputed";
  if (!LIVE) badge.classList.add("pre");
  if (D.note) { $("note").textContent = D.note; $("note").hidden = false; }
  if (!LIVE) $("numbers-heading").nextElementSibling.before(el("p", { class: "hint" }, "Precomputed by resonant at the file's parameter values; the frequency slider moves along the computed curve."));
  buildControls();
  buildShown();
  $("play").addEventListener("click", () => (S.playing ? window.resonant.pause() : window.resonant.play()));
  $("scale").addEventListener("input", () => { captionMotion(); drawMotion(); });
  if (!DR) {  // bars: the scale of a drawing does not apply; as tall as the coordinates need
    $("scale").closest(".toolbar").querySelectorAll("label, input, .hint").forEach(e => { e.hidden = true; });
    const tallest = window.matchMedia("(max-width: 899px)").matches ? 220 : 420;  // a phone: it stays in view
    $("mechanism").style.height = `${Math.min(tallest, Math.max(90, 34 * BARS.length + 24))}px`;
  }
  window.addEventListener("resize", () => render());
  recompute();
  syncControls();
  requestAnimationFrame(frame);
})();
