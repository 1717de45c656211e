// three.js GLTFLoader plugin for GLTFWARP_implicit_texcoords: rebuilds the
// texture coordinates (and MikkTSpace tangents where the extension asks for
// them) from the decoded geometry and the stream, in a worker.
//
//   loader.setDRACOLoader(dracoLoader);
//   loader.register((parser) => new GLTFWarpLoaderPlugin(parser));
//
// Where it hooks in, and why there: GLTFLoader has no plugin hook between
// "geometry decoded" and "mesh created" (KHR_draco_mesh_compression itself is
// a built-in extension, not a plugin). The rebuilt geometry must exist before
// the mesh does, because GLTFLoader picks the material variant from the
// geometry's attributes (assignFinalMaterial: derivative tangents flip
// normalScale.y when there is no `tangent`). So the plugin wraps the parser's
// loadGeometries: each primitive's geometry, Draco-decoded or read from
// accessors, is replaced by the rebuilt one before loadMesh sees it.
//
// Vertex order: the stream applies to the mesh exactly as Draco decodes it
// (spec 3.3). DRACOLoader reads points with GetAttributeDataArrayForAllPoints
// and faces with GetTrianglesUInt32Array, the same point and face order as the
// C++ decoder's draco::Mesh walk, so nothing needs reconciling; the split of
// 3.4 then numbers vertices as the C++ does, and the resulting index, uv and
// tangent arrays equal those of `gltf-warp decode` element for element (the
// tests compare them).
import { BufferAttribute, BufferGeometry } from 'three';
import { WorkerPool } from './worker_pool.js';

export const EXTENSION_NAME = 'GLTFWARP_implicit_texcoords';

let sharedPool = null;

export class GLTFWarpLoaderPlugin {
  // options.workerLimit: workers of the shared pool (default: the hardware
  // threads but one, 1 to 4: DRACOLoader's workers and the page need cores
  // too, more workers than cores only slice the same cores finer, and each
  // worker compiles the decoder afresh: on 2 threads, 1 worker measured a
  // lower Draco + rebuild time than 2 or 4; 0 decodes on the main thread).
  // options.pool: a WorkerPool of your own.
  constructor(parser, options = {}) {
    this.name = EXTENSION_NAME;
    this.parser = parser;
    this.pool = options.pool ?? (sharedPool ??= new WorkerPool(options.workerLimit ?? defaultWorkerLimit()));
    this.rebuilt = new WeakMap(); // source geometry -> Promise of the rebuilt one
    const loadGeometries = parser.loadGeometries.bind(parser);
    parser.loadGeometries = (primitives) =>
      loadGeometries(primitives).then((geometries) =>
        Promise.all(geometries.map((g, i) => this.rebuild(g, primitives[i]))));
  }

  rebuild(geometry, primitiveDef) {
    const ext = primitiveDef.extensions?.[EXTENSION_NAME];
    if (!ext) return geometry;
    // GLTFLoader shares one geometry between primitives with the same data.
    if (!this.rebuilt.has(geometry)) this.rebuilt.set(geometry, this.rebuildOnce(geometry, ext));
    return this.rebuilt.get(geometry);
  }

