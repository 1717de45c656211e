// The viewer page: drop a .glb, see it through GLTFLoader + DRACOLoader +
// GLTFWarpLoaderPlugin with orbit controls, its bytes per part, patch count
// and decode time; a toggle colours the patches and shows the atlas (the
// rebuilt UVs drawn over the base-colour image).
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { DRACOLoader } from 'three/addons/loaders/DRACOLoader.js';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { GLTFWarpLoaderPlugin } from '../src/GLTFWarpLoaderPlugin.js';
import { glbParts } from './glb_parts.js';

const viewEl = document.getElementById('view');
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio);
viewEl.appendChild(renderer.domElement);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0x303030);
scene.add(new THREE.HemisphereLight(0xffffff, 0x444444, 2));
const sun = new THREE.DirectionalLight(0xffffff, 2);
sun.position.set(2, 3, 4);
scene.add(sun);
const camera = new THREE.PerspectiveCamera(45, 1, 0.01, 1000);
const controls = new OrbitControls(camera, renderer.domElement);
const draco = new DRACOLoader().setDecoderPath('./node_modules/three/examples/jsm/libs/draco/');
let model = null, implicitMeshes = [];

function resize() {
  const { clientWidth: w, clientHeight: h } = viewEl;
  renderer.setSize(w, h);
  camera.aspect = w / h;
  camera.updateProjectionMatrix();
}
window.addEventListener('resize', resize);
resize();
renderer.setAnimationLoop(() => {
  controls.update();
  renderer.render(scene, camera);
});

function row(label, value) {
  return `<tr><td>${label}</td><td>${value}</td></tr>`;
}
const kb = (n) => `${(n / 1024).toFixed(1)} KiB`;

async function open(name, buffer) {
  document.getElementById('name').textContent = name;
  const stats = document.getElementById('stats');
  stats.innerHTML = row('loading…', '');
  const loader = new GLTFLoader().setDRACOLoader(draco);
  loader.register((parser) => new GLTFWarpLoaderPlugin(parser));
  const t0 = performance.now();
  let gltf;
  try {
    gltf = await loader.parseAsync(buffer, '');
  } catch (e) {
    stats.innerHTML = `<tr><td class="error">${e.message}</td></tr>`;
    return;
  }
  const loadMs = performance.now() - t0;
  if (model) scene.remove(model);
  model = gltf.scene;
  scene.add(model);
  implicitMeshes = [];
  model.traverse((o) => { if (o.isMesh && o.geometry.userData.gltfWarp) implicitMeshes.push(o); });
  const warp = [...new Set(implicitMeshes.map((m) => m.geometry))].map((g) => g.userData.gltfWarp);
  const parts = glbParts(buffer) ?? {};
  let html = Object.entries(parts).map(([k, v]) => row(k, kb(v))).join('');
  html += row('implicit primitives', warp.length);
  html += row('patches', warp.reduce((s, w) => s + w.patchCount, 0));
  html += row('UV rebuild (slowest primitive)', `${Math.max(0, ...warp.map((w) => w.decodeMs)).toFixed(1)} ms`);
  html += row('whole load', `${loadMs.toFixed(1)} ms`);
  stats.innerHTML = html;
  // Frame the model.
  const box = new THREE.Box3().setFromObject(model);
  const center = box.getCenter(new THREE.Vector3()), radius = box.getSize(new THREE.Vector3()).length() / 2 || 1;
  camera.near = radius / 100;
  camera.far = radius * 100;
  camera.position.copy(center).add(new THREE.Vector3(0.6, 0.5, 1).normalize().multiplyScalar(radius * 2.4));
  controls.target.copy(center);
  camera.updateProjectionMatrix();
  showPatches(document.getElementById('patches').checked);
  window.viewerState = { loaded: true, parts, patches: warp.reduce((s, w) => s + w.patchCount, 0) };
}

// A distinct colour per patch id (golden-ratio hues).
function patchColour(p, out) {
  return out.setHSL((p * 0.618034) % 1, 0.65, 0.55);
}

