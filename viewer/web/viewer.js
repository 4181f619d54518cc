// The semfuse-viewer page: the map's labeled mesh block by block as the viewer pushes it over
// the WebSocket (layouts in viewer/src/page_messages.hpp), the cameras' frustums and paths, the
// server's counters, the legend with vertex counts, and labels_at on a click.
import * as THREE from 'three';
import { OrbitControls } from './OrbitControls.js';

const params = new URLSearchParams(location.search);
const KIND_BLOCK = 1, KIND_REMOVED = 2, KIND_CLEARED = 3, KIND_RAYCAST = 4;

// ---- scene ----
const container = document.getElementById('view');
const renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
// Colours are the legend's bytes and reach the screen unchanged (no sRGB conversion), so a
// label's pixels have its legend colour exactly (the viewer's test relies on it).
THREE.ColorManagement.enabled = false;
renderer.outputColorSpace = THREE.LinearSRGBColorSpace;
renderer.setPixelRatio(window.devicePixelRatio);
container.appendChild(renderer.domElement);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0x1d1f24);
const camera = new THREE.PerspectiveCamera(55, 1, 0.02, 500);
camera.up.set(0, 0, 1);
camera.position.set(3, -4, 4);
const controls = new OrbitControls(camera, renderer.domElement);
scene.add(new THREE.HemisphereLight(0xffffff, 0x555555, 1.6));
const sun = new THREE.DirectionalLight(0xffffff, 1.2);
sun.position.set(1, -2, 3);
scene.add(sun);
const mapGroup = new THREE.Group();
const cameraGroup = new THREE.Group();
scene.add(mapGroup, cameraGroup);

let shaded = params.get('flat') !== '1';
document.getElementById('shaded').checked = shaded;
function makeMaterial() {
  const options = { vertexColors: true, side: THREE.FrontSide };
  return shaded ? new THREE.MeshLambertMaterial(options) : new THREE.MeshBasicMaterial(options);
}
let material = makeMaterial();

function resize() {
  const w = container.clientWidth, h = container.clientHeight;
  renderer.setSize(w, h);
  camera.aspect = w / Math.max(1, h);
  camera.updateProjectionMatrix();
}
window.addEventListener('resize', resize);
resize();

// ---- legend and colouring ----
let legend = new Map();  // id -> {name, rgb, background}
let legendName = '';
let coloring = params.get('color') || 'label';
for (const input of document.querySelectorAll('input[name=color]')) {
  input.checked = input.value === coloring;
  input.addEventListener('change', () => { coloring = input.value; recolorAll(); });
}

function labelColor(id) {
  const info = legend.get(id);
  if (info) return info.rgb;
  // Labels outside the legend: a fixed colour per id.
  const h = Math.imul(id + 1, 2654435761) >>> 0;
  return [64 + (h & 127), 64 + ((h >> 8) & 127), 64 + ((h >> 16) & 127)];
}

// Confidence (the label's evidence, relative to the strongest in view) from dark blue to yellow.
let maxScore = 1e-6;
function confidenceColor(score, out, i) {
  const t = Math.min(1, Math.max(0, score / maxScore));
  out[i] = Math.round(255 * Math.min(1, 2 * t));
  out[i + 1] = Math.round(255 * t);
  out[i + 2] = Math.round(255 * (1 - t) * 0.8);
}

function fillColors(block) {
  const colors = block.mesh.geometry.getAttribute('color').array;
  const n = block.labels.length;
  for (let v = 0; v < n; ++v) {
    const i = 3 * v;
    if (coloring === 'rgb') {
      colors[i] = block.rgb[i]; colors[i + 1] = block.rgb[i + 1]; colors[i + 2] = block.rgb[i + 2];
    } else if (coloring === 'confidence') {
      confidenceColor(block.scores[v], colors, i);
    } else {
      const c = labelColor(block.labels[v]);
      colors[i] = c[0]; colors[i + 1] = c[1]; colors[i + 2] = c[2];
    }
  }
  block.mesh.geometry.getAttribute('color').needsUpdate = true;
}

function recolorAll() {
  if (coloring === 'confidence') {
    maxScore = 1e-6;
    for (const block of blocks.values()) for (const s of block.scores) if (s > maxScore) maxScore = s;
  }
  for (const block of blocks.values()) fillColors(block);
}

// ---- blocks ----
const blocks = new Map();  // "x,y,z" -> {mesh, labels, scores, rgb, own}
const labelCounts = new Map();  // label -> own vertices with it
let bounds = new THREE.Box3();
let userMoved = false;

function countLabels(block, sign) {
  for (let v = 0; v < block.own; ++v) {
    const id = block.labels[v];
    labelCounts.set(id, (labelCounts.get(id) || 0) + sign);
  }
}

