// resonant explore: the rotor panel (a model with [campbell]).  Reads the page's data
// (D.rotor, computed by resonant: resonant.views.explore.rotor_data): a speed slider over
// the Campbell diagram's speeds, the unbalance orbits of the stations drawn at the current
// speed (their semi-axes 0-pk computed here from the complex amplitudes X, Y; on a live
// page X, Y are solved here at the parameter sliders' values), the forces the bearings
// transmit (their amplitudes computed here from the complex x and y forces, live likewise)
// against speed, the Campbell diagram with the current speed marked, the modes at that
// speed and the undamped critical speed map (drawn from resonant's chart of it).
"use strict";
(() => {
  const R = JSON.parse(document.getElementById("resonant-data").textContent).rotor;
  const H = window.resonantPage;
  if (!R || !H) return;
  const $ = id => document.getElementById(id);
  const { el, fmt, number, canvasContext, niceTicks, logRange, COLOURS, NOW } = H;
  const N = R.speeds.length;
  // the decades below its highest critical speed that the map's axis spans
  const MAP_DECADES = 3;
  // the speed shown in the unit of its slider (rpm where the model gives rpm), else rad/s
  const control = H.PARAMS.find(c => c.name === R.speed_parameter);
  const unit = control && control.unit ? control.unit : "rad/s";
  const factor = control && control.unit ? control.factor : 1;
  // the speed shown (its index) and the map shown (the undamped one where there is one)
  const S = { k: Math.min(Math.max(R.start, 0), N - 1),
    map: R.map && !R.map.undamped && R.map.damped ? "damped" : "undamped" };

  // a number of the data: null (NaN in resonant's JSON: an unbounded response) is NaN
  const num = v => (v === null ? NaN : v);

  // The orbits and the bearing forces follow the sliders on a live page: at each speed of
  // the slider the unbalance response (K - W^2 M + i W C) z = W^2 (c - i s), M, C (with
  // W G), K printed from the model at the sliders' values with the speed parameter at W
  // (what resonant.analyses.unbalance.unbalance_response solves), and each bearing's force
  // (K_b + i W C_b)(z_station - z_pedestal) with its coefficients printed
  // (resonantBearings).  Elsewhere (a precomputed page) they are resonant's, at the file's
  // values.  The Campbell diagram, its modes and the map are always the file's.
  const LIVE = Boolean(H.LIVE && R.orbits && R.orbits.rows);
  const BEARINGS = LIVE && R.forces && R.forces.station && typeof resonantBearings === "function";
  // the complex amplitudes shown: {X, Y} per station, {FX, FY} per bearing ({re, im}[k][i])
  // at every slider speed, and each bearing's force (0-pk) along the chart's finer grid
  let O = R.orbits, F = R.forces, CURVE = R.forces ? R.forces.curve.major.map(v => v.map(num)) : [];
  let ERROR = "";
  function table(rows, cols) { return { re: rows.map(() => new Array(cols).fill(NaN)), im: rows.map(() => new Array(cols).fill(NaN)) }; }
  // z of the unbalance at speed w (null where the solve is singular: an undamped critical speed)
  function solveAt(w) {
    const p = H.parametersWith({ [R.speed_parameter]: w });
    const { M, C, K } = H.matricesAt(p);
    const n = Math.round(Math.sqrt(M.length)), L = R.orbits.load;
    const ar = new Float64Array(n * n), ai = new Float64Array(n * n);
    for (let i = 0; i < n * n; i++) { ar[i] = K[i] - w * w * M[i]; ai[i] = w * C[i]; }
    const z = H.NUM.complexSolve(n, ar, ai, L.c.map(v => w * w * v), L.s.map(v => -w * w * v));
    return z.singular ? null : { re: z.re, im: z.im, coefficients: BEARINGS ? resonantBearings(p) : null };
  }
  // bearing b's x and y forces [fxr, fxi, fyr, fyi] at speed w from the response z
  function bearingForce(z, b, w) {
    const [ix, iy] = R.forces.station[b], ped = R.forces.pedestal[b];
    const d = [ix, iy].map((i, j) => [z.re[i] - (ped ? z.re[ped[j]] : 0), z.im[i] - (ped ? z.im[ped[j]] : 0)]);
    const k = z.coefficients.slice(8 * b, 8 * b + 8);  // kxx kxy kyx kyy cxx cxy cyx cyy
    const out = [];
    for (const r of [0, 1]) {
      let fr = 0, fi = 0;
      for (const c of [0, 1]) {
        const kr = k[2 * r + c], ki = w * k[4 + 2 * r + c];
        fr += kr * d[c][0] - ki * d[c][1]; fi += kr * d[c][1] + ki * d[c][0];
      }
      out.push(fr, fi);
    }
    return out;
  }
  function follow() {
    if (!LIVE) return;
    try {
      const stations = R.orbits.rows, nb = BEARINGS ? R.forces.bearings.length : 0;
      const o = { ...R.orbits, X: table(R.speeds, stations.length), Y: table(R.speeds, stations.length) };
      const f = BEARINGS ? { ...R.forces, FX: table(R.speeds, nb), FY: table(R.speeds, nb) } : R.forces;
      R.speeds.forEach((w, k) => {
        const z = solveAt(w);
        if (!z) return;
        stations.forEach(([ix, iy], i) => {
          o.X.re[k][i] = z.re[ix]; o.X.im[k][i] = z.im[ix]; o.Y.re[k][i] = z.re[iy]; o.Y.im[k][i] = z.im[iy];
        });
        for (let b = 0; b < nb; b++) {
          const [xr, xi, yr, yi] = bearingForce(z, b, w);
          f.FX.re[k][b] = xr; f.FX.im[k][b] = xi; f.FY.re[k][b] = yr; f.FY.im[k][b] = yi;
        }
      });
      if (BEARINGS) {
        CURVE = R.forces.bearings.map(() => new Array(R.forces.curve.speeds.length).fill(NaN));
        R.forces.curve.speeds.forEach((w, j) => {
          const z = solveAt(w);
          if (z) for (let b = 0; b < nb; b++) CURVE[b][j] = ellipse(bearingForce(z, b, w)).major;
        });
      }
      O = o; F = f; ERROR = "";
    } catch (e) {
      // the sliders' values make M, C or K not finite: the file's numbers stay, and say so
      O = R.orbits; F = R.forces; CURVE = R.forces ? R.forces.curve.major.map(v => v.map(num)) : [];
      ERROR = String(e.message || e);
    }
  }
  // the orbit of station i at speed k: x = Re(X e^(i theta)), y = Re(Y e^(i theta))
  function amplitudes(k, i) {
    return [O.X.re[k][i], O.X.im[k][i], O.Y.re[k][i], O.Y.im[k][i]].map(num);
  }
  // the ellipse x = Re(X e^(i theta)), y = Re(Y e^(i theta)): its forward and backward
  // circles |X + iY|/2, |conj X + i conj Y|/2 give the semi-axes 0-pk
  function ellipse([xr, xi, yr, yi]) {
    const f = Math.hypot(xr - yi, xi + yr) / 2, b = Math.hypot(xr + yi, yr - xi) / 2;
    const line = Math.abs(f - b) <= 1e-9 * Math.max(f + b, 1e-300);
    return { major: f + b, minor: Math.abs(f - b), precession: line ? "line" : (f > b ? "forward" : "backward") };
  }
  function semiAxes(k, i) { return ellipse(amplitudes(k, i)); }
  // the force bearing i transmits at speed k: the complex amplitudes of its x and y forces
  function forceAmplitudes(k, i) {
    return [F.FX.re[k][i], F.FX.im[k][i], F.FY.re[k][i], F.FY.im[k][i]].map(num);
  }
  function forceState(k) {
    if (!R.forces) return null;
    return R.forces.bearings.map((name, i) => {
      const e = ellipse(forceAmplitudes(k, i));
      return { bearing: name, major: e.major, minor: e.minor };
    });
  }
  // each bearing's force (major semi-axis, 0-pk) at every speed, for its chart
  const forcesAtSpeeds = () => (R.forces ? R.forces.bearings.map((_, i) => R.speeds.map((_, k) => ellipse(forceAmplitudes(k, i)).major)) : []);

  function orbitState(k) {
    if (!R.orbits) return null;
    return R.orbits.stations.map((name, i) => ({ station: name, ...semiAxes(k, i) }));
  }

  // a critical speed map as the page holds it, and the speeds (rpm) its chart draws
  function mapState(m) {
    return m ? { stiffness: m.stiffness, orders: m.orders, speeds: m.speeds, whirl: m.whirl,
      damping_ratios: m.damping_ratios, drawn: m.chart.curves.map(c => c.y) } : null;
  }

  function state() {
    const k = S.k;
    return JSON.parse(JSON.stringify({
      index: k, speed: R.speeds[k], speed_parameter: R.speed_parameter,
      frequencies: R.frequencies[k], damping_ratios: R.damping_ratios[k], whirl: R.whirl[k],
      orbits: orbitState(k), amplitude_convention: "0-pk (pk-pk = 2 x 0-pk)",
      follows_sliders: { orbits: LIVE && !ERROR, bearing_forces: Boolean(BEARINGS) && !ERROR, note: followsText() },
      bearing_forces: forceState(k),
      map: R.map ? { own: R.map.own, shown: S.map, note: R.map.note, undamped: mapState(R.map.undamped), damped: mapState(R.map.damped) } : null,
      threshold: R.threshold, critical: R.critical }));
  }

  function speedText(w) { return `${fmt(w / factor, 5)} ${unit}${unit === "rad/s" ? "" : ` (${fmt(w, 5)} rad/s)`}`; }

  function drawOrbit() {
    const { ctx, w, h } = canvasContext($("rotor-orbit"));
    const caption = $("rotor-orbit-caption");
    if (!R.orbits) {
      ctx.fillStyle = "#5b5b60"; ctx.fillText("No [[unbalance]] in the model: no orbit.", 12, 24);
      caption.textContent = ""; return;
    }
    const k = S.k, stations = R.orbits.stations;
    const axes = stations.map((_, i) => semiAxes(k, i));
    const largest = Math.max(...axes.map(a => a.major).filter(Number.isFinite), 0);
    const cx = w / 2, cy = h / 2, radius = Math.min(w, h) / 2 - 22;
    ctx.strokeStyle = "#e4e1da"; ctx.lineWidth = 1;
    ctx.beginPath(); ctx.moveTo(cx - radius - 8, cy); ctx.lineTo(cx + radius + 8, cy);
    ctx.moveTo(cx, cy - radius - 8); ctx.lineTo(cx, cy + radius + 8); ctx.stroke();
    ctx.fillStyle = "#5b5b60"; ctx.textAlign = "left";
    ctx.fillText("x", cx + radius + 10 > w - 8 ? w - 10 : cx + radius + 2, cy - 4);
    ctx.fillText("y", cx + 4, 12);
    if (!(largest > 0)) {
      // nothing to draw: say why (at rest the unbalance force m e Omega^2 is zero)
      const w0 = R.speeds[k], unbounded = axes.some(a => !Number.isFinite(a.major));
      const why = w0 === 0 ? "the rotor is at rest: the unbalance force m e Ω² is zero, so there is no unbalance motion."
        : (unbounded ? "the response is unbounded here (an undamped critical speed)." : "no motion.");
      ctx.fillStyle = "#5b5b60"; ctx.textAlign = "center";
      ctx.fillText(w0 === 0 ? "At rest: no unbalance force (∝ Ω²)" : `${why[0].toUpperCase()}${why.slice(1)}`, cx, cy + 20);
      caption.textContent = `At ${speedText(w0)}: ${why}` + (w0 === 0 ? " It grows as Ω²: move the speed slider." : "");
      return;
    }
    const scale = radius / largest;
    stations.forEach((name, i) => {
      const [xr, xi, yr, yi] = amplitudes(k, i);
      ctx.strokeStyle = COLOURS[i % COLOURS.length]; ctx.fillStyle = ctx.strokeStyle; ctx.lineWidth = 2;
      ctx.beginPath();
      for (let j = 0; j <= 96; j++) {
        const t = 2 * Math.PI * j / 96;
        const x = xr * Math.cos(t) - xi * Math.sin(t), y = yr * Math.cos(t) - yi * Math.sin(t);
        if (j === 0) ctx.moveTo(cx + scale * x, cy - scale * y); else ctx.lineTo(cx + scale * x, cy - scale * y);
      }
      ctx.stroke();
      // where the station is at t = 0 (the unbalance along its phase)
      ctx.beginPath(); ctx.arc(cx + scale * xr, cy - scale * yr, 3.5, 0, 2 * Math.PI); ctx.fill();
      ctx.textAlign = "left";
      ctx.fillText(name || "(x, y)", 8, 16 + 14 * i);
    });
    caption.textContent = `The orbits at ${speedText(R.speeds[k])}, the largest major semi-axis ${fmt(largest, 4)} m 0-pk ` +
      `(${fmt(2 * largest, 4)} m pk-pk) filling the plot; a dot: where each station is at t = 0.`;
  }

  // a power of ten as text: 1e5, 0.01, 100
  function powerText(e) { return Math.abs(e) >= 4 ? `1e${e}` : fmt(Math.pow(10, e), 3); }
  // the ticks of an axis from a to b (log10 of the values on a log axis): decades, with 2
  // and 5 between them where there are fewer than two
  function ticks(a, b, log, count) {
    if (!log) return niceTicks(a, b, count).map(v => [v, fmt(v, 4)]);
    const out = [], first = Math.ceil(a - 1e-9), last = Math.floor(b + 1e-9);
    const every = Math.max(1, Math.ceil((last - first + 1) / count));
    const steps = last - first < 1 ? [1, 2, 5] : [1];
    for (let e = Math.floor(a); e <= last; e++) {
      for (const m of steps) {
        const v = Math.log10(m) + e;
        if (v >= a - 1e-9 && v <= b + 1e-9 && (m !== 1 || (e - first) % every === 0)) out.push([v, m === 1 ? powerText(e) : fmt(m * Math.pow(10, e), 3)]);
      }
    }
    return out;
  }
  // a chart's frame: the grid, the ticks and the axes' titles; x and y are the ranges
  // (log10 of the values on a log axis); returns the maps from values to pixels
  function frame(ctx, w, h, a) {
    const left = 62, right = 22, top = 12, bottom = 36;
    const tx = a.xlog ? Math.log10 : (v => v), ty = a.ylog ? Math.log10 : (v => v);
    const X = x => left + (w - left - right) * (tx(x) - a.x[0]) / ((a.x[1] - a.x[0]) || 1);
    const Y = y => top + (h - top - bottom) * (1 - (ty(y) - a.y[0]) / ((a.y[1] - a.y[0]) || 1));
    const back = v => (a.xlog ? Math.pow(10, v) : v), up = v => (a.ylog ? Math.pow(10, v) : v);
    ctx.strokeStyle = "#e4e1da"; ctx.fillStyle = "#5b5b60"; ctx.lineWidth = 1; ctx.textAlign = "center";
    for (const [v, text] of ticks(a.x[0], a.x[1], a.xlog, Math.max(3, Math.min(6, Math.floor((w - left - right) / 70))))) {
      const px = X(back(v));
      ctx.beginPath(); ctx.moveTo(px, top); ctx.lineTo(px, h - bottom); ctx.stroke();
      ctx.fillText(text, px, h - bottom + 14);
    }
    ctx.textAlign = "right";
    for (const [v, text] of ticks(a.y[0], a.y[1], a.ylog, 5)) {
      const py = Y(up(v));
      ctx.beginPath(); ctx.moveTo(left, py); ctx.lineTo(w - right, py); ctx.stroke();
      ctx.fillText(text, left - 4, py + 4);
    }
    ctx.fillStyle = "#1d1d1f"; ctx.textAlign = "center";
    ctx.fillText(a.xlabel, left + (w - left - right) / 2, h - 4);
    ctx.save(); ctx.translate(12, top + (h - top - bottom) / 2); ctx.rotate(-Math.PI / 2);
    ctx.fillText(a.ylabel, 0, 0); ctx.restore();
    const clip = () => { ctx.save(); ctx.beginPath(); ctx.rect(left, top, w - left - right, h - top - bottom); ctx.clip(); };
    return { X, Y, left, right, top, bottom, clip };
  }
  // a curve through the points (xs[k], ys[k]), broken where a value is not finite (or not
  // positive on a log axis)
  function polyline(ctx, f, xs, ys, log) {
    ctx.beginPath();
    let pen = false;
    for (let k = 0; k < xs.length; k++) {
      const x = xs[k], y = ys[k];
      if (!Number.isFinite(x) || !Number.isFinite(y) || (log && !(y > 0))) { pen = false; continue; }
      if (pen) ctx.lineTo(f.X(x), f.Y(y)); else ctx.moveTo(f.X(x), f.Y(y));
      pen = true;
    }
    ctx.stroke();
  }
  // the names of the curves in their colours, at the top left or the bottom right (below
  // the rise of a force or a critical speed)
  function legend(ctx, f, w, h, items, bottomRight) {
    ctx.textAlign = bottomRight ? "right" : "left";
    items.forEach(([text, colour], i) => {
      ctx.fillStyle = colour;
      if (bottomRight) ctx.fillText(text, w - f.right - 6, h - f.bottom - 8 - 14 * (items.length - 1 - i));
      else ctx.fillText(text, f.left + 6, f.top + 14 + 14 * i);
    });
  }
  // a stiffness as text: 1e6, 2.5e5
  function stiffnessText(k) { return k >= 1e4 ? k.toExponential(3).replace(/\.?0+e/, "e").replace("e+", "e") : fmt(k, 4); }

  function drawForces() {
    const { ctx, w, h } = canvasContext($("rotor-forces"));
    const caption = $("rotor-forces-caption");
    if (!R.forces) {
      ctx.fillStyle = "#5b5b60"; ctx.textAlign = "left";
      ctx.fillText(R.orbits ? "No [rotor] bearings: no bearing forces." : "No [[unbalance]] in the model: no bearing forces.", 12, 24);
      caption.textContent = ""; return;
    }
    // the curve on its own finer grid (a lightly damped peak falls between the slider's
    // speeds), the dots at the slider's speed
    const k = S.k, xs = R.speeds.map(v => v / factor);
    const curve = R.forces.curve, cs = curve.speeds.map(v => v / factor);
    const CURVES = CURVE, FORCES = forcesAtSpeeds();
    const y = logRange(CURVES.flat().concat(FORCES.flat()));
    const f = frame(ctx, w, h, { x: [xs[0], xs[N - 1]], y, xlog: false, ylog: true,
      xlabel: `speed ${R.speed_parameter} (${unit})`, ylabel: "bearing force 0-pk (N)" });
    f.clip();
    CURVES.forEach((values, i) => {
      ctx.strokeStyle = COLOURS[i % COLOURS.length]; ctx.lineWidth = 1.8;
      polyline(ctx, f, cs, values, true);
    });
    const px = f.X(xs[k]);
    ctx.strokeStyle = NOW; ctx.lineWidth = 2;
    ctx.beginPath(); ctx.moveTo(px, f.top); ctx.lineTo(px, h - f.bottom); ctx.stroke();
    FORCES.forEach((values, i) => {
      if (values[k] > 0) { ctx.fillStyle = COLOURS[i % COLOURS.length]; ctx.beginPath(); ctx.arc(px, f.Y(values[k]), 3.5, 0, 2 * Math.PI); ctx.fill(); }
    });
    ctx.restore();
    legend(ctx, f, w, h, R.forces.bearings.map((name, i) => [name, COLOURS[i % COLOURS.length]]), true);
    const now = forceState(k).map(b => `${b.bearing} ${fmt(b.major, 4)} N`).join(", ");
    caption.textContent = `The force each bearing transmits, (K + iΩC)(z − z_pedestal), its major semi-axis 0-pk (pk-pk = 2 × 0-pk) against speed, log scale; ` +
      (R.speeds[k] === 0 ? `at rest none (the unbalance force m e Ω² is zero)` : `at ${speedText(R.speeds[k])}: ${now}`) + "; the dark line: the current speed.";
  }

  function drawMap() {
    const { ctx, w, h } = canvasContext($("rotor-map"));
    const caption = $("rotor-map-caption");
    const M = R.map, shown = M ? M[S.map] : null;
    if (!shown) {
      ctx.fillStyle = "#5b5b60"; ctx.textAlign = "left";
      ctx.fillText(M ? "No critical speed map (see the caption)." : "No [rotor] bearings: no critical speed map.", 12, 24);
      caption.textContent = M && M.note ? `${M.note[0].toUpperCase()}${M.note.slice(1)}.` : ""; return;
    }
    const C = shown.chart, damped = S.map === "damped";
    const now = R.speeds[S.k] / R.rpm;
    // at most MAP_DECADES below the highest speed: a damped map's critical speed of a nearly
    // critically damped mode (its damped frequency close to 0) runs off the bottom
    const values = C.curves.flatMap(c => c.y.map(num)).filter(v => v > 0);
    const highest = Math.max(...values, 0), cut = values.some(v => v < highest * Math.pow(10, -MAP_DECADES));
    const y = logRange(values.filter(v => v >= highest * Math.pow(10, -MAP_DECADES)));
    const f = frame(ctx, w, h, { x: C.xlim.map(Math.log10), y, xlog: true, ylog: true,
      xlabel: C.xtext || C.xlabel, ylabel: C.ytext || C.ylabel });
    f.clip();
    // the bearings' own stiffness: grey dotted lines (there the map's speeds are the
    // Campbell diagram's critical speeds)
    ctx.strokeStyle = "#8a8a8a"; ctx.lineWidth = 1; ctx.setLineDash([2, 3]);
    for (const k of M.own) { ctx.beginPath(); ctx.moveTo(f.X(k), f.top); ctx.lineTo(f.X(k), h - f.bottom); ctx.stroke(); }
    for (const c of C.curves) {
      ctx.strokeStyle = c.color; ctx.fillStyle = c.color; ctx.lineWidth = 1.3 * c.width;
      ctx.setLineDash(c.dash ? c.dash.split(/[ ,]+/).map(v => Number(v) * c.width).filter(v => Number.isFinite(v) && v >= 0) : []);
      const ys = c.y.map(num);
      if (c.line) polyline(ctx, f, c.x, ys, true);
      ctx.setLineDash([]);
      if (c.marker) c.x.forEach((x, i) => { if (ys[i] > 0) { ctx.beginPath(); ctx.arc(f.X(x), f.Y(ys[i]), 2.5, 0, 2 * Math.PI); ctx.fill(); } });
    }
    // the current speed across the map
    const inside = now > 0 && Math.log10(now) >= y[0] && Math.log10(now) <= y[1];
    if (inside) {
      ctx.strokeStyle = NOW; ctx.lineWidth = 2;
      ctx.beginPath(); ctx.moveTo(f.left, f.Y(now)); ctx.lineTo(w - f.right, f.Y(now)); ctx.stroke();
    }
    ctx.restore();
    legend(ctx, f, w, h, C.curves.map(c => [c.text || c.label, c.color]), true);
    const own = M.own.map(k => `${stiffnessText(k)} N/m`).join(", ");
    caption.textContent = (damped ? "The damped critical speeds (where a mode's damped frequency is the order times the speed) against the bearings' stiffness (every bearing kxx = kyy = k, its damping and cross coupling kept)"
      : "The undamped critical speeds against the bearings' stiffness (every bearing kxx = kyy = k, no cross coupling, no damping)") +
      `, log-log, as resonant speed-map${damped ? " --damped" : ""} draws them` +
      (own ? `; dotted: the bearings' own stiffness (${own})` : "") +
      (inside ? `; the dark line: the current speed, ${fmt(now, 5)} rpm.` : `; the current speed, ${fmt(now, 5)} rpm, is outside the plot.`) +
      (cut ? ` Critical speeds below ${fmt(highest * Math.pow(10, -MAP_DECADES), 3)} rpm run off the bottom (a nearly critically damped mode on soft bearings has a damped frequency close to 0).` : "") +
      (M.note ? ` (${M.note}.)` : "");
  }

  function drawCampbell() {
    const { ctx, w, h } = canvasContext($("rotor-campbell"));
    const left = 58, right = 24, top = 14, bottom = 36;
    const xs = R.speeds, x0 = xs[0], x1 = xs[N - 1];
    let top_ = 0;
    for (const row of R.frequencies) for (const y of row) if (Number.isFinite(y)) top_ = Math.max(top_, y);
    const y1 = (top_ || 1) * 1.08;
    const X = x => left + (w - left - right) * (x - x0) / ((x1 - x0) || 1);
    const Y = y => top + (h - top - bottom) * (1 - y / y1);
    ctx.strokeStyle = "#e4e1da"; ctx.fillStyle = "#5b5b60"; ctx.lineWidth = 1; ctx.textAlign = "center";
    for (const x of niceTicks(x0 / factor, x1 / factor, Math.max(3, Math.min(6, Math.floor((w - left - right) / 70))))) {
      const px = X(x * factor);
      ctx.beginPath(); ctx.moveTo(px, top); ctx.lineTo(px, h - bottom); ctx.stroke();
      ctx.fillText(fmt(x, 4), px, h - bottom + 14);
    }
    ctx.textAlign = "right";
    for (const y of niceTicks(0, y1, 5)) {
      const py = Y(y);
      ctx.beginPath(); ctx.moveTo(left, py); ctx.lineTo(w - right, py); ctx.stroke();
      ctx.fillText(fmt(y, 4), left - 4, py + 4);
    }
    ctx.fillStyle = "#1d1d1f"; ctx.textAlign = "center";
    ctx.fillText(`speed ${R.speed_parameter} (${unit})`, left + (w - left - right) / 2, h - 4);
    ctx.save(); ctx.translate(12, top + (h - top - bottom) / 2); ctx.rotate(-Math.PI / 2);
    ctx.fillText("damped natural frequency (rad/s)", 0, 0); ctx.restore();
    ctx.save(); ctx.beginPath(); ctx.rect(left, top, w - left - right, h - top - bottom); ctx.clip();
    // the excitation orders r Omega: grey dashed lines
    ctx.setLineDash([5, 4]); ctx.strokeStyle = "#8a8a8a"; ctx.lineWidth = 1;
    for (const r of R.orders) { ctx.beginPath(); ctx.moveTo(X(x0), Y(r * x0)); ctx.lineTo(X(x1), Y(r * x1)); ctx.stroke(); }
    ctx.setLineDash([]);
    // the branches: forward solid, backward dashed
    const branches = R.frequencies[0].length;
    for (let j = 0; j < branches; j++) {
      ctx.strokeStyle = COLOURS[j % COLOURS.length]; ctx.lineWidth = 1.8;
      ctx.setLineDash(R.whirl[S.k][j] === "backward" ? [6, 3] : []);
      ctx.beginPath();
      let pen = false;
      for (let k = 0; k < N; k++) {
        const y = R.frequencies[k][j];
        if (!Number.isFinite(y)) { pen = false; continue; }
        if (pen) ctx.lineTo(X(xs[k]), Y(y)); else ctx.moveTo(X(xs[k]), Y(y));
        pen = true;
      }
      ctx.stroke();
    }
    ctx.setLineDash([]);
    // the critical speeds: open circles on the order lines
    ctx.strokeStyle = NOW; ctx.lineWidth = 1.5;
    for (const c of R.critical) { ctx.beginPath(); ctx.arc(X(c.speed), Y(c.order * c.speed), 4, 0, 2 * Math.PI); ctx.stroke(); }
    if (R.threshold.speed !== null) {
      ctx.strokeStyle = "#a8322d"; ctx.setLineDash([2, 3]);
      ctx.beginPath(); ctx.moveTo(X(R.threshold.speed), top); ctx.lineTo(X(R.threshold.speed), h - bottom); ctx.stroke();
      ctx.setLineDash([]);
    }
    // the current speed
    const px = X(xs[S.k]);
    ctx.strokeStyle = NOW; ctx.lineWidth = 2;
    ctx.beginPath(); ctx.moveTo(px, top); ctx.lineTo(px, h - bottom); ctx.stroke();
    ctx.fillStyle = NOW;
    for (let j = 0; j < branches; j++) {
      const y = R.frequencies[S.k][j];
      if (Number.isFinite(y)) { ctx.beginPath(); ctx.arc(px, Y(y), 3.5, 0, 2 * Math.PI); ctx.fill(); }
    }
    ctx.restore();
    const crit = R.critical.map(c => `${fmt(c.speed / factor, 5)} ${unit} (${c.order}x, ${c.whirl})`).join("; ");
    const th = R.threshold.speed !== null ? `threshold of instability ${fmt(R.threshold.speed / factor, 5)} ${unit} (red dotted)` : `threshold: ${R.threshold.verdict}`;
    $("rotor-campbell-caption").textContent = `Branches: forward solid, backward dashed; grey: the orders ${R.orders.map(r => `${r}x`).join(", ")}; ` +
      `circles: critical speeds${crit ? ` ${crit}` : ": none in the range"}; ${th}; the dark line: the current speed.`;
  }

  function row(table, cells, header) {
    const tr = el("tr");
    for (const c of cells) {
      const td = el(header ? "th" : "td");
      if (c instanceof Node) td.append(c); else td.textContent = c;
      tr.append(td);
    }
    table.append(tr);
  }

  function renderTables() {
    const k = S.k;
    const modes = $("rotor-modes");
    modes.replaceChildren();
    row(modes, ["branch", "frequency (rad/s)", "(Hz)", "damping ratio", "whirl", "motion"], true);
    R.frequencies[k].forEach((f, j) => row(modes, [String(j + 1), number(f, 6, `rotor.frequency.${j}`),
      number(f / (2 * Math.PI), 6), number(R.damping_ratios[k][j], 4, `rotor.damping.${j}`),
      R.whirl[k][j], R.motion[j] || ""]));
    const orbits = $("rotor-orbits");
    orbits.replaceChildren();
    if (!R.orbits) return;
    row(orbits, ["station", "major semi-axis 0-pk (m)", "minor semi-axis 0-pk (m)", "major axis pk-pk (m)", "precession"], true);
    orbitState(k).forEach((o, i) => row(orbits, [o.station || "(x, y)", number(o.major, 6, `rotor.major.${i}`),
      number(o.minor, 6, `rotor.minor.${i}`), number(2 * o.major, 6), o.precession]));
    const forces = $("rotor-forces-table");
    forces.replaceChildren();
    if (!R.forces) return;
    row(forces, ["bearing", "force 0-pk (N)", "minor semi-axis 0-pk (N)", "force pk-pk (N)"], true);
    forceState(k).forEach((b, i) => row(forces, [b.bearing, number(b.major, 6, `rotor.force.${i}`),
      number(b.minor, 6), number(2 * b.major, 6)]));
  }

  // what follows the parameter sliders and what is the file's, said on the page
  function followsText() {
    const fixed = "The Campbell diagram, the modes at each speed and the critical speed map are resonant's at the file's parameter values (they do not follow the parameter sliders)";
    if (!R.orbits) return `${fixed}.`;
    if (ERROR) return `${fixed}; the orbits and bearing forces too, for now: at the sliders' values ${ERROR}.`;
    if (!LIVE) return `${fixed}; so are the orbits and bearing forces (this page is precomputed).`;
    if (R.forces && !BEARINGS) return `The orbits follow the parameter sliders (solved here at each speed); the bearing forces are resonant's at the file's values. ${fixed}.`;
    return `The orbits${R.forces ? " and bearing forces" : ""} follow the parameter sliders (solved here at each speed of this slider). ${fixed}.`;
  }

  function render() {
    $("rotor-follows").textContent = followsText();
    $("rotor-speed-out").textContent = speedText(R.speeds[S.k]);
    $("rotor-speed").setAttribute("aria-valuetext", speedText(R.speeds[S.k]));
    drawOrbit();
    drawCampbell();
    drawForces();
    drawMap();
    renderTables();
  }

  function set(k) {
    const index = Math.round(Number(k));
    if (!Number.isFinite(index) || index < 0 || index >= N) throw new Error(`the speed index must be 0 to ${N - 1}`);
    S.k = index;
    $("rotor-speed").value = String(index);
    render();
    return state();
  }

  // the map's buttons (where there are two maps)
  const kinds = $("rotor-map-kind");
  if (R.map && R.map.undamped && R.map.damped) {
    kinds.hidden = false;
    for (const button of kinds.querySelectorAll("button")) {
      button.setAttribute("aria-pressed", String(button.dataset.kind === S.map));
      button.addEventListener("click", () => {
        S.map = button.dataset.kind;
        for (const b of kinds.querySelectorAll("button")) b.setAttribute("aria-pressed", String(b === button));
        drawMap();
      });
    }
  }
  $("rotor-panel").hidden = false;
  const slider = $("rotor-speed");
  slider.max = String(N - 1);
  slider.value = String(S.k);
  slider.addEventListener("input", () => { S.k = Number(slider.value); render(); });
  window.addEventListener("resize", () => render());
  // the map shown: "undamped" or "damped"
  function showMap(kind) {
    if (!R.map || !R.map[kind]) throw new Error(`no ${kind} critical speed map on this page`);
    S.map = kind;
    for (const b of kinds.querySelectorAll("button")) b.setAttribute("aria-pressed", String(b.dataset.kind === kind));
    drawMap();
    return state();
  }
  window.resonantRotor = Object.freeze({ state, set, showMap, speeds: () => R.speeds.slice() });
  H.listen(() => { follow(); render(); });
  follow();
  render();
})();
