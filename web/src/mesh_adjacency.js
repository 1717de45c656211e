// Section 6.2 of spec/README.md, and the vertex -> faces lists the partition
// and the replay share. Linear time: counting sorts, no hashing.
const NONE = 0xffffffff;
export { NONE };

// Vertex -> incident faces in ascending face order (CSR: offsets[v]..offsets[v+1]);
// a face naming v twice is listed twice.
export function vertexFaces(indices, vertexCount) {
  const nc = indices.length;
  const offsets = new Uint32Array(vertexCount + 1);
  for (let c = 0; c < nc; ++c) ++offsets[indices[c] + 1];
  for (let v = 0; v < vertexCount; ++v) offsets[v + 1] += offsets[v];
  const faces = new Uint32Array(nc);
  const fill = offsets.slice(0, vertexCount);
  for (let f = 0, c = 0; c + 2 < nc; ++f) // a face counter, not c / 3: no division per corner
    for (let k = 0; k < 3; ++k) faces[fill[indices[c++]]++] = f;
  return { offsets, faces };
}

// lower[3f+k]: the lowest face g < f with an edge joining the vertices of edge
// k of f (either direction), or NONE. Each undirected edge {a, b}, a <= b, is
// met from a's face list in ascending face order, so the first face met with
// it is its lowest.
export function lowerNeighbours(indices, vertexCount, vf) {
  const lower = new Uint32Array(indices.length).fill(NONE);
  const stamp = new Uint32Array(vertexCount), first = new Uint32Array(vertexCount);
  for (let a = 0; a < vertexCount; ++a) {
    let prev = NONE;
    for (let i = vf.offsets[a]; i < vf.offsets[a + 1]; ++i) {
      const g = vf.faces[i];
      if (g === prev) continue; // a face naming a twice is listed twice
      prev = g;
      const t = 3 * g;
      for (let k = 0; k < 3; ++k) {
        const x = indices[t + k], y = indices[t + (k === 2 ? 0 : k + 1)];
        if ((x < y ? x : y) !== a) continue;
        const b = x < y ? y : x;
        if (stamp[b] !== a + 1) {
          stamp[b] = a + 1;
          first[b] = g;
        }
        if (first[b] < g) lower[t + k] = first[b];
      }
    }
  }
  return lower;
}
