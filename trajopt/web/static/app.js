// mpa explorer: the page of `mpa serve`. Plain JavaScript, SVG and canvas; talks to the JSON API of trajopt.web.
"use strict";

const SVGNS = "http://www.w3.org/2000/svg";
// Start markers are drawn above their point on the track and goal markers below it (screen pixels), joined to it
// by a tick, so that a start and a goal at the same place can both be grabbed.
const LIFT = { start: -14, goal: 14 };
const lift = (key) => LIFT[key.endsWith("start") ? "start" : "goal"];
const COLORS = { a: "#1f5fbf", b: "#d0601a" };
const DOMAIN_RGB = { "-1": [230, 150, 150], 0: [85, 85, 85], 1: [127, 167, 217], 2: [242, 166, 90], 3: [140, 201, 140] };

const state = {
  config: null,
  source: null, // {track, stick, loop} or {layout, name}
  geometry: null, // answer of /api/track
  markers: {}, // a_start, b_start, a_goal, b_goal: {edge, offset}
  plan: null,
  cspace: null,
  traj: null, // {summary, csv, rows, columns}
  animT: 0,
  playing: false,
  inflight: false,
  pending: false,
  latencies: [],
  urls: [],
};
window.mpa = state; // read by the browser tests

const $ = (id) => document.getElementById(id);
const isPaper = () => state.source && state.source.track !== undefined;

async function api(path, body) {
  const r = await fetch(path, { method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(body) });
  const data = await r.json();
  return { status: r.status, data };
}

// ---------------------------------------------------------------------------------------------- positions
function edgePoint(e, offset) {
  const pts = e.points;
  const n = pts.length - 1;
  const f = Math.min(Math.max(offset / e.length, 0), 1) * n;
  const i = Math.min(Math.floor(f), n - 1);
  const w = f - i;
  return [pts[i][1] * (1 - w) + pts[i + 1][1] * w, pts[i][2] * (1 - w) + pts[i + 1][2] * w];
}

function edgeIndex(name) {
  return state.geometry.edges.findIndex((e) => e.name === name);
}

// A paper track coordinate p as {edge, offset} (the stick includes P; the loop wraps at P).
function fromCoordinate(p) {
  const edges = state.geometry.edges;
  if (state.geometry.kind === "lollipop") {
    const stick = edges[edgeIndex("stick")];
    if (p <= stick.length) return { edge: edgeIndex("stick"), offset: p };
    return { edge: edgeIndex("loop"), offset: p - stick.length };
  }
  return { edge: 0, offset: p };
}

function toCoordinate(m) {
  const e = state.geometry.edges[m.edge];
  let off = m.offset;
  if (e.name === "loop" && off >= e.length - 1e-9) off = 0; // back at P
  return Math.round((e.p0 + off) * 1e5) / 1e5;
}

function positionText(m) {
  const e = state.geometry.edges[m.edge];
  return `${e.name}:${(Math.round(m.offset * 1e4) / 1e4).toFixed(4)}`;
}

function markerValue(m) {
  return isPaper() ? toCoordinate(m) : positionText(m);
}

// ---------------------------------------------------------------------------------------------- request bodies
function number(id) {
  const v = parseFloat($(id).value);
  return Number.isFinite(v) ? v : null;
}

function trackBody() {
  if (isPaper()) {
    const b = { track: state.source.track };
    if (state.source.track !== "circle") b.stick = number("stick");
    if (state.source.track !== "interval") b.loop = number("loop");
    return b;
  }
  return { layout: state.source.layout };
}

function queryBody() {
  const m = state.markers;
  const body = Object.assign(trackBody(), {
    start: [markerValue(m.a_start), markerValue(m.b_start)],
    goal: [markerValue(m.a_goal), markerValue(m.b_goal)],
    clearance: number("clearance"),
  });
  if ($("planner").value) body.planner = $("planner").value;
  body.objective = $("objective").value;
  const fp = $("footprint").value.trim();
  if (fp) body.footprint = fp;
  return body;
}
state.query = queryBody;

// ---------------------------------------------------------------------------------------------- the track view
let view = null; // {scale, ox, oy} metres -> pixels

