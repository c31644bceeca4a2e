// resonant explore: the numerics of the page (no library, no eval).
// Matrices are Float64Arrays in row-major order.  n <= 50 (the page's limit for live models).
// - complexSolve: Gaussian elimination with partial pivoting, (K - w^2 M + i w C) z = F_C - i F_S
// - generalized symmetric eigenproblem K x = lambda M x: Cholesky of M, then cyclic Jacobi
// - eigenvalues of a real matrix (the state matrix): balancing, Hessenberg reduction and the
//   Francis double-shift QR iteration (the classic EISPACK hqr scheme)
// - the stationary solution's peak amplitude and phase, as resonant computes them
// - a periodic load's response summed over its harmonics (an FFT)
"use strict";
const ResonantNumerics = (() => {
  const EPS = 2.220446049250313e-16;

  function identity(n) {
    const a = new Float64Array(n * n);
    for (let i = 0; i < n; i++) a[i * n + i] = 1;
    return a;
  }

  function maxAbs(a) {
    let m = 0;
    for (let i = 0; i < a.length; i++) { const v = Math.abs(a[i]); if (v > m) m = v; }
    return m;
  }

  // numpy.allclose(a, a.T, rtol=1e-12, atol=1e-12 * max|a|), as resonant tests symmetry
  function isSymmetric(n, a) {
    const atol = 1e-12 * maxAbs(a);
    for (let i = 0; i < n; i++) {
      for (let j = i + 1; j < n; j++) {
        const x = a[i * n + j], y = a[j * n + i];
        if (Math.abs(x - y) > atol + 1e-12 * Math.abs(y)) return false;
      }
    }
    return true;
  }

  // -- linear systems -------------------------------------------------------------------
  // Solves A z = b for complex A (ar + i ai) and b; returns {re, im, singular}.
  function complexSolve(n, ar0, ai0, br0, bi0) {
    const ar = Float64Array.from(ar0), ai = Float64Array.from(ai0);
    const br = Float64Array.from(br0), bi = Float64Array.from(bi0);
    let scale = 0;
    for (let i = 0; i < n * n; i++) scale = Math.max(scale, Math.hypot(ar[i], ai[i]));
    let singular = scale === 0;
    for (let k = 0; k < n; k++) {
      let p = k, best = -1;
      for (let i = k; i < n; i++) {
        const v = Math.hypot(ar[i * n + k], ai[i * n + k]);
        if (v > best) { best = v; p = i; }
      }
      if (!(best > 1e-14 * scale)) { singular = true; if (best === 0) continue; }
      if (p !== k) {
        for (let j = 0; j < n; j++) {
          let t = ar[k * n + j]; ar[k * n + j] = ar[p * n + j]; ar[p * n + j] = t;
          t = ai[k * n + j]; ai[k * n + j] = ai[p * n + j]; ai[p * n + j] = t;
        }
        let t = br[k]; br[k] = br[p]; br[p] = t;
        t = bi[k]; bi[k] = bi[p]; bi[p] = t;
      }
      const pr = ar[k * n + k], pi = ai[k * n + k];
      const d = pr * pr + pi * pi;
      for (let i = k + 1; i < n; i++) {
        const xr = ar[i * n + k], xi = ai[i * n + k];
        if (xr === 0 && xi === 0) continue;
        // f = x / pivot
        const fr = (xr * pr + xi * pi) / d, fi = (xi * pr - xr * pi) / d;
        for (let j = k + 1; j < n; j++) {
          const yr = ar[k * n + j], yi = ai[k * n + j];
          ar[i * n + j] -= fr * yr - fi * yi;
          ai[i * n + j] -= fr * yi + fi * yr;
        }
        const yr = br[k], yi = bi[k];
        br[i] -= fr * yr - fi * yi;
        bi[i] -= fr * yi + fi * yr;
        ar[i * n + k] = 0; ai[i * n + k] = 0;
      }
    }
    const zr = new Float64Array(n), zi = new Float64Array(n);
    for (let i = n - 1; i >= 0; i--) {
      let sr = br[i], si = bi[i];
      for (let j = i + 1; j < n; j++) {
        const xr = ar[i * n + j], xi = ai[i * n + j];
        sr -= xr * zr[j] - xi * zi[j];
        si -= xr * zi[j] + xi * zr[j];
      }
      const pr = ar[i * n + i], pi = ai[i * n + i], d = pr * pr + pi * pi;
      zr[i] = (sr * pr + si * pi) / d;
      zi[i] = (si * pr - sr * pi) / d;
    }
    return { re: zr, im: zi, singular };
  }

  // Solves A X = B for real A (n x n) and B (n x m), partial pivoting; null if singular.
  function realSolve(n, a0, b0, m) {
    const a = Float64Array.from(a0), b = Float64Array.from(b0);
    for (let k = 0; k < n; k++) {
      let p = k, best = -1;
      for (let i = k; i < n; i++) {
        const v = Math.abs(a[i * n + k]);
        if (v > best) { best = v; p = i; }
      }
      if (best === 0) return null;
      if (p !== k) {
        for (let j = 0; j < n; j++) { const t = a[k * n + j]; a[k * n + j] = a[p * n + j]; a[p * n + j] = t; }
        for (let j = 0; j < m; j++) { const t = b[k * m + j]; b[k * m + j] = b[p * m + j]; b[p * m + j] = t; }
      }
      const piv = a[k * n + k];
      for (let i = k + 1; i < n; i++) {
        const f = a[i * n + k] / piv;
        if (f === 0) continue;
        for (let j = k + 1; j < n; j++) a[i * n + j] -= f * a[k * n + j];
        for (let j = 0; j < m; j++) b[i * m + j] -= f * b[k * m + j];
      }
    }
    for (let i = n - 1; i >= 0; i--) {
      for (let j = 0; j < m; j++) {
        let s = b[i * m + j];
        for (let k = i + 1; k < n; k++) s -= a[i * n + k] * b[k * m + j];
        b[i * m + j] = s / a[i * n + i];
      }
    }
    return b;
  }

  // -- symmetric eigenproblems ----------------------------------------------------------
  // Cyclic Jacobi on a symmetric matrix: {values, vectors (columns)}, unsorted.
  function jacobi(n, a0) {
    const a = Float64Array.from(a0), v = identity(n);
    for (let sweep = 0; sweep < 100; sweep++) {
      let off = 0, diag = 0;
      for (let i = 0; i < n; i++) {
        diag += a[i * n + i] * a[i * n + i];
        for (let j = i + 1; j < n; j++) off += a[i * n + j] * a[i * n + j];
      }
      if (off === 0 || off <= EPS * EPS * 1e-4 * diag) break;
      for (let p = 0; p < n; p++) {
        for (let q = p + 1; q < n; q++) {
          const apq = a[p * n + q];
          if (apq === 0) continue;
          const app = a[p * n + p], aqq = a[q * n + q];
          if (Math.abs(apq) <= 1e-18 * Math.sqrt(Math.abs(app * aqq)) && sweep > 3) {
            a[p * n + q] = a[q * n + p] = 0;
            continue;
          }
          const theta = (aqq - app) / (2 * apq);
          const t = (theta >= 0 ? 1 : -1) / (Math.abs(theta) + Math.sqrt(theta * theta + 1));
          const c = 1 / Math.sqrt(t * t + 1), s = t * c;
          for (let k = 0; k < n; k++) {  // columns p and q
            const kp = a[k * n + p], kq = a[k * n + q];
            a[k * n + p] = c * kp - s * kq;
            a[k * n + q] = s * kp + c * kq;
          }
          for (let k = 0; k < n; k++) {  // rows p and q
            const pk = a[p * n + k], qk = a[q * n + k];
            a[p * n + k] = c * pk - s * qk;
            a[q * n + k] = s * pk + c * qk;
          }
          a[p * n + q] = a[q * n + p] = 0;
          for (let k = 0; k < n; k++) {
            const kp = v[k * n + p], kq = v[k * n + q];
            v[k * n + p] = c * kp - s * kq;
            v[k * n + q] = s * kp + c * kq;
          }
        }
      }
    }
    const values = new Float64Array(n);
    for (let i = 0; i < n; i++) values[i] = a[i * n + i];
    return { values, vectors: v };
  }

  // Lower Cholesky factor of a symmetric positive definite matrix, or null.
  function cholesky(n, m) {
    const l = new Float64Array(n * n);
    for (let j = 0; j < n; j++) {
      let d = m[j * n + j];
      for (let k = 0; k < j; k++) d -= l[j * n + k] * l[j * n + k];
      if (!(d > 0)) return null;
      const r = Math.sqrt(d);
      l[j * n + j] = r;
      for (let i = j + 1; i < n; i++) {
        let s = m[i * n + j];
        for (let k = 0; k < j; k++) s -= l[i * n + k] * l[j * n + k];
        l[i * n + j] = s / r;
      }
    }
    return l;
  }

  // K x = lambda M x for symmetric K and positive definite M: ascending values and the
  // mass-normalised vectors (columns), or null when M is not positive definite.
  function generalizedSymmetric(n, m, k) {
    const l = cholesky(n, m);
    if (l === null) return null;
    // X = L^-1 K (forward substitution on the columns), then A = X L^-T
    const x = new Float64Array(n * n);
    for (let j = 0; j < n; j++) {
      for (let i = 0; i < n; i++) {
        let s = k[i * n + j];
        for (let q = 0; q < i; q++) s -= l[i * n + q] * x[q * n + j];
        x[i * n + j] = s / l[i * n + i];
      }
    }
    const a = new Float64Array(n * n);
    for (let i = 0; i < n; i++) {
      for (let j = 0; j < n; j++) {
        let s = x[i * n + j];
        for (let q = 0; q < j; q++) s -= a[i * n + q] * l[j * n + q];
        a[i * n + j] = s / l[j * n + j];
      }
    }
    for (let i = 0; i < n; i++) {  // symmetric up to rounding: use the mean
      for (let j = i + 1; j < n; j++) {
        const s = 0.5 * (a[i * n + j] + a[j * n + i]);
        a[i * n + j] = a[j * n + i] = s;
      }
    }
    const { values, vectors } = jacobi(n, a);
    // x = L^-T y (back substitution on each column)
    const phi = new Float64Array(n * n);
    for (let c = 0; c < n; c++) {
      for (let i = n - 1; i >= 0; i--) {
        let s = vectors[i * n + c];
        for (let q = i + 1; q < n; q++) s -= l[q * n + i] * phi[q * n + c];
        phi[i * n + c] = s / l[i * n + i];
      }
    }
    return sortModes(n, Array.from(values), phi);
  }

  function sortModes(n, values, vectors) {
    const order = values.map((_, i) => i).sort((i, j) => values[i] - values[j]);
    const sorted = new Float64Array(n * n);
    order.forEach((src, dst) => {
      for (let i = 0; i < n; i++) sorted[i * n + dst] = vectors[i * n + src];
    });
    return { values: order.map(i => values[i]), vectors: sorted };
  }

  // -- general real eigenvalues ---------------------------------------------------------
  function balance(n, a) {
    const radix = 2, sqrdx = radix * radix;
    let done = false;
    while (!done) {
      done = true;
      for (let i = 0; i < n; i++) {
        let r = 0, c = 0;
        for (let j = 0; j < n; j++) {
          if (j !== i) { c += Math.abs(a[j * n + i]); r += Math.abs(a[i * n + j]); }
        }
        if (c !== 0 && r !== 0) {
          let g = r / radix, f = 1;
          const s = c + r;
          while (c < g) { f *= radix; c *= sqrdx; }
          g = r * radix;
          while (c > g) { f /= radix; c /= sqrdx; }
          if ((c + r) / f < 0.95 * s) {
            done = false;
            g = 1 / f;
            for (let j = 0; j < n; j++) a[i * n + j] *= g;
            for (let j = 0; j < n; j++) a[j * n + i] *= f;
          }
        }
      }
    }
  }

  // Reduction to upper Hessenberg form by stabilized elementary similarity transformations.
  function hessenberg(n, a) {
    for (let m = 1; m < n - 1; m++) {
      let x = 0, i = m;
      for (let j = m; j < n; j++) {
        if (Math.abs(a[j * n + m - 1]) > Math.abs(x)) { x = a[j * n + m - 1]; i = j; }
      }
      if (i !== m) {
        for (let j = m - 1; j < n; j++) { const t = a[i * n + j]; a[i * n + j] = a[m * n + j]; a[m * n + j] = t; }
        for (let j = 0; j < n; j++) { const t = a[j * n + i]; a[j * n + i] = a[j * n + m]; a[j * n + m] = t; }
      }
      if (x !== 0) {
        for (let r = m + 1; r < n; r++) {
          let y = a[r * n + m - 1];
          if (y !== 0) {
            y /= x;
            a[r * n + m - 1] = y;
            for (let j = m; j < n; j++) a[r * n + j] -= y * a[m * n + j];
            for (let j = 0; j < n; j++) a[j * n + m] += y * a[j * n + r];
          }
        }
      }
    }
    for (let i = 2; i < n; i++) for (let j = 0; j < i - 1; j++) a[i * n + j] = 0;
  }

  // Francis double-shift QR on an upper Hessenberg matrix: {re, im} of the eigenvalues.
  function hqr(n, a) {
    const wr = new Float64Array(n), wi = new Float64Array(n);
    let anorm = 0;
    for (let i = 0; i < n; i++) for (let j = Math.max(i - 1, 0); j < n; j++) anorm += Math.abs(a[i * n + j]);
    let nn = n - 1, t = 0;
    const A = (i, j) => a[i * n + j];
    while (nn >= 0) {
      let its = 0, l;
      do {
        for (l = nn; l >= 1; l--) {
          let s = Math.abs(A(l - 1, l - 1)) + Math.abs(A(l, l));
          if (s === 0) s = anorm;
          if (Math.abs(A(l, l - 1)) <= EPS * s) { a[l * n + l - 1] = 0; break; }
        }
        let x = A(nn, nn);
        if (l === nn) {
          wr[nn] = x + t; wi[nn] = 0; nn--;
        } else {
          let y = A(nn - 1, nn - 1), w = A(nn, nn - 1) * A(nn - 1, nn);
          if (l === nn - 1) {
            const p = 0.5 * (y - x), q = p * p + w;
            let z = Math.sqrt(Math.abs(q));
            x += t;
            if (q >= 0) {
              z = p + (p >= 0 ? Math.abs(z) : -Math.abs(z));
              wr[nn - 1] = wr[nn] = x + z;
              if (z) wr[nn] = x - w / z;
              wi[nn - 1] = wi[nn] = 0;
            } else {
              wr[nn - 1] = wr[nn] = x + p;
              wi[nn - 1] = -z; wi[nn] = z;
            }
            nn -= 2;
          } else {
            if (its >= 60) throw new Error("the eigenvalue iteration did not converge");
            if (its > 0 && its % 10 === 0) {  // exceptional shift
              t += x;
              for (let i = 0; i <= nn; i++) a[i * n + i] -= x;
              const s = Math.abs(A(nn, nn - 1)) + Math.abs(A(nn - 1, nn - 2));
              y = x = 0.75 * s;
              w = -0.4375 * s * s;
            }
            ++its;
            let m, p = 0, q = 0, r = 0, z;
            for (m = nn - 2; m >= l; m--) {
              z = A(m, m);
              r = x - z;
              let s = y - z;
              p = (r * s - w) / A(m + 1, m) + A(m, m + 1);
              q = A(m + 1, m + 1) - z - r - s;
              r = A(m + 2, m + 1);
              s = Math.abs(p) + Math.abs(q) + Math.abs(r);
              p /= s; q /= s; r /= s;
              if (m === l) break;
              const u = Math.abs(A(m, m - 1)) * (Math.abs(q) + Math.abs(r));
              const v = Math.abs(p) * (Math.abs(A(m - 1, m - 1)) + Math.abs(z) + Math.abs(A(m + 1, m + 1)));
              if (u <= EPS * v) break;
            }
            for (let i = m + 2; i <= nn; i++) {
              a[i * n + i - 2] = 0;
              if (i !== m + 2) a[i * n + i - 3] = 0;
            }
            for (let k = m; k <= nn - 1; k++) {
              if (k !== m) {
                p = A(k, k - 1); q = A(k + 1, k - 1); r = 0;
                if (k !== nn - 1) r = A(k + 2, k - 1);
                x = Math.abs(p) + Math.abs(q) + Math.abs(r);
                if (x !== 0) { p /= x; q /= x; r /= x; }
              }
              const root = Math.sqrt(p * p + q * q + r * r);
              const s = p >= 0 ? root : -root;
              if (s !== 0) {
                if (k === m) {
                  if (l !== m) a[k * n + k - 1] = -A(k, k - 1);
                } else {
                  a[k * n + k - 1] = -s * x;
                }
                p += s;
                x = p / s; y = q / s; z = r / s;
                q /= p; r /= p;
                for (let j = k; j <= nn; j++) {
                  p = A(k, j) + q * A(k + 1, j);
                  if (k !== nn - 1) { p += r * A(k + 2, j); a[(k + 2) * n + j] -= p * z; }
                  a[(k + 1) * n + j] -= p * y;
                  a[k * n + j] -= p * x;
                }
                const mmin = nn < k + 3 ? nn : k + 3;
                for (let i = l; i <= mmin; i++) {
                  p = x * A(i, k) + y * A(i, k + 1);
                  if (k !== nn - 1) { p += z * A(i, k + 2); a[i * n + k + 2] -= p * r; }
                  a[i * n + k + 1] -= p * q;
                  a[i * n + k] -= p;
                }
              }
            }
          }
        }
      } while (l < nn - 1);
    }
    return { re: wr, im: wi };
  }

  // Eigenvalues of a real square matrix (copied).
  function eigenvalues(n, a0) {
    if (n === 0) return { re: new Float64Array(0), im: new Float64Array(0) };
    const a = Float64Array.from(a0);
    balance(n, a);
    hessenberg(n, a);
    return hqr(n, a);
  }

  // A real eigenvector of A for the real eigenvalue lambda, by inverse iteration.
  function inverseIteration(n, a, lambda) {
    const shifted = Float64Array.from(a);
    const bump = Math.max(Math.abs(lambda), maxAbs(a), 1e-300) * 1e-10;
    for (let i = 0; i < n; i++) shifted[i * n + i] -= lambda + bump;
    let x = new Float64Array(n).fill(1);
    for (let it = 0; it < 4; it++) {
      const y = realSolve(n, shifted, x, 1);
      if (y === null) break;
      const norm = maxAbs(y) || 1;
      x = y.map(v => v / norm);
    }
    return x;
  }

  // -- the model's quantities -----------------------------------------------------------
  // lambda = omega^2 (ascending) and mode shapes of K x = lambda M x (resonant's
  // undamped_eigen: symmetric solver when M and K are symmetric, general otherwise)
  function undampedEigen(n, m, k) {
    if (isSymmetric(n, m) && isSymmetric(n, k)) {
      const found = generalizedSymmetric(n, m, k);
      if (found !== null) return found;
    }
    const minvk = realSolve(n, m, k, n);
    if (minvk === null) return { values: [], vectors: new Float64Array(0) };
    const ev = eigenvalues(n, minvk);
    const values = Array.from(ev.re);
    const vectors = new Float64Array(n * n);
    values.forEach((lam, c) => {
      const x = inverseIteration(n, minvk, lam);
      for (let i = 0; i < n; i++) vectors[i * n + c] = x[i];
    });
    return sortModes(n, values, vectors);
  }

  function frequenciesFromEigenvalues(lam) {
    let scale = 1e-300;
    for (const v of lam) scale = Math.max(scale, Math.abs(v));
    return lam.map(v => (Math.abs(v) < 1e-12 * scale ? 0 : v)).filter(v => v >= 0).map(Math.sqrt);
  }

  // Largest component +1, tiny components (rounding noise of exact zeros) 0.
  function unitShape(n, vectors, c) {
    let big = 0;
    for (let i = 0; i < n; i++) if (Math.abs(vectors[i * n + c]) > Math.abs(big)) big = vectors[i * n + c];
    const out = [];
    for (let i = 0; i < n; i++) {
      const v = big ? vectors[i * n + c] / big : 0;
      out.push(Math.abs(v) < 1e-13 ? 0 : v);
    }
    return out;
  }

  // Eigenvalues of the state matrix [[0, I], [-M^-1 K, -M^-1 C]].
  function stateEigenvalues(n, m, c, k) {
    const rhs = new Float64Array(n * 2 * n);
    for (let i = 0; i < n; i++) {
      for (let j = 0; j < n; j++) { rhs[i * 2 * n + j] = k[i * n + j]; rhs[i * 2 * n + n + j] = c[i * n + j]; }
    }
    const x = realSolve(n, m, rhs, 2 * n);
    if (x === null) return null;
    const N = 2 * n, a = new Float64Array(N * N);
    for (let i = 0; i < n; i++) {
      a[i * N + n + i] = 1;
      for (let j = 0; j < 2 * n; j++) a[(n + i) * N + j] = -x[i * 2 * n + j];
    }
    return eigenvalues(N, a);
  }

  function classify(eig) {
    const count = eig.re.length;
    if (count === 0) return "asymptotically stable";
    let scale = 1;
    for (let i = 0; i < count; i++) scale = Math.max(scale, Math.hypot(eig.re[i], eig.im[i]));
    const tol = 1e-9 * scale;
    let all = true;
    for (let i = 0; i < count; i++) {
      // a multiple zero (rigid-body mode) is known to sqrt(eps) only: it counts as 0
      const zero = Math.hypot(eig.re[i], eig.im[i]) <= 1.5e-8 * scale;
      if (eig.re[i] > tol && !zero) return "unstable";
      if (!(eig.re[i] < -tol)) all = false;
    }
    return all ? "asymptotically stable" : "marginally stable";
  }

  // Damping ratio -Re s/|s| and damped frequency Im s of every s with Im s >= 0, in the
  // modal kernel's order (resonant.modal.order): by |s| to 12 significant digits of
  // the largest |s|, then by Im s.
  function dampingRatios(eig) {
    const upper = [];
    let scale = 1;
    for (let i = 0; i < eig.re.length; i++) scale = Math.max(scale, Math.hypot(eig.re[i], eig.im[i]));
    for (let i = 0; i < eig.re.length; i++) {
      let re = eig.re[i], im = eig.im[i], size = Math.hypot(re, im);
      if (size <= 1.5e-8 * scale) { re = 0; im = 0; size = 0; }  // a rigid-body mode's round-off
      if (im >= -1e-12 * Math.max(1, size)) upper.push([re, im, size, Math.round(size / scale * 1e12)]);
    }
    upper.sort((x, y) => x[3] - y[3] || x[1] - y[1]);
    return {
      ratios: upper.map(([re, , size]) => (size > 0 ? -re / size : 0)),
      damped: upper.map(([, im]) => Math.abs(im)),
    };
  }

  // -- amplitudes and phases ------------------------------------------------------------
  function phaseAngle(L, N) {
    const delta = Math.atan2(L, N) + 0;
    return delta <= -Math.PI ? Math.PI : delta;
  }

  // The exact fraction of a double: [numerator, denominator] as BigInts.
  function exactFraction(x) {
    const view = new DataView(new ArrayBuffer(8));
    view.setFloat64(0, x);
    const hi = view.getUint32(0), lo = view.getUint32(4);
    const sign = hi >>> 31 ? -1n : 1n;
    const exponent = (hi >>> 20) & 0x7ff;
    let mantissa = (BigInt(hi & 0xfffff) << 32n) | BigInt(lo);
    let e;
    if (exponent === 0) { e = -1074; } else { mantissa |= 1n << 52n; e = exponent - 1075; }
    if (mantissa === 0n) return [0n, 1n];
    let num = sign * mantissa, den = 1n;
    if (e >= 0) num <<= BigInt(e); else den <<= BigInt(-e);
    const g = gcd(num < 0n ? -num : num, den);
    return [num / g, den / g];
  }

  function gcd(a, b) { while (b) { [a, b] = [b, a % b]; } return a; }

  const floorDiv = (a, b) => { const q = a / b; return (a % b !== 0n && ((a < 0n) !== (b < 0n))) ? q - 1n : q; };
  const absBig = v => (v < 0n ? -v : v);

  // Python's Fraction.limit_denominator: the closest fraction with denominator <= limit.
  function limitDenominator(x, limit) {
    const [num, den] = exactFraction(x);
    const big = BigInt(limit);
    if (den <= big) return [num, den];
    let p0 = 0n, q0 = 1n, p1 = 1n, q1 = 0n, n = num, d = den;
    for (;;) {
      const a = floorDiv(n, d);
      const q2 = q0 + a * q1;
      if (q2 > big) break;
      [p0, q0, p1, q1] = [p1, q1, p0 + a * p1, q2];
      [n, d] = [d, n - a * d];
    }
    const k = floorDiv(big - q0, q1);
    const b1 = [p0 + k * p1, q0 + k * q1], b2 = [p1, q1];
    // |b - x| compared exactly: |bn * den - num * bd| / (bd * den)
    const dist = ([bn, bd]) => [absBig(bn * den - num * bd), bd * den];
    const [e2n, e2d] = dist(b2), [e1n, e1d] = dist(b1);
    return e2n * e1d <= e1n * e2d ? b2 : b1;
  }

  // The common period 2 pi q / w_min of frequencies with rational ratios (q <= 1000), or null.
  function commonPeriod(omegas) {
    const moving = omegas.filter(w => w > 0);
    if (!moving.length) return null;
    const base = Math.min(...moving);
    let lcm = 1n;
    for (const w of moving) {
      const [p, q] = limitDenominator(w / base, 1000);
      if (Math.abs(Number(p) / Number(q) - w / base) > 1e-9 * w / base) return null;
      lcm = lcm / gcd(lcm, q) * q;
    }
    return 2 * Math.PI * Number(lcm) / base;
  }

  // Peak |x(t)| of x = sum L_i cos(w_i t) + N_i sin(w_i t), as resonant.analyses.stationary.peak.
  function peak(omegas, pairs, fast) {
    const active = [];
    omegas.forEach((w, i) => { if (Math.hypot(pairs[i][0], pairs[i][1]) > 0) active.push([w, pairs[i][0], pairs[i][1]]); });
    if (!active.length) return 0;
    let statik = 0;
    for (const [w, L] of active) if (w === 0) statik += L;
    const moving = active.filter(([w]) => w > 0);
    const bound = () => Math.abs(statik) + moving.reduce((s, [, L, N]) => s + Math.hypot(L, N), 0);
    if (moving.length <= 1) return bound();
    const period = commonPeriod(moving.map(([w]) => w));
    if (period === null) return bound();
    const highest = Math.max(...moving.map(([w]) => w));
    const samples = fast ? 400 : Math.floor(Math.min(20000, Math.max(4000, 200 * highest * period / (2 * Math.PI))));
    const value = t => {
      let y = statik;
      for (const [w, L, N] of moving) y += L * Math.cos(w * t) + N * Math.sin(w * t);
      return Math.abs(y);
    };
    const ys = new Float64Array(samples);
    let best = 0;
    for (let i = 0; i < samples; i++) { ys[i] = value(period * i / samples); if (ys[i] > best) best = ys[i]; }
    if (fast) return best;
    const top = Array.from(ys.keys()).sort((i, j) => ys[i] - ys[j]).slice(-16);
    const step = period / samples, g = (Math.sqrt(5) - 1) / 2;
    for (const i of top) {
      let a = period * i / samples - step, b = period * i / samples + step;
      for (let it = 0; it < 60; it++) {
        const c = b - g * (b - a), d = a + g * (b - a);
        if (value(c) > value(d)) b = d; else a = c;
      }
      best = Math.max(best, value((a + b) / 2));
    }
    return best;
  }

  // -- periodic loads ----------------------------------------------------------------------
  // In-place radix-2 FFT of (re, im) (length a power of two): sum_k x_k e^(sign 2 pi i jk/N).
  function fft(re, im, sign) {
    const N = re.length;
    for (let i = 1, j = 0; i < N; i++) {
      let bit = N >> 1;
      for (; j & bit; bit >>= 1) j ^= bit;
      j ^= bit;
      if (i < j) { [re[i], re[j]] = [re[j], re[i]]; [im[i], im[j]] = [im[j], im[i]]; }
    }
    for (let len = 2; len <= N; len <<= 1) {
      const angle = sign * 2 * Math.PI / len, wr = Math.cos(angle), wi = Math.sin(angle);
      for (let i = 0; i < N; i += len) {
        let cr = 1, ci = 0;
        for (let k = 0; k < len / 2; k++) {
          const a = i + k, b = a + len / 2;
          const xr = re[b] * cr - im[b] * ci, xi = re[b] * ci + im[b] * cr;
          re[b] = re[a] - xr; im[b] = im[a] - xi; re[a] += xr; im[a] += xi;
          [cr, ci] = [cr * wr - ci * wi, cr * wi + ci * wr];
        }
      }
    }
  }

  // The response over one period to a periodic load, as resonant sums it: mean + sum over
  // the harmonics k = 1..H of Re(Z_k e^(i k W t)), sampled at the smallest power of two of
  // at least 16 H (and 4096) points by an inverse FFT; {values, largest}.
  function periodicHistory(Zre, Zim, mean) {
    const H = Zre.length;
    let count = 4096;
    while (count < 16 * H) count *= 2;
    const re = new Float64Array(count), im = new Float64Array(count);
    for (let k = 1; k <= H; k++) {  // Re(Z e^(i w t)) = (Z e^(i w t) + conj(Z) e^(-i w t)) / 2
      re[k] = Zre[k - 1] / 2; im[k] = Zim[k - 1] / 2;
      re[count - k] = Zre[k - 1] / 2; im[count - k] = -Zim[k - 1] / 2;
    }
    fft(re, im, 1);
    let largest = 0;
    for (let j = 0; j < count; j++) { re[j] += mean; largest = Math.max(largest, Math.abs(re[j])); }
    return { values: re, largest };
  }

  return {
    fft, periodicHistory, complexSolve, realSolve, jacobi, cholesky, generalizedSymmetric, eigenvalues,
    undampedEigen, frequenciesFromEigenvalues, unitShape, stateEigenvalues, classify,
    dampingRatios, phaseAngle, limitDenominator, commonPeriod, peak, isSymmetric,
  };
})();
if (typeof module !== "undefined") module.exports = ResonantNumerics;
