// The live preview page: shows the frames the server renders and sends the user's edits.
// Plain browser JavaScript, no build step and nothing from elsewhere; the API is documented in
// src/server/api.h. window.ptPreview holds what the page knows (read by tests/serve_browser.py).
'use strict';

const $ = (id) => document.getElementById(id);
const preview = window.ptPreview = {
  frames: 0, frameId: 0, generation: 0, spp: 0, selected: null, errors: 0, lastError: '',
  latencyMs: null, stats: null,
};
let scene = null;         // GET /api/scene
let camera = null;        // the camera as this page last set it
let initialCamera = null;
const editSent = new Map();  // generation -> time the edit that asked for it was sent

// ---- Small vector maths for the camera ---------------------------------------------------------
const add = (a, b) => a.map((v, i) => v + b[i]);
const sub = (a, b) => a.map((v, i) => v - b[i]);
const scale = (a, s) => a.map((v) => v * s);
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const norm = (a) => Math.hypot(a[0], a[1], a[2]);
const unit = (a) => scale(a, 1 / norm(a));
// Rodrigues: v rotated by angle (radians) about the unit axis k.
function rotate(v, k, angle) {
  const c = Math.cos(angle), s = Math.sin(angle);
  return add(add(scale(v, c), scale(cross(k, v), s)), scale(k, dot(k, v) * (1 - c)));
}
function basis(cam) {
  const forward = unit(sub(cam.look_at, cam.position));
  const right = unit(cross(forward, cam.up || [0, 1, 0]));
  return { forward, right, up: cross(right, forward) };
}
// World units per displayed pixel at a distance along the view direction.
function unitsPerPixel(depth) {
  const img = $('view');
  return 2 * depth * Math.tan((camera.fov_y * Math.PI) / 360) / Math.max(1, img.clientHeight);
}

// ---- Requests ---------------------------------------------------------------------------------
function showError(message) {
  preview.errors += 1;
  preview.lastError = message;
  $('error').textContent = message;
  clearTimeout(showError.timer);
  showError.timer = setTimeout(() => { $('error').textContent = ''; }, 6000);
}

async function post(path, body) {
  const response = await fetch(path, {
    method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body),
  });
  const answer = await response.json().catch(() => ({}));
  if (!response.ok) throw new Error(answer.error || `HTTP ${response.status}`);
  return answer;
}

// An edit: its generation is timed until the first frame that shows it.
async function edit(path, body) {
  const sent = performance.now();
  try {
    const answer = await post(path, body);
    if (answer.generation !== undefined && !editSent.has(answer.generation)) {
      editSent.set(answer.generation, sent);
    }
    return answer;
  } catch (e) {
    showError(e.message);
    return null;
  }
}

// Sends only the newest value, one request at a time (a drag makes many).
function latestSender(send) {
  let pending = null, busy = false;
  return async (value) => {
    pending = value;
    if (busy) return;
    busy = true;
    while (pending !== null) {
      const v = pending;
      pending = null;
      await send(v);
    }
    busy = false;
  };
}
const sendCamera = latestSender((cam) => edit('/api/camera', cam));

// ---- Frames -----------------------------------------------------------------------------------
const frameTimes = [];
function showFrame(blob, response) {
  const img = $('view');
  const old = img.src;
  img.src = URL.createObjectURL(blob);
  if (old.startsWith('blob:')) URL.revokeObjectURL(old);
  preview.frames += 1;
  preview.frameId = Number(response.headers.get('X-Frame-Id'));
  preview.generation = Number(response.headers.get('X-Generation'));
  preview.spp = Number(response.headers.get('X-Spp'));
  const now = performance.now();
  for (const [generation, sent] of editSent) {
    if (generation > preview.generation) continue;
    if (generation === preview.generation) {
      preview.latencyMs = now - sent;
      $('s-latency').textContent = `${preview.latencyMs.toFixed(0)} ms`;
    }
    editSent.delete(generation);
  }
  frameTimes.push(now);
  while (frameTimes.length > 1 && now - frameTimes[0] > 2000) frameTimes.shift();
  const fps = frameTimes.length > 1 ? (frameTimes.length - 1) * 1000 / (now - frameTimes[0]) : 0;
  $('s-fps').textContent = fps.toFixed(1);
}

