// Pure decoder against the golden vectors of spec section 9: the UV hash, the
// seeds, every proper prefix -> truncated, one appended byte ->
// trailing_bytes, and the header rules of 4.1 on edited copies (the same
// checks as spec/reference_decoder.py).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { decodeUvs } from '../src/decode_uvs.js';
import { facesByPatch } from '../src/placements.js';
import { solvePatch } from '../src/layout_solve.js';
import { fnv1a64 } from './support/fnv1a.js';
import { goldenMesh, goldenVector } from './support/golden_vectors.js';

const mesh = goldenMesh();

function errorCode(bytes) {
  try {
    decodeUvs(mesh, bytes);
    return 'ok';
  } catch (e) {
    if (!e.code) throw e;
    return e.code;
  }
}

function edited(bytes, i, v) {
  const b = bytes.slice();
  b[i] = v;
  return b;
}

for (const [name, medianSeeds] of [['1_0', false], ['1_1', true], ['1_2', true], ['1_3', true], ['1_4', true]]) {
  const { bytes, hash } = goldenVector(name);

  test(`golden ${name}: UV hash`, () => {
    const { uv } = decodeUvs(mesh, bytes);
    assert.equal(uv.length, 1152);
    assert.equal(fnv1a64(uv), hash);
  });

  test(`golden ${name}: seeds are the ${medianSeeds ? 'median' : 'lowest'} face of each patch`, () => {
    const { header, patchOfFace, placements } = decodeUvs(mesh, bytes);
    const by = facesByPatch(patchOfFace, header.patchCount);
    for (let p = 0; p < header.patchCount; ++p) {
      const n = by.start[p + 1] - by.start[p];
      assert.equal(placements.seed[p], by.faces[by.start[p] + (medianSeeds ? n >> 1 : 0)]);
    }
  });

  test(`golden ${name}: every proper prefix is truncated`, () => {
    for (let n = 0; n < bytes.length; ++n) assert.equal(errorCode(bytes.subarray(0, n)), 'truncated', `prefix ${n}`);
  });

  test(`golden ${name}: header rules`, () => {
    const longer = new Uint8Array(bytes.length + 1);
    longer.set(bytes);
    assert.equal(errorCode(longer), 'trailing_bytes');
    assert.equal(errorCode(edited(bytes, 5, 5)), 'unsupported_version');
    assert.equal(errorCode(edited(bytes, 0, 0x48)), 'bad_magic');
    assert.equal(errorCode(edited(bytes, 6, bytes[6] | 0x40)), 'reserved_bits');
    if (bytes[6] & 0x04) {
      assert.equal(errorCode(edited(bytes, 5, 0)), 'reserved_bits');
    } else if (bytes[5] === 0) {
      assert.equal(errorCode(edited(bytes, 6, bytes[6] | 0x04)), 'reserved_bits');
      assert.equal(fnv1a64(decodeUvs(mesh, edited(bytes, 5, 1)).uv), hash, 'minor 1 without SEEDS');
    }
    if (bytes[6] & 0x08) {
      assert.equal(errorCode(edited(bytes, 5, 1)), 'reserved_bits');
    } else {
      assert.equal(errorCode(edited(bytes, 6, bytes[6] | 0x08)), 'reserved_bits');
      assert.equal(fnv1a64(decodeUvs(mesh, edited(bytes, 5, 2)).uv), hash, 'minor 2 without METHODS');
    }
    if (bytes[6] & 0x10) {
      assert.equal(errorCode(edited(bytes, 5, 2)), 'reserved_bits');
    } else {
      assert.equal(errorCode(edited(bytes, 6, bytes[6] | 0x10)), 'reserved_bits');
      assert.equal(fnv1a64(decodeUvs(mesh, edited(bytes, 5, 3)).uv), hash, 'minor 3 without FINE');
    }
    if (bytes[6] & 0x20) {
      assert.equal(errorCode(edited(bytes, 5, 3)), 'reserved_bits');
      assert.equal(errorCode(edited(bytes, 6, bytes[6] & ~0x08)), 'reserved_bits', 'COTANGENT without METHODS');
    } else {
      assert.equal(errorCode(edited(bytes, 6, bytes[6] | 0x20)), 'reserved_bits');
      assert.equal(fnv1a64(decodeUvs(mesh, edited(bytes, 5, 4)).uv), hash, 'minor 4 without COTANGENT');
    }
  });

  test(`golden ${name}: a mesh with another face count is face_count_mismatch`, () => {
    const fewer = { positions: mesh.positions, indices: mesh.indices.subarray(0, mesh.indices.length - 3) };
    assert.throws(() => decodeUvs(fewer, bytes), { code: 'face_count_mismatch' });
  });

  test(`golden ${name}: an index past the vertices is bad_mesh`, () => {
    const bad = { positions: mesh.positions, indices: mesh.indices.slice() };
    bad.indices[7] = 1000;
    assert.throws(() => decodeUvs(bad, bytes), { code: 'bad_mesh' });
  });
}