function setupView() {
  const svg = $("track-view");
  svg.replaceChildren();
  const g = state.geometry;
  let xs = [], ys = [];
  for (const e of g.edges) for (const p of e.points) { xs.push(p[1]); ys.push(p[2]); }
  const minx = Math.min(...xs), maxx = Math.max(...xs), miny = Math.min(...ys), maxy = Math.max(...ys);
  const W = svg.width.baseVal.value, H = svg.height.baseVal.value, pad = 40;
  const scale = Math.min((W - 2 * pad) / Math.max(maxx - minx, 1e-9), (H - 2 * pad) / Math.max(maxy - miny, 1e-9));
  view = { scale, ox: pad + ((W - 2 * pad) - scale * (maxx - minx)) / 2 - scale * minx, oy: H - pad - ((H - 2 * pad) - scale * (maxy - miny)) / 2 + scale * miny };
  const layer = (id) => { const el = document.createElementNS(SVGNS, "g"); el.id = id; svg.appendChild(el); return el; };
  const edgesG = layer("edges");
  for (const e of g.edges) {
    const path = document.createElementNS(SVGNS, "polyline");
    path.setAttribute("points", e.points.map((p) => px([p[1], p[2]]).join(",")).join(" "));
    path.setAttribute("fill", "none");
    path.setAttribute("stroke", "#888");
    path.setAttribute("stroke-width", "6");
    path.setAttribute("stroke-linecap", "round");
    edgesG.appendChild(path);
    const mid = px(edgePoint(e, e.length / 2));
    const t = document.createElementNS(SVGNS, "text");
    t.setAttribute("x", mid[0] + 6); t.setAttribute("y", mid[1] - 8);
    t.setAttribute("font-size", "11"); t.setAttribute("fill", "#667");
    t.textContent = e.name;
    edgesG.appendChild(t);
  }
  for (const [name, xy] of Object.entries(g.vertices)) {
    const q = px(xy);
    const c = document.createElementNS(SVGNS, "circle");
    c.setAttribute("cx", q[0]); c.setAttribute("cy", q[1]); c.setAttribute("r", 4); c.setAttribute("fill", "#444");
    edgesG.appendChild(c);
    const t = document.createElementNS(SVGNS, "text");
    t.setAttribute("x", q[0] - 4); t.setAttribute("y", q[1] + 18); t.setAttribute("font-size", "12");
    t.textContent = name;
    edgesG.appendChild(t);
  }
  // scale bar: 10 cm, 1 m or 10 m
  const bar = [0.1, 0.5, 1, 5, 10, 50].find((b) => b * scale > 50) || 100;
  const sb = document.createElementNS(SVGNS, "g");
  sb.innerHTML = `<line x1="10" y1="${H - 12}" x2="${10 + bar * scale}" y2="${H - 12}" stroke="#000" stroke-width="2"/>` +
    `<text x="10" y="${H - 16}" font-size="11">${bar} m</text>`;
  svg.appendChild(sb);
  layer("bodies");
  layer("robots");
  const markersG = layer("markers");
  for (const key of ["a_goal", "b_goal", "a_start", "b_start"]) {
    const robot = key[0];
    const grp = document.createElementNS(SVGNS, "g");
    grp.id = `marker-${key}`;
    grp.classList.add("marker");
    const tick = document.createElementNS(SVGNS, "line");
    tick.setAttribute("x1", 0); tick.setAttribute("y1", -lift(key)); tick.setAttribute("x2", 0); tick.setAttribute("y2", 0);
    tick.setAttribute("stroke", COLORS[robot]); tick.setAttribute("stroke-width", 2);
    const dot = document.createElementNS(SVGNS, "circle");
    dot.setAttribute("cy", -lift(key)); dot.setAttribute("r", 2.5); dot.setAttribute("fill", COLORS[robot]);
    const c = document.createElementNS(SVGNS, "circle");
    c.setAttribute("r", key.endsWith("start") ? 9 : 11);
    c.setAttribute("fill", key.endsWith("start") ? COLORS[robot] : "white");
    c.setAttribute("fill-opacity", key.endsWith("start") ? 1 : 0.6);
    c.setAttribute("stroke", COLORS[robot]);
    c.setAttribute("stroke-width", key.endsWith("start") ? 1 : 3);
    const t = document.createElementNS(SVGNS, "text");
    t.setAttribute("font-size", "11"); t.setAttribute("text-anchor", "middle"); t.setAttribute("dy", "4");
    t.setAttribute("fill", key.endsWith("start") ? "white" : COLORS[robot]);
    t.setAttribute("pointer-events", "none");
    t.textContent = robot.toUpperCase();
    grp.append(tick, dot, c, t);
    markersG.appendChild(grp);
    grp.addEventListener("pointerdown", (ev) => startDrag(ev, key));
  }
  placeMarkers();
}

