// Section 3.3 of spec/README.md: the mesh the stream applies to is the
// primitive's points welded by exact position bits (no tolerance), vertices
// numbered in order of first appearance in point order, as
// codec/embedding_mesh.cpp does. Open addressing over the 32-bit patterns;
// the hash only decides speed, never the numbering.
import { GltfWarpError } from './errors.js';

// positions: Float32Array, 3 per point; pointIndices: 3 per face, point ids.
// Returns { positions, indices } of the welded mesh (indices name vertices).
export function weldByPosition(positions, pointIndices) {
  const n = positions.length / 3;
  const bits = new Uint32Array(positions.buffer, positions.byteOffset, positions.length);
  let cap = 16;
  while (cap < 2 * n) cap *= 2;
  const mask = cap - 1;
  const slot = new Int32Array(cap).fill(-1);
  const pointToVertex = new Uint32Array(n);
  const welded = new Float32Array(3 * n);
  const weldedBits = new Uint32Array(welded.buffer);
  let vertices = 0;
  for (let p = 0; p < n; ++p) {
    const x = bits[3 * p], y = bits[3 * p + 1], z = bits[3 * p + 2];
    let h = Math.imul(x, 0x9e3779b1) ^ Math.imul(y ^ (x >>> 15), 0x85ebca77) ^ Math.imul(z ^ (y >>> 13), 0xc2b2ae3d);
    h ^= h >>> 16;
    for (let i = h & mask; ; i = (i + 1) & mask) {
      const v = slot[i];
      if (v < 0) {
        slot[i] = vertices;
        welded[3 * vertices] = positions[3 * p];
        welded[3 * vertices + 1] = positions[3 * p + 1];
        welded[3 * vertices + 2] = positions[3 * p + 2];
        pointToVertex[p] = vertices++;
        break;
      }
      if (weldedBits[3 * v] === x && weldedBits[3 * v + 1] === y && weldedBits[3 * v + 2] === z) {
        pointToVertex[p] = v;
        break;
      }
    }
  }
  const indices = new Uint32Array(pointIndices.length);
  for (let c = 0; c < indices.length; ++c) {
    const p = pointIndices[c];
    if (p >= n) throw new GltfWarpError('bad_mesh', `point index ${p} of ${n} points`);
    indices[c] = pointToVertex[p];
  }
  return { positions: welded.subarray(0, 3 * vertices), indices };
}
