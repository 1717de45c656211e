// Page side of the browser test: loads the encoded file through GLTFLoader +
// DRACOLoader + the plugin and the C++-decoded file through plain GLTFLoader,
// compares their geometry arrays, renders both from one camera and returns
// the two images' PSNR. window.compareModels(encodedUrl, decodedUrl).
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { DRACOLoader } from 'three/addons/loaders/DRACOLoader.js';
import { GLTFWarpLoaderPlugin } from '../../src/GLTFWarpLoaderPlugin.js';

const SIZE = 256;
const renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
renderer.setPixelRatio(1);
renderer.setSize(SIZE, SIZE);
document.body.appendChild(renderer.domElement);
const draco = new DRACOLoader().setDecoderPath('/node_modules/three/examples/jsm/libs/draco/');

function meshes(root) {
  const out = [];
  root.traverse((o) => { if (o.isMesh) out.push(o); });
  return out;
}

function sameBits(a, b) {
  if (!a || !b) return a === b;
  if (a.array.length !== b.array.length || a.itemSize !== b.itemSize) return false;
  const x = new Uint8Array(a.array.buffer, a.array.byteOffset, a.array.byteLength);
  const y = new Uint8Array(b.array.buffer, b.array.byteOffset, b.array.byteLength);
  if (a.array.BYTES_PER_ELEMENT !== b.array.BYTES_PER_ELEMENT) return Array.from(a.array).every((v, i) => v === b.array[i]);
  return x.every((v, i) => v === y[i]);
}

function render(scene, camera) {
  renderer.render(scene, camera);
  const gl = renderer.getContext();
  const pixels = new Uint8Array(SIZE * SIZE * 4);
  gl.readPixels(0, 0, SIZE, SIZE, gl.RGBA, gl.UNSIGNED_BYTE, pixels);
  return pixels;
}

function psnr(a, b) {
  let se = 0;
  for (let i = 0; i < a.length; ++i) if ((i & 3) !== 3) se += (a[i] - b[i]) ** 2;
  const mse = se / (a.length * 3 / 4);
  return mse === 0 ? Infinity : 10 * Math.log10(255 * 255 / mse);
}

function stage(model) {
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0x404040);
  scene.add(new THREE.AmbientLight(0xffffff, 1.5));
  const sun = new THREE.DirectionalLight(0xffffff, 2);
  sun.position.set(1, 2, 3);
  scene.add(sun);
  scene.add(model);
  return scene;
}

window.compareModels = async (encodedUrl, decodedUrl) => {
  const plugged = new GLTFLoader().setDRACOLoader(draco);
  plugged.register((parser) => new GLTFWarpLoaderPlugin(parser));
  const t0 = performance.now();
  const ours = await plugged.loadAsync(encodedUrl);
  const loadMs = performance.now() - t0;
  const theirs = await new GLTFLoader().loadAsync(decodedUrl);
  const a = meshes(ours.scene), b = meshes(theirs.scene);
  const report = { meshes: a.length, rebuilt: 0, uvEqual: 0, indexEqual: 0, tangentEqual: 0, tangents: 0, loadMs };
  if (a.length !== b.length) return { ...report, error: `mesh count ${a.length} vs ${b.length}` };
  for (let i = 0; i < a.length; ++i) {
    const ga = a[i].geometry, gb = b[i].geometry;
    if (!ga.userData.gltfWarp) continue;
    report.rebuilt++;
    if (sameBits(ga.getAttribute('uv'), gb.getAttribute('uv'))) report.uvEqual++;
    if (sameBits(ga.index, gb.index)) report.indexEqual++;
    if (gb.getAttribute('tangent')) {
      report.tangents++;
      if (sameBits(ga.getAttribute('tangent'), gb.getAttribute('tangent'))) report.tangentEqual++;
    }
  }
  // One camera for both: framed on the decoded model's bounds.
  const box = new THREE.Box3().setFromObject(theirs.scene);
  const center = box.getCenter(new THREE.Vector3()), radius = box.getSize(new THREE.Vector3()).length() / 2 || 1;
  const camera = new THREE.PerspectiveCamera(40, 1, radius / 100, radius * 100);
  camera.position.copy(center).add(new THREE.Vector3(0.6, 0.5, 1).normalize().multiplyScalar(radius * 2.6));
  camera.lookAt(center);
  const imageA = render(stage(ours.scene), camera);
  const imageB = render(stage(theirs.scene), camera);
  let differing = 0;
  for (let i = 0; i < imageA.length; i += 4)
    if (imageA[i] !== imageB[i] || imageA[i + 1] !== imageB[i + 1] || imageA[i + 2] !== imageB[i + 2]) ++differing;
  let background = 0;
  for (let i = 0; i < imageB.length; i += 4) if (imageB[i] === 0x40 && imageB[i + 1] === 0x40 && imageB[i + 2] === 0x40) ++background;
  return { ...report, identical: differing === 0, differingPixels: differing, psnr: psnr(imageA, imageB), coverage: 1 - background / (SIZE * SIZE) };
};
window.pageReady = true;