function removeBlock(key) {
  const block = blocks.get(key);
  if (!block) return;
  countLabels(block, -1);
  mapGroup.remove(block.mesh);
  block.mesh.geometry.dispose();
  blocks.delete(key);
}

function clearBlocks() {
  for (const key of [...blocks.keys()]) removeBlock(key);
  labelCounts.clear();
  bounds = new THREE.Box3();
}

function readBlock(buffer) {
  const head = new Int32Array(buffer, 4, 3);
  const [nv, nt, own] = new Uint32Array(buffer, 16, 3);
  let at = 28;
  const positions = new Float32Array(buffer, at, 3 * nv); at += 12 * nv;
  const scores = new Float32Array(buffer, at, nv); at += 4 * nv;
  const indices = new Uint32Array(buffer, at, 3 * nt); at += 12 * nt;
  const labels = new Uint16Array(buffer, at, nv); at += 2 * nv; at = (at + 3) & ~3;
  const rgb = new Uint8Array(buffer, at, 3 * nv);
  const key = `${head[0]},${head[1]},${head[2]}`;
  removeBlock(key);
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  geometry.setAttribute('color', new THREE.BufferAttribute(new Uint8Array(3 * nv), 3, true));
  geometry.setIndex(new THREE.BufferAttribute(indices, 1));
  geometry.computeVertexNormals();
  geometry.computeBoundingBox();
  const mesh = new THREE.Mesh(geometry, material);
  const block = { mesh, labels, scores, rgb, own };
  for (const s of scores) if (s > maxScore) maxScore = s;
  fillColors(block);
  countLabels(block, +1);
  bounds.union(geometry.boundingBox);
  blocks.set(key, block);
  mapGroup.add(mesh);
}

function onBinary(buffer) {
  const kind = new Uint32Array(buffer, 0, 1)[0];
  if (kind === KIND_BLOCK) readBlock(buffer);
  else if (kind === KIND_REMOVED) { const o = new Int32Array(buffer, 4, 3); removeBlock(`${o[0]},${o[1]},${o[2]}`); }
  else if (kind === KIND_CLEARED) clearBlocks();
  else if (kind === KIND_RAYCAST) showRaycast(buffer);
  dataDirty = true;
}

// ---- cameras ----
const cameraViews = new Map();  // camera id -> {path: [Vector3], line, frustum}
const cameraColors = [0xffffff, 0xff66cc, 0x66ddff, 0xffcc33, 0x99ff66];

function frustumGeometry() {
  // The camera looks along +z with x right and y down (the frames' convention); 15 cm deep.
  const d = 0.15, w = 0.1, h = 0.075;
  const c = [0, 0, 0], p = [[-w, -h, d], [w, -h, d], [w, h, d], [-w, h, d]];
  const points = [];
  for (let i = 0; i < 4; ++i) points.push(...c, ...p[i], ...p[i], ...p[(i + 1) % 4]);
  points.push(-w * 0.4, -h, d, 0, -h * 1.6, d, 0, -h * 1.6, d, w * 0.4, -h, d);  // "up" tick
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.Float32BufferAttribute(points, 3));
  return g;
}

function cameraView(id) {
  let view = cameraViews.get(id);
  if (view) return view;
  const color = cameraColors[cameraViews.size % cameraColors.length];
  const line = new THREE.Line(new THREE.BufferGeometry(), new THREE.LineBasicMaterial({ color }));
  const frustum = new THREE.LineSegments(frustumGeometry(), new THREE.LineBasicMaterial({ color }));
  frustum.matrixAutoUpdate = false;
  cameraGroup.add(line, frustum);
  view = { path: [], line, frustum, seq: 0, state: '' };
  cameraViews.set(id, view);
  return view;
}

function onPoses(poses) {
  const touched = new Set();
  for (const pose of poses) {
    const view = cameraView(pose.camera);
    view.seq = pose.seq;
    view.state = pose.state;
    if (!pose.posed) continue;
    const m = new THREE.Matrix4().fromArray(pose.m);
    view.frustum.matrix.copy(m);
    view.path.push(new THREE.Vector3().setFromMatrixPosition(m));
    touched.add(view);
  }
  for (const view of touched) {
    // A new geometry each time: setFromPoints keeps an existing buffer's length.
    view.line.geometry.dispose();
    view.line.geometry = new THREE.BufferGeometry().setFromPoints(view.path);
  }
  dataDirty = true;
}

// ---- panel ----
const fmt = (n) => (n === undefined || n === null) ? '–' : Number(n).toLocaleString('en-US');
function rows(table, list) {
  table.innerHTML = list.map(([k, v]) => `<tr><td>${k}</td><td class="n">${v}</td></tr>`).join('');
}