async function frameLoop() {
  for (;;) {
    try {
      const response = await fetch(`/api/frame?after=${preview.frameId}`, { cache: 'no-store' });
      if (response.status === 200) {
        showFrame(await response.blob(), response);
        refreshStats();
      } else if (response.status !== 204) {
        throw new Error(`frame: HTTP ${response.status}`);
      }
    } catch (e) {
      $('status').textContent = 'disconnected: retrying';
      await new Promise((resolve) => setTimeout(resolve, 1000));
    }
  }
}

const si = (v) => (v >= 1e9 ? `${(v / 1e9).toFixed(2)} G` : v >= 1e6 ? `${(v / 1e6).toFixed(2)} M`
  : v >= 1e3 ? `${(v / 1e3).toFixed(1)} k` : v.toFixed(0));

async function refreshStats() {
  let s;
  try {
    const response = await fetch('/api/stats', { cache: 'no-store' });
    if (!response.ok) return;
    s = await response.json();
  } catch (e) {
    return;
  }
  preview.stats = s;
  $('status').textContent = `${s.spp} / ${s.target_spp} spp`;
  $('s-spp').textContent = `${s.spp} / ${s.target_spp}`;
  $('s-samples').textContent = si(s.samples_per_s);
  $('s-rays').textContent = si(s.rays_per_s);
  $('s-pass').textContent = s.pass_ms.toFixed(2);
  $('s-backend').textContent = s.device ? `${s.backend} (${s.device})` : `${s.backend}, ${s.threads} threads`;
  $('s-variant').textContent = s.specialization;
  $('s-used').textContent = `${s.compact_used ? 'on' : 'off'} / ${s.sort_used ? 'on' : 'off'}`;
  if (s.rebuilds) {  // what object moves cost: instances re-place through the top level alone
    const r = s.rebuilds;
    $('s-rebuilds').textContent = `${r.scene} / ${r.top_level}` +
        (r.scene + r.top_level > 0 ? ` (last ${r.last_ms.toFixed(1)} ms)` : '');
  }
  const stages = $('stages');
  const entries = Object.entries(s.stage_ms);
  const most = Math.max(1e-9, ...entries.map(([, ms]) => ms));
  stages.replaceChildren(...entries.map(([name, ms]) => {
    const row = document.createElement('div');
    row.className = 'stage-row';
    const label = document.createElement('span');
    label.textContent = name;
    const bar = document.createElement('span');
    bar.className = 'bar';
    bar.style.width = `${(150 * ms) / most}px`;
    const value = document.createElement('span');
    value.textContent = ms.toFixed(3);
    row.append(label, bar, value);
    return row;
  }));
}

// ---- Scene, flags and camera controls ---------------------------------------------------------
async function loadScene() {
  const response = await fetch('/api/scene', { cache: 'no-store' });
  scene = await response.json();
  if (!camera) {
    camera = { position: scene.camera.position, look_at: scene.camera.look_at,
      up: scene.camera.up || [0, 1, 0], fov_y: scene.camera.fov_y };
    initialCamera = structuredClone(camera);
  }
  $('title').textContent = scene.scene;
  document.title = `${scene.scene}: pathtracer preview`;
  $('f-compact').value = scene.options.compact;
  $('f-sort').value = scene.options.sort;
  $('f-integrator').value = scene.options.integrator;
  $('f-specialize').checked = scene.options.specialize;
  $('f-light-sampler').value = scene.options.light_sampler;
  $('f-max-depth').value = scene.render.max_depth;
  $('f-spp').value = scene.render.spp;
  showFov();
  fitView();
}

// The image as large as the space left of the controls allows, at its aspect ratio (a small
// render is scaled up: the mouse maps through clientWidth/clientHeight to its pixels).
function fitView() {
  const main = document.querySelector('main');
  const availableWidth = main.clientWidth - 24, availableHeight = window.innerHeight - 60;
  const s = Math.min(availableWidth / scene.width, availableHeight / scene.height);
  $('view').style.width = `${Math.floor(scene.width * s)}px`;
  $('view').style.height = `${Math.floor(scene.height * s)}px`;
}

function showFov() {
  $('c-fov').value = camera.fov_y;
  $('c-fov-value').textContent = `${Number(camera.fov_y).toFixed(1)}°`;
}

