// gltf-warp-three: the three.js GLTFLoader plugin for GLTFWARP_implicit_texcoords,
// and the plain decoder underneath it.
export { GLTFWarpLoaderPlugin, EXTENSION_NAME } from './src/GLTFWarpLoaderPlugin.js';
export { WorkerPool } from './src/worker_pool.js';
export { decodeUvs } from './src/decode_uvs.js';
export { decodePrimitive } from './src/decode_primitive.js';
export { GltfWarpError } from './src/errors.js';