let lastStatus = null;
function onStatus(status) {
  lastStatus = status;
  const s = status.server || {}, v = status.viewer;
  rows(document.getElementById('counters'), [
    ['frames integrated', `<span id="frames-integrated">${fmt(s.frames_integrated)}</span>`],
    ['frames received', fmt(s.frames_received)],
    ['frames lost', fmt(s.frames_lost)],
    ['dropped / rejected', `${fmt(s.dropped)} / ${fmt(s.rejected)}`],
    ['queued frames', fmt(s.queued_frames)],
    ['map blocks', fmt(s.allocated_blocks)],
    ['map MiB', s.map_bytes === undefined ? '–' : (s.map_bytes / 1048576).toFixed(1)],
    ['mesh blocks', `<span id="mesh-blocks">${fmt(v.blocks)}</span>`],
    ['mesh vertices', fmt(v.vertices)],
    ['updates / catch-ups', `${fmt(v.updates)} / ${fmt(v.catch_ups)}`],
    ['pages open', fmt(v.browsers)],
  ]);
  const cams = (s.cameras || []).map((c) => [c.id, `${fmt(c.integrated)} ${c.state}`]);
  rows(document.getElementById('cameras'), cams);
  updateLegend();
}

function updateLegend() {
  const present = [...labelCounts.entries()].filter(([, n]) => n > 0).sort((a, b) => b[1] - a[1]);
  document.getElementById('legend-name').textContent = legendName ? `(${legendName})` : '';
  document.getElementById('legend').innerHTML = present.map(([id, n]) => {
    const info = legend.get(id);
    const [r, g, b] = labelColor(id);
    const name = info ? info.name : `label ${id}`;
    return `<tr class="label" data-id="${id}"><td><span class="swatch" style="background:rgb(${r},${g},${b})"></span> ` +
      `${name}</td><td class="n">${fmt(n)}</td></tr>`;
  }).join('');
}

function onLegend(message) {
  legend = new Map(message.labels.map((l) => [l.id, l]));
  legendName = message.name;
  recolorAll();
  updateLegend();
  dirty = true;
}

// ---- click: labels_at ----
const probe = document.getElementById('probe');
const marker = new THREE.Mesh(new THREE.SphereGeometry(0.02, 12, 8), new THREE.MeshBasicMaterial({ color: 0xff00ff }));
marker.visible = false;
scene.add(marker);
let downAt = null;
renderer.domElement.addEventListener('pointerdown', (e) => { downAt = [e.clientX, e.clientY]; });
renderer.domElement.addEventListener('pointerup', (e) => {
  if (!downAt || Math.hypot(e.clientX - downAt[0], e.clientY - downAt[1]) > 4) return;
  const rect = renderer.domElement.getBoundingClientRect();
  const ndc = new THREE.Vector2(((e.clientX - rect.left) / rect.width) * 2 - 1, -((e.clientY - rect.top) / rect.height) * 2 + 1);
  const ray = new THREE.Raycaster();
  ray.setFromCamera(ndc, camera);
  const hit = ray.intersectObjects(mapGroup.children, false)[0];
  if (!hit) return;
  // Half a voxel behind the surface, where the label is kept.
  const p = hit.point.clone();
  if (hit.face) p.addScaledVector(hit.face.normal, -0.01);
  marker.position.copy(hit.point);
  marker.visible = true;
  dirty = true;
  probe.textContent = `asking at ${p.x.toFixed(3)} ${p.y.toFixed(3)} ${p.z.toFixed(3)}…`;
  if (socket && socket.readyState === WebSocket.OPEN) {
    socket.send(`labels_at ${p.x} ${p.y} ${p.z}`);
    socket.send(raycastRequest());
  }
});

// The server's raycast from this view: 320 pixels wide, the page's field of view; the camera
// looks along +z with y down, three.js's along -z with y up.
function raycastRequest() {
  const w = 320, h = Math.max(1, Math.round(w / camera.aspect));
  const f = (h / 2) / Math.tan(THREE.MathUtils.degToRad(camera.fov) / 2);
  camera.updateMatrixWorld();
  const m = camera.matrixWorld.clone().multiply(new THREE.Matrix4().makeScale(1, -1, -1));
  // Far enough to reach the whole map from here.
  const range = bounds.isEmpty() ? 0
    : camera.position.distanceTo(bounds.getCenter(new THREE.Vector3())) + bounds.getSize(new THREE.Vector3()).length();
  return `raycast ${w} ${h} ${f} ${f} ${(w - 1) / 2} ${(h - 1) / 2} ${range} ${m.elements.join(' ')}`;
}

let raycastUrl = null;
function showRaycast(buffer) {
  if (raycastUrl) URL.revokeObjectURL(raycastUrl);
  raycastUrl = URL.createObjectURL(new Blob([buffer.slice(4)], { type: 'image/png' }));
  document.getElementById('raycast').src = raycastUrl;
}

