// Section 6.3 of spec/README.md: the patch of every face, predicted from its
// lower neighbours (sharing an edge), then from faces sharing a vertex, else
// coded explicitly. Typed arrays only; no allocation per face.
import { GltfWarpError } from './errors.js';
import { contexts, RangeDecoder } from './range_decoder.js';
import { NONE } from './mesh_adjacency.js';

const VERTEX_SCAN = 16; // faces examined per vertex for the second tier
const MAX_VCAND = 8; // second-tier candidates

// Returns patchOfFace (Uint32Array, one per face).
export function decodePartition(section, indices, faceCount, patchCount, vf, lower) {
  const patch = new Uint32Array(faceCount);
  if (faceCount === 0) return patch;
  const d = new RangeDecoder(section);
  const hit = contexts(27); // [m - 1][seam context][lower neighbours - 1]
  const pick2 = contexts(3), pick3a = contexts(3), pick3b = contexts(3);
  const fresh = contexts(2), vhit = contexts(1), vidx = contexts(MAX_VCAND - 1);
  const seam = new Uint8Array(faceCount);
  const cand = new Uint32Array(3), count = new Uint32Array(3), vcand = new Uint32Array(MAX_VCAND);
  let created = 1;
  seam[0] = 1;
  for (let f = 1; f < faceCount; ++f) {
    // Candidates: distinct patches of the lower neighbours, most frequent
    // first, ties in edge order (stable).
    let m = 0, n = 0, seams = 0;
    for (let k = 0; k < 3; ++k) {
      const g = lower[3 * f + k];
      if (g === NONE) continue;
      ++n;
      seams += seam[g];
      const p = patch[g];
      let i = 0;
      while (i < m && cand[i] !== p) ++i;
      if (i === m) {
        cand[m] = p;
        count[m++] = 0;
      }
      ++count[i];
    }
    for (let i = 1; i < m; ++i)
      for (let j = i; j > 0 && count[j] > count[j - 1]; --j) {
        let t = count[j]; count[j] = count[j - 1]; count[j - 1] = t;
        t = cand[j]; cand[j] = cand[j - 1]; cand[j - 1] = t;
      }
    const s = seams < 2 ? seams : 2;
    let isHit = 0, p = 0;
    if (m >= 1) {
      isHit = d.bit(hit, (m - 1) * 9 + s * 3 + (n - 1));
      if (isHit) {
        let idx = 0;
        if (m === 2) idx = d.bit(pick2, s);
        else if (m === 3 && d.bit(pick3a, s)) idx = 1 + d.bit(pick3b, s);
        p = cand[idx];
      }
    }
    if (!isHit) {
      const isFresh = created < patchCount ? d.bit(fresh, m > 0 ? 1 : 0) : 0;
      if (isFresh) {
        p = created++;
      } else {
        const vm = vertexCandidates(vf, indices, f, patch, cand, m, vcand);
        if (vm >= 1 && d.bit(vhit, 0)) {
          let i = 0;
          while (i + 1 < vm && d.bit(vidx, i)) ++i;
          p = vcand[i];
        } else {
          p = d.uniform32(created);
        }
      }
    }
    patch[f] = p;
    seam[f] = m === 1 && isHit ? 0 : 1;
    for (let k = 0; k < 3; ++k) {
      const g = lower[3 * f + k];
      if (g !== NONE && patch[g] !== p) seam[g] = 1;
    }
  }
  if (created !== patchCount) throw new GltfWarpError('bad_count', `partition creates ${created} of ${patchCount} patches`);
  d.finish('partition');
  return patch;
}

// Second tier: per vertex of f in corner order, the (at most 16) highest
// incident faces below f, descending; their patches not among cand, distinct,
// at most 8. Returns vm.
function vertexCandidates(vf, indices, f, patch, cand, m, vcand) {
  let vm = 0;
  for (let k = 0; k < 3; ++k) {
    const w = indices[3 * f + k];
    const begin = vf.offsets[w];
    // lower_bound of f in the ascending list.
    let lo = begin, hi = vf.offsets[w + 1];
    while (lo < hi) {
      const mid = (lo + hi) >>> 1;
      if (vf.faces[mid] < f) lo = mid + 1;
      else hi = mid;
    }
    for (let it = lo, seen = 0; it > begin && seen < VERTEX_SCAN; ++seen) {
      const p = patch[vf.faces[--it]];
      let dup = false;
      for (let i = 0; i < m && !dup; ++i) dup = cand[i] === p;
      for (let i = 0; i < vm && !dup; ++i) dup = vcand[i] === p;
      if (dup) continue;
      vcand[vm++] = p;
      if (vm === MAX_VCAND) return vm;
    }
  }
  return vm;
}
