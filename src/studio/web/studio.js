// taxel studio's page. The server compiles (the CLI's pipeline); this page
// shows the result and plays the bundle with the runtime compiled to
// WebAssembly (player.js). Nothing from a drawing is ever put into the page
// as markup: drawings come as PNG pictures, names as text.

import { Player } from "/player.js";

const $ = (id) => document.getElementById(id);
const state = {
  start: null,
  result: null,
  module: null,
  player: null,
  finger: { x: 0, y: 0 },
  t0: performance.now(),
  lastName: null,
  lastFrame: null,
  lastKey: "",
  vibrateAt: 0,
  preview: null,
  // When the fragment was last written, and a later write that waits.
  hashAt: -Infinity,
  hashTimer: 0,
  // How long the last drawn frame took, in ms (the benchmark reads it).
  frameMs: 0,
};
// For tests and for the curious: the studio's live state.
window.taxelStudio = state;

function say(text) {
  $("status").textContent = text;
}

async function api(url, options) {
  const r = await fetch(url, options);
  const body = await r.json().catch(() => ({ error: `the server answered ${r.status}` }));
  if (!r.ok) {
    const e = new Error(body.error || `the server answered ${r.status}`);
    e.status = r.status;
    throw e;
  }
  return body;
}

// ---- views ----------------------------------------------------------------

function show(view) {
  for (const v of ["teacher", "explore"]) {
    $(v).hidden = v !== view;
    $(`tab-${v}`).setAttribute("aria-pressed", String(v === view));
  }
  if (view === "explore") {
    drawSurface();
  }
}

// ---- opening and building -------------------------------------------------

async function init() {
  $("tab-teacher").addEventListener("click", () => show("teacher"));
  $("tab-explore").addEventListener("click", () => show("explore"));
  $("file").addEventListener("change", () => {
    const f = $("file").files[0];
    if (f) upload(f);
  });
  for (const id of ["profile", "fit"]) {
    $(id).addEventListener("change", () => {
      if (state.source) rebuild();
    });
  }
  document.addEventListener("dragover", (e) => {
    e.preventDefault();
    document.body.classList.add("drop");
  });
  document.addEventListener("dragleave", () => document.body.classList.remove("drop"));
  document.addEventListener("drop", (e) => {
    e.preventDefault();
    document.body.classList.remove("drop");
    const f = e.dataTransfer.files[0];
    if (f) upload(f);
  });
  $("apply").addEventListener("click", restyle);
  $("profile-file").addEventListener("change", uploadProfile);
  for (const id of ["target-element", "target-fill"]) $(id).addEventListener("change", chooseTarget);
  $("preview").addEventListener("click", pickElement);
  setupExplore();
  try {
    state.module = await Player.compile("/taxel.wasm");
  } catch (e) {
    say(`The player could not start: ${e.message}`);
  }
  const start = await api("/api/start");
  state.start = start;
  for (const name of start.profiles) {
    const o = document.createElement("option");
    o.value = name;
    o.textContent = name;
    $("profile").append(o);
  }
  if (start.default_profile) $("profile").value = start.default_profile;
  const list = $("files");
  for (const f of start.files) {
    const li = document.createElement("li");
    const b = document.createElement("button");
    b.type = "button";
    b.textContent = f;
    b.addEventListener("click", () => open(f));
    li.append(b);
    list.append(li);
  }
  $("folder").hidden = start.files.length === 0;
  if (start.file) {
    await open(start.file);
  } else {
    say(`Ready. Open a drawing${start.files.length ? " from the folder, or your own" : ""}.`);
  }
}

