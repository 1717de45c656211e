// One primitive's whole rebuild, as the worker runs it: weld (3.3), decode
// (6), split by coordinate (3.4), and tangents when asked. Plain typed arrays
// in and out, no three.js, so it runs in a worker, in node, or inline.
import { decodeUvs } from './decode_uvs.js';
import { GltfWarpError } from './errors.js';
import { splitByCornerUv } from './split_vertices.js';
import { vertexTangents } from './tangents.js';
import { weldByPosition } from './weld.js';

// job: { positions: Float32Array (3 per point, finite, else bad_mesh),
// indices: Uint32Array (3 per face, point ids), stream: Uint8Array, normals?:
// Float32Array (3 per point), tangents: boolean, attributes?: [{ array,
// itemSize }] (per-point values to copy to the new vertices) }.
// Returns { index (corner -> new vertex), origin (new vertex -> point), uv
// (2 per new vertex), tangent? (4 per new vertex), patchOfVertex, patchCount,
// timings }; with job.attributes also positions (3 per new vertex) and
// attributes (one array per job attribute, per new vertex).
export function decodePrimitive(job) {
  const t0 = performance.now();
  const { positions } = job;
  for (let i = 0; i < positions.length; ++i)
    if (!Number.isFinite(positions[i])) throw new GltfWarpError('bad_mesh', 'POSITION holds a NaN or infinite value');
  const mesh = weldByPosition(job.positions, job.indices);
  const t1 = performance.now();
  const { uv: cornerUv, header, patchOfFace, timings: stages } = decodeUvs(mesh, job.stream);
  const t2 = performance.now();
  const split = splitByCornerUv(job.indices, job.positions.length / 3, cornerUv);
  const vertexCount = split.origin.length;
  const patchOfVertex = new Uint32Array(vertexCount);
  for (let f = 0, c = 0; c < split.index.length; ++f)
    for (let k = 0; k < 3; ++k) patchOfVertex[split.index[c++]] = patchOfFace[f];
  const t3 = performance.now();
  let tangent = null, vertexPositions = null, attributes = null;
  if ((job.tangents && job.normals) || job.attributes) vertexPositions = gather(positions, split.origin, 3);
  if (job.tangents && job.normals)
    tangent = vertexTangents(vertexPositions, gather(job.normals, split.origin, 3), split.uv, split.index);
  if (job.attributes) attributes = job.attributes.map((a) => gather(a.array, split.origin, a.itemSize));
  const t4 = performance.now();
  return {
    index: split.index, origin: split.origin, uv: split.uv, tangent, patchOfVertex, positions: vertexPositions, attributes,
    patchCount: header.patchCount, atlasWidth: header.atlasWidth, atlasHeight: header.atlasHeight,
    timings: { weld: t1 - t0, decode: t2 - t1, ...stages, split: t3 - t2, attributes: t4 - t3 },
  };
}

// Per-new-vertex copy of a per-point attribute with n components.
export function gather(array, origin, n) {
  const out = new array.constructor(origin.length * n);
  for (let i = 0; i < origin.length; ++i) {
    const s = origin[i] * n, d = i * n;
    for (let k = 0; k < n; ++k) out[d + k] = array[s + k];
  }
  return out;
}
