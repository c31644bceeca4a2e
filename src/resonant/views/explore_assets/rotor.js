// resonant explore: the rotor panel (a model with [campbell]).  Reads the page's data
// (D.rotor, computed by resonant: resonant.views.explore.rotor_data): a speed slider over
// the Campbell diagram's speeds, the unbalance orbits of the stations drawn at the current
// speed (their semi-axes 0-pk computed here from the complex amplitudes X, Y), the Campbell
// diagram with the current speed marked, and the modes at that speed.
"use strict";
(() => {
  const R = JSON.parse(document.getElementById("resonant-data").textContent).rotor;
  const H = window.resonantPage;
  if (!R || !H) return;
  const $ = id => document.getElementById(id);
  const { el, fmt, number, canvasContext, niceTicks, COLOURS, NOW } = H;
  const N = R.speeds.length;
  // the speed shown in the unit of its slider (rpm where the model gives rpm), else rad/s
  const control = H.PARAMS.find(c => c.name === R.speed_parameter);
  const unit = control && control.unit ? control.unit : "rad/s";
  const factor = control && control.unit ? control.factor : 1;
  const S = { k: Math.min(Math.max(R.start, 0), N - 1) };

  // the orbit of station i at speed k: x = Re(X e^(i theta)), y = Re(Y e^(i theta))
  function amplitudes(k, i) {
    const O = R.orbits;
    return [O.X.re[k][i], O.X.im[k][i], O.Y.re[k][i], O.Y.im[k][i]];
  }
  // forward and backward circles |X + iY|/2, |conj X + i conj Y|/2: the semi-axes 0-pk
  function semiAxes(k, i) {
    const [xr, xi, yr, yi] = amplitudes(k, i);
    const f = Math.hypot(xr - yi, xi + yr) / 2, b = Math.hypot(xr + yi, yr - xi) / 2;
    const line = Math.abs(f - b) <= 1e-9 * Math.max(f + b, 1e-300);
    return { major: f + b, minor: Math.abs(f - b), precession: line ? "line" : (f > b ? "forward" : "backward") };
  }

  function orbitState(k) {
    if (!R.orbits) return null;
    return R.orbits.stations.map((name, i) => ({ station: name, ...semiAxes(k, i) }));
  }

  function state() {
    const k = S.k;
    return JSON.parse(JSON.stringify({
      index: k, speed: R.speeds[k], speed_parameter: R.speed_parameter,
      frequencies: R.frequencies[k], damping_ratios: R.damping_ratios[k], whirl: R.whirl[k],
      orbits: orbitState(k), amplitude_convention: "0-pk (pk-pk = 2 x 0-pk)",
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
    if (!(largest > 0)) { caption.textContent = `At ${speedText(R.speeds[k])}: no motion.`; return; }
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
  }

  function render() {
    $("rotor-speed-out").textContent = speedText(R.speeds[S.k]);
    $("rotor-speed").setAttribute("aria-valuetext", speedText(R.speeds[S.k]));
    drawOrbit();
    drawCampbell();
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

  $("rotor-panel").hidden = false;
  const slider = $("rotor-speed");
  slider.max = String(N - 1);
  slider.value = String(S.k);
  slider.addEventListener("input", () => { S.k = Number(slider.value); render(); });
  window.addEventListener("resize", () => render());
  window.resonantRotor = Object.freeze({ state, set, speeds: () => R.speeds.slice() });
  render();
})();
