// Section 3.4 of spec/README.md: a point whose corners received different
// coordinates is split, one copy per distinct (bitwise) coordinate pair; new
// vertices are numbered in order of their first corner, exactly as
// split_by_corner_uv in codec/implicit_uv_primitive.cpp, so the output
// vertex order equals the C++ decoder's.

// pointIndices: 3 per face; cornerUv: Float32Array, 2 per corner.
// Returns { index: Uint32Array (corner -> new vertex), origin: Uint32Array
// (new vertex -> point), uv: Float32Array (2 per new vertex) }.
export function splitByCornerUv(pointIndices, pointCount, cornerUv) {
  const corners = pointIndices.length;
  const uvBits = new Uint32Array(cornerUv.buffer, cornerUv.byteOffset, cornerUv.length);
  // New vertices of each point as a chain: head[point] -> next[vertex] -> ...
  const head = new Int32Array(pointCount).fill(-1);
  let next = new Int32Array(pointCount + (pointCount >> 2) + 16);
  let origin = new Uint32Array(next.length);
  let outBits = new Uint32Array(2 * next.length);
  const index = new Uint32Array(corners);
  let count = 0;
  for (let c = 0; c < corners; ++c) {
    const p = pointIndices[c];
    const u = uvBits[2 * c], v = uvBits[2 * c + 1];
    let found = head[p];
    while (found >= 0 && !(outBits[2 * found] === u && outBits[2 * found + 1] === v)) found = next[found];
    if (found < 0) {
      if (count === next.length) [next, origin, outBits] = [grow(next), grow(origin), grow(outBits)];
      found = count++;
      origin[found] = p;
      next[found] = head[p];
      head[p] = found;
      outBits[2 * found] = u;
      outBits[2 * found + 1] = v;
    }
    index[c] = found;
  }
  const uv = new Float32Array(outBits.buffer.slice(0, 8 * count));
  return { index, origin: origin.slice(0, count), uv };
}

function grow(a) {
  const b = new a.constructor(a.length * 2);
  b.set(a);
  return b;
}
