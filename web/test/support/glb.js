// Minimal GLB reader for the tests: the JSON chunk and the BIN chunk, and
// accessor / bufferView views into it (tightly packed accessors only, which
// is what gltf-warp writes).
import { readFileSync } from 'node:fs';

const COMPONENTS = { SCALAR: 1, VEC2: 2, VEC3: 3, VEC4: 4 };
const ARRAYS = { 5120: Int8Array, 5121: Uint8Array, 5122: Int16Array, 5123: Uint16Array, 5125: Uint32Array, 5126: Float32Array };

export function readGlb(path) {
  const data = readFileSync(path);
  const bytes = new Uint8Array(data.buffer, data.byteOffset, data.byteLength);
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  if (view.getUint32(0, true) !== 0x46546c67) throw new Error(`${path}: not a GLB`);
  let json = null, bin = null;
  for (let p = 12; p + 8 <= bytes.length;) {
    const length = view.getUint32(p, true), type = view.getUint32(p + 4, true);
    const chunk = bytes.subarray(p + 8, p + 8 + length);
    if (type === 0x4e4f534a) json = JSON.parse(new TextDecoder().decode(chunk));
    else if (type === 0x004e4942) bin = chunk;
    p += 8 + length;
  }
  return { json, bin, bytes };
}

export function bufferViewBytes(glb, index) {
  const bv = glb.json.bufferViews[index];
  return glb.bin.subarray(bv.byteOffset ?? 0, (bv.byteOffset ?? 0) + bv.byteLength);
}

// A copy of the accessor's elements as a typed array.
export function accessorArray(glb, index) {
  const a = glb.json.accessors[index];
  const bv = glb.json.bufferViews[a.bufferView];
  const Type = ARRAYS[a.componentType];
  const n = a.count * COMPONENTS[a.type];
  if (bv.byteStride && bv.byteStride !== Type.BYTES_PER_ELEMENT * COMPONENTS[a.type]) throw new Error('strided accessor');
  const start = glb.bin.byteOffset + (bv.byteOffset ?? 0) + (a.byteOffset ?? 0);
  return new Type(glb.bin.buffer.slice(start, start + n * Type.BYTES_PER_ELEMENT));
}