  async rebuildOnce(geometry, ext) {
    const start = performance.now();
    const streamView = await this.parser.getDependency('bufferView', ext.bufferView);
    const position = geometry.getAttribute('position');
    if (!position || position.itemSize !== 3) throw new Error(`${EXTENSION_NAME}: primitive has no usable POSITION`);
    const pointCount = position.count;
    const positions = readFloats(position);
    const indices = geometry.index ? new Uint32Array(geometry.index.array) : sequence(pointCount); // a copy: it is transferred
    const normal = geometry.getAttribute('normal');
    const wantTangents = ext.tangents === true && normal !== undefined && normal.itemSize === 3;
    // The worker also copies each point's attribute values to its new
    // vertices (position, normal and every other plain attribute), so the
    // main thread only wraps the arrays it gets back.
    const uvName = (ext.texCoord ?? 0) === 0 ? 'uv' : `uv${ext.texCoord}`;
    const gathered = Object.entries(geometry.attributes).filter(([name, attr]) =>
      name !== uvName && name !== 'position' && !attr.isInterleavedBufferAttribute &&
      !(name === 'tangent' && wantTangents) && attr.array.length === attr.count * attr.itemSize);
    const job = {
      positions, indices, stream: new Uint8Array(streamView.slice(0)),
      normals: wantTangents ? readFloats(normal) : null, tangents: wantTangents,
      attributes: gathered.map(([, attr]) => ({ array: attr.array.slice(), itemSize: attr.itemSize })),
    };
    const streamBytes = job.stream.byteLength;
    const sent = performance.now();
    const r = await this.pool.run(job);
    const received = performance.now();

    const out = new BufferGeometry();
    out.name = geometry.name;
    const fromWorker = new Map(gathered.map(([name], i) => [name, r.attributes[i]]));
    for (const [name, attr] of Object.entries(geometry.attributes)) {
      if (name === uvName || (name === 'tangent' && r.tangent)) continue;
      const array = name === 'position' ? r.positions : fromWorker.get(name);
      if (array === undefined) {
        out.setAttribute(name, remap(attr, r.origin));
        continue;
      }
      if (name === 'position' && !(attr.array instanceof Float32Array)) {
        out.setAttribute(name, remap(attr, r.origin)); // a quantized POSITION keeps its type
        continue;
      }
      const copy = new BufferAttribute(array, attr.itemSize, attr.normalized);
      copy.name = attr.name;
      out.setAttribute(name, copy);
    }
    for (const [name, list] of Object.entries(geometry.morphAttributes))
      out.morphAttributes[name] = list.map((attr) => remap(attr, r.origin));
    out.morphTargetsRelative = geometry.morphTargetsRelative;
    out.setAttribute(uvName, new BufferAttribute(r.uv, 2));
    if (r.tangent) out.setAttribute('tangent', new BufferAttribute(r.tangent, 4));
    out.setIndex(new BufferAttribute(r.index, 1));
    for (const g of geometry.groups) out.addGroup(g.start, g.count, g.materialIndex);
    out.boundingBox = geometry.boundingBox; // same positions
    out.boundingSphere = geometry.boundingSphere;
    out.userData = {
      ...geometry.userData,
      gltfWarp: {
        patchCount: r.patchCount, atlasWidth: r.atlasWidth, atlasHeight: r.atlasHeight, streamBytes,
        patchOfVertex: r.patchOfVertex, decodeMs: performance.now() - start,
        // Main thread before and after the worker, the worker's round trip
        // (queue + transfer + decode), and the worker's own stages.
        timings: { prepare: sent - start, worker: received - sent, assemble: performance.now() - received, ...r.timings },
      },
    };
    geometry.dispose();
    return out;
  }
}

function defaultWorkerLimit() {
  const threads = globalThis.navigator?.hardwareConcurrency ?? 4;
  return Math.max(1, Math.min(4, threads - 1));
}

// Positions / normals as float32, whatever the attribute stores: normalized
// integers convert as glTF defines (three's getX does, e.g. max(v / 32767, -1)),
// and the float32 store rounds once, as the C++ VertexAttribute::get does.
function readFloats(attr) {
  if (!attr.isInterleavedBufferAttribute && attr.array instanceof Float32Array && attr.itemSize === 3)
    return attr.array.slice(0, attr.count * 3);
  const out = new Float32Array(attr.count * 3);
  for (let i = 0; i < attr.count; ++i) {
    out[3 * i] = attr.getX(i);
    out[3 * i + 1] = attr.getY(i);
    out[3 * i + 2] = attr.getZ(i);
  }
  return out;
}

function sequence(n) {
  const a = new Uint32Array(n - (n % 3));
  for (let i = 0; i < a.length; ++i) a[i] = i;
  return a;
}

// One copy of each point's element per new vertex, raw values (also from
// interleaved attributes, which DRACOLoader makes for 3-byte colours).
function remap(attr, origin) {
  const n = attr.itemSize;
  let src, stride, offset;
  if (attr.isInterleavedBufferAttribute) {
    src = attr.data.array;
    stride = attr.data.stride;
    offset = attr.offset;
  } else {
    src = attr.array;
    stride = n;
    offset = 0;
  }
  const out = new src.constructor(origin.length * n);
  for (let i = 0; i < origin.length; ++i) {
    const s = origin[i] * stride + offset, d = i * n;
    for (let k = 0; k < n; ++k) out[d + k] = src[s + k];
  }
  const result = new BufferAttribute(out, n, attr.normalized);
  result.name = attr.name;
  return result;
}
