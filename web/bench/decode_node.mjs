// Benchmark (not a test): the rebuild of every implicit primitive of an
// encoded model in node, one thread, stage by stage, against three.js's Draco
// wasm decoding the same geometry. It shows where the worker's time goes
// (the browser benchmark, decode_bench.mjs, times the whole page path), and
// prints a hash of all outputs so a speed change can be checked to leave the
// bits alone. Times are CPU time of this process (user + system), not wall
// time, so that they mean something on a loaded machine; --wall for wall time.
//   node bench/decode_node.mjs big_enc.glb [runs] [--wall]
import { basename } from 'node:path';
import { decodePrimitive } from '../src/decode_primitive.js';
import { dracoDecode, dracoModule } from '../test/support/draco_node.js';
import { fnv1a64 } from '../test/support/fnv1a.js';
import { bufferViewBytes, readGlb } from '../test/support/glb.js';

const args = process.argv.slice(2).filter((a) => a !== '--wall');
const wall = args.length < process.argv.length - 2;
if (!wall) {
  // decodePrimitive and decodeUvs time their stages with performance.now().
  performance.now = () => {
    const u = process.cpuUsage();
    return (u.user + u.system) / 1000;
  };
}
const file = args[0];
if (!file) {
  console.error('usage: node bench/decode_node.mjs <encoded.glb> [runs]');
  process.exit(2);
}
const runs = Math.max(1, Number(args[1] ?? 3));
const glb = readGlb(file);
const prims = (glb.json.meshes ?? []).flatMap((m) => m.primitives).filter((p) => p.extensions?.GLTFWARP_implicit_texcoords);
await dracoModule();

const median = (a) => [...a].sort((x, y) => x - y)[a.length >> 1];
const stageRuns = {}; // stage -> per-run sums
const dracoRuns = [], totalRuns = [];
let hash = 0n, faces = 0;
for (let run = 0; run <= runs; ++run) {
  const sums = {};
  let draco = 0, total = 0;
  hash = 0n;
  faces = 0;
  for (const prim of prims) {
    const d = prim.extensions.KHR_draco_mesh_compression, ours = prim.extensions.GLTFWARP_implicit_texcoords;
    const ids = [d.attributes.POSITION];
    if (d.attributes.NORMAL !== undefined) ids.push(d.attributes.NORMAL);
    let t = performance.now();
    const g = await dracoDecode(bufferViewBytes(glb, d.bufferView), ids);
    draco += performance.now() - t;
    t = performance.now();
    const r = decodePrimitive({
      positions: g.attributes[d.attributes.POSITION], indices: g.index,
      normals: g.attributes[d.attributes.NORMAL] ?? null, stream: bufferViewBytes(glb, ours.bufferView).slice(),
      tangents: ours.tangents === true,
    });
    total += performance.now() - t;
    for (const [k, v] of Object.entries(r.timings)) sums[k] = (sums[k] ?? 0) + v;
    if (run === runs) {
      hash ^= fnv1a64(r.uv) ^ (fnv1a64(r.index) << 1n);
      if (r.tangent) hash ^= fnv1a64(r.tangent) << 2n;
    }
    faces += g.index.length / 3;
  }
  if (run === 0) continue; // warm-up: JIT
  dracoRuns.push(draco);
  totalRuns.push(total);
  for (const [k, v] of Object.entries(sums)) (stageRuns[k] ??= []).push(v);
}
console.log(`${basename(file)}: ${prims.length} implicit primitives, ${faces} faces, median of ${runs} runs, one thread, ${wall ? 'wall' : 'CPU'} time`);
console.log(`  Draco (three.js wasm):   ${median(dracoRuns).toFixed(1)} ms`);
console.log(`  rebuild (all stages):    ${median(totalRuns).toFixed(1)} ms  = ${(median(totalRuns) / median(dracoRuns)).toFixed(2)} x Draco`);
for (const [k, v] of Object.entries(stageRuns)) console.log(`    ${k.padEnd(22)}${median(v).toFixed(1).padStart(8)} ms`);
console.log(`  output hash: ${hash.toString(16)}`);
