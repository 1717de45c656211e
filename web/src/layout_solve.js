// Section 6.7 of spec/README.md: the solve layout method (format 1.2; its
// cotangent weights 1.4). A disc
// patch gets Tutte's embedding with its boundary on a circle (Tutte 1963;
// Floater 2003), then local-global ARAP rounds (Sorkine & Alexa 2007; Liu et
// al. 2008); every linear solve is a fixed number of conjugate-gradient
// steps. The C++ original is codec/core/layout_solve.cpp; each loop and sum
// below runs in the same order, so the result is the same bits.
//
// Floating point: binary64 numbers, + - * / and Math.sqrt only (spec 2.2).
import { GltfWarpError } from './errors.js';

const TINY = 1e-300;
const MIN_COT = 1 / 16384, MAX_COT = 16; // the cotangent weight clamp (1.4)

// The ARAP weight of a face's edge from the corner opposite it in the face's
// isometric copy (a and b the two edges from that corner): its cotangent,
// clamped by comparisons that pass a NaN through, as the spec writes them.
export function cotangentWeight(ax, ay, bx, by) {
  const q = (ax * bx + ay * by) / (Math.abs(ax * by - ay * bx) + TINY);
  return q < MIN_COT ? MIN_COT : (q > MAX_COT ? MAX_COT : q);
}

function length2(pos, u, w) {
  const dx = pos[3 * u] - pos[3 * w];
  const dy = pos[3 * u + 1] - pos[3 * w + 1];
  const dz = pos[3 * u + 2] - pos[3 * w + 2];
  return dx * dx + dy * dy + dz * dz;
}

// The boundary point of arc length fraction u on the circle of radius r
// through the origin.
export function circlePoint(u, r) {
  const a = 0.7853981633974483 * u;
  const a2 = a * a;
  const t = a * (15 - a2) / (15 - 6 * a2);
  const t2 = t * t;
  const c1 = (1 - t2) / (1 + t2), s1 = (2 * t) / (1 + t2);
  const c2 = c1 * c1 - s1 * s1, s2 = (2 * c1) * s1;
  const c = c2 * c2 - s2 * s2, s = (2 * c2) * s2;
  return [r * (c - 1), r * s];
}

function notDisc(why) {
  return new GltfWarpError('layout_not_disc', why);
}