// A profile file chosen in the page: read by the server as `--profile FILE`
// reads one; a bad one is refused with the reader's message, shown beside
// the control and announced.
async function uploadProfile() {
  const input = $("profile-file");
  const f = input.files[0];
  const err = $("profile-error");
  if (!f) return;
  const refuse = (message) => {
    err.textContent = `${f.name} was not used: ${message}`;
    err.hidden = false;
    input.setAttribute("aria-invalid", "true");
    say(err.textContent);
  };
  if (f.size > state.start.max_input_bytes) {
    refuse(`it is larger than the ${state.start.max_input_bytes >> 20} MB input limit`);
    return;
  }
  try {
    const p = await api(`/api/profile?name=${encodeURIComponent(f.name)}`, { method: "POST", body: f });
    err.hidden = true;
    err.textContent = "";
    input.removeAttribute("aria-invalid");
    const select = $("profile");
    let o = Array.from(select.options).find((o) => o.value === p.key);
    if (!o) {
      o = document.createElement("option");
      o.value = p.key;
      o.textContent = `${p.name} (${p.family}, from ${p.file})`;
      select.append(o);
    }
    select.value = p.key;
    say(`Profile ${p.name} read from ${p.file}.`);
    if (state.source) await rebuild();
  } catch (e) {
    refuse(e.message);
  }
}

function profileQuery() {
  const p = $("profile").value;
  return (p ? `&profile=${encodeURIComponent(p)}` : "") + ($("fit").checked ? "&fit=1" : "");
}

async function open(path) {
  state.source = { path };
  say(`Building ${path}…`);
  try {
    await showResult(await api(`/api/open?path=${encodeURIComponent(path)}${profileQuery()}`, { method: "POST" }));
  } catch (e) {
    say(`${path}: ${e.message}`);
  }
}

async function upload(file) {
  if (file.size > state.start.max_input_bytes) {
    say(`${file.name} is larger than the ${state.start.max_input_bytes >> 20} MB input limit.`);
    return;
  }
  state.source = { file };
  say(`Building ${file.name}…`);
  try {
    const url = `/api/build?name=${encodeURIComponent(file.name)}${profileQuery()}`;
    await showResult(await api(url, { method: "POST", body: file }));
  } catch (e) {
    say(`${file.name}: ${e.message}`);
  }
}

function rebuild() {
  if (state.source.path) return open(state.source.path);
  return upload(state.source.file);
}

async function showResult(r) {
  state.result = r;
  $("result").hidden = false;
  const b = r.bundle;
  $("summary").textContent = b
    ? `${r.name}: a bundle of ${b.bytes} bytes for ${b.profile} (${b.family})${r.styles ? `; ${r.styles}` : ""}.`
    : `${r.name}: no bundle (see the diagnostics).`;
  setPicture("drawing", r.has_drawing, `The drawing ${r.name}`);
  setPicture("preview", r.has_preview, `What will be felt of ${r.name}`);
  $("drawing-fig").hidden = !r.has_drawing;
  $("preview-fig").hidden = !r.has_preview;
  clearMarks();
  showDiagnostics(r);
  showDownloads(r);
  $("styling").hidden = r.kind !== "drawing";
  $("copy").replaceChildren();
  if (r.kind === "drawing" && $("target-fill").checked) loadFills();
  await loadPlayer(r);
  const what = `${r.errors} error${r.errors === 1 ? "" : "s"}, ${r.warnings} warning${r.warnings === 1 ? "" : "s"}`;
  say(`Built ${r.name}: ${what}.${b ? " Explore it with the Explore view." : ""}`);
}

function setPicture(id, has, alt) {
  const img = $(id);
  img.alt = alt;
  if (has) img.src = `${state.result.base}${id}.png`;
  else img.removeAttribute("src");
}

function showDiagnostics(r) {
  const total = r.groups.reduce((n, g) => n + g.count, 0);
  $("counts").textContent = total
    ? `${r.errors} errors, ${r.warnings} warnings, ${r.notes} notes, grouped by rule. Select one to show its elements.`
    : "No diagnostics.";
  const list = $("diagnostics");
  list.replaceChildren();
  for (const g of r.groups) {
    const li = document.createElement("li");
    const b = document.createElement("button");
    b.type = "button";
    b.className = g.severity;
    b.setAttribute("aria-pressed", "false");
    b.textContent = g.lines.join("\n");
    b.dataset.code = g.code;
    b.addEventListener("click", () => selectGroup(b, g));
    li.append(b);
    list.append(li);
  }
}

