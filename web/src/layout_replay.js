// Section 6.5 of spec/README.md: the layout replay. Each patch is grown from
// its seed face in breadth-first rounds; every new vertex is unfolded from the
// placed faces around it and relaxed (Sorkine & Cohen-Or, "Warped Textures for
// UV Mapping Encoding", 2001, section 3; the relaxation is two steps of stress
// majorization restricted to the new vertex). The C++ original is
// codec/layout.cpp; this follows its data layout so that it runs in linear
// time: per-vertex face runs sorted by (patch, face), generation stamps
// instead of clears, typed arrays, no allocation per vertex.
//
// Floating point: JavaScript numbers are binary64 with round-to-nearest and no
// fused multiply-add, which is what spec section 2.2 demands. Only + - * /
// and Math.sqrt (correctly rounded) are used, each expression in the order the
// spec writes it.
import { GltfWarpError } from './errors.js';
import { vertexFaces } from './mesh_adjacency.js';

const RELAX_STEPS = 2;
const NEXT = [1, 2, 0], PREV = [2, 0, 1]; // (k + 1) % 3, (k + 2) % 3
const NO_VERTEX = 0xffffffff;

function length2(pos, u, w) {
  const dx = pos[3 * u] - pos[3 * w];
  const dy = pos[3 * u + 1] - pos[3 * w + 1];
  const dz = pos[3 * u + 2] - pos[3 * w + 2];
  return dx * dx + dy * dy + dz * dz;
}

// Unfoldings of the current vertex, 7 doubles each: A.x, A.y, B.x, B.y, la, lb, lab2.
class Unfoldings {
  constructor() {
    this.data = new Float64Array(7 * 32);
    this.invL2 = new Float64Array(2 * 32);
    this.n = 0;
  }
  push(ax, ay, bx, by, la, lb, lab2) {
    if (7 * (this.n + 1) > this.data.length) {
      const grown = new Float64Array(this.data.length * 2);
      grown.set(this.data);
      this.data = grown;
      this.invL2 = new Float64Array(this.invL2.length * 2);
    }
    const d = this.data, o = 7 * this.n++;
    d[o] = ax; d[o + 1] = ay; d[o + 2] = bx; d[o + 3] = by; d[o + 4] = la; d[o + 5] = lb; d[o + 6] = lab2;
  }
}

// The placement rule: weighted unfolding, then RELAX_STEPS relaxation steps.
// Writes the result to out[0], out[1].
function placeVertex(u, out) {
  const d = u.data, n = u.n;
  let sx = 0, sy = 0, sw = 0, mx = 0, my = 0;
  for (let i = 0; i < n; ++i) {
    const o = 7 * i;
    const ax = d[o], ay = d[o + 1], bx = d[o + 2], by = d[o + 3], la = d[o + 4], lb = d[o + 5], lab2 = d[o + 6];
    const ex = bx - ax, ey = by - ay;
    let ux, uy;
    if (lab2 > 0) {
      const s = (la * la - lb * lb + lab2) / (2 * lab2);
      const t2 = la * la / lab2 - s * s;
      const t = Math.sqrt(t2 > 0 ? t2 : 0);
      ux = ax + s * ex - t * ey;
      uy = ay + s * ey + t * ex;
    } else {
      ux = (ax + bx) / 2;
      uy = (ay + by) / 2;
    }
    const d2 = ex * ex + ey * ey;
    const den = d2 + lab2;
    const e = den > 0 ? 2 * Math.sqrt(d2) * Math.sqrt(lab2) / den : 1;
    const w = e * e;
    sx += w * ux;
    sy += w * uy;
    sw += w;
    mx += ux;
    my += uy;
  }
  let px, py;
  if (sw > 0) {
    px = sx / sw;
    py = sy / sw;
  } else {
    px = mx / n;
    py = my / n;
  }
  // 1 / l^2 does not change between steps: the same values computed once.
  const inv = u.invL2;
  for (let i = 0; i < n; ++i) {
    const la = d[7 * i + 4], lb = d[7 * i + 5];
    inv[2 * i] = la !== 0 ? 1 / (la * la) : 0;
    inv[2 * i + 1] = lb !== 0 ? 1 / (lb * lb) : 0;
  }
  for (let step = 0; step < RELAX_STEPS; ++step) {
    let nx = 0, ny = 0, nw = 0;
    for (let i = 0; i < n; ++i) {
      const o = 7 * i;
      for (let k = 0; k < 2; ++k) {
        const xx = d[o + 2 * k], xy = d[o + 2 * k + 1], l = d[o + 4 + k];
        const dx = px - xx, dy = py - xy;
        const r = Math.sqrt(dx * dx + dy * dy);
        if (l === 0 || r === 0) continue;
        const w = inv[2 * i + k], g = l / r;
        nx += w * (xx + g * dx);
        ny += w * (xy + g * dy);
        nw += w;
      }
    }
    if (nw > 0) {
      px = nx / nw;
      py = ny / nw;
    }
  }
  out[0] = px;
  out[1] = py;
}

