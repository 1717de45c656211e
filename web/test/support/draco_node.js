// The Draco decoder that ships with three.js (examples/jsm/libs/draco, the
// same wasm DRACOLoader runs in the browser), loaded in node, and a decode
// that reads points and faces exactly as DRACOLoader's worker does
// (GetAttributeDataArrayForAllPoints as float, GetTrianglesUInt32Array).
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { fileURLToPath } from 'node:url';

const dir = fileURLToPath(new URL('../../node_modules/three/examples/jsm/libs/draco/', import.meta.url));

let modulePromise = null;
export function dracoModule() {
  if (!modulePromise) {
    const code = readFileSync(`${dir}draco_wasm_wrapper.js`, 'utf8');
    const module = { exports: {} };
    // The wrapper is a CommonJS/UMD script inside an ES-module package.
    new Function('module', 'exports', 'require', '__filename', '__dirname', code)(
      module, module.exports, createRequire(import.meta.url), `${dir}draco_wasm_wrapper.js`, dir);
    const factory = module.exports;
    modulePromise = factory({ wasmBinary: readFileSync(`${dir}draco_decoder.wasm`) });
  }
  return modulePromise;
}

// Returns { index: Uint32Array, attributes: { [uniqueId]: Float32Array } }.
export async function dracoDecode(bytes, uniqueIds) {
  const draco = await dracoModule();
  const decoder = new draco.Decoder();
  const mesh = new draco.Mesh();
  const status = decoder.DecodeArrayToMesh(bytes, bytes.byteLength, mesh);
  if (!status.ok()) throw new Error(`Draco: ${status.error_msg()}`);
  const nf = mesh.num_faces(), np = mesh.num_points();
  let ptr = draco._malloc(nf * 12);
  decoder.GetTrianglesUInt32Array(mesh, nf * 12, ptr);
  const index = new Uint32Array(draco.HEAPF32.buffer, ptr, nf * 3).slice();
  draco._free(ptr);
  const attributes = {};
  for (const id of uniqueIds) {
    const att = decoder.GetAttributeByUniqueId(mesh, id);
    const n = att.num_components() * np;
    ptr = draco._malloc(n * 4);
    decoder.GetAttributeDataArrayForAllPoints(mesh, att, draco.DT_FLOAT32, n * 4, ptr);
    attributes[id] = new Float32Array(draco.HEAPF32.buffer, ptr, n).slice();
    draco._free(ptr);
  }
  draco.destroy(mesh);
  draco.destroy(decoder);
  return { index, attributes };
}
