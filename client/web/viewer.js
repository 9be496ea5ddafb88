// Tessera's web viewer: lists the server's meshes, loads one as a GLB at a relative tolerance or
// at a pixel accuracy for the current view, and orbits it with three.js; or shows the server's
// own frames of the current view while the camera moves (the latest camera wins: at most one
// frame request is in flight, and the newest view waits for it). Query parameters preset the
// form: ?mesh=ID&relative=1e-3 (or &pixel_accuracy=0.5), &frames=1, &token=T.
// window.tesseraViewer reports what happened, for people debugging and for the tests.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { MeshoptDecoder } from 'three/addons/libs/meshopt_decoder.module.js';

const $ = (id) => document.getElementById(id);
const state = { phase: 'starting', meshes: [], triangles: 0, glbBytes: 0, framesReceived: 0, lastError: '', framed: false };
window.tesseraViewer = state;

const canvas = $('view');
const renderer = new THREE.WebGLRenderer({ canvas, antialias: true });
renderer.setPixelRatio(1);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0x20242a);
scene.add(new THREE.HemisphereLight(0xffffff, 0x404050, 1.2));
const sun = new THREE.DirectionalLight(0xffffff, 1.5);
sun.position.set(1, 2, 3);
scene.add(sun);
const camera = new THREE.PerspectiveCamera(45, 1, 0.01, 1000);
camera.position.set(0, 0, 5);
const controls = new OrbitControls(camera, canvas);
let model = null;

function report(phase, message = '') {
  state.phase = phase;
  document.body.dataset.state = phase;
  $('status').textContent = message || phase;
}

function headers() {
  const token = $('token').value.trim();
  return token ? { Authorization: `Bearer ${token}` } : {};
}

// A refusal's JSON ({"code", "message"}) as one line.
async function failure(response) {
  const text = await response.text();
  try {
    const body = JSON.parse(text);
    return `${response.status} ${body.code}: ${body.message}`;
  } catch {
    return `${response.status} ${text}`;
  }
}

function resize() {
  const width = window.innerWidth, height = window.innerHeight;
  renderer.setSize(width, height, false);
  camera.aspect = width / height;
  camera.updateProjectionMatrix();
}

const noMeshesYet = 'the server has no meshes yet (POST /v1/meshes?id=ID with an OBJ body)';

const vector = (v) => `${v.x},${v.y},${v.z}`;

// The camera as the API's query parameters (the same view the canvas shows).
function cameraQuery() {
  return `eye=${vector(camera.position)}&target=${vector(controls.target)}&up=${vector(camera.up)}` +
         `&fov=${camera.fov}&size=${canvas.width}x${canvas.height}`;
}

