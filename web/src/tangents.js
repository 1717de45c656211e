// TANGENT for the rebuilt coordinates, in the MikkTSpace convention glTF
// viewers use (Mikkelsen, "Simulation of Wrinkled Surfaces Revisited", 2008).
// A line-by-line port of vertex_tangents in codec/tangents.cpp, whose header
// lists its deviations from mikktspace.c; the same double expressions in the
// same order, so the floats match the C++ decoder's. One function is not
// among the spec's correctly rounded operations: the corner angle uses
// Math.acos where the C++ uses std::acos. Both are within an ulp of the true
// value and the angle is only a weight of a sum rounded to float, so a
// difference, where it happens, moves a tangent by at most one float ulp.
// (The tangents are not part of the bit-exact format; the UVs are.)

const EMPTY = 0xffffffff;

// positions (3 per vertex), normals (3 per vertex), uvs (2 per vertex):
// Float32Array; indices: Uint32Array. Returns Float32Array, 4 per vertex.
export function vertexTangents(positions, normals, uvs, indices) {
  const nv = positions.length / 3;
  const nc = indices.length - (indices.length % 3), nf = nc / 3;
  const out = new Float32Array(4 * nv);
  for (let v = 0; v < nv; ++v) out[4 * v] = out[4 * v + 3] = 1;
  for (let c = 0; c < nc; ++c) if (indices[c] >= nv) return out;

  // Welding classes: vertices with equal (position, normal, uv) bits (-0 as
  // +0), numbered by the first corner that names them.
  const cls = vertexClasses(positions, normals, uvs, indices, nc, nv);
  const classes = cls.count, vclass = cls.vclass;

  // Per face: unit tangent (du), unit bitangent (toward decreasing v), and
  // whether the frame is mirrored.
  const faceT = new Float64Array(3 * nf), faceB = new Float64Array(3 * nf);
  const faceOk = new Uint8Array(nf), faceFlip = new Uint8Array(nf);
  const P = (c, i) => positions[3 * indices[c] + i];
  const U = (c, i) => uvs[2 * indices[c] + i];
  for (let f = 0; f < nf; ++f) {
    const c0 = 3 * f;
    const d1x = P(c0 + 1, 0) - P(c0, 0), d1y = P(c0 + 1, 1) - P(c0, 1), d1z = P(c0 + 1, 2) - P(c0, 2);
    const d2x = P(c0 + 2, 0) - P(c0, 0), d2y = P(c0 + 2, 1) - P(c0, 1), d2z = P(c0 + 2, 2) - P(c0, 2);
    const s1 = U(c0 + 1, 0) - U(c0, 0), t1 = U(c0 + 1, 1) - U(c0, 1);
    const s2 = U(c0 + 2, 0) - U(c0, 0), t2 = U(c0 + 2, 1) - U(c0, 1);
    const r = s1 * t2 - s2 * t1;
    const ir = 1.0 / r;
    const ux = ir * (t2 * d1x - t1 * d2x), uy = ir * (t2 * d1y - t1 * d2y), uz = ir * (t2 * d1z - t1 * d2z);
    const vx = ir * (s1 * d2x - s2 * d1x), vy = ir * (s1 * d2y - s2 * d1y), vz = ir * (s1 * d2z - s2 * d1z);
    const lu = Math.sqrt(ux * ux + uy * uy + uz * uz), lv = Math.sqrt(vx * vx + vy * vy + vz * vz);
    if (r !== 0 && Number.isFinite(lu) && lu > 0 && lv > 0) {
      faceOk[f] = 1;
      const iu = 1.0 / lu;
      const tx = iu * ux, ty = iu * uy, tz = iu * uz;
      const nbx = -1.0 * vx, nby = -1.0 * vy, nbz = -1.0 * vz;
      const lb = Math.sqrt(nbx * nbx + nby * nby + nbz * nbz), ib = 1.0 / lb;
      const bx = ib * nbx, by = ib * nby, bz = ib * nbz;
      faceT[3 * f] = tx; faceT[3 * f + 1] = ty; faceT[3 * f + 2] = tz;
      faceB[3 * f] = bx; faceB[3 * f + 1] = by; faceB[3 * f + 2] = bz;
      const fnx = d1y * d2z - d1z * d2y, fny = d1z * d2x - d1x * d2z, fnz = d1x * d2y - d1y * d2x;
      const cx = fny * tz - fnz * ty, cy = fnz * tx - fnx * tz, cz = fnx * ty - fny * tx;
      faceFlip[f] = cx * bx + cy * by + cz * bz < 0 ? 1 : 0;
    }
  }

  // Per group (class, flip): angle-weighted sums of the projected tangents
  // and of the bitangent sign, in corner order.
  const sum = new Float64Array(6 * classes), bsign = new Float64Array(2 * classes);
  const n = new Float64Array(3);
  const unitNormal = (c) => {
    const v = indices[c];
    const x = normals[3 * v], y = normals[3 * v + 1], z = normals[3 * v + 2];
    const l = Math.sqrt(x * x + y * y + z * z);
    if (l > 0) {
      const il = 1.0 / l;
      n[0] = il * x; n[1] = il * y; n[2] = il * z;
    } else {
      n[0] = x; n[1] = y; n[2] = z;
    }
  };
  for (let c = 0; c < nc; ++c) {
    const f = (c / 3) | 0;
    if (!faceOk[f]) continue;
    const g = 2 * vclass[indices[c]] + faceFlip[f];
    const c0 = 3 * f, k0 = c - c0;
    const ca = c0 + (k0 + 1) % 3, cb = c0 + (k0 + 2) % 3;
    let e1x = P(ca, 0) - P(c, 0), e1y = P(ca, 1) - P(c, 1), e1z = P(ca, 2) - P(c, 2);
    let l = Math.sqrt(e1x * e1x + e1y * e1y + e1z * e1z);
    if (l > 0) { const il = 1.0 / l; e1x = il * e1x; e1y = il * e1y; e1z = il * e1z; }
    let e2x = P(cb, 0) - P(c, 0), e2y = P(cb, 1) - P(c, 1), e2z = P(cb, 2) - P(c, 2);
    l = Math.sqrt(e2x * e2x + e2y * e2y + e2z * e2z);
    if (l > 0) { const il = 1.0 / l; e2x = il * e2x; e2y = il * e2y; e2z = il * e2z; }
    let cosine = e1x * e2x + e1y * e2y + e1z * e2z;
    // std::max(-1.0, std::min(1.0, x)) as the C++ evaluates it (NaN -> 1).
    cosine = cosine < 1.0 ? cosine : 1.0;
    cosine = -1.0 < cosine ? cosine : -1.0;
    const angle = Math.acos(cosine);
    unitNormal(c);
    const ftx = faceT[3 * f], fty = faceT[3 * f + 1], ftz = faceT[3 * f + 2];
    const dt = ftx * n[0] + fty * n[1] + ftz * n[2];
    let tx = ftx - dt * n[0], ty = fty - dt * n[1], tz = ftz - dt * n[2];
    l = Math.sqrt(tx * tx + ty * ty + tz * tz);
    if (l > 0) { const il = 1.0 / l; tx = il * tx; ty = il * ty; tz = il * tz; }
    sum[3 * g] = sum[3 * g] + angle * tx;
    sum[3 * g + 1] = sum[3 * g + 1] + angle * ty;
    sum[3 * g + 2] = sum[3 * g + 2] + angle * tz;
    const fbx = faceB[3 * f], fby = faceB[3 * f + 1], fbz = faceB[3 * f + 2];
    const db = fbx * n[0] + fby * n[1] + fbz * n[2];
    const bx = fbx - db * n[0], by = fby - db * n[1], bz = fbz - db * n[2];
    const cx = n[1] * tz - n[2] * ty, cy = n[2] * tx - n[0] * tz, cz = n[0] * ty - n[1] * tx;
    bsign[g] += angle * (cx * bx + cy * by + cz * bz);
  }

  // Each vertex takes the tangent of its first corner.
  const done = new Uint8Array(nv);
  for (let c = 0; c < nc; ++c) {
    const v = indices[c];
    if (done[v]) continue;
    done[v] = 1;
    const g = 2 * vclass[v] + faceFlip[(c / 3) | 0];
    unitNormal(c);
    const sx = sum[3 * g], sy = sum[3 * g + 1], sz = sum[3 * g + 2];
    const ds = sx * n[0] + sy * n[1] + sz * n[2];
    let tx = sx - ds * n[0], ty = sy - ds * n[1], tz = sz - ds * n[2];
    let l = Math.sqrt(tx * tx + ty * ty + tz * tz);
    if (l > 0) { const il = 1.0 / l; tx = il * tx; ty = il * ty; tz = il * tz; }
    l = Math.sqrt(tx * tx + ty * ty + tz * tz);
    if (!(l > 0.5)) [tx, ty, tz] = orthogonal(n);
    out[4 * v] = tx; out[4 * v + 1] = ty; out[4 * v + 2] = tz;
    out[4 * v + 3] = bsign[g] < 0 ? -1 : 1;
  }
  return out;
}