// ---------------------------------------------------------------------------------------------- bodies to scale
// The bodies of a footprint spec as mpa --footprint reads it ("0.3", "2.0x0.8", "0.3,2x0.8"), for drawing only (the
// server checks the spec): [A, B], each {radius} or {length, width} in metres; null when empty or malformed.
function parseFootprint(spec) {
  const text = (spec || "").trim().toLowerCase();
  if (!text) return null;
  const parts = text.split(",");
  if (parts.length > 2) return null;
  const bodies = parts.map((p) => {
    const v = p.split("x").map((x) => Number(x.trim()));
    if (v.length > 2 || v.some((x) => !Number.isFinite(x) || x <= 0) || p.trim() === "") return null;
    return v.length === 1 ? { radius: v[0] } : { length: v[0], width: v[1] };
  });
  if (bodies.some((b) => b === null)) return null;
  return [bodies[0], bodies[1] || bodies[0]];
}

// Point (metres) and heading (radians) of a position: the drawn polyline's piece there, as the planner's drawing.
function edgePose(e, offset) {
  const pts = e.points;
  const n = pts.length - 1;
  const f = Math.min(Math.max(offset / e.length, 0), 1) * n;
  const i = Math.min(Math.floor(f), n - 1);
  const heading = Math.atan2(pts[i + 1][2] - pts[i][2], pts[i + 1][1] - pts[i][1]);
  return { xy: edgePoint(e, offset), heading };
}

// An SVG element of one body centred at a position, to scale (view.scale pixels per metre).
function bodyElement(body, m, robot, filled, id) {
  const { xy, heading } = edgePose(state.geometry.edges[m.edge], m.offset);
  let el;
  if (body.radius !== undefined) {
    el = document.createElementNS(SVGNS, "circle");
    const q = px(xy);
    el.setAttribute("cx", q[0]); el.setAttribute("cy", q[1]); el.setAttribute("r", body.radius * view.scale);
  } else {
    const c = Math.cos(heading), s = Math.sin(heading), hx = body.length / 2, hy = body.width / 2;
    const corners = [[-hx, -hy], [hx, -hy], [hx, hy], [-hx, hy]].map(([u, v]) => px([xy[0] + c * u - s * v, xy[1] + s * u + c * v]));
    el = document.createElementNS(SVGNS, "polygon");
    el.setAttribute("points", corners.map((q) => q.join(",")).join(" "));
  }
  el.setAttribute("id", id);
  el.setAttribute("fill", filled ? COLORS[robot] : "none");
  el.setAttribute("fill-opacity", 0.3);
  el.setAttribute("stroke", COLORS[robot]);
  el.setAttribute("stroke-width", 1.5);
  if (!filled) el.setAttribute("stroke-dasharray", "4 3");
  el.setAttribute("pointer-events", "none");
  return el;
}

// The bodies at the four markers (start filled, goal dashed), or nothing without a footprint.
function drawBodies() {
  const g = $("bodies");
  if (!g) return;
  g.replaceChildren();
  const fp = parseFootprint($("footprint").value);
  if (!fp || !view) return;
  for (const key of ["a_start", "b_start", "a_goal", "b_goal"]) {
    const k = key[0] === "a" ? 0 : 1;
    g.appendChild(bodyElement(fp[k], state.markers[key], key[0], key.endsWith("start"), `body-${key}`));
  }
}
state.viewScale = () => view.scale; // pixels per metre (read by the browser tests)

function px(xy) {
  return [view.ox + view.scale * xy[0], view.oy - view.scale * xy[1]];
}

function markerXY(key) {
  const m = state.markers[key];
  return px(edgePoint(state.geometry.edges[m.edge], m.offset));
}