async function listMeshes() {
  const response = await fetch('/v1/meshes?page_size=1000', { headers: headers() });
  if (!response.ok) throw new Error(await failure(response));
  const page = await response.json();
  state.meshes = (page.meshes || []).map((m) => m.name.replace(/^meshes\//, ''));
  $('mesh').replaceChildren(...state.meshes.map((id) => new Option(id, id)));
}

function frameTheModel(object) {
  const box = new THREE.Box3().setFromObject(object);
  const centre = box.getCenter(new THREE.Vector3());
  const radius = box.getSize(new THREE.Vector3()).length() / 2 || 1;
  controls.target.copy(centre);
  camera.position.copy(centre).add(new THREE.Vector3(0.6, 0.4, 1).normalize().multiplyScalar(radius * 2.6));
  camera.near = radius / 100;
  camera.far = radius * 100;
  camera.updateProjectionMatrix();
  controls.update();
}

// ?mesh=ID, if the server has it; the message says which case it is when it does not.
function requestedMesh(id) {
  if (state.meshes.includes(id)) return id;
  if (state.meshes.length === 0) throw new Error(noMeshesYet);
  const some = state.meshes.slice(0, 5).join(', ') + (state.meshes.length > 5 ? ', ...' : '');
  throw new Error(`the server has no mesh "${id}"; it has ${state.meshes.length}: ${some}`);
}

async function loadGlb() {
  const id = $('mesh').value;
  if (!id) throw new Error(state.meshes.length === 0 ? noMeshesYet : 'choose a mesh');
  const value = $('value').value.trim();
  const accuracy = $('mode').value === 'pixel' ? `${cameraQuery()}&pixel_accuracy=${value}` : `relative=${value}`;
  report('loading', `tessellating ${id}`);
  const response = await fetch(`/v1/meshes/${encodeURIComponent(id)}/tessellation.glb?${accuracy}&encoding=meshopt`,
                               { headers: headers() });
  if (!response.ok) throw new Error(await failure(response));
  const bytes = await response.arrayBuffer();
  const loader = new GLTFLoader().setMeshoptDecoder(MeshoptDecoder);
  const gltf = await loader.parseAsync(bytes, '');
  if (model) scene.remove(model);
  model = gltf.scene;
  scene.add(model);
  state.triangles = 0;
  model.traverse((node) => {
    if (node.isMesh) {
      node.material = new THREE.MeshStandardMaterial({ color: 0xb8bcc6, roughness: 0.55, metalness: 0.05 });
      state.triangles += node.geometry.index ? node.geometry.index.count / 3 : 0;
    }
  });
  state.glbBytes = bytes.byteLength;
  if (!state.framed) {
    frameTheModel(model);  // the first model only: later loads keep the user's view
    state.framed = true;
  }
  report('loaded', `${id}: ${state.triangles} triangles, ${(state.glbBytes / 1024).toFixed(0)} KiB`);
}

// Server frames: one request in flight; a newer view replaces the waiting one.
let frameInFlight = false, frameWanted = false;
async function requestFrame() {
  if (!$('serverFrames').checked || !$('mesh').value) return;
  if (frameInFlight) {
    frameWanted = true;
    return;
  }
  frameInFlight = true;
  try {
    const id = encodeURIComponent($('mesh').value);
    const response = await fetch(`/v1/meshes/${id}/frame.jpg?${cameraQuery()}&pixel_accuracy=1`, { headers: headers() });
    if (!response.ok) throw new Error(await failure(response));
    const url = URL.createObjectURL(await response.blob());
    const image = $('frame');
    const previous = image.src;
    image.src = url;
    await image.decode();
    if (previous.startsWith('blob:')) URL.revokeObjectURL(previous);
    state.framesReceived += 1;
  } catch (error) {
    fail(error);
  } finally {
    frameInFlight = false;
    if (frameWanted) {
      frameWanted = false;
      requestFrame();
    }
  }
}

function fail(error) {
  state.lastError = String(error.message || error);
  report('error', state.lastError);
}

// For tests and scripts: turn the camera about the target by `radians`, as a drag would.
state.orbit = (radians) => {
  const offset = camera.position.clone().sub(controls.target);
  offset.applyAxisAngle(new THREE.Vector3(0, 1, 0), radians);
  camera.position.copy(controls.target).add(offset);
  controls.update();
};

function animate() {
  controls.update();
  renderer.render(scene, camera);
  requestAnimationFrame(animate);
}

async function start() {
  const query = new URLSearchParams(location.search);
  if (query.has('token')) $('token').value = query.get('token');
  for (const mode of ['relative', 'pixel_accuracy']) {
    if (!query.has(mode)) continue;
    $('mode').value = mode === 'relative' ? 'relative' : 'pixel';
    $('value').value = query.get(mode);
  }
  $('serverFrames').checked = query.get('frames') === '1';
  document.body.classList.toggle('server-frames', $('serverFrames').checked);
  resize();
  window.addEventListener('resize', () => (resize(), requestFrame()));
  controls.addEventListener('change', requestFrame);
  $('load').addEventListener('click', () => loadGlb().then(requestFrame).catch(fail));
  $('serverFrames').addEventListener('change', () => {
    document.body.classList.toggle('server-frames', $('serverFrames').checked);
    requestFrame();
  });
  animate();
  try {
    await listMeshes();
    if (query.has('mesh')) $('mesh').value = requestedMesh(query.get('mesh'));
    report('ready', `${state.meshes.length} meshes`);
    if (query.has('mesh')) {
      await loadGlb();
      requestFrame();
    }
  } catch (error) {
    fail(error);
  }
}

start();