function showDownloads(r) {
  const list = $("downloads");
  list.replaceChildren();
  const stem = r.name.replace(/^.*\//, "").replace(/\.[^.]*$/, "");
  const add = (href, text, file) => {
    const li = document.createElement("li");
    const a = document.createElement("a");
    a.href = href;
    a.textContent = text;
    a.download = file;
    li.append(a);
    list.append(li);
  };
  if (!r.bundle) {
    const li = document.createElement("li");
    li.textContent = "No bundle to download: the input has errors.";
    list.append(li);
    return;
  }
  add(`${r.base}bundle`, `Bundle (${stem}.taxel)`, `${stem}.taxel`);
  // The key's bundles, a page each: NAME.key.taxel, NAME.key2.taxel ...
  const pages = Number(r.bundle.key) || 0;
  for (let k = 1; k <= pages; k++) {
    const file = k === 1 ? `${stem}.key.taxel` : `${stem}.key${k}.taxel`;
    const what = pages === 1 ? "Key, a bundle of its own" : `Key, page ${k} of ${pages}`;
    add(`${r.base}${k === 1 ? "key" : `key${k}`}`, `${what} (${file})`, file);
  }
  const names = { dtms: "Dot Pad (DTMS)", graphiti: "Graphiti", unicode: "Unicode braille text" };
  for (const f of r.bundle.exports) add(`${r.base}export/${f}`, names[f], "");
}

// ---- highlighting -----------------------------------------------------------

function clearMarks() {
  $("drawing-marks").replaceChildren();
  $("preview-marks").replaceChildren();
  for (const b of $("diagnostics").querySelectorAll("button")) b.setAttribute("aria-pressed", "false");
}

async function selectGroup(button, group) {
  const was = button.getAttribute("aria-pressed") === "true";
  clearMarks();
  if (was) return;
  button.setAttribute("aria-pressed", "true");
  if (!group.elements.length) {
    say(`${group.code}: no element to show.`);
    return;
  }
  const ids = group.elements.slice(0, 200).join(",");
  const shapes = await api(`${state.result.base}outlines?ids=${encodeURIComponent(ids)}`);
  // Another diagnostic chosen meanwhile draws its own marks.
  if (button.getAttribute("aria-pressed") !== "true") return;
  const r = state.result;
  await drawMarks("drawing", shapes, 0, 0, r.drawing_px_per_mm);
  if (r.preview_frame) {
    const f = r.preview_frame;
    await drawMarks("preview", shapes, f.x0_mm, f.y0_mm, f.px_per_mm);
  }
  const found = new Set(shapes.map((s) => s.id)).size;
  say(`${group.code}: ${found} of ${group.elements.length} elements shown${found < group.elements.length ? " (the others are not in the bundle)" : ""}.`);
}

async function drawMarks(id, shapes, x0, y0, k) {
  const svg = $(`${id}-marks`);
  const img = $(id);
  // A picture still loading (a large preview, a diagnostic chosen at once)
  // is waited for: the marks are drawn in its pixels.
  if (!img.naturalWidth && img.getAttribute("src")) await img.decode().catch(() => {});
  if (!img.naturalWidth) return;
  svg.setAttribute("viewBox", `0 0 ${img.naturalWidth} ${img.naturalHeight}`);
  svg.setAttribute("preserveAspectRatio", "none");
  const ns = "http://www.w3.org/2000/svg";
  for (const s of shapes) {
    for (const ring of s.rings) {
      const pts = ring.map(([x, y]) => `${((x - x0) * k).toFixed(1)},${((y - y0) * k).toFixed(1)}`).join(" ");
      const el = document.createElementNS(ns, s.area ? "polygon" : "polyline");
      el.setAttribute("points", pts);
      el.setAttribute("class", s.area ? "mark" : "line");
      svg.append(el);
    }
  }
}

// ---- style changes ----------------------------------------------------------

function pickElement(e) {
  const r = state.result;
  if (!state.player || !r.preview_frame) return;
  const img = $("preview");
  const rect = img.getBoundingClientRect();
  const f = r.preview_frame;
  const x = f.x0_mm + ((e.clientX - rect.left) * img.naturalWidth) / rect.width / f.px_per_mm;
  const y = f.y0_mm + ((e.clientY - rect.top) * img.naturalHeight) / rect.height / f.px_per_mm;
  const id = state.player.idAt(x, y);
  if (id) {
    $("element").value = id;
    say(`Picked #${id} (${state.player.nameAt(x, y)}).`);
  } else {
    say(`Nothing at ${x.toFixed(1)}, ${y.toFixed(1)} mm.`);
  }
}

// Whether the change is for one element or for a fill colour.
function chooseTarget() {
  const byFill = $("target-fill").checked;
  $("by-element").hidden = byFill;
  $("by-fill").hidden = !byFill;
  if (byFill) loadFills();
}

// The drawing's fill colours, most used first, into the colour menu (the
// colour chosen before is kept when the drawing still has it).
async function loadFills() {
  const r = state.result;
  if (!r || r.kind !== "drawing") return;
  const select = $("fill");
  const was = select.value;
  try {
    const fills = await api(`${r.base}fills`);
    select.replaceChildren();
    for (const f of fills) {
      const o = document.createElement("option");
      o.value = f.fill;
      o.textContent = `${f.fill} (${f.count} element${f.count === 1 ? "" : "s"})`;
      select.append(o);
    }
    if (fills.some((f) => f.fill === was)) select.value = was;
    if (!fills.length) say("The drawing has no plain fill colour to change.");
  } catch (e) {
    say(e.message);
  }
}

async function restyle() {
  const byFill = $("target-fill").checked;
  const element = $("element").value.trim();
  const fill = $("fill").value;
  if (!byFill && !element) {
    say("Give the id of the element to change (select it on the felt preview).");
    $("element").focus();
    return;
  }
  if (byFill && !fill) {
    say("Choose the fill colour to change.");
    $("fill").focus();
    return;
  }
  const kind = $("style-kind").value;
  const params = $("style-params").value.trim();
  const style = kind === "none" ? "none" : `${kind}(${params})`;
  const base = state.result.base;
  const what = byFill ? `every element filled with ${fill}` : `#${element}`;
  const target = byFill ? `fill=${encodeURIComponent(fill)}` : `element=${encodeURIComponent(element)}`;
  say(`Rebuilding with ${what}: ${style}…`);
  try {
    const r = await api(`${base}restyle?${target}&style=${encodeURIComponent(style)}`, { method: "POST" });
    await showResult(r);
    showCopy(r);
  } catch (e) {
    say(e.message);
  }
}

// What the changes are saved as: the changed copy of the drawing (styles
// by element), the teacher's style sheet (styles by fill colour), or both.
function showCopy(r) {
  const list = $("copy");
  list.replaceChildren();
  const stem = r.name.replace(/^.*\//, "").replace(/\.[^.]*$/, "").replace(/\.tactile$/, "");
  const item = (node) => {
    const li = document.createElement("li");
    li.append(node);
    list.append(li);
  };
  const link = (href, file, text) => {
    const a = document.createElement("a");
    a.href = href;
    a.download = file;
    a.textContent = text;
    item(a);
  };
  const saveButton = (text, what) => {
    const b = document.createElement("button");
    b.type = "button";
    b.textContent = text;
    b.addEventListener("click", () => save(r, what, false));
    item(b);
  };
  if (r.changed) {
    link(`${r.base}copy.svg`, `${stem}.tactile.svg`, `Download the changed copy (${stem}.tactile.svg)`);
    if (r.can_save) saveButton(`Save ${stem}.tactile.svg beside the original`, "svg");
  }
  if (r.sheet) {
    link(`${r.base}sheet.toml`, r.sheet, `Download the style sheet (${r.sheet})`);
    if (r.can_save) saveButton(`Save ${r.sheet} beside the original`, "sheet");
    const note = document.createElement("span");
    note.textContent = `Build with it: taxel build --style ${r.sheet} ${r.changed ? `${stem}.tactile.svg` : r.name.replace(/^.*\//, "")}`;
    item(note);
    if (r.sheet_from_auto) {
      const auto = document.createElement("span");
      auto.textContent =
        "The sheet starts from the automatic style sheet's choices for this drawing. A style sheet cannot select texts " +
        "and small marks, so their braille and point symbols are left out: give those elements a style one by one to keep them.";
      item(auto);
    }
  }
}

async function save(r, what, overwrite) {
  try {
    const done = await api(`${r.base}save?what=${what}&overwrite=${overwrite ? 1 : 0}`, { method: "POST" });
    say(`Saved ${done.saved}.`);
  } catch (e) {
    if (e.status === 409 && window.confirm(e.message)) return save(r, what, true);
    say(e.message);
  }
}

// ---- exploring --------------------------------------------------------------

async function loadPlayer(r) {
  state.player = null;
  state.preview = null;
  if (!r.bundle || !state.module) return;
  try {
    const bytes = await (await fetch(`${r.base}bundle`)).arrayBuffer();
    state.player = await Player.load(state.module, bytes);
  } catch (e) {
    say(`The bundle cannot be played here: ${e.message}`);
    return;
  }
  if (r.has_preview) {
    const img = new Image();
    img.src = `${r.base}preview.png`;
    await img.decode().catch(() => {});
    state.preview = img;
  }
  state.lastName = null;
  const at = fromHash();
  const info = state.player.info;
  place(at ? at.x : info.surface_w_mm / 2, at ? at.y : info.surface_h_mm / 2);
}

function fromHash() {
  const m = /^#at=(-?[0-9.]+),(-?[0-9.]+)$/.exec(location.hash);
  return m ? { x: Number(m[1]), y: Number(m[2]) } : null;
}

function tick() {
  const info = state.player.info;
  if ($("pause").checked) {
    if (state.heldTick === undefined) state.heldTick = Math.floor(((performance.now() - state.t0) * info.rate_hz) / 1000);
    return state.heldTick;
  }
  state.heldTick = undefined;
  return Math.floor(((performance.now() - state.t0) * info.rate_hz) / 1000);
}

function place(x, y) {
  if (!state.player) return;
  const info = state.player.info;
  const clamp = (v, hi) => Math.min(Math.max(Math.round(v * 10) / 10, 0), hi);
  state.finger = { x: clamp(x, info.surface_w_mm), y: clamp(y, info.surface_h_mm) };
  const { x: fx, y: fy } = state.finger;
  $("pos").textContent = `${fx.toFixed(1)}, ${fy.toFixed(1)} mm`;
  shareHash();
  const name = state.player.nameAt(fx, fy) || "nothing";
  if (name !== state.lastName) {
    state.lastName = name;
    $("under").textContent = name;
    if ($("speak").checked && "speechSynthesis" in window) {
      speechSynthesis.cancel();
      speechSynthesis.speak(new SpeechSynthesisUtterance(name));
    }
  }
  drawSurface();
}

// Keeps `#at=X,Y` in the URL. Browsers refuse a page more than a few
// hundred history changes in ten seconds (a pointer moves the finger at
// every display frame), so the fragment is written at most every 200 ms,
// and the last position always.
function shareHash() {
  clearTimeout(state.hashTimer);
  const write = () => {
    state.hashAt = performance.now();
    history.replaceState(null, "", `#at=${state.finger.x},${state.finger.y}`);
  };
  const wait = state.hashAt + 200 - performance.now();
  if (wait <= 0) write();
  else state.hashTimer = setTimeout(write, wait);
}

function setupExplore() {
  const s = $("surface");
  s.addEventListener("keydown", (e) => {
    if (!state.player) return;
    const step = e.shiftKey ? 5 : 1;
    const { x, y } = state.finger;
    const info = state.player.info;
    const moves = {
      ArrowLeft: [x - step, y],
      ArrowRight: [x + step, y],
      ArrowUp: [x, y - step],
      ArrowDown: [x, y + step],
      Home: [info.surface_w_mm / 2, info.surface_h_mm / 2],
    };
    const to = moves[e.key];
    if (to) {
      e.preventDefault();
      place(to[0], to[1]);
    }
  });
  const fromPointer = (e) => {
    if (!state.player) return;
    const rect = s.getBoundingClientRect();
    const v = view();
    const px = ((e.clientX - rect.left) * s.width) / rect.width;
    const py = ((e.clientY - rect.top) * s.height) / rect.height;
    place((px - v.ox) / v.k, (py - v.oy) / v.k);
  };
  s.addEventListener("pointerdown", (e) => {
    s.setPointerCapture(e.pointerId);
    s.focus();
    fromPointer(e);
  });
  s.addEventListener("pointermove", (e) => {
    if (e.pointerType === "mouse" || e.buttons) fromPointer(e);
  });
  $("speak").addEventListener("change", () => {
    if ($("speak").checked && !("speechSynthesis" in window)) say("This browser cannot speak.");
  });
  window.addEventListener("hashchange", () => {
    const at = fromHash();
    if (at && (at.x !== state.finger.x || at.y !== state.finger.y)) place(at.x, at.y);
  });
  requestAnimationFrame(frameLoop);
}

// How the surface (mm) maps onto the surface canvas.
function view() {
  const s = $("surface");
  const info = state.player.info;
  const k = Math.min(s.width / info.surface_w_mm, s.height / info.surface_h_mm);
  return { k, ox: (s.width - info.surface_w_mm * k) / 2, oy: (s.height - info.surface_h_mm * k) / 2 };
}

function drawSurface() {
  const s = $("surface");
  const g = s.getContext("2d");
  g.fillStyle = "#fff";
  g.fillRect(0, 0, s.width, s.height);
  if (!state.player) {
    g.fillStyle = "#1a1a1a";
    g.font = "16px system-ui, sans-serif";
    g.fillText("Open a drawing first.", 20, 40);
    return;
  }
  const info = state.player.info;
  const v = view();
  g.fillStyle = "#e6e6e0";
  g.fillRect(v.ox, v.oy, info.surface_w_mm * v.k, info.surface_h_mm * v.k);
  const f = state.result.preview_frame;
  if (state.preview && f) {
    // The felt preview, placed by its own frame (page mm at its pixel 0, pixels per mm).
    const sc = v.k / f.px_per_mm;
    g.drawImage(state.preview, v.ox + f.x0_mm * v.k, v.oy + f.y0_mm * v.k, state.preview.naturalWidth * sc, state.preview.naturalHeight * sc);
  }
  const cx = v.ox + state.finger.x * v.k;
  const cy = v.oy + state.finger.y * v.k;
  if (info.family === "laterotactile") {
    // The array's footprint around the finger.
    const w = info.cols * info.pitch_x_mm * v.k;
    const h = info.rows * info.pitch_y_mm * v.k;
    g.strokeStyle = "#0b5cad";
    g.lineWidth = 2;
    g.strokeRect(cx - w / 2, cy - h / 2, w, h);
  }
  g.strokeStyle = "#c2410c";
  g.lineWidth = 3;
  g.beginPath();
  g.arc(cx, cy, 8, 0, 2 * Math.PI);
  g.moveTo(cx - 14, cy);
  g.lineTo(cx + 14, cy);
  g.moveTo(cx, cy - 14);
  g.lineTo(cx, cy + 14);
  g.stroke();
}

function frameLoop() {
  requestAnimationFrame(frameLoop);
  if (!state.player || $("explore").hidden) return;
  const started = performance.now();
  drawFrame();
  state.frameMs = performance.now() - started;
}

// The frame under the finger at this tick, drawn.
function drawFrame() {
  const t = tick();
  const { x, y } = state.finger;
  const info = state.player.info;
  const c = $("frame");
  const g = c.getContext("2d");
  g.fillStyle = "#fff";
  g.fillRect(0, 0, c.width, c.height);
  let values;
  let note = "";
  if (info.family === "laterotactile") {
    values = state.player.lateroFrame(t, x, y);
    const max = 2 ** info.output_bits - 1;
    cells(g, c, info.rows, info.cols, (i) => values[i] / max);
    const key = `${x},${y}`;
    // A vibrating border: the frame changes while the finger stays still.
    if (state.lastFrame && key === state.lastKey && !sameArray(values, state.lastFrame) && navigator.vibrate) {
      if (performance.now() - state.vibrateAt > 100) {
        navigator.vibrate(60);
        state.vibrateAt = performance.now();
      }
    }
    state.lastKey = key;
    note = `${info.cols} × ${info.rows} actuators, codes 0 to ${max}.`;
  } else if (info.family === "pins") {
    const p = state.player.pinsFrame(t, x, y);
    values = p.pins;
    const max = Math.max(1, info.pin_levels);
    cells(g, c, info.rows, info.cols, (i) => values[i] / max, true);
    note = `The display at pin ${p.col}, ${p.row} of the image: ${info.cols} × ${info.rows} pins.`;
  } else if (info.family === "finger") {
    values = state.player.fingerSample(t, x, y, true);
    const labels = ["left", "down", "right"];
    for (let i = 0; i < 3; i++) {
      const h = values[i] * (c.height - 40);
      g.fillStyle = "#1a1a1a";
      g.fillRect(20 + i * 75, c.height - 25 - h, 50, h);
      g.font = "14px system-ui, sans-serif";
      g.fillText(labels[i], 25 + i * 75, c.height - 8);
    }
    note = `Height ${values[4].toFixed(2)} mm${values[5] ? ", on a step" : ""}; period ${values[3].toFixed(0)} ms.`;
  } else {
    const end = Math.max(1, info.strokes_end);
    values = state.player.gridFrame(t % (end + 1));
    cells(g, c, info.rows, info.cols, (i) => values[i]);
    note = `The strokes play on the ${info.cols} × ${info.rows} grid (tick ${t % (end + 1)} of ${end}).`;
  }
  // The player's frames are views of its buffer: the last one is copied
  // into an array kept from frame to frame.
  if (!state.lastFrame || state.lastFrame.length !== values.length || state.lastFrame.constructor !== values.constructor) {
    state.lastFrame = new values.constructor(values.length);
  }
  state.lastFrame.set(values);
  c.dataset.tick = String(t);
  c.dataset.x = String(x);
  c.dataset.y = String(y);
  c.dataset.values = Array.from(values).join(",");
  if ($("frame-note").textContent !== note) $("frame-note").textContent = note;
}

function cells(g, c, rows, cols, level, round) {
  const size = Math.min(c.width / cols, c.height / rows);
  for (let r = 0; r < rows; r++) {
    for (let col = 0; col < cols; col++) {
      const v = Math.min(1, Math.max(0, level(r * cols + col)));
      const shade = Math.round(255 * (1 - v));
      g.fillStyle = `rgb(${shade},${shade},${shade})`;
      if (round) {
        g.beginPath();
        g.arc((col + 0.5) * size, (r + 0.5) * size, size * 0.4, 0, 2 * Math.PI);
        g.fill();
        g.strokeStyle = "#888";
        g.stroke();
      } else {
        g.fillRect(col * size + 1, r * size + 1, size - 2, size - 2);
      }
    }
  }
}

function sameArray(a, b) {
  if (a.length !== b.length) return false;
  for (let i = 0; i < a.length; i++) if (a[i] !== b[i]) return false;
  return true;
}

init().catch((e) => say(`The studio could not start: ${e.message}`));