function bindFlags() {
  const flag = (id, key, read) => $(id).addEventListener('change', () => {
    const value = read($(id));
    if (value !== undefined) edit('/api/options', { [key]: value });
  });
  const text = (el) => el.value;
  const integer = (el) => (Number.isInteger(Number(el.value)) && el.value !== '' ? Number(el.value) : undefined);
  flag('f-compact', 'compact', text);
  flag('f-sort', 'sort', text);
  flag('f-integrator', 'integrator', text);
  flag('f-specialize', 'specialize', (el) => el.checked);
  flag('f-light-sampler', 'light_sampler', text);
  flag('f-max-depth', 'max_depth', integer);
  flag('f-spp', 'spp', integer);
  $('c-fov').addEventListener('input', () => {
    camera.fov_y = Number($('c-fov').value);
    showFov();
    sendCamera(structuredClone(camera));
  });
  $('c-reset').addEventListener('click', () => {
    camera = structuredClone(initialCamera);
    showFov();
    sendCamera(structuredClone(camera));
  });
  $('d-exposure').addEventListener('input', () => {
    const stops = Number($('d-exposure').value);
    $('d-exposure-value').textContent = stops;
    post('/api/display', { exposure: stops }).catch((e) => showError(e.message));
  });
}

function orbit(dx, dy) {
  const k = 0.3 * Math.PI / 180;
  const up = unit(camera.up || [0, 1, 0]);
  let offset = rotate(sub(camera.position, camera.look_at), up, -dx * k);
  const right = unit(cross(offset, up));
  const turned = rotate(offset, right, dy * k);
  const cosUp = dot(unit(turned), up);
  if (Math.abs(cosUp) < 0.995) offset = turned;  // never over the pole
  camera.position = add(camera.look_at, offset);
}

function pan(dx, dy) {
  const b = basis(camera);
  const s = unitsPerPixel(norm(sub(camera.look_at, camera.position)));
  const delta = add(scale(b.right, -dx * s), scale(b.up, dy * s));
  camera.position = add(camera.position, delta);
  camera.look_at = add(camera.look_at, delta);
}

function zoom(wheelDelta) {
  const offset = sub(camera.position, camera.look_at);
  const distance = Math.max(1e-4, norm(offset) * Math.exp(wheelDelta * 0.001));
  camera.position = add(camera.look_at, scale(unit(offset), distance));
}

// ---- Selection, moving and material editing ---------------------------------------------------
function imagePixel(event) {
  const img = $('view');
  return { x: (event.offsetX / img.clientWidth) * scene.width,
    y: (event.offsetY / img.clientHeight) * scene.height };
}

async function pick(event) {
  try {
    return await post('/api/pick', imagePixel(event));
  } catch (e) {
    showError(e.message);
    return { object: null };
  }
}

// Moves accumulate while a request is out, so no displacement is lost.
const pendingMove = { delta: [0, 0, 0], busy: false };
async function moveSelected(delta) {
  pendingMove.delta = add(pendingMove.delta, delta);
  if (pendingMove.busy) return;
  pendingMove.busy = true;
  while (norm(pendingMove.delta) > 0) {
    const d = pendingMove.delta;
    pendingMove.delta = [0, 0, 0];
    await edit(`/api/objects/${preview.selected}/move`, { translate: d });
  }
  pendingMove.busy = false;
}

function select(hit) {
  preview.selected = hit.object ?? null;
  const box = $('selection');
  const form = $('material');
  form.replaceChildren();
  if (preview.selected === null) {
    box.textContent = 'Nothing selected (the background).';
    return;
  }
  const object = scene.objects[preview.selected];
  const material = scene.materials[hit.material];
  box.textContent = `object ${preview.selected} (${object.type}${object.file ? `: ${object.file.split('/').pop()}` : ''})` +
    `, material "${material.name}" (${material.type})`;
  if (material.editable) buildMaterialForm(form, hit.material, material.fields);
  else box.textContent += ': defined by the mesh file, not editable here';
}

function numberInput(value, onChange) {
  const input = document.createElement('input');
  input.type = 'number';
  input.step = 'any';
  input.value = value;
  input.addEventListener('change', onChange);
  return input;
}