// Client (screen) coordinates of a marker, or of a paper track coordinate p (used by the browser tests).
state.markerScreen = (key) => {
  const r = $(`marker-${key}`).querySelector("circle:nth-of-type(2)").getBoundingClientRect();
  return [r.left + r.width / 2, r.top + r.height / 2];
};
// Where to drop marker `key` (default: a start) to put it at track coordinate p.
state.screenOf = (p, key = "a_start") => {
  const m = fromCoordinate(p);
  const q = px(edgePoint(state.geometry.edges[m.edge], m.offset));
  const r = $("track-view").getBoundingClientRect();
  return [r.left + q[0], r.top + q[1] + lift(key)];
};

function placeMarkers() {
  for (const key of Object.keys(state.markers)) {
    const q = markerXY(key);
    const el = $(`marker-${key}`);
    if (el) el.setAttribute("transform", `translate(${q[0]},${q[1] + lift(key)})`);
  }
  drawBodies();
}

function nearestPosition(x, y) {
  let best = null, bd = Infinity;
  state.geometry.edges.forEach((e, i) => {
    for (const p of e.points) {
      const q = px([p[1], p[2]]);
      const d = (q[0] - x) ** 2 + (q[1] - y) ** 2;
      if (d < bd) { bd = d; best = { edge: i, offset: p[0] }; }
    }
  });
  return best;
}

function startDrag(ev, key) {
  ev.preventDefault();
  const svg = $("track-view");
  const move = (e) => {
    const r = svg.getBoundingClientRect();
    state.markers[key] = nearestPosition(e.clientX - r.left, e.clientY - r.top - lift(key));
    placeMarkers();
    requestPlan(key.endsWith("goal"));
  };
  const up = () => { window.removeEventListener("pointermove", move); window.removeEventListener("pointerup", up); };
  window.addEventListener("pointermove", move);
  window.addEventListener("pointerup", up);
}

// ---------------------------------------------------------------------------------------------- the answer
let goalChanged = true;

function requestPlan(goalMoved) {
  if (goalMoved) goalChanged = true;
  if (state.inflight) { state.pending = true; return; }
  state.inflight = true;
  state.pending = false;
  const body = queryBody();
  const t0 = performance.now();
  api("/api/plan", body).then(({ status, data }) => {
    const ms = performance.now() - t0;
    state.latencies.push(ms);
    $("latency").textContent = `${ms.toFixed(1)} ms`;
    showAnswer(status, data, body);
  }).catch((err) => showAnswer(0, { error: String(err) }, body)).finally(() => {
    state.inflight = false;
    scheduleMakespan();
    if (state.pending) requestPlan(false);
    else if (goalChanged && isPaper()) { goalChanged = false; requestCspace(); }
    else drawCspace();
  });
}

function showAnswer(status, data, body) {
  state.plan = status === 200 ? data : null;
  state.planBody = body;
  state.planStatus = status;
  $("query").textContent = `start (${body.start.join(", ")}) → goal (${body.goal.join(", ")})`;
  $("reason").textContent = status === 200 ? "" : status === 422 ? `no motion: ${data.no_motion}` : `error: ${data.error}`;
  if (status !== 200) {
    for (const id of ["domain", "rule", "routes", "word", "makespan"]) $(id).textContent = "–";
    return;
  }
  const graph = data.planner === "graph";
  $("domain").textContent = graph ? "– (graph planner)" : String(data.domain);
  $("rule").textContent = graph ? "complete graph planner, objective " + data.objective : data.rule;
  $("word").textContent = data.word && data.word.length ? data.word.join(" ") : "(trivial)";
  if (graph) {
    $("routes").textContent = ["a", "b"].map((k) => `${k.toUpperCase()}: ${routeText(data.routes[k])}`).join("; ");
    $("makespan").textContent = `${data.makespan.toFixed(3)} s at the speed limits (no acceleration limits)`;
  } else {
    $("routes").textContent = `A travels ${data.travel[0].toFixed(3)} m, B ${data.travel[1].toFixed(3)} m`;
    $("makespan").textContent = "… (verifying the trajectory)";
  }
}

