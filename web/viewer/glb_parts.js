// Bytes per part of a .glb, for the viewer's table: Draco geometry, the
// GLTFWARP streams, images, and everything else in the binary chunk.
export function glbParts(buffer) {
  const view = new DataView(buffer);
  if (view.getUint32(0, true) !== 0x46546c67) return null;
  let json = null, jsonBytes = 0;
  for (let p = 12; p + 8 <= buffer.byteLength;) {
    const length = view.getUint32(p, true), type = view.getUint32(p + 4, true);
    if (type === 0x4e4f534a) {
      json = JSON.parse(new TextDecoder().decode(new Uint8Array(buffer, p + 8, length)));
      jsonBytes = length;
    }
    p += 8 + length;
  }
  const role = new Map(); // bufferView -> part
  for (const mesh of json.meshes ?? [])
    for (const prim of mesh.primitives) {
      const ext = prim.extensions ?? {};
      if (ext.KHR_draco_mesh_compression) role.set(ext.KHR_draco_mesh_compression.bufferView, 'geometry (Draco)');
      if (ext.GLTFWARP_implicit_texcoords) role.set(ext.GLTFWARP_implicit_texcoords.bufferView, 'UV streams');
    }
  for (const image of json.images ?? []) if (image.bufferView !== undefined) role.set(image.bufferView, 'images');
  const parts = { 'geometry (Draco)': 0, 'UV streams': 0, images: 0, 'other binary': 0, JSON: jsonBytes };
  (json.bufferViews ?? []).forEach((bv, i) => { parts[role.get(i) ?? 'other binary'] += bv.byteLength; });
  parts.total = buffer.byteLength;
  return parts;
}
