// Page side of the decode benchmark: for every implicit primitive of ?model=,
// all in parallel, the time of the plain Draco decode (DRACOLoader, in its
// workers) against Draco decode + the plugin's rebuild (weld, stream decode,
// layout replay, split, attribute remap; in its workers), and the rebuild
// alone, in the same page, alternating, after a warm-up. Writes
// window.benchResult.
import { DRACOLoader } from 'three/addons/loaders/DRACOLoader.js';
import { GLTFWarpLoaderPlugin } from '../src/GLTFWarpLoaderPlugin.js';

const params = new URLSearchParams(location.search);
const runs = Number(params.get('runs') ?? 5);
const workerLimit = params.has('workers') ? Number(params.get('workers')) : undefined; // the plugin's default otherwise

function parseGlb(buffer) {
  const view = new DataView(buffer);
  let json = null, bin = null;
  for (let p = 12; p + 8 <= buffer.byteLength;) {
    const length = view.getUint32(p, true), type = view.getUint32(p + 4, true);
    if (type === 0x4e4f534a) json = JSON.parse(new TextDecoder().decode(new Uint8Array(buffer, p + 8, length)));
    else if (type === 0x004e4942) bin = new Uint8Array(buffer, p + 8, length);
    p += 8 + length;
  }
  return { json, bin };
}

function viewBytes(glb, index) {
  const bv = glb.json.bufferViews[index];
  return glb.bin.slice(bv.byteOffset ?? 0, (bv.byteOffset ?? 0) + bv.byteLength).buffer;
}

const median = (a) => [...a].sort((x, y) => x - y)[a.length >> 1];

async function main() {
  const glb = parseGlb(await (await fetch(params.get('model'))).arrayBuffer());
  // Every implicit primitive (the encoder cuts a large mesh into primitives of
  // about an atlas page each), decoded in parallel as GLTFLoader would.
  const prims = glb.json.meshes.flatMap((m) => m.primitives).filter((p) => p.extensions?.GLTFWARP_implicit_texcoords);
  const loader = new DRACOLoader().setDecoderPath('/node_modules/three/examples/jsm/libs/draco/');
  const jobs = prims.map((prim) => {
    const draco = prim.extensions.KHR_draco_mesh_compression, ours = prim.extensions.GLTFWARP_implicit_texcoords;
    const attributeIds = {}, attributeTypes = {};
    for (const [name, id] of Object.entries(draco.attributes)) {
      const three = { POSITION: 'position', NORMAL: 'normal', TEXCOORD_0: 'uv', COLOR_0: 'color' }[name] ?? name.toLowerCase();
      attributeIds[three] = id;
      attributeTypes[three] = 'Float32Array';
    }
    const dracoBytes = viewBytes(glb, draco.bufferView), stream = viewBytes(glb, ours.bufferView);
    const decode = () => new Promise((resolve, reject) =>
      loader.decodeDracoFile(dracoBytes.slice(0), resolve, attributeIds, attributeTypes, undefined, reject));
    // The plugin with the one parser method its rebuild uses.
    const plugin = new GLTFWarpLoaderPlugin({ loadGeometries: () => [], getDependency: async () => stream.slice(0) }, { workerLimit });
    return { ours, decode, plugin };
  });

  // Three timings per run, in the same page: Draco alone, Draco + rebuild
  // (the loader's path: each primitive's rebuild starts when its Draco decode
  // ends), and the rebuild alone on geometries Draco decoded beforehand.
  const plain = [], full = [], alone = [];
  const stages = jobs.map(() => ({})); // per primitive: stage -> [ms per run]
  let info = null;
  for (let i = 0; i <= runs; ++i) {
    let t = performance.now();
    await Promise.all(jobs.map((j) => j.decode()));
    const tPlain = performance.now() - t;
    t = performance.now();
    const rebuilt = await Promise.all(jobs.map(async (j) => j.plugin.rebuildOnce(await j.decode(), j.ours)));
    const tFull = performance.now() - t;
    const decoded = await Promise.all(jobs.map((j) => j.decode()));
    t = performance.now();
    await Promise.all(jobs.map((j, k) => j.plugin.rebuildOnce(decoded[k], j.ours)));
    const tAlone = performance.now() - t;
    if (i === 0) continue; // warm-up: worker start, wasm compile
    plain.push(tPlain);
    full.push(tFull);
    alone.push(tAlone);
    rebuilt.forEach((g, k) => {
      for (const [name, ms] of Object.entries(g.userData.gltfWarp.timings)) (stages[k][name] ??= []).push(ms);
    });
    const sum = (f) => rebuilt.reduce((s, g) => s + f(g), 0);
    info = {
      primitives: rebuilt.length, faces: sum((g) => g.index.count / 3), vertices: sum((g) => g.getAttribute('position').count),
      patchCount: sum((g) => g.userData.gltfWarp.patchCount), facesOf: rebuilt.map((g) => g.index.count / 3),
    };
  }
  const result = {
    runs, primitives: info.primitives, faces: info.faces, vertices: info.vertices, patches: info.patchCount,
    dracoMs: median(plain), dracoPlusUvMs: median(full), rebuildAloneMs: median(alone),
    ratio: median(full) / median(plain), workers: jobs[0]?.plugin.pool.workerLimit,
    hardwareConcurrency: navigator.hardwareConcurrency,
    perPrimitive: stages.map((st, k) => ({
      faces: info.facesOf[k], ...Object.fromEntries(Object.entries(st).map(([name, v]) => [name, median(v)])),
    })),
  };
  document.getElementById('out').textContent = JSON.stringify(result, null, 2);
  window.benchResult = result;
  loader.dispose();
  jobs[0]?.plugin.pool.dispose();
}
main().catch((e) => { window.benchResult = { error: String(e.stack ?? e) }; });