function routeText(pieces) {
  if (!pieces || !pieces.length) return "stays";
  return pieces.map((p) => `${p.edge}${p.dir > 0 ? "+" : "-"}`).join(" → ");
}

// The makespan of a paper plan is the verified trajectory's: asked for once the answer settles (not per frame).
let makespanTimer = null;
let makespanSeq = 0;

function scheduleMakespan() {
  clearTimeout(makespanTimer);
  if (state.pending || state.planStatus !== 200 || !state.plan || state.plan.planner === "graph") return;
  const seq = ++makespanSeq;
  makespanTimer = setTimeout(async () => {
    const body = Object.assign(queryBody(), { vmax: number("vmax"), amax: number("amax"), jmax: number("jmax"), rate: number("rate") });
    const { status, data } = await api("/api/trajectory", body);
    if (seq !== makespanSeq || state.inflight || state.pending) return; // the query moved on meanwhile
    $("makespan").textContent = status === 200 ? `${data.summary.makespan.toFixed(3)} s (verified trajectory)` : status === 422 ? `no motion: ${data.no_motion}` : `– (${data.error})`;
  }, 400);
}

// ---------------------------------------------------------------------------------------------- configuration space
function requestCspace() {
  const body = queryBody();
  api("/api/cspace", Object.assign({}, body, { cells: 120 })).then(({ status, data }) => {
    state.cspace = status === 200 ? data : null;
    drawCspace();
  });
}

function drawCspace() {
  const cv = $("cspace");
  const ctx = cv.getContext("2d");
  ctx.clearRect(0, 0, cv.width, cv.height);
  const c = state.cspace;
  if (!c || !isPaper()) return;
  const n = c.cells, L = c.extent[1], W = cv.width, H = cv.height;
  const img = ctx.createImageData(n, n);
  const mode = $("cspace-mode").value;
  for (let i = 0; i < n; i++) for (let j = 0; j < n; j++) {
    const d = c.domain[i][j];
    const rgb = mode === "free" ? (d === 0 ? DOMAIN_RGB[0] : [236, 236, 236]) : DOMAIN_RGB[d];
    const k = 4 * ((n - 1 - i) * n + j); // row i = B, drawn upwards
    img.data[k] = rgb[0]; img.data[k + 1] = rgb[1]; img.data[k + 2] = rgb[2]; img.data[k + 3] = 255;
  }
  const off = document.createElement("canvas");
  off.width = n; off.height = n;
  off.getContext("2d").putImageData(img, 0, 0);
  ctx.imageSmoothingEnabled = false;
  ctx.drawImage(off, 0, 0, W, H);
  const P = (s) => [(s[0] / L) * W, H - (s[1] / L) * H];
  const line = (pts, color, width) => {
    ctx.strokeStyle = color; ctx.lineWidth = width; ctx.beginPath();
    let prev = null;
    for (const s of pts) {
      const q = P(s);
      if (prev && (Math.abs(s[0] - prev[0]) > L / 2 || Math.abs(s[1] - prev[1]) > L / 2)) ctx.moveTo(q[0], q[1]);
      else if (prev) ctx.lineTo(q[0], q[1]);
      else ctx.moveTo(q[0], q[1]);
      prev = s;
    }
    ctx.stroke();
  };
  for (const s of c.skeleton) line(s.points, "#000", 1.5);
  if (state.plan && state.plan.path && typeof state.plan.path[0][0] === "number") line(state.plan.path, "#d22", 2.5);
  const body = state.planBody;
  if (body && typeof body.start[0] === "number") {
    const s = P(body.start), g = P(body.goal);
    ctx.fillStyle = "#222"; ctx.beginPath(); ctx.arc(s[0], s[1], 5, 0, 2 * Math.PI); ctx.fill();
    ctx.strokeStyle = "#222"; ctx.lineWidth = 2; ctx.beginPath(); ctx.arc(g[0], g[1], 7, 0, 2 * Math.PI); ctx.stroke();
  }
  if (state.traj && state.traj.coords) {
    const q = P(trajStateAt(state.animT).coords);
    ctx.fillStyle = "#fff"; ctx.strokeStyle = "#000"; ctx.beginPath(); ctx.arc(q[0], q[1], 4, 0, 2 * Math.PI); ctx.fill(); ctx.stroke();
  }
}

