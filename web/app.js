// The live preview page: shows the frames the server renders and sends the user's edits.
// Plain browser JavaScript, no build step and nothing from elsewhere; the API is documented in
// src/server/api.h. window.ptPreview holds what the page knows (read by tests/serve_browser.py).
'use strict';

const $ = (id) => document.getElementById(id);
const preview = window.ptPreview = {
  frames: 0, frameId: 0, generation: 0, spp: 0, kind: '', selected: null, errors: 0,
  lastError: '', lastErrorField: '', latencyMs: null, fps: 0, stats: null, state: null,
  events: 0, framesByKind: { coarse: 0, render: 0, display: 0 },
};
let scene = null;         // the "scene" event: objects, materials, cameras, maps
let state = null;         // the "state" event: what the render uses (camera, options, display...)
let camera = null;        // the camera this page moves (state.camera when nothing is dragged)
let interacting = 0;      // drags and camera sends under way: the page's own camera wins
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

// ---- Requests and errors -----------------------------------------------------------------------
// The control each field of the server's errors names.
const fieldInputs = {
  compact: 'f-compact', sort: 'f-sort', integrator: 'f-integrator', specialize: 'f-specialize',
  light_sampler: 'f-light-sampler', sampler: 'f-sampler', max_depth: 'f-max-depth', spp: 'f-spp', denoise: 'f-denoise',
  exposure: 'd-exposure', tone_mapping: 'd-tonemap', map: 'l-map', strength: 'l-strength',
  rotation: 'l-rotation',
};

function clearFieldErrors() {
  for (const e of document.querySelectorAll('.field-error')) e.remove();
}

// The message at the top of the controls and next to the field it is about (the field itself
// already shows the value in force again: see applyState).
function showError(message, input) {
  preview.errors += 1;
  preview.lastError = message;
  $('error').textContent = message;
  clearTimeout(showError.timer);
  showError.timer = setTimeout(() => { $('error').textContent = ''; }, 8000);
  if (!input) return;
  const label = input.closest('label') || input.parentElement;
  const note = document.createElement('div');
  note.className = 'field-error';
  note.textContent = message;
  label.after(note);
}

async function post(path, body) {
  const response = await fetch(path, {
    method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body),
  });
  const answer = await response.json().catch(() => ({}));
  if (!response.ok) {
    const error = new Error(answer.error || `HTTP ${response.status}`);
    error.field = answer.field || '';
    throw error;
  }
  return answer;
}

// An edit: a restart is timed from sending it to the first rendered frame that shows it. A
// refusal puts the value in force back and its message next to the field (`input`, or the
// control of the field the server names).
async function edit(path, body, input = null) {
  const sent = performance.now();
  if (input) clearFieldErrors();  // a new value for a control: its old message goes
  try {
    const answer = await post(path, body);
    if (answer.restarts && !editSent.has(answer.generation)) editSent.set(answer.generation, sent);
    return answer;
  } catch (e) {
    preview.lastErrorField = e.field || '';
    if (state) applyState(state, true);
    let target = input;
    if (input && input.dataset.material !== undefined) {  // the form again, as in force
      refreshMaterialForm(true);
      target = $('material').elements[input.name] || null;
    }
    showError(e.message, target || (e.field && $(fieldInputs[e.field])) || null);
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
    interacting += 1;
    while (pending !== null) {
      const v = pending;
      pending = null;
      await send(v);
    }
    interacting -= 1;
    busy = false;
  };
}
const sendCamera = latestSender((cam) => edit('/api/camera', cam));
const sendExposure = latestSender((stops) => edit('/api/display', { exposure: stops }, $('d-exposure')));
const sendRotation = latestSender((deg) => edit('/api/lighting', { rotation: deg }, $('l-rotation')));

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
  preview.kind = response.headers.get('X-Frame-Kind') || 'render';
  preview.framesByKind[preview.kind] = (preview.framesByKind[preview.kind] || 0) + 1;
  const now = performance.now();
  if (preview.kind !== 'display') {
    for (const [generation, sent] of editSent) {
      if (generation > preview.generation) continue;
      if (generation === preview.generation) {
        preview.latencyMs = now - sent;
        $('s-latency').textContent = `${preview.latencyMs.toFixed(0)} ms`;
      }
      editSent.delete(generation);
    }
  }
  frameTimes.push(now);
  showFps();
}