function onLabelsAt(m) {
  probe.textContent = `point ${m.point.map((x) => x.toFixed(3)).join(' ')}\n` +
    (m.observed ? `label ${m.name} (${m.label})\nconfidence ${m.confidence.toFixed(3)}\ntsdf ${m.tsdf.toFixed(3)}, weight ${m.weight.toFixed(1)}`
      : 'not observed') +
    (m.object ? `\nobject #${m.object.id}: ${m.object.voxels} voxels, ${m.object.size.map((x) => x.toFixed(2)).join(' x ')} m` : '');
}

// ---- view ----
function fitView() {
  if (bounds.isEmpty()) return;
  const center = bounds.getCenter(new THREE.Vector3());
  const size = bounds.getSize(new THREE.Vector3()).length();
  const up = camera.up.clone();
  const side = Math.abs(up.z) > 0.5 ? new THREE.Vector3(0.5, -0.9, 0) : new THREE.Vector3(0.5, 0, -0.9);
  camera.position.copy(center).addScaledVector(side, 0.75 * size).addScaledVector(up, 0.85 * size);
  controls.target.copy(center);
  camera.near = size / 500;
  camera.far = size * 20;
  camera.updateProjectionMatrix();
  controls.update();
  dirty = true;
}
controls.addEventListener('start', () => { userMoved = true; });
controls.addEventListener('change', () => { dirty = true; });
document.getElementById('fit').addEventListener('click', () => { userMoved = false; fitView(); });
const ups = [['z', [0, 0, 1]], ['-y', [0, -1, 0]], ['y', [0, 1, 0]]];
let upIndex = Math.max(0, ups.findIndex(([name]) => name === (params.get('up') || 'z')));
function applyUp() {
  camera.up.set(...ups[upIndex][1]);
  document.getElementById('up').textContent = `up: ${ups[upIndex][0]}`;
  fitView();
}
document.getElementById('up').addEventListener('click', () => { upIndex = (upIndex + 1) % ups.length; applyUp(); });
applyUp();
document.getElementById('shaded').addEventListener('change', (e) => {
  shaded = e.target.checked;
  material = makeMaterial();
  for (const block of blocks.values()) block.mesh.material = material;
  dirty = true;
});

// Two reasons to draw: the user (the view, the colours: draw at the next frame) and the data
// (blocks and poses arriving several times a second: draw at most every 500 ms). Software WebGL
// (a headless browser, a machine without a GPU) takes a core per continuous redraw.
let dirty = true;
let dataDirty = false;
let lastDataDraw = 0;
let lastFit = 0;
let fittedBounds = '';
function frame(t) {
  requestAnimationFrame(frame);
  // Follow the growing map until the user moves the view; refit only when the map grew.
  if (!userMoved && t - lastFit > 500) {
    lastFit = t;
    const key = bounds.isEmpty() ? '' : [...bounds.min.toArray(), ...bounds.max.toArray()].join(',');
    if (key !== fittedBounds) { fittedBounds = key; fitView(); }
  }
  if (dataDirty && t - lastDataDraw >= 500) { dataDirty = false; lastDataDraw = t; dirty = true; }
  if (!dirty) return;
  dirty = false;
  renderer.render(scene, camera);
  document.body.dataset.blocks = String(blocks.size);
  document.body.dataset.poses = String([...cameraViews.values()].reduce((n, v) => n + v.path.length, 0));
}
requestAnimationFrame(frame);

// Where a world point lands on the page, in CSS pixels (for tests and the console).
window.semfuseProject = (x, y, z) => {
  const p = new THREE.Vector3(x, y, z).project(camera);
  const rect = renderer.domElement.getBoundingClientRect();
  return [rect.left + (p.x + 1) / 2 * rect.width, rect.top + (1 - p.y) / 2 * rect.height];
};

// ---- connection ----
let socket = null;
const connection = document.getElementById('connection');
function connect() {
  socket = new WebSocket(`${location.protocol === 'https:' ? 'wss' : 'ws'}://${location.host}/ws`);
  socket.binaryType = 'arraybuffer';
  socket.onopen = () => { connection.textContent = 'connected'; connection.className = 'ok'; };
  socket.onclose = () => {
    connection.textContent = 'disconnected: retrying'; connection.className = 'lost';
    setTimeout(connect, 1000);
  };
  socket.onmessage = (e) => {
    if (typeof e.data !== 'string') return onBinary(e.data);
    const m = JSON.parse(e.data);
    if (m.type === 'status') onStatus(m);
    else if (m.type === 'poses') onPoses(m.poses);
    else if (m.type === 'legend') onLegend(m);
    else if (m.type === 'labels_at') onLabelsAt(m);
    else if (m.type === 'error') probe.textContent = `${m.what}: ${m.message}`;
  };
}
connect();