function cspaceDrag() {
  const cv = $("cspace");
  const set = (e) => {
    if (!state.cspace || !isPaper()) return;
    const r = cv.getBoundingClientRect(), L = state.cspace.extent[1];
    const a = Math.min(Math.max(((e.clientX - r.left) / r.width) * L, 0), L * 0.99999);
    const b = Math.min(Math.max((1 - (e.clientY - r.top) / r.height) * L, 0), L * 0.99999);
    state.markers.a_start = fromCoordinate(a);
    state.markers.b_start = fromCoordinate(b);
    placeMarkers();
    requestPlan(false);
  };
  cv.addEventListener("pointerdown", (e) => {
    set(e);
    const up = () => { window.removeEventListener("pointermove", set); window.removeEventListener("pointerup", up); };
    window.addEventListener("pointermove", set);
    window.addEventListener("pointerup", up);
  });
}

// ---------------------------------------------------------------------------------------------- trajectory
function parseCsv(text) {
  const lines = text.trim().split("\n");
  const columns = lines[0].split(",");
  const rows = lines.slice(1).map((l) => l.split(","));
  return { columns, rows };
}

async function requestTrajectory() {
  const body = Object.assign(queryBody(), { vmax: number("vmax"), amax: number("amax"), jmax: number("jmax"), rate: number("rate"), formats: ["csv", "ros2-yaml"] });
  $("traj-info").textContent = "computing…";
  const { status, data } = await api("/api/trajectory", body);
  if (status !== 200) {
    $("traj-info").textContent = status === 422 ? `no motion: ${data.no_motion}` : `error: ${data.error}`;
    return;
  }
  const { columns, rows } = parseCsv(data.csv);
  const col = (name) => columns.indexOf(name);
  const num = (name) => rows.map((r) => parseFloat(r[col(name)]));
  const t = num("time");
  const tr = {
    summary: data.summary, csv: data.csv, columns, t,
    s: [num("a_s"), num("b_s")], v: [num("a_v"), num("b_v")], a: [num("a_a"), num("b_a")], j: [num("a_j"), num("b_j")],
    pos: ["a", "b"].map((r) => rows.map((row) => ({ edge: edgeIndex(row[col(`${r}_edge`)]), offset: parseFloat(row[col(`${r}_offset`)]) }))),
  };
  tr.footprint = data.summary.footprint ? data.summary.footprint.spec : null; // the bodies of this motion
  if (col("a_track") >= 0) tr.coords = t.map((_, i) => [parseFloat(rows[i][col("a_track")]), parseFloat(rows[i][col("b_track")])]);
  state.traj = tr;
  setDownloads(data);
  const s = data.summary;
  $("traj-info").textContent = `makespan ${s.makespan.toFixed(3)} s, ${s.rows} rows at ${s.rate} Hz, min separation ${s.min_separation.toFixed(4)} m; ` +
    `A ${s.words.A}; B ${s.words.B}`;
  $("makespan").textContent = `${s.makespan.toFixed(3)} s (trajectory)`;
  $("time").max = String(t[t.length - 1]);
  $("time").step = String(1 / s.rate);
  $("time").disabled = false;
  $("play-btn").disabled = false;
  state.animT = 0;
  play();
}

function setDownloads(data) {
  for (const u of state.urls) URL.revokeObjectURL(u);
  const files = { "dl-csv": [data.csv, "text/csv"], "dl-summary": [JSON.stringify(data.summary, null, 2) + "\n", "application/json"], "dl-yaml": [data.ros2_yaml, "application/yaml"] };
  state.urls = [];
  for (const [id, [text, type]] of Object.entries(files)) {
    const url = URL.createObjectURL(new Blob([text], { type }));
    state.urls.push(url);
    $(id).href = url;
    $(id).classList.remove("disabled");
  }
}

function trajIndex(time) {
  const t = state.traj.t;
  let lo = 0, hi = t.length - 1;
  while (hi - lo > 1) { const mid = (lo + hi) >> 1; if (t[mid] <= time) lo = mid; else hi = mid; }
  return lo;
}