// Lays out one patch (faces: ascending face ids) and returns
// { verts (ascending vertex ids), x, y } with the positions of verts[i].
export function solvePatch(pos, indices, faces, params) {
  const F = faces.length;
  // Local numbering: the patch's vertices in ascending id.
  const all = new Uint32Array(3 * F);
  for (let i = 0; i < F; ++i) for (let k = 0; k < 3; ++k) all[3 * i + k] = indices[3 * faces[i] + k];
  all.sort();
  let n = 0;
  for (let i = 0; i < all.length; ++i) if (i === 0 || all[i] !== all[i - 1]) all[n++] = all[i];
  const verts = all.slice(0, n);
  const local = new Map();
  for (let i = 0; i < n; ++i) local.set(verts[i], i);
  const tri = new Uint32Array(3 * F);
  for (let i = 0; i < 3 * F; ++i) tri[i] = local.get(indices[3 * faces[(i / 3) | 0] + (i % 3)]);

  // Validation: an oriented, edge-manifold disc.
  const outOff = new Uint32Array(n + 1);
  for (let t = 0; t < F; ++t) {
    const a = tri[3 * t], b = tri[3 * t + 1], c = tri[3 * t + 2];
    if (a === b || b === c || a === c) throw notDisc('a face names a vertex twice');
    ++outOff[a + 1]; ++outOff[b + 1]; ++outOff[c + 1];
  }
  for (let i = 0; i < n; ++i) outOff[i + 1] += outOff[i];
  const outTo = new Uint32Array(3 * F), fill = outOff.slice(0, n);
  for (let t = 0; t < F; ++t)
    for (let k = 0; k < 3; ++k) outTo[fill[tri[3 * t + k]]++] = tri[3 * t + (k + 1) % 3];
  for (let i = 0; i < n; ++i) {
    const row = outTo.subarray(outOff[i], outOff[i + 1]);
    row.sort();
    for (let k = 1; k < row.length; ++k) if (row[k] === row[k - 1]) throw notDisc('a directed edge twice');
  }
  const hasEdge = (a, b) => {
    let lo = outOff[a], hi = outOff[a + 1];
    while (lo < hi) {
      const m = (lo + hi) >>> 1;
      if (outTo[m] < b) lo = m + 1; else hi = m;
    }
    return lo < outOff[a + 1] && outTo[lo] === b;
  };
  const NONE = 0xffffffff;
  const bout = new Uint32Array(n).fill(NONE);
  let B = 0;
  for (let a = 0; a < n; ++a)
    for (let e = outOff[a]; e < outOff[a + 1]; ++e) {
      const b = outTo[e];
      if (hasEdge(b, a)) continue;
      if (bout[a] !== NONE) throw notDisc('two boundary edges leave one vertex');
      bout[a] = b;
      ++B;
    }
  if (B < 3) throw notDisc('no boundary loop');
  let start = 0;
  while (bout[start] === NONE) ++start;
  const loop = [];
  for (let v = start; loop.length <= B;) {
    loop.push(v);
    v = bout[v];
    if (v === NONE) throw notDisc('open boundary');
    if (v === start) break;
  }
  if (loop.length !== B) throw notDisc('more than one boundary loop');
  if (2 * n - F - B !== 2) throw notDisc('Euler characteristic is not 1');

  // Laplacian rows: neighbours ascending with the number of faces on the edge.
  const cnt = new Uint32Array(n + 1);
  for (let a = 0; a < n; ++a)
    for (let e = outOff[a]; e < outOff[a + 1]; ++e) { ++cnt[a + 1]; ++cnt[outTo[e] + 1]; }
  for (let i = 0; i < n; ++i) cnt[i + 1] += cnt[i];
  const raw = new Uint32Array(cnt[n]), rf = cnt.slice(0, n);
  for (let a = 0; a < n; ++a)
    for (let e = outOff[a]; e < outOff[a + 1]; ++e) { const b = outTo[e]; raw[rf[a]++] = b; raw[rf[b]++] = a; }
  const nbrOff = new Uint32Array(n + 1), nbr = new Uint32Array(raw.length), weight = new Float64Array(raw.length);
  const diag = new Float64Array(n);
  let w = 0;
  for (let i = 0; i < n; ++i) {
    const row = raw.subarray(cnt[i], cnt[i + 1]);
    row.sort();
    nbrOff[i] = w;
    for (let k = 0; k < row.length; ++k) {
      if (k > 0 && row[k] === row[k - 1]) ++weight[w - 1];
      else { nbr[w] = row[k]; weight[w++] = 1; }
    }
    diag[i] = row.length;
  }
  nbrOff[n] = w;
  const seen = new Uint8Array(n), queue = [start];
  seen[start] = 1;
  for (let h = 0; h < queue.length; ++h) {
    const a = queue[h];
    for (let e = nbrOff[a]; e < nbrOff[a + 1]; ++e) if (!seen[nbr[e]]) { seen[nbr[e]] = 1; queue.push(nbr[e]); }
  }
  if (queue.length !== n) throw notDisc('a vertex does not reach the boundary');

  // Boundary on the circle, by cumulative 3D arc length.
  const x = new Float64Array(n), y = new Float64Array(n);
  const arc = new Float64Array(B);
  let total = 0;
  for (let i = 0; i < B; ++i) {
    arc[i] = total;
    total += Math.sqrt(length2(pos, verts[loop[i]], verts[loop[(i + 1) % B]]));
  }
  const radius = total / 6.283185307179586;
  for (let i = 0; i < B; ++i) {
    const [px, py] = circlePoint(arc[i] / (total + TINY), radius);
    x[loop[i]] = px;
    y[loop[i]] = py;
  }
  const fixed = new Uint8Array(n);
  for (const v of loop) fixed[v] = 1;

  const row = (i, v) => {
    let s = 0;
    for (let e = nbrOff[i]; e < nbrOff[i + 1]; ++e) if (!fixed[nbr[e]]) s += weight[e] * v[nbr[e]];
    return diag[i] * v[i] - s;
  };
  const addFixed = (bx, by) => {
    for (let i = 0; i < n; ++i) {
      if (fixed[i]) continue;
      let fx = 0, fy = 0;
      for (let e = nbrOff[i]; e < nbrOff[i + 1]; ++e) {
        const j = nbr[e];
        if (!fixed[j]) continue;
        fx += weight[e] * x[j];
        fy += weight[e] * y[j];
      }
      bx[i] = bx[i] + fx;
      by[i] = by[i] + fy;
    }
  };
  const rx = new Float64Array(n), ry = new Float64Array(n), px = new Float64Array(n), py = new Float64Array(n);
  const qx = new Float64Array(n), qy = new Float64Array(n);
  const cg = (bx, by, steps) => {
    rx.fill(0); ry.fill(0); px.fill(0); py.fill(0); qx.fill(0); qy.fill(0);
    let rrx = 0, rry = 0;
    for (let i = 0; i < n; ++i) {
      if (fixed[i]) continue;
      rx[i] = bx[i] - row(i, x);
      ry[i] = by[i] - row(i, y);
      px[i] = rx[i];
      py[i] = ry[i];
      rrx += rx[i] * rx[i];
      rry += ry[i] * ry[i];
    }
    for (let step = 0; step < steps; ++step) {
      let pqx = 0, pqy = 0;
      for (let i = 0; i < n; ++i) {
        if (fixed[i]) continue;
        qx[i] = row(i, px);
        qy[i] = row(i, py);
        pqx += px[i] * qx[i];
        pqy += py[i] * qy[i];
      }
      const ax = rrx / (pqx + TINY), ay = rry / (pqy + TINY);
      let nx = 0, ny = 0;
      for (let i = 0; i < n; ++i) {
        if (fixed[i]) continue;
        x[i] = x[i] + ax * px[i];
        y[i] = y[i] + ay * py[i];
        rx[i] = rx[i] - ax * qx[i];
        ry[i] = ry[i] - ay * qy[i];
        nx += rx[i] * rx[i];
        ny += ry[i] * ry[i];
      }
      const gx = nx / (rrx + TINY), gy = ny / (rry + TINY);
      for (let i = 0; i < n; ++i) {
        if (fixed[i]) continue;
        px[i] = rx[i] + gx * px[i];
        py[i] = ry[i] + gy * py[i];
      }
      rrx = nx;
      rry = ny;
    }
  };

  // Tutte.
  const bx = new Float64Array(n), by = new Float64Array(n);
  addFixed(bx, by);
  cg(bx, by, params.tutteSteps);

  // Each face's isometric copy: X0 = (0, 0), X1 = (l1, 0), X2.
  const frame = new Float64Array(6 * F);
  for (let t = 0; t < F; ++t) {
    const f = faces[t], i0 = 3 * indices[3 * f], i1 = 3 * indices[3 * f + 1], i2 = 3 * indices[3 * f + 2];
    const e1x = pos[i1] - pos[i0], e1y = pos[i1 + 1] - pos[i0 + 1], e1z = pos[i1 + 2] - pos[i0 + 2];
    const e2x = pos[i2] - pos[i0], e2y = pos[i2 + 1] - pos[i0 + 1], e2z = pos[i2 + 2] - pos[i0 + 2];
    const l1 = Math.sqrt(e1x * e1x + e1y * e1y + e1z * e1z);
    const dot = e1x * e2x + e1y * e2y + e1z * e2z;
    const cx = e1y * e2z - e1z * e2y, cy = e1z * e2x - e1x * e2z, cz = e1x * e2y - e1y * e2x;
    const cross = Math.sqrt(cx * cx + cy * cy + cz * cz);
    frame[6 * t + 2] = l1;
    frame[6 * t + 4] = dot / (l1 + TINY);
    frame[6 * t + 5] = cross / (l1 + TINY);
  }

  // Edge weights: 1 per face, or (1.4) each face's clamped cotangent; the
  // Laplacian is rebuilt from them (an edge's two terms commute exactly, and
  // the diagonal sums each row in ascending neighbour order).
  const cot = params.cotangent === true;
  const faceWeight = new Float64Array(3 * F).fill(1);
  if (cot) {
    const entry = (a, b) => {
      let lo = nbrOff[a], hi = nbrOff[a + 1];
      while (lo < hi) { const mid = (lo + hi) >>> 1; if (nbr[mid] < b) lo = mid + 1; else hi = mid; }
      return lo;
    };
    weight.fill(0);
    for (let t = 0; t < F; ++t) {
      const X = 6 * t;
      for (let k = 0; k < 3; ++k) {
        const k1 = (k + 1) % 3, k2 = (k + 2) % 3;
        const wk = cotangentWeight(frame[X + 2 * k] - frame[X + 2 * k2], frame[X + 2 * k + 1] - frame[X + 2 * k2 + 1],
          frame[X + 2 * k1] - frame[X + 2 * k2], frame[X + 2 * k1 + 1] - frame[X + 2 * k2 + 1]);
        faceWeight[3 * t + k] = wk;
        const i = tri[3 * t + k], j = tri[3 * t + k1];
        weight[entry(i, j)] += wk;
        weight[entry(j, i)] += wk;
      }
    }
    for (let i = 0; i < n; ++i) {
      let d = 0;
      for (let e = nbrOff[i]; e < nbrOff[i + 1]; ++e) d += weight[e];
      diag[i] = d;
    }
  }

  // ARAP: the loop start stays pinned at the origin.
  fixed.fill(0);
  fixed[start] = 1;
  const rot = new Float64Array(2 * F);
  for (let round = 0; round < params.arapRounds; ++round) {
    for (let t = 0; t < F; ++t) {
      const X = 6 * t;
      let a = 0, b = 0, c = 0, d = 0;
      for (let k = 0; k < 3; ++k) {
        const k1 = (k + 1) % 3, i = tri[3 * t + k], j = tri[3 * t + k1];
        const wk = faceWeight[3 * t + k];
        const ux = wk * (x[j] - x[i]), uy = wk * (y[j] - y[i]);
        const vx = frame[X + 2 * k1] - frame[X + 2 * k], vy = frame[X + 2 * k1 + 1] - frame[X + 2 * k + 1];
        a += ux * vx;
        b += ux * vy;
        c += uy * vx;
        d += uy * vy;
      }
      const pc = a + d, ps = c - b;
      const len = Math.sqrt(pc * pc + ps * ps);
      rot[2 * t] = pc / (len + TINY);
      rot[2 * t + 1] = ps / (len + TINY);
    }
    bx.fill(0);
    by.fill(0);
    for (let t = 0; t < F; ++t) {
      const X = 6 * t, co = rot[2 * t], si = rot[2 * t + 1];
      for (let k = 0; k < 3; ++k)
        for (let m = 1; m <= 2; ++m) {
          const j = (k + m) % 3, i = tri[3 * t + k];
          const we = faceWeight[3 * t + (m === 1 ? k : j)]; // the face edge joining corners k and j
          const ex = we * (frame[X + 2 * k] - frame[X + 2 * j]), ey = we * (frame[X + 2 * k + 1] - frame[X + 2 * j + 1]);
          bx[i] += co * ex - si * ey;
          by[i] += si * ex + co * ey;
        }
    }
    addFixed(bx, by);
    cg(bx, by, params.arapSteps);
  }

  // Similarity scale: 3D over 2D edge length sums.
  let l3 = 0, l2 = 0;
  for (let t = 0; t < F; ++t) {
    const f = faces[t];
    for (let k = 0; k < 3; ++k) {
      const k1 = (k + 1) % 3;
      l3 += Math.sqrt(length2(pos, indices[3 * f + k], indices[3 * f + k1]));
      const dx = x[tri[3 * t + k1]] - x[tri[3 * t + k]], dy = y[tri[3 * t + k1]] - y[tri[3 * t + k]];
      l2 += Math.sqrt(dx * dx + dy * dy);
    }
  }
  const scale = l3 / (l2 + TINY);
  for (let i = 0; i < n; ++i) {
    x[i] = scale * x[i];
    y[i] = scale * y[i];
  }
  return { verts, x, y, local };
}

// For layoutPatches: solveAt(p) lays out patch p and hands each of its faces
// to emit(p, f, xy) when methods[p] is 1 (solve), and returns whether it did.
export function solvePatchAt(positions, indices, byPatch, methods, params, emit) {
  const xy = new Float64Array(6);
  return (p) => {
    if (methods[p] !== 1) return false;
    const faces = byPatch.faces.subarray(byPatch.start[p], byPatch.start[p + 1]);
    const { x, y, local } = solvePatch(positions, indices, faces, params);
    for (const f of faces) {
      for (let k = 0; k < 3; ++k) {
        const i = local.get(indices[3 * f + k]);
        xy[2 * k] = x[i];
        xy[2 * k + 1] = y[i];
      }
      emit(p, f, xy);
    }
    return true;
  };
}
