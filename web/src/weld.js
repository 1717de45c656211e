// Section 3.3 of spec/README.md: the mesh the stream applies to is the
// primitive's points welded by exact position bits (no tolerance), vertices
// numbered in order of first appearance in point order, as
// codec/embedding_mesh.cpp does. Open addressing over the 32-bit patterns;
// the hash only decides speed, never the numbering.
import { GltfWarpError } from './errors.js';

// positions: Float32Array, 3 per point; pointIndices: 3 per face, point ids.
// Returns { positions, indices } of the welded mesh (indices name vertices).
// When no two points share a position (Draco's usual output) the weld is the
// identity, and the result shares the caller's arrays (read them, do not
// write them).
export function weldByPosition(positions, pointIndices) {
  const n = positions.length / 3;
  const bits = new Uint32Array(positions.buffer, positions.byteOffset, positions.length);
  let cap = 16;
  while (cap < 2 * n) cap *= 2;
  const mask = cap - 1;
  const slot = new Int32Array(cap).fill(-1); // first point of a position
  const pointToVertex = new Uint32Array(n);
  let vertices = 0;
  for (let p = 0; p < n; ++p) {
    const x = bits[3 * p], y = bits[3 * p + 1], z = bits[3 * p + 2];
    let h = Math.imul(x, 0x9e3779b1) ^ Math.imul(y ^ (x >>> 15), 0x85ebca77) ^ Math.imul(z ^ (y >>> 13), 0xc2b2ae3d);
    h ^= h >>> 16;
    for (let i = h & mask; ; i = (i + 1) & mask) {
      const q = slot[i];
      if (q < 0) {
        slot[i] = p;
        pointToVertex[p] = vertices++;
        break;
      }
      if (bits[3 * q] === x && bits[3 * q + 1] === y && bits[3 * q + 2] === z) {
        pointToVertex[p] = pointToVertex[q];
        break;
      }
    }
  }
  if (vertices === n) {
    for (let c = 0; c < pointIndices.length; ++c)
      if (pointIndices[c] >= n) throw new GltfWarpError('bad_mesh', `point index ${pointIndices[c]} of ${n} points`);
    return { positions, indices: pointIndices };
  }
  const welded = new Float32Array(3 * vertices);
  for (let p = 0, v = 0; p < n; ++p)
    if (pointToVertex[p] === v) {
      welded[3 * v] = positions[3 * p];
      welded[3 * v + 1] = positions[3 * p + 1];
      welded[3 * v + 2] = positions[3 * p + 2];
      ++v;
    }
  const indices = new Uint32Array(pointIndices.length);
  for (let c = 0; c < indices.length; ++c) {
    const p = pointIndices[c];
    if (p >= n) throw new GltfWarpError('bad_mesh', `point index ${p} of ${n} points`);
    indices[c] = pointToVertex[p];
  }
  return { positions: welded, indices };
}