function trajStateAt(time) {
  const i = trajIndex(time);
  const tr = state.traj;
  return { i, pos: [tr.pos[0][i], tr.pos[1][i]], coords: tr.coords ? tr.coords[i] : null };
}

function drawRobots() {
  const g = $("robots");
  g.replaceChildren();
  if (!state.traj) return;
  const st = trajStateAt(state.animT);
  const fp = parseFootprint(state.traj.footprint);
  ["a", "b"].forEach((r, k) => {
    const m = st.pos[k];
    if (m.edge < 0) return;
    if (fp) g.appendChild(bodyElement(fp[k], m, r, true, `body-${r}`));
    const q = px(edgePoint(state.geometry.edges[m.edge], m.offset));
    const c = document.createElementNS(SVGNS, "rect");
    c.setAttribute("x", q[0] - 8); c.setAttribute("y", q[1] - 8); c.setAttribute("width", 16); c.setAttribute("height", 16);
    c.setAttribute("fill", COLORS[r]); c.setAttribute("stroke", "#000"); c.setAttribute("id", `robot-${r}`);
    g.appendChild(c);
  });
}

function drawPlots() {
  const cv = $("plots");
  const ctx = cv.getContext("2d");
  ctx.clearRect(0, 0, cv.width, cv.height);
  const tr = state.traj;
  if (!tr) return;
  const rows = [["s", "position σ (m)"], ["v", "speed (m/s)"], ["a", "acceleration (m/s²)"], ["j", "jerk (m/s³)"]];
  const W = cv.width, h = cv.height / 4, T = tr.t[tr.t.length - 1] || 1;
  rows.forEach(([key, label], k) => {
    const y0 = k * h;
    const all = tr[key][0].concat(tr[key][1]);
    let lo = Math.min(...all), hi = Math.max(...all);
    if (hi - lo < 1e-12) { lo -= 1; hi += 1; }
    const X = (t) => 50 + ((W - 60) * t) / T, Y = (v) => y0 + h - 14 - ((h - 24) * (v - lo)) / (hi - lo);
    ctx.strokeStyle = "#ccc"; ctx.strokeRect(50, y0 + 6, W - 60, h - 18);
    ctx.fillStyle = "#333"; ctx.font = "11px sans-serif"; ctx.fillText(label, 54, y0 + 18);
    const tick = (v) => (Math.abs(v) < 1e-9 ? "0" : v.toPrecision(3));
    ctx.fillText(tick(hi), 2, y0 + 14); ctx.fillText(tick(lo), 2, y0 + h - 12);
    [0, 1].forEach((r) => {
      ctx.strokeStyle = COLORS["ab"[r]]; ctx.lineWidth = 1.5; ctx.beginPath();
      tr.t.forEach((t, i) => (i ? ctx.lineTo(X(t), Y(tr[key][r][i])) : ctx.moveTo(X(t), Y(tr[key][r][i]))));
      ctx.stroke();
    });
    ctx.strokeStyle = "#000"; ctx.beginPath(); ctx.moveTo(X(state.animT), y0 + 6); ctx.lineTo(X(state.animT), y0 + h - 12); ctx.stroke();
  });
}

function setTime(t) {
  state.animT = t;
  $("time").value = String(t);
  $("time-label").textContent = `t = ${t.toFixed(2)} s`;
  drawRobots();
  drawPlots();
  drawCspace();
}

function play() {
  if (!state.traj) return;
  const T = state.traj.t[state.traj.t.length - 1];
  if (state.animT >= T) state.animT = 0;
  state.playing = true;
  $("play-btn").textContent = "pause";
  let last = performance.now();
  const step = (now) => {
    if (!state.playing) return;
    const t = Math.min(state.animT + (now - last) / 1000, T);
    last = now;
    setTime(t);
    if (t >= T) { state.playing = false; $("play-btn").textContent = "play"; return; }
    requestAnimationFrame(step);
  };
  requestAnimationFrame(step);
}