// Any unit vector orthogonal to n (as orthogonal() in tangents.cpp).
function orthogonal(n) {
  const [ax, ay, az] = Math.abs(n[0]) < 0.9 ? [1, 0, 0] : [0, 1, 0];
  const d = ax * n[0] + ay * n[1] + az * n[2];
  let tx = ax - d * n[0], ty = ay - d * n[1], tz = az - d * n[2];
  let l = Math.sqrt(tx * tx + ty * ty + tz * tz);
  if (l > 0) { const il = 1.0 / l; tx = il * tx; ty = il * ty; tz = il * tz; }
  l = Math.sqrt(tx * tx + ty * ty + tz * tz);
  return l > 0 ? [tx, ty, tz] : [1, 0, 0];
}

// Class of each vertex: equal canonical (position, normal, uv) bits share a
// class; classes numbered by first appearance in corner order.
function vertexClasses(positions, normals, uvs, indices, nc, nv) {
  const pb = new Uint32Array(positions.buffer, positions.byteOffset, positions.length);
  const nb = new Uint32Array(normals.buffer, normals.byteOffset, normals.length);
  const ub = new Uint32Array(uvs.buffer, uvs.byteOffset, uvs.length);
  const key = new Uint32Array(8 * nv); // keys of the classes, 8 words each
  const canon = (b) => (b === 0x80000000 ? 0 : b); // -0 welds with +0
  let cap = 16;
  while (cap < 2 * nv) cap *= 2;
  const mask = cap - 1, slot = new Uint32Array(cap).fill(EMPTY);
  const vclass = new Uint32Array(nv).fill(EMPTY);
  const k = new Uint32Array(8);
  let count = 0;
  for (let c = 0; c < nc; ++c) {
    const v = indices[c];
    if (vclass[v] !== EMPTY) continue;
    k[0] = canon(pb[3 * v]); k[1] = canon(pb[3 * v + 1]); k[2] = canon(pb[3 * v + 2]);
    k[3] = canon(nb[3 * v]); k[4] = canon(nb[3 * v + 1]); k[5] = canon(nb[3 * v + 2]);
    k[6] = canon(ub[2 * v]); k[7] = canon(ub[2 * v + 1]);
    let h = 0x9e3779b9;
    for (let i = 0; i < 8; ++i) h = Math.imul(h ^ k[i], 0x85ebca6b) ^ (h >>> 15);
    for (let i = (h ^ (h >>> 13)) & mask; ; i = (i + 1) & mask) {
      const s = slot[i];
      if (s === EMPTY) {
        slot[i] = count;
        key.set(k, 8 * count);
        vclass[v] = count++;
        break;
      }
      let same = true;
      for (let j = 0; j < 8 && same; ++j) same = key[8 * s + j] === k[j];
      if (same) {
        vclass[v] = s;
        break;
      }
    }
  }
  return { vclass, count };
}
