// The layout's per-vertex incidence order (spec 6.5 replays faces around a
// vertex in (patch, face) order): the in-place sort of a vertex's ascending
// face list by patch must equal a plain stable sort, for the short lists of
// ordinary vertices (insertion) and the long fans that take the other branch.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { sortRunByPatch } from '../src/layout_replay.js';

function lcg(seed) {
  let s = seed >>> 0;
  return () => (s = (Math.imul(s, 1664525) + 1013904223) >>> 0) / 2 ** 32;
}

test('sortRunByPatch orders each run by (patch, face), leaving the rest alone', () => {
  const random = lcg(7);
  for (const length of [0, 1, 2, 3, 6, 7, 31, 32, 33, 100, 1000]) {
    for (const patches of [1, 2, 3, 50]) {
      const faceCount = length * 3 + 10;
      const patchOfFace = Uint32Array.from({ length: faceCount }, () => Math.floor(random() * patches));
      // An ascending face list with repeats (a face naming the vertex twice).
      const run = [];
      for (let f = 0; run.length < length; f += 1 + Math.floor(random() * 3)) {
        run.push(f);
        if (random() < 0.1 && run.length < length) run.push(f);
      }
      const faces = Uint32Array.from([99, 98, ...run, 97]);
      sortRunByPatch(faces, 2, 2 + length, patchOfFace);
      const expected = [...run].sort((a, b) => patchOfFace[a] - patchOfFace[b] || a - b);
      assert.deepEqual([...faces], [99, 98, ...expected, 97], `length ${length}, ${patches} patches`);
    }
  }
});