test('golden 1_2: solve patches are laid out, unfold patches decode as in 1.1', () => {
  const v12 = decodeUvs(mesh, goldenVector('1_2').bytes), v11 = decodeUvs(mesh, goldenVector('1_1').bytes);
  const { method } = v12.placements;
  assert.deepEqual(Array.from(method), [1, 0, 0, 1, 1, 0, 1, 0, 1, 1]);
  for (let f = 0; f < 192; ++f) {
    if (method[v12.patchOfFace[f]]) continue;
    for (let k = 0; k < 6; ++k) assert.equal(v12.uv[6 * f + k], v11.uv[6 * f + k], `face ${f}`);
  }
});

test('golden 1_3: fine placements; coarse patches decode as in 1.2, mirrored ones reverse their winding', () => {
  const v13 = decodeUvs(mesh, goldenVector('1_3').bytes), v12 = decodeUvs(mesh, goldenVector('1_2').bytes);
  const pl = v13.placements;
  assert.deepEqual(Array.from(pl.fine), [0, 0, 1, 0, 0, 1, 1, 0, 0, 1]);
  assert.deepEqual(Array.from(pl.mirror), [0, 0, 0, 0, 0, 1, 1, 0, 0, 0]);
  assert.deepEqual(Array.from(pl.cosQ), [0, 0, 28000, 0, 0, 32768, -20000, 0, 0, 0]);
  assert.deepEqual(Array.from(pl.sinQ), [0, 0, -17000, 0, 0, 0, 30000, 0, 0, -65536]);
  assert.deepEqual(Array.from(pl.xFrac), [0, 0, 77, 0, 0, 0, 255, 0, 0, 5]);
  assert.deepEqual(Array.from(pl.yFrac), [0, 0, 200, 0, 0, 128, 1, 0, 0, 0]);
  for (let f = 0; f < 192; ++f) {
    const p = v13.patchOfFace[f], c = v13.uv.subarray(6 * f, 6 * f + 6);
    const same = c.every((v, k) => Object.is(v, v12.uv[6 * f + k]));
    assert.equal(same, !pl.fine[p], `face ${f}`);
    const area = (c[2] - c[0]) * (c[5] - c[1]) - (c[3] - c[1]) * (c[4] - c[0]);
    assert.ok(pl.mirror[p] ? area < 0 : area > 0, `face ${f}: area ${area}`);
  }
});

test('golden 1_2: solve parameters past their limits are bad_value', () => {
  const { bytes } = goldenVector('1_2');
  assert.equal(bytes[24], 4); // arap_rounds, after 23 header bytes and tutte_steps
  assert.equal(errorCode(edited(bytes, 24, 65)), 'bad_value');
});

test('solve rejects patches that are not discs', () => {
  const { patchOfFace } = decodeUvs(mesh, goldenVector('1_2').bytes);
  const params = { tutteSteps: 4, arapRounds: 1, arapSteps: 2 };
  for (const [p, disc] of [[0, true], [1, false], [7, false]]) {
    const faces = Uint32Array.from([...patchOfFace.keys()].filter((f) => patchOfFace[f] === p));
    const run = () => solvePatch(mesh.positions, mesh.indices, faces, params);
    if (disc) run();
    else assert.throws(run, { code: 'layout_not_disc' }, `patch ${p}`);
  }
  const all = Uint32Array.from({ length: 192 }, (_, f) => f);
  const whole = solvePatch(mesh.positions, mesh.indices, all, params); // the whole grid is one disc
  assert.equal(whole.verts.length, 117);
});

test('golden 1_4: cotangent weights move only the solve patches', () => {
  const v14 = decodeUvs(mesh, goldenVector('1_4').bytes), v13 = decodeUvs(mesh, goldenVector('1_3').bytes);
  assert.equal(v14.header.solve.cotangent, true);
  assert.equal(v13.header.solve.cotangent, false);
  const { method } = v14.placements;
  const moved = new Array(method.length).fill(0), size = new Array(method.length).fill(0);
  for (let f = 0; f < 192; ++f) {
    const p = v14.patchOfFace[f];
    ++size[p];
    for (let k = 0; k < 6; ++k) if (v14.uv[6 * f + k] !== v13.uv[6 * f + k]) { ++moved[p]; break; }
  }
  for (let p = 0; p < method.length; ++p) {
    if (!method[p]) assert.equal(moved[p], 0, `unfold patch ${p}`);
    else if (size[p] > 1) assert.ok(moved[p] > 0, `solve patch ${p}`);
  }
});