// Frames shown in the last 2 s: falls to 0 when none come (converged, or only display changes).
function showFps() {
  const now = performance.now();
  while (frameTimes.length && now - frameTimes[0] > 2000) frameTimes.shift();
  preview.fps = frameTimes.length / 2;
  $('s-fps').textContent = preview.fps.toFixed(1);
}

async function frameLoop() {
  for (;;) {
    try {
      const response = await fetch(`/api/frame?after=${preview.frameId}`, { cache: 'no-store' });
      if (response.status === 200) {
        showFrame(await response.blob(), response);
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

// The "progress" event: the latest frame's statistics, or why the render ended.
function showProgress(s) {
  preview.stats = s;
  if (s.spp === undefined) return;
  const ended = s.state === 'done' || s.state === 'stopped';
  $('status').textContent = `${s.spp} / ${s.target_spp} spp` + (s.state === 'stopped' ? ' (stopped)' : '');
  $('s-spp').textContent = `${s.spp} / ${s.target_spp}`;
  $('s-state').textContent = ended && s.message ? s.message : s.state || '–';
  if (s.samples_per_s === undefined) return;
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
  // The denoiser's time on the frame shown; "off" when the frame is not denoised (coarse ones never are).
  $('s-denoise').textContent = s.denoise_ms === undefined ? 'off' :
      `${s.denoise_ms.toFixed(1)}` + (s.denoise_variance ? ` (${s.denoise_variance} variance` +
      (s.denoise_emission ? `, emission ${s.denoise_emission === 'keep' ? 'kept' : 'filtered'}` : '') +
      ')' : '');
  showStages(s.stage_ms);
}

function showStages(stageMs) {
  const entries = Object.entries(stageMs || {});
  const most = Math.max(1e-9, ...entries.map(([, ms]) => ms));
  $('stages').replaceChildren(...entries.map(([name, ms]) => {
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

// ---- The server's state, pushed (GET /api/events) ----------------------------------------------
function connectEvents() {
  const events = new EventSource('/api/events');
  events.addEventListener('scene', (e) => { preview.events += 1; applyScene(JSON.parse(e.data)); });
  events.addEventListener('state', (e) => { preview.events += 1; applyState(JSON.parse(e.data)); });
  events.addEventListener('progress', (e) => { preview.events += 1; showProgress(JSON.parse(e.data)); });
  events.addEventListener('error', () => { $('status').textContent = 'disconnected: retrying'; });
}

function option(value, text) {
  const o = document.createElement('option');
  o.value = value;
  o.textContent = text;
  return o;
}

function applyScene(next) {
  const first = !scene;
  scene = next;
  $('title').textContent = scene.scene;
  document.title = `${scene.scene}: pathtracer preview`;
  $('c-choice').replaceChildren(option('', '(moved)'),
    ...scene.cameras.map((c) => option(String(c.index), c.name)));
  $('l-map').replaceChildren(option('scene', "the scene's own"), option('none', 'none'),
    ...scene.maps.map((m) => option(m, m)));
  const denoise = Boolean(scene.options.denoise_available);
  $('f-denoise-row').hidden = !denoise;
  $('denoise-key').hidden = !denoise;
  $('s-denoise-row').hidden = !denoise;
  if (first) fitView();
  if (state) applyState(state, true);
  refreshMaterialForm();
}

// Every control shows what the render uses; the camera too, unless this page is moving it.
function applyState(next, again = false) {
  const selectionChanged = !state || JSON.stringify(state.selection) !== JSON.stringify(next.selection);
  const cameraChanged = !state || JSON.stringify(state.camera) !== JSON.stringify(next.camera);
  state = preview.state = next;
  if (!interacting || !camera) camera = structuredClone(state.camera);
  if (!camera.up) camera.up = [0, 1, 0];
  showFov();
  const o = state.options;
  $('f-compact').value = o.compact;
  $('f-sort').value = o.sort;
  $('f-integrator').value = o.integrator;
  $('f-specialize').checked = o.specialize;
  $('f-light-sampler').value = o.light_sampler;
  $('f-sampler').value = o.sampler;
  $('f-max-depth').value = o.max_depth;
  $('f-spp').value = o.spp;
  $('f-denoise').checked = Boolean(o.denoise);
  $('c-choice').value = state.camera_choice === null ? '' : String(state.camera_choice);
  if (!sliding.has('d-exposure')) {
    $('d-exposure').value = state.display.exposure;
    $('d-exposure-value').textContent = state.display.exposure;
  }
  $('d-tonemap').value = state.display.tone_mapping;
  $('l-map').value = state.lighting.map;
  $('l-strength').value = state.lighting.strength;
  if (!sliding.has('l-rotation')) {
    $('l-rotation').value = state.lighting.rotation;
    $('l-rotation-value').textContent = `${state.lighting.rotation}°`;
  }
  preview.selected = state.selection.object;
  if (selectionChanged) showSelection();
  if (selectionChanged || cameraChanged) refreshOutline();
}

// The image as large as the space left of the controls allows, at its aspect ratio (a small
// render is scaled up: the mouse maps through clientWidth/clientHeight to its pixels).
function fitView() {
  const main = document.querySelector('main');
  const availableWidth = main.clientWidth - 24, availableHeight = window.innerHeight - 60;
  const s = Math.min(availableWidth / scene.width, availableHeight / scene.height);
  for (const id of ['view', 'outline']) {
    $(id).style.width = `${Math.floor(scene.width * s)}px`;
    $(id).style.height = `${Math.floor(scene.height * s)}px`;
  }
}

function showFov() {
  $('c-fov').value = camera.fov_y;
  $('c-fov-value').textContent = `${Number(camera.fov_y).toFixed(1)}°`;
}

// Sliders being dragged keep their own value until released.
const sliding = new Set();

function bindControls() {
  const flag = (id, key, read) => $(id).addEventListener('change', () => {
    const value = read($(id));
    if (value === undefined) {
      applyState(state, true);
      showError(`${key} needs a whole number`, $(id));
    } else {
      edit('/api/options', { [key]: value }, $(id));
    }
  });
  const text = (el) => el.value;
  const integer = (el) => (Number.isInteger(Number(el.value)) && el.value !== '' ? Number(el.value) : undefined);
  flag('f-compact', 'compact', text);
  flag('f-sort', 'sort', text);
  flag('f-integrator', 'integrator', text);
  flag('f-specialize', 'specialize', (el) => el.checked);
  flag('f-light-sampler', 'light_sampler', text);
  flag('f-sampler', 'sampler', text);
  flag('f-max-depth', 'max_depth', integer);
  flag('f-spp', 'spp', integer);
  flag('f-denoise', 'denoise', (el) => el.checked);
  for (const id of ['d-exposure', 'l-rotation', 'c-fov']) {
    $(id).addEventListener('pointerdown', () => sliding.add(id));
    $(id).addEventListener('change', () => sliding.delete(id));
  }
  $('c-fov').addEventListener('input', () => {
    camera.fov_y = Number($('c-fov').value);
    showFov();
    sendCamera(structuredClone(camera));
  });
  $('c-choice').addEventListener('change', () => {
    if ($('c-choice').value !== '') edit('/api/camera', { choose: Number($('c-choice').value) });
  });
  $('c-reset').addEventListener('click', resetCamera);
  $('c-frame').addEventListener('click', frameSelected);
  $('d-exposure').addEventListener('input', () => {
    const stops = Number($('d-exposure').value);
    $('d-exposure-value').textContent = stops;
    sendExposure(stops);
  });
  $('d-tonemap').addEventListener('change', () => edit('/api/display', { tone_mapping: $('d-tonemap').value }, $('d-tonemap')));
  $('l-map').addEventListener('change', () => edit('/api/lighting', { map: $('l-map').value }, $('l-map')));
  $('l-strength').addEventListener('change', () => edit('/api/lighting', { strength: Number($('l-strength').value) }, $('l-strength')));
  $('l-rotation').addEventListener('input', () => {
    $('l-rotation-value').textContent = `${$('l-rotation').value}°`;
    sendRotation(Number($('l-rotation').value));
  });
}

const resetCamera = () => edit('/api/camera', { choose: 0 });
const frameSelected = () => edit('/api/camera', { frame: 'selection' });
const deselect = () => edit('/api/select', { object: null });

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

// The selected object's outline over the image (the server casts it through the camera in
// force): fetched again when the selection, the camera or the object's place changes.
async function refreshOutline() {
  const img = $('outline');
  if (preview.selected === null || preview.selected === undefined) {
    img.hidden = true;
    return;
  }
  const ask = (refreshOutline.asked = (refreshOutline.asked || 0) + 1);
  const response = await fetch('/api/outline.png?max=320', { cache: 'no-store' }).catch(() => null);
  if (ask !== refreshOutline.asked || !response) return;  // a newer one is on its way
  if (response.status !== 200) {
    img.hidden = true;
    return;
  }
  const old = img.src;
  img.src = URL.createObjectURL(await response.blob());
  if (old.startsWith('blob:')) URL.revokeObjectURL(old);
  img.hidden = false;
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
  refreshOutline();
}

function showSelection() {
  const box = $('selection');
  if (preview.selected === null || !scene) {
    box.textContent = 'Nothing selected.';
    $('material').replaceChildren();
    return;
  }
  const object = scene.objects[preview.selected];
  const materialIndex = state.selection.material;
  const material = scene.materials[materialIndex];
  box.textContent = `object ${preview.selected} (${object.type}${object.file ? `: ${object.file.split('/').pop()}` : ''})` +
    (material ? `, material "${material.name}" (${material.type})` : '');
  refreshMaterialForm();
  if (material && !material.editable) box.textContent += ': defined by the mesh file, not editable here';
}

// The selected material's form, as the scene in force has it (not while the user is typing in
// it, unless `force`).
function refreshMaterialForm(force = false) {
  const form = $('material');
  if (!force && form.contains(document.activeElement)) return;
  form.replaceChildren();
  if (!state || !scene || preview.selected === null) return;
  const index = state.selection.material;
  const material = scene.materials[index];
  if (material && material.editable) buildMaterialForm(form, index, material.fields);
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
    const send = (v, input) => {
      materialEdits = materialEdits.then(() => edit(`/api/materials/${index}`, { [key]: v }, input))
        .catch(() => {});  // a failure must not stop later edits
      return materialEdits;
    };
    if (typeof value === 'number') {
      const input = numberInput(value, () => send(Number(input.value), input));
      input.name = key;
      input.dataset.material = index;
      label.append(input);
    } else if (Array.isArray(value) && value.length === 3 && value.every((v) => typeof v === 'number')) {
      const vec = document.createElement('span');
      vec.className = 'vec';
      const inputs = value.map((v) => numberInput(v, (e) => send(inputs.map((i) => Number(i.value)), e.target)));
      inputs.forEach((input, i) => { input.name = `${key}.${i}`; input.dataset.material = index; });
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

// ---- Mouse and keys ---------------------------------------------------------------------------
function bindMouse() {
  const img = $('view');
  let drag = null;  // {x, y, mode: 'pending'|'orbit'|'pan'|'move', moved, hit, queued}
  img.addEventListener('contextmenu', (e) => e.preventDefault());
  img.addEventListener('mousedown', (e) => {
    if (!scene) return;
    e.preventDefault();
    const panning = e.button === 2 || e.shiftKey;
    drag = { x: e.clientX, y: e.clientY, moved: false, queued: [], mode: panning ? 'pan' : 'pending',
      pixel: imagePixel(e) };
    interacting += 1;
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
    $('outline').hidden = true;  // stale while the view moves
    drag.x = e.clientX;
    drag.y = e.clientY;
    if (drag.mode === 'pending') drag.queued.push([dx, dy]);
    else apply(drag, dx, dy);
  });
  window.addEventListener('mouseup', () => {
    if (!drag) return;
    const done = drag;
    drag = null;
    interacting -= 1;
    img.classList.remove('dragging', 'moving');
    if (!done.moved) edit('/api/select', done.pixel);
    else refreshOutline();
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

// F: frame the selection, Home: the scene's camera, Esc: deselect, D: denoise (when offered).
function bindKeys() {
  window.addEventListener('keydown', (e) => {
    if (e.ctrlKey || e.metaKey || e.altKey || e.target.closest('input, select, textarea')) return;
    const key = e.key.toLowerCase();
    if (key === 'f') frameSelected();
    else if (key === 'home') resetCamera();
    else if (key === 'escape') deselect();
    else if (key === 'd' && scene && scene.options.denoise_available) {
      edit('/api/options', { denoise: !state.options.denoise }, $('f-denoise'));
    } else return;
    e.preventDefault();
  });
}

function start() {
  bindControls();
  bindMouse();
  bindKeys();
  window.addEventListener('resize', () => scene && fitView());
  setInterval(showFps, 500);
  connectEvents();
  frameLoop();
}
start();