function showPatches(on) {
  const atlas = document.getElementById('atlas');
  atlas.style.display = on && implicitMeshes.length ? 'block' : 'none';
  for (const mesh of implicitMeshes) {
    if (!mesh.userData.originalMaterial) mesh.userData.originalMaterial = mesh.material;
    if (!on) {
      mesh.material = mesh.userData.originalMaterial;
      continue;
    }
    const g = mesh.geometry;
    if (!g.getAttribute('patchColor')) {
      const ids = g.userData.gltfWarp.patchOfVertex, colours = new Float32Array(3 * ids.length), c = new THREE.Color();
      ids.forEach((p, i) => patchColour(p, c).toArray(colours, 3 * i));
      g.setAttribute('patchColor', new THREE.BufferAttribute(colours, 3));
    }
    const material = new THREE.MeshStandardMaterial({ vertexColors: true, side: THREE.DoubleSide });
    material.onBeforeCompile = (shader) => {
      // Use patchColor (not the file's COLOR_0) as the vertex colour.
      shader.vertexShader = shader.vertexShader.replace('#include <color_pars_vertex>', 'attribute vec3 patchColor;\n#include <color_pars_vertex>')
        .replace('#include <color_vertex>', 'vColor = vec4(patchColor, 1.0);');
    };
    mesh.material = material;
  }
  if (on && implicitMeshes.length) drawAtlas(atlas, implicitMeshes[0]);
}

// The first implicit primitive's atlas: its base-colour image with the
// rebuilt UV triangles drawn over it in their patch colours.
function drawAtlas(canvas, mesh) {
  const image = mesh.userData.originalMaterial.map?.image;
  const w = image?.width ?? mesh.geometry.userData.gltfWarp.atlasWidth, h = image?.height ?? mesh.geometry.userData.gltfWarp.atlasHeight;
  const scale = Math.min(1, 1024 / Math.max(w, h));
  canvas.width = Math.round(w * scale);
  canvas.height = Math.round(h * scale);
  const ctx = canvas.getContext('2d');
  ctx.fillStyle = '#000';
  ctx.fillRect(0, 0, canvas.width, canvas.height);
  if (image) ctx.drawImage(image, 0, 0, canvas.width, canvas.height);
  const g = mesh.geometry, uv = g.getAttribute('uv'), index = g.index, ids = g.userData.gltfWarp.patchOfVertex;
  const c = new THREE.Color();
  ctx.lineWidth = 1;
  for (let f = 0; f < index.count; f += 3) {
    const a = index.getX(f), b = index.getX(f + 1), d = index.getX(f + 2);
    ctx.strokeStyle = `#${patchColour(ids[a], c).getHexString()}`;
    ctx.beginPath();
    ctx.moveTo(uv.getX(a) * canvas.width, uv.getY(a) * canvas.height);
    ctx.lineTo(uv.getX(b) * canvas.width, uv.getY(b) * canvas.height);
    ctx.lineTo(uv.getX(d) * canvas.width, uv.getY(d) * canvas.height);
    ctx.closePath();
    ctx.stroke();
  }
}

document.getElementById('patches').addEventListener('change', (e) => showPatches(e.target.checked));
const openFile = async (file) => {
  document.getElementById('drop').style.display = 'none';
  await open(file.name, await file.arrayBuffer());
};
document.getElementById('file').addEventListener('change', (e) => e.target.files[0] && openFile(e.target.files[0]));
viewEl.addEventListener('dragover', (e) => e.preventDefault());
viewEl.addEventListener('drop', (e) => {
  e.preventDefault();
  if (e.dataTransfer.files[0]) openFile(e.dataTransfer.files[0]);
});
// For scripted use (and the headless check): viewer.html?model=url.
const url = new URLSearchParams(location.search).get('model');
if (url) fetch(url).then((r) => r.arrayBuffer()).then((b) => { document.getElementById('drop').style.display = 'none'; return open(url.split('/').pop(), b); });
window.viewerOpen = open;
