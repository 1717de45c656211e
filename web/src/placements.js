// Section 6.4 of spec/README.md: each patch's rotation, translation, page,
// scale step, (1.1) seed face, (1.2) layout method and (1.3) fine placement.
import { GltfWarpError } from './errors.js';
import { contexts, RangeDecoder } from './range_decoder.js';
import { FLAG_FINE, FLAG_METHODS, FLAG_ROTATIONS, FLAG_SCALES, FLAG_SEEDS } from './stream_header.js';

const MAX_SCALE_MAGNITUDE = 31;
// 1.3: cos_q and sin_q in [-2 * FINE_UNIT, 2 * FINE_UNIT], coded offset by 2 * FINE_UNIT.
export const FINE_UNIT = 32768;
const FINE_CODES = 4 * FINE_UNIT + 1, FINE_FRAC_STEPS = 256;

// Faces of each patch, ascending (CSR by counting sort): faces[start[p] .. start[p + 1]).
export function facesByPatch(patchOfFace, patchCount) {
  const start = new Uint32Array(patchCount + 1);
  for (let f = 0; f < patchOfFace.length; ++f) ++start[patchOfFace[f] + 1];
  for (let p = 0; p < patchCount; ++p) start[p + 1] += start[p];
  const faces = new Uint32Array(patchOfFace.length);
  const fill = start.slice(0, patchCount);
  for (let f = 0; f < patchOfFace.length; ++f) faces[fill[patchOfFace[f]]++] = f;
  return { start, faces };
}

// Returns { rotation, x, y, page, scaleStep, seed, method, fine, mirror, cosQ,
// sinQ, xFrac, yFrac } typed arrays, one entry per patch. Without SEEDS the
// seed is the patch's lowest face; a coarse patch has fine = 0 and zero fine
// fields, a fine one rotation 0 (its coded rotation is ignored).
export function decodePlacements(header, byPatch) {
  const P = header.patchCount;
  const out = {
    rotation: new Uint8Array(P), x: new Uint32Array(P), y: new Uint32Array(P),
    page: new Uint32Array(P), scaleStep: new Int8Array(P), seed: new Uint32Array(P), method: new Uint8Array(P),
    fine: new Uint8Array(P), mirror: new Uint8Array(P), cosQ: new Int32Array(P), sinQ: new Int32Array(P),
    xFrac: new Uint8Array(P), yFrac: new Uint8Array(P),
  };
  const d = new RangeDecoder(header.placements);
  const nonzero = contexts(1), negative = contexts(1), magnitude = contexts(16), method = contexts(1), fine = contexts(1);
  const { flags } = header;
  for (let p = 0; p < P; ++p) {
    if (flags & FLAG_ROTATIONS) out.rotation[p] = d.uniform(256);
    out.x[p] = d.uniform32(header.atlasWidth + 1);
    out.y[p] = d.uniform32(header.atlasHeight + 1);
    if (header.pageCount > 1) out.page[p] = d.uniform32(header.pageCount);
    if (flags & FLAG_SCALES && d.bit(nonzero, 0)) {
      const neg = d.bit(negative, 0);
      const mag = d.expGolomb(magnitude);
      if (mag > MAX_SCALE_MAGNITUDE) throw new GltfWarpError('bad_value', `scale magnitude ${mag}`);
      out.scaleStep[p] = neg ? -(mag + 1) : mag + 1;
    }
    const first = byPatch.start[p];
    const rank = flags & FLAG_SEEDS ? d.uniform32(byPatch.start[p + 1] - first) : 0;
    out.seed[p] = byPatch.faces[first + rank];
    if (flags & FLAG_METHODS) out.method[p] = d.bit(method, 0); // 1.2: 0 unfold, 1 solve
    if (flags & FLAG_FINE && d.bit(fine, 0)) { // 1.3: a fine placement (section 4.3)
      out.fine[p] = 1;
      out.rotation[p] = 0;
      out.mirror[p] = d.equiprobable();
      const cosQ = d.uniform32(FINE_CODES) - 2 * FINE_UNIT, sinQ = d.uniform32(FINE_CODES) - 2 * FINE_UNIT;
      const xFrac = d.uniform(FINE_FRAC_STEPS), yFrac = d.uniform(FINE_FRAC_STEPS);
      if (cosQ === 0 && sinQ === 0) throw new GltfWarpError('bad_value', `patch ${p}: fine placement without a direction`);
      if ((xFrac && out.x[p] === header.atlasWidth) || (yFrac && out.y[p] === header.atlasHeight))
        throw new GltfWarpError('bad_value', `patch ${p}: fine translation past the page`);
      out.cosQ[p] = cosQ;
      out.sinQ[p] = sinQ;
      out.xFrac[p] = xFrac;
      out.yFrac[p] = yFrac;
    }
  }
  d.finish('placement');
  return out;
}