// The seed rule: positions of the seed face's three corners (6 doubles).
function placeSeed(pos, v0, v1, v2, sp) {
  sp.fill(0);
  const l01s = length2(pos, v0, v1), l02s = length2(pos, v0, v2);
  const l01 = Math.sqrt(l01s), l02 = Math.sqrt(l02s);
  if (v1 !== v0) sp[2] = l01;
  if (v2 === v0) {
    // (0, 0)
  } else if (v2 === v1) {
    sp[4] = sp[2];
  } else if (v1 === v0) {
    sp[4] = l02;
  } else if (l01 === 0) {
    sp[5] = l02;
  } else {
    const x = (l01s + l02s - length2(pos, v1, v2)) / (2 * l01);
    const y2 = l02s - x * x;
    sp[4] = x;
    sp[5] = Math.sqrt(y2 > 0 ? y2 : 0);
  }
}

// Lays out every patch. pos: vertex positions (Float32Array, 3 per vertex),
// indices: Uint32Array (all < vertexCount), patchOfFace / byPatch / seeds from
// the stream. emit(patch, face, xy) gets each face once its patch is placed,
// xy a Float64Array of 6 (reused between calls). vf: optional, the
// vertexFaces(indices, vertexCount) the caller already has; its face lists
// are reordered here (by patch), so the caller must be done with them.
export function layoutPatches(pos, indices, vertexCount, patchOfFace, patchCount, byPatch, seeds, emit, vf = null, solveAt = null) {
  const nf = patchOfFace.length;
  // Incidences per vertex, sorted by (patch, face): each vertex's face list
  // (ascending) stably sorted by patch. Almost every list is one patch
  // already, so this is mostly a check.
  const { offsets, faces: entFace } = vf ?? vertexFaces(indices, vertexCount);
  for (let v = 0; v < vertexCount; ++v) sortRunByPatch(entFace, offsets[v], offsets[v + 1], patchOfFace);
  const cursor = offsets.slice(0, vertexCount);
  // v's run in patch p is [cursor[v], runEnd(v, p)): the cursor moves past runs
  // of earlier patches (patches are replayed in ascending order, so each entry
  // is skipped once overall). Inlined by hand below, as in the C++ run_of.

  // placed[v] === p + 1: v is placed in patch p; listed[v] === stamp: already a candidate this round.
  const placed = new Uint32Array(vertexCount), listed = new Uint32Array(vertexCount);
  const xyOf = new Float64Array(2 * vertexCount);
  let list = new Uint32Array(64), listN = 0;
  const unf = new Unfoldings();
  const sp = new Float64Array(6), q2 = new Float64Array(2), xy = new Float64Array(6);
  let stamp = 0;
  // Candidates of a round: the unplaced vertex of every face of the patch with
  // exactly two placed corners (a face naming q twice never makes q a
  // candidate: it then has at most one placed corner while q is unplaced).
  // placedCorners[f] counts f's placed corners (a face is in one patch only,
  // so it is never reset); a face reaching two is noted in `pending` while its
  // vertex is placed, and looked at once the round is over (a face whose last
  // corner was placed in the same round yields nothing). The order found does
  // not matter: the list is sorted.
  const placedCorners = new Uint8Array(nf);
  const pending = new Uint32Array(nf); // each face reaches two once
  let pendingN = 0;

  for (let p = 0; p < patchCount; ++p) {
    if (solveAt && solveAt(p)) continue; // 1.2: a solve patch (layout_solve.js), laid out in patch order
    const mark = p + 1;
    const seed = seeds[p];
    placeSeed(pos, indices[3 * seed], indices[3 * seed + 1], indices[3 * seed + 2], sp);
    pendingN = 0;
    for (let k = 0; k < 3; ++k) {
      const v = indices[3 * seed + k];
      if (placed[v] === mark) continue; // a repeated vertex keeps its first position
      placed[v] = mark;
      xyOf[2 * v] = sp[2 * k];
      xyOf[2 * v + 1] = sp[2 * k + 1];
      const stop = offsets[v + 1];
      let i = cursor[v];
      while (i < stop && patchOfFace[entFace[i]] < p) ++i;
      cursor[v] = i;
      for (; i < stop && patchOfFace[entFace[i]] === p; ++i)
        if (++placedCorners[entFace[i]] === 2) pending[pendingN++] = entFace[i];
    }
    for (;;) {
      ++stamp;
      listN = 0;
      for (let j = 0; j < pendingN; ++j) {
        const t = 3 * pending[j];
        const x = indices[t], y = indices[t + 1], z = indices[t + 2];
        const q = placed[x] !== mark ? x : placed[y] !== mark ? y : placed[z] !== mark ? z : NO_VERTEX;
        if (q === NO_VERTEX || listed[q] === stamp) continue;
        listed[q] = stamp;
        if (listN === list.length) list = grow(list);
        list[listN++] = q;
      }
      pendingN = 0;
      if (listN === 0) break;
      list.subarray(0, listN).sort();
      for (let j = 0; j < listN; ++j) {
        const q = list[j];
        unf.n = 0;
        const stop = offsets[q + 1];
        let i = cursor[q];
        while (i < stop && patchOfFace[entFace[i]] < p) ++i;
        cursor[q] = i;
        for (; i < stop && patchOfFace[entFace[i]] === p; ++i) {
          const f = entFace[i], t = 3 * f;
          if (++placedCorners[f] === 2) pending[pendingN++] = f;
          const k = indices[t] === q ? 0 : indices[t + 1] === q ? 1 : 2;
          const a = indices[t + NEXT[k]], b = indices[t + PREV[k]];
          if (a === q || b === q) continue; // q not exactly once in this face
          if (placed[a] !== mark || placed[b] !== mark) continue;
          unf.push(xyOf[2 * a], xyOf[2 * a + 1], xyOf[2 * b], xyOf[2 * b + 1],
            Math.sqrt(length2(pos, q, a)), Math.sqrt(length2(pos, q, b)), length2(pos, a, b));
        }
        placeVertex(unf, q2);
        xyOf[2 * q] = q2[0];
        xyOf[2 * q + 1] = q2[1];
        placed[q] = mark;
      }
    }
    for (let i = byPatch.start[p]; i < byPatch.start[p + 1]; ++i) {
      const f = byPatch.faces[i];
      for (let k = 0; k < 3; ++k) {
        const v = indices[3 * f + k];
        if (placed[v] !== mark) throw new GltfWarpError('layout_unreachable_face', `face ${f} of patch ${p}`);
        xy[2 * k] = xyOf[2 * v];
        xy[2 * k + 1] = xyOf[2 * v + 1];
      }
      emit(p, f, xy);
    }
  }
}

// Stable sort of faces[lo, hi) by patch: insertion for the short lists of an
// ordinary vertex, a comparison sort (patch, then face) for a long fan.
// Exported for its test.
export function sortRunByPatch(faces, lo, hi, patchOfFace) {
  let sorted = true;
  for (let i = lo + 1; i < hi && sorted; ++i) sorted = patchOfFace[faces[i - 1]] <= patchOfFace[faces[i]];
  if (sorted) return;
  if (hi - lo > 32) {
    const run = Array.from(faces.subarray(lo, hi));
    run.sort((a, b) => patchOfFace[a] - patchOfFace[b] || a - b);
    faces.set(run, lo);
    return;
  }
  for (let i = lo + 1; i < hi; ++i) {
    const f = faces[i], p = patchOfFace[f];
    let j = i;
    for (; j > lo && patchOfFace[faces[j - 1]] > p; --j) faces[j] = faces[j - 1];
    faces[j] = f;
  }
}

function grow(a) {
  const b = new Uint32Array(a.length * 2);
  b.set(a);
  return b;
}
