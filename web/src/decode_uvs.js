// decodeUvs: stream + mesh -> two floats per corner (spec/README.md section 6),
// the JavaScript twin of format/decode_uvs.cpp. A pure function over the
// caller's arrays; it throws a GltfWarpError whose `code` is the spec's error
// name, at the first error, in the spec's order.
import { GltfWarpError } from './errors.js';
import { lowerNeighbours, vertexFaces } from './mesh_adjacency.js';
import { decodePartition } from './partition.js';
import { decodePlacements, facesByPatch } from './placements.js';
import { layoutPatches } from './layout_replay.js';
import { solvePatchAt } from './layout_solve.js';
import { readHeader } from './stream_header.js';
import { patchScale, rotationCosSin } from './transform_tables.js';

// mesh: { positions: Float32Array (3 per vertex), indices: Uint32Array (3 per face) },
// the welded mesh of spec section 3.3. bytes: Uint8Array, the stream.
// Returns { uv: Float32Array (2 per corner), header, patchOfFace, placements,
// timings (ms per stage) }.
export function decodeUvs(mesh, bytes) {
  const t0 = performance.now();
  const { positions, indices } = mesh;
  if (indices.length % 3 !== 0 || positions.length % 3 !== 0)
    throw new GltfWarpError('bad_mesh', 'mesh buffers are not whole triples');
  const faceCount = indices.length / 3, vertexCount = positions.length / 3;
  const header = readHeader(bytes, faceCount);
  for (let c = 0; c < indices.length; ++c)
    if (indices[c] >= vertexCount) throw new GltfWarpError('bad_mesh', `index ${indices[c]} of ${vertexCount} vertices`);

  const vf = vertexFaces(indices, vertexCount);
  const lower = lowerNeighbours(indices, vertexCount, vf);
  const t1 = performance.now();
  const patchOfFace = decodePartition(header.partition, indices, faceCount, header.patchCount, vf, lower);
  const byPatch = facesByPatch(patchOfFace, header.patchCount);
  const placements = decodePlacements(header, byPatch);
  const t2 = performance.now();

  // Section 6.6: per patch (c, s) scaled and the origin (X, Y), then per
  // corner the texel position divided by the atlas size, rounded once to
  // float. A fine patch (1.3) takes (c, s) = (cos_q, sin_q) / 2^15 and the
  // fractions into (X, Y) (all exact), and a mirrored one negates py.
  const P = header.patchCount;
  const sc = new Float64Array(P), ss = new Float64Array(P), X = new Float64Array(P), Y = new Float64Array(P);
  for (let p = 0; p < P; ++p) {
    let c, s;
    X[p] = placements.x[p];
    Y[p] = placements.y[p];
    if (placements.fine[p]) {
      c = placements.cosQ[p] * 2 ** -15;
      s = placements.sinQ[p] * 2 ** -15;
      X[p] += placements.xFrac[p] * 2 ** -8;
      Y[p] += placements.yFrac[p] * 2 ** -8;
    } else {
      [c, s] = rotationCosSin(placements.rotation[p]);
    }
    const scale = header.texelScale * patchScale(placements.scaleStep[p]);
    sc[p] = scale * c;
    ss[p] = scale * s;
  }
  const mirror = placements.mirror;
  const W = header.atlasWidth, H = header.atlasHeight;
  const uv = new Float32Array(2 * indices.length);
  // Every corner of vertex v in patch p gets the same pair, so it is computed
  // once per (vertex, patch) and copied: doneIn[v] === p + 1 says uvOf[v] is
  // the pair of v in patch p (the same expression, so the same bits).
  const doneIn = new Uint32Array(vertexCount), uvOf = new Float32Array(2 * vertexCount);
  const emit = (p, f, xy) => {
    for (let k = 0; k < 3; ++k) {
      const v = indices[3 * f + k], o = 6 * f + 2 * k;
      if (doneIn[v] !== p + 1) {
        doneIn[v] = p + 1;
        const a = sc[p], b = ss[p], px = xy[2 * k], py = mirror[p] ? -xy[2 * k + 1] : xy[2 * k + 1];
        const tx = (a * px - b * py) + X[p];
        const ty = (b * px + a * py) + Y[p];
        uvOf[2 * v] = tx / W; // Float32Array store: round to nearest even
        uvOf[2 * v + 1] = ty / H;
      }
      uv[o] = uvOf[2 * v];
      uv[o + 1] = uvOf[2 * v + 1];
    }
  };
  // 1.2: solve patches (section 6.7) are laid out by layout_solve.js, in patch order.
  const solveAt = header.solve ? solvePatchAt(positions, indices, byPatch, placements.method, header.solve, emit) : null;
  layoutPatches(positions, indices, vertexCount, patchOfFace, P, byPatch, placements.seed, emit, vf, solveAt); // vf: the layout may reorder it
  const t3 = performance.now();
  return { uv, header, patchOfFace, placements, timings: { adjacency: t1 - t0, partition: t2 - t1, layout: t3 - t2 } };
}
