// Bit-exactness on real models: every corpus model is encoded and decoded by
// the C++ CLI; its Draco geometry is decoded here with three.js's own Draco
// wasm, exactly as DRACOLoader reads it, and decodePrimitive must give the
// same index, TEXCOORD_0 and TANGENT arrays as `gltf-warp decode`, compared by
// FNV-1a 64 hash of their bytes.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { rmSync } from 'node:fs';
import { decodePrimitive } from '../src/decode_primitive.js';
import { corpusModels, encodeAndDecode, prerequisites, workDir } from './support/corpus.js';
import { dracoDecode } from './support/draco_node.js';
import { fnv1a64 } from './support/fnv1a.js';
import { accessorArray, bufferViewBytes, readGlb } from './support/glb.js';

const skip = prerequisites();
const dir = skip ? null : workDir();
const models = skip ? [] : corpusModels();
let rebuiltTotal = 0;

test('corpus present', { skip: skip ?? false }, () => assert.ok(models.length > 0));

for (const model of models) {
  test(`corpus ${model.name}: JS UVs equal the C++ decoder's`, async () => {
    const { encoded, decoded } = encodeAndDecode(model, dir);
    const enc = readGlb(encoded), dec = readGlb(decoded);
    let rebuilt = 0;
    for (const [mi, mesh] of (enc.json.meshes ?? []).entries())
      for (const [pi, prim] of mesh.primitives.entries()) {
        const ours = prim.extensions?.GLTFWARP_implicit_texcoords;
        if (!ours) continue;
        const draco = prim.extensions.KHR_draco_mesh_compression;
        assert.ok(draco, 'the CLI writes Draco geometry by default');
        const ids = [draco.attributes.POSITION];
        if (draco.attributes.NORMAL !== undefined) ids.push(draco.attributes.NORMAL);
        const geometry = await dracoDecode(bufferViewBytes(enc, draco.bufferView), ids);
        const r = decodePrimitive({
          positions: geometry.attributes[draco.attributes.POSITION], indices: geometry.index,
          normals: geometry.attributes[draco.attributes.NORMAL] ?? null, stream: bufferViewBytes(enc, ours.bufferView),
          tangents: ours.tangents === true,
        });
        const plain = dec.json.meshes[mi].primitives[pi];
        const where = `mesh ${mi} primitive ${pi}`;
        assert.equal(fnv1a64(r.uv), fnv1a64(accessorArray(dec, plain.attributes.TEXCOORD_0)), `${where}: TEXCOORD_0`);
        assert.equal(fnv1a64(r.index), fnv1a64(Uint32Array.from(accessorArray(dec, plain.indices))), `${where}: indices`);
        if (plain.attributes.TANGENT !== undefined)
          assert.equal(fnv1a64(r.tangent), fnv1a64(accessorArray(dec, plain.attributes.TANGENT)), `${where}: TANGENT`);
        ++rebuilt;
      }
    rebuiltTotal += rebuilt;
    if (rebuilt === 0) test.diagnostic?.(`${model.name}: no implicit primitive`);
  });
}

test('corpus: some primitives were rebuilt', { skip: skip ?? false }, () => {
  assert.ok(rebuiltTotal > 0);
  rmSync(dir, { recursive: true, force: true });
});