// Material edits go out one at a time, in order: requests in flight together may be applied in
// any order, and an older value (of a vector edited component by component) could win.
let materialEdits = Promise.resolve();

// One input per editable field of the material as the scene file has it: numbers, and
// colours or vectors of 3 numbers; other fields (type, texture files) are shown, not edited.
function buildMaterialForm(form, index, fields) {
  const set = document.createElement('fieldset');
  const legend = document.createElement('legend');
  legend.textContent = `material ${index}`;
  set.append(legend);
  for (const [key, value] of Object.entries(fields)) {
    const label = document.createElement('label');
    label.append(key);
    const send = (v) => {
      materialEdits = materialEdits.then(() => edit(`/api/materials/${index}`, { [key]: v }))
        .then(() => refreshMaterials()).catch(() => {});  // a failure must not stop later edits
      return materialEdits;
    };
    if (typeof value === 'number') {
      const input = numberInput(value, () => send(Number(input.value)));
      input.name = key;
      label.append(input);
    } else if (Array.isArray(value) && value.length === 3 && value.every((v) => typeof v === 'number')) {
      const vec = document.createElement('span');
      vec.className = 'vec';
      const inputs = value.map((v) => numberInput(v, () => send(inputs.map((i) => Number(i.value)))));
      inputs.forEach((input, i) => { input.name = `${key}.${i}`; });
      vec.append(...inputs);
      label.append(vec);
    } else {
      const shown = document.createElement('span');
      shown.textContent = JSON.stringify(value);
      label.append(shown);
    }
    set.append(label);
  }
  form.append(set);
}

async function refreshMaterials() {
  const response = await fetch('/api/scene', { cache: 'no-store' });
  if (response.ok) scene = await response.json();
}

// ---- Mouse ------------------------------------------------------------------------------------
function bindMouse() {
  const img = $('view');
  let drag = null;  // {x, y, mode: 'pending'|'orbit'|'pan'|'move', moved, hit, queued}
  img.addEventListener('contextmenu', (e) => e.preventDefault());
  img.addEventListener('mousedown', (e) => {
    if (!scene) return;
    e.preventDefault();
    const panning = e.button === 2 || e.shiftKey;
    drag = { x: e.clientX, y: e.clientY, moved: false, queued: [], mode: panning ? 'pan' : 'pending' };
    drag.hit = pick(e);
    const current = drag;
    drag.hit.then((hit) => {
      if (current.mode !== 'pending') return;
      const own = preview.selected !== null && hit.object === preview.selected;
      current.mode = own ? 'move' : 'orbit';
      current.depth = own ? dot(sub(hit.point, camera.position), basis(camera).forward) : 0;
      img.classList.toggle('moving', own);
      for (const [dx, dy] of current.queued) apply(current, dx, dy);
      current.queued = [];
    });
  });
  window.addEventListener('mousemove', (e) => {
    if (!drag) return;
    const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
    if (!drag.moved && Math.hypot(dx, dy) < 3) return;
    drag.moved = true;
    img.classList.add('dragging');
    drag.x = e.clientX;
    drag.y = e.clientY;
    if (drag.mode === 'pending') drag.queued.push([dx, dy]);
    else apply(drag, dx, dy);
  });
  window.addEventListener('mouseup', async () => {
    if (!drag) return;
    const done = drag;
    drag = null;
    img.classList.remove('dragging', 'moving');
    if (!done.moved) select(await done.hit);
  });
  img.addEventListener('wheel', (e) => {
    e.preventDefault();
    zoom(e.deltaY);
    sendCamera(structuredClone(camera));
  }, { passive: false });
}

function apply(drag, dx, dy) {
  if (drag.mode === 'move') {
    const b = basis(camera);
    const s = unitsPerPixel(Math.max(1e-4, drag.depth));
    moveSelected(add(scale(b.right, dx * s), scale(b.up, -dy * s)));
    return;
  }
  if (drag.mode === 'pan') pan(dx, dy);
  else orbit(dx, dy);
  sendCamera(structuredClone(camera));
}

async function start() {
  try {
    await loadScene();
  } catch (e) {
    $('status').textContent = 'cannot reach the server';
    setTimeout(start, 1000);
    return;
  }
  bindFlags();
  bindMouse();
  window.addEventListener('resize', fitView);
  frameLoop();
}
start();
