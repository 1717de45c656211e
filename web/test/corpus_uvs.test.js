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

// Encodes and decodes `model` with the CLI, rebuilds every implicit
// primitive here and compares it with the C++ decoder's; returns how many
// primitives it rebuilt and the stream versions it met.
async function expectJsEqualsCpp(model, extra = [], tag = '') {
  const { encoded, decoded } = encodeAndDecode(model, dir, extra, tag);
  const enc = readGlb(encoded), dec = readGlb(decoded);
  let rebuilt = 0;
  const minors = new Set();
  for (const [mi, mesh] of (enc.json.meshes ?? []).entries())
    for (const [pi, prim] of mesh.primitives.entries()) {
      const ours = prim.extensions?.GLTFWARP_implicit_texcoords;
      if (!ours) continue;
      const draco = prim.extensions.KHR_draco_mesh_compression;
      assert.ok(draco, 'the CLI writes Draco geometry by default');
      const ids = [draco.attributes.POSITION];
      if (draco.attributes.NORMAL !== undefined) ids.push(draco.attributes.NORMAL);
      const geometry = await dracoDecode(bufferViewBytes(enc, draco.bufferView), ids);
      const stream = bufferViewBytes(enc, ours.bufferView);
      minors.add(stream[5]);
      const r = decodePrimitive({
        positions: geometry.attributes[draco.attributes.POSITION], indices: geometry.index,
        normals: geometry.attributes[draco.attributes.NORMAL] ?? null, stream, tangents: ours.tangents === true,
      });
      const plain = dec.json.meshes[mi].primitives[pi];
      const where = `mesh ${mi} primitive ${pi}`;
      assert.equal(fnv1a64(r.uv), fnv1a64(accessorArray(dec, plain.attributes.TEXCOORD_0)), `${where}: TEXCOORD_0`);
      assert.equal(fnv1a64(r.index), fnv1a64(Uint32Array.from(accessorArray(dec, plain.indices))), `${where}: indices`);
      if (plain.attributes.TANGENT !== undefined)
        assert.equal(fnv1a64(r.tangent), fnv1a64(accessorArray(dec, plain.attributes.TANGENT)), `${where}: TANGENT`);
      ++rebuilt;
    }
  return { rebuilt, minors };
}

for (const model of models) {
  test(`corpus ${model.name}: JS UVs equal the C++ decoder's`, async () => {
    const { rebuilt } = await expectJsEqualsCpp(model);
    rebuiltTotal += rebuilt;
    if (rebuilt === 0) test.diagnostic?.(`${model.name}: no implicit primitive`);
  });
}

// The solve layout (--layout mixed; cotangent-weighted ARAP, format 1.4) on
// real meshes: thousands of CG steps, where one differently ordered sum
// would show. The Duck and the Fox both get solve patches.
for (const name of ['Duck', 'Fox']) {
  const model = models.find((m) => m.name.startsWith(`${name}-`) && m.path.endsWith(`${name}.gltf`));
  test(`corpus ${name} --layout mixed: JS solve layouts equal the C++ decoder's`, { skip: skip ?? !model }, async () => {
    const { rebuilt, minors } = await expectJsEqualsCpp(model, ['--layout', 'mixed'], 'mixed');
    assert.ok(rebuilt > 0);
    assert.ok(minors.has(4), `a stream with cotangent-weighted solve patches (versions ${[...minors]})`);
  });
}

test('corpus: some primitives were rebuilt', { skip: skip ?? false }, () => {
  assert.ok(rebuiltTotal > 0);
  rmSync(dir, { recursive: true, force: true });
});