// ---------------------------------------------------------------------------------------------- tracks
async function loadSource(source) {
  const previous = state.source;
  state.source = source;
  state.traj = null;
  state.cspace = null;
  for (const el of document.querySelectorAll(".paper-only")) el.classList.toggle("hidden", !isPaper());
  if (isPaper()) {
    $("stick").disabled = source.track === "circle";
    $("loop").disabled = source.track === "interval";
  }
  const { status, data } = await api("/api/track", trackBody());
  if (status !== 200) {
    $("reason").textContent = `error: ${data.error}`;
    state.source = previous; // keep exploring the track shown
    for (const el of document.querySelectorAll(".paper-only")) el.classList.toggle("hidden", !isPaper());
    return;
  }
  state.geometry = data;
  defaultMarkers();
  setupView();
  drawPlots();
  goalChanged = true;
  requestPlan(true);
}

function defaultMarkers() {
  const g = state.geometry;
  if (isPaper()) {
    const L = g.total_length;
    const q = g.kind === "lollipop" ? [0.2 * L / 2, 0.5 * L / 2, 0.5 * L / 2, 0.2 * L / 2] : g.kind === "circle" ? [0.1 * L, 0.6 * L, 0.3 * L, 0.8 * L] : [0.2 * L, 0.6 * L, 0.4 * L, 0.8 * L];
    [state.markers.a_start, state.markers.b_start, state.markers.a_goal, state.markers.b_goal] = q.map(fromCoordinate);
  } else {
    const first = 0, last = g.edges.length - 1;
    const at = (i, f) => ({ edge: i, offset: g.edges[i].length * f });
    state.markers = { a_start: at(first, 0.2), b_start: at(last, 0.6), a_goal: at(last, 0.6), b_goal: at(first, 0.2) };
  }
}

function sourceFromSelect() {
  const v = $("track-select").value;
  if (v.startsWith("paper:")) return { track: v.slice(6) };
  if (v === "initial") return state.config.initial;
  return null;
}

async function init() {
  const r = await fetch("/api/config");
  state.config = await r.json();
  const d = state.config.defaults;
  $("clearance").value = d.clearance; $("vmax").value = d.vmax; $("amax").value = d.amax; $("jmax").value = d.jmax; $("rate").value = d.rate;
  const sel = $("track-select");
  const init0 = state.config.initial;
  const opts = [["paper:lollipop", "paper: lollipop"], ["paper:circle", "paper: circle"], ["paper:interval", "paper: interval"]];
  if (init0.layout) opts.unshift(["initial", `layout: ${init0.name || "given"}`]);
  for (const name of state.config.examples) opts.push([`example:${name}`, `example: ${name}`]);
  for (const [v, t] of opts) { const o = document.createElement("option"); o.value = v; o.textContent = t; sel.appendChild(o); }
  if (init0.layout) sel.value = "initial";
  else { sel.value = `paper:${init0.track}`; if (init0.stick) $("stick").value = init0.stick; if (init0.loop) $("loop").value = init0.loop; }
  sel.addEventListener("change", async () => {
    const v = sel.value;
    if (v.startsWith("example:")) {
      const lay = await (await fetch(`/api/examples/${encodeURIComponent(v.slice(8))}`)).json();
      loadSource({ layout: lay, name: v.slice(8) });
    } else loadSource(sourceFromSelect());
  });
  for (const id of ["stick", "loop"]) $(id).addEventListener("change", () => loadSource(state.source));
  for (const id of ["clearance", "planner", "objective", "footprint"]) $(id).addEventListener("change", () => requestPlan(true));
  $("footprint").addEventListener("input", drawBodies);
  $("cspace-mode").addEventListener("change", drawCspace);
  $("upload").addEventListener("change", () => {
    const f = $("upload").files[0];
    if (!f) return;
    f.text().then((text) => {
      let lay;
      try { lay = JSON.parse(text); } catch (e) { $("reason").textContent = `error: ${f.name} is not JSON (${e.message})`; return; }
      loadSource({ layout: lay, name: f.name });
    });
  });
  $("trajectory-btn").addEventListener("click", requestTrajectory);
  $("play-btn").addEventListener("click", () => { if (state.playing) { state.playing = false; $("play-btn").textContent = "play"; } else play(); });
  $("time").addEventListener("input", () => { state.playing = false; $("play-btn").textContent = "play"; setTime(parseFloat($("time").value)); });
  cspaceDrag();
  await loadSource(init0.layout ? init0 : { track: init0.track });
  state.ready = true;
}

init();
