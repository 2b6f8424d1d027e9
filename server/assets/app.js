// luxfarm dashboard: a hash-routed single page over the REST API (/api/v1). No framework.
// Every API error is shown in the banner (#error) with the server's JSON `error` and `detail`.
// Lists (jobs, workers, sequences) arrive pushed over Server-Sent Events (/api/v1/events);
// pages poll only while that stream is not open (a browser or proxy without SSE).

const API = "/api/v1";
const main = document.getElementById("main");
let timer = null; // the current page's poll timer
let page = 0; // bumps on every navigation so stale polls stop

// ---- API access -------------------------------------------------------------------------

function token() {
  return localStorage.getItem("luxfarm-token") || "";
}

function authHeaders(extra = {}) {
  const t = token();
  return t ? { ...extra, Authorization: `Bearer ${t}` } : extra;
}

class ApiError extends Error {}

async function failure(resp) {
  let text = `${resp.status} ${resp.statusText}`;
  try {
    const body = await resp.json();
    if (body && body.error) text = `${resp.status} ${body.error}: ${body.detail || ""}`;
  } catch (_) { /* not JSON: keep the status line */ }
  if (resp.status === 401) showTokenForm();
  return new ApiError(text);
}

async function api(path, opts = {}) {
  let resp;
  try {
    resp = await fetch(API + path, { ...opts, headers: authHeaders(opts.headers || {}) });
  } catch (e) {
    throw new ApiError(`network error: ${e.message}`);
  }
  if (!resp.ok) throw await failure(resp);
  return resp.json();
}

function showError(e) {
  document.getElementById("error-text").textContent = e instanceof Error ? e.message : String(e);
  document.getElementById("error").hidden = false;
}

function clearError() {
  document.getElementById("error").hidden = true;
}

function showTokenForm() {
  document.getElementById("token-form").hidden = false;
  document.getElementById("token-input").focus();
}

// ---- push updates -------------------------------------------------------------------------

// The latest `jobs`, `workers` and `sequences` events, and the current page's listener.
const live = { source: null, open: false, data: {}, listener: null };

function connectEvents() {
  if (!window.EventSource || live.source) return;
  const t = token();
  const src = new EventSource(`${API}/events${t ? `?token=${encodeURIComponent(t)}` : ""}`);
  live.source = src;
  const mark = () => { document.body.dataset.live = live.open ? "sse" : "poll"; };
  src.onopen = () => { live.open = true; mark(); };
  src.onerror = () => {
    // EventSource reconnects by itself; pages poll meanwhile.
    live.open = src.readyState === EventSource.OPEN;
    mark();
  };
  for (const kind of ["jobs", "workers", "sequences"]) {
    src.addEventListener(kind, (ev) => {
      live.open = true;
      mark();
      try { live.data[kind] = JSON.parse(ev.data); } catch (_) { return; }
      if (live.listener) live.listener(kind, live.data[kind]);
    });
  }
}

function reconnectEvents() {
  if (live.source) live.source.close();
  live.source = null;
  live.open = false;
  connectEvents();
}

// Calls `onData(kind, data)` on pushed updates; `poll` runs every 2.5 s only while the event
// stream is not open.
function follow(onData, poll) {
  live.listener = onData;
  for (const [k, v] of Object.entries(live.data)) onData(k, v);
  timer = setInterval(() => { if (!live.open) poll(); }, 2500);
  if (!live.open) poll();
}

// ---- formatting -------------------------------------------------------------------------

const el = (tag, attrs = {}, ...kids) => {
  const n = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (k === "class") n.className = v;
    else if (k.startsWith("on")) n.addEventListener(k.slice(2), v);
    else if (v !== undefined && v !== null) n.setAttribute(k, v);
  }
  for (const k of kids) if (k !== null && k !== undefined) n.append(k);
  return n;
};

function num(x, digits = 1) {
  if (x === null || x === undefined || !isFinite(x)) return "–";
  if (Math.abs(x) >= 1e6) return (x / 1e6).toFixed(digits) + "M";
  if (Math.abs(x) >= 1e4) return (x / 1e3).toFixed(digits) + "k";
  return x.toFixed(digits);
}

function dur(s) {
  if (s === null || s === undefined || !isFinite(s)) return "–";
  s = Math.round(s);
  const h = Math.floor(s / 3600), m = Math.floor((s % 3600) / 60), r = s % 60;
  return h ? `${h}h${String(m).padStart(2, "0")}m` : m ? `${m}m${String(r).padStart(2, "0")}s` : `${r}s`;
}

function bar(frac) {
  const f = Math.max(0, Math.min(1, frac || 0));
  return el("span", { class: "bar" }, el("i", { style: `width:${(f * 100).toFixed(1)}%` }));
}

function progress(value, goal, fmt) {
  if (goal === null || goal === undefined) return el("span", { class: "mute" }, fmt(value));
  return el("span", {}, bar(value / goal), `${fmt(value)} / ${fmt(goal)}`);
}

// Convergence: the failing-pixel fraction falls towards the threshold.
function convergence(j) {
  if (j.haltthreshold === null || j.haltthreshold === undefined) return el("span", { class: "mute" }, "–");
  if (j.convergence === null || j.convergence === undefined) return `– / ${j.haltthreshold}`;
  const frac = j.convergence <= j.haltthreshold ? 1 : j.haltthreshold / j.convergence;
  return el("span", {}, bar(frac), `${j.convergence.toFixed(4)} / ${j.haltthreshold}`);
}

const stateBadge = (s) => el("span", { class: `state state-${s}` }, s);

// ---- job list -----------------------------------------------------------------------------

const COLUMNS = [
  ["name", "job", (j) => el("a", { href: `#/job/${j.id}` }, j.name)],
  ["frame", "frame", (j) => (j.frame === null || j.frame === undefined ? el("span", { class: "mute" }, "–") : String(j.frame))],
  ["state", "state", (j) => stateBadge(j.state)],
  ["spp", "spp", (j) => progress(j.spp, j.haltspp, (x) => num(x, 1))],
  ["elapsed", "time", (j) => progress(j.elapsed, j.halttime, dur)],
  ["convergence", "convergence", convergence],
  ["samples_per_sec", "samples/s", (j) => num(j.samples_per_sec)],
  ["eta", "ETA", (j) => dur(j.eta)],
  ["active_leases", "workers", (j) => String(j.active_leases)],
  ["priority", "prio", (j) => String(j.priority)],
];
const listState = { sort: null, asc: true, filter: "" };

async function jobsPage(my) {
  const filter = el("select", { id: "state-filter", onchange: (e) => { listState.filter = e.target.value; refresh(); } },
    ...["", "queued", "rendering", "done", "cancelled", "failed"].map((s) =>
      el("option", { value: s }, s || "all states")));
  filter.value = listState.filter;
  const table = el("table", { id: "jobs" });
  const strips = el("div", { id: "sequences" });
  main.replaceChildren(strips, el("div", { class: "toolbar" }, el("h2", {}, "Jobs"), el("label", {}, "state ", filter)),
    el("div", { class: "scroll" }, table));
  let jobs = [];
  const draw = () => {
    let rows = jobs.filter((j) => !listState.filter || j.state === listState.filter);
    if (listState.sort) {
      const k = listState.sort, s = listState.asc ? 1 : -1;
      rows = [...rows].sort((a, b) => (a[k] ?? -Infinity) > (b[k] ?? -Infinity) ? s : (a[k] ?? -Infinity) < (b[k] ?? -Infinity) ? -s : 0);
    }
    const head = el("tr", {}, ...COLUMNS.map(([k, label]) => el("th", {
      class: `sortable ${listState.sort === k ? "sorted" : ""} ${listState.asc ? "asc" : ""}`,
      onclick: () => { listState.asc = listState.sort === k ? !listState.asc : true; listState.sort = k; draw(); },
    }, label)));
    const body = rows.map((j) => el("tr", { "data-id": j.id, "data-state": j.state },
      ...COLUMNS.map(([, , f]) => el("td", {}, f(j)))));
    if (!rows.length) body.push(el("tr", {}, el("td", { colspan: COLUMNS.length, class: "mute" }, "no jobs")));
    table.replaceChildren(el("thead", {}, head), el("tbody", {}, ...body));
  };
  let sequences = [];
  const drawStrips = () => {
    strips.replaceChildren(...sequences.map(sequenceStrip));
  };
  const refresh = async () => {
    try {
      [jobs, sequences] = await Promise.all([api("/jobs"), api("/sequences")]);
      if (my === page) { draw(); drawStrips(); }
    } catch (e) { showError(e); }
  };
  follow((kind, data) => {
    if (my !== page) return;
    if (kind === "jobs") { jobs = data; draw(); }
    if (kind === "sequences") { sequences = data; drawStrips(); }
  }, refresh);
}

// A sequence as a strip of frames: each cell shows the frame's state, number, spp and a
// thumbnail once it has samples.
function sequenceStrip(q) {
  const t = token();
  const auth = t ? `&token=${encodeURIComponent(t)}` : "";
  const cells = q.frames.map((f) => {
    const kids = [el("span", { class: "frame-no" }, String(f.number).padStart(4, "0"))];
    // preview.png answers with an ETag and no-cache: the browser revalidates each redraw.
    if (f.spp > 0) kids.unshift(el("img", { src: `${API}/jobs/${f.job_id}/preview.png?max_size=64${auth}`, alt: f.output }));
    kids.push(el("span", { class: "frame-spp" }, f.haltspp ? `${num(f.spp, 0)}/${num(f.haltspp, 0)}` : num(f.spp, 0)));
    return el("a", { class: `frame state-${f.state}${f.halting ? " halting" : ""}`, href: `#/job/${f.job_id}`,
      "data-number": String(f.number), "data-state": f.state, title: `${f.output}: ${f.state}${f.reason ? ` (${f.reason})` : ""}` }, ...kids);
  });
  return el("section", { class: "sequence", "data-id": q.id, "data-state": q.state },
    el("h3", {}, `${q.name} `, stateBadge(q.state), el("span", { class: "mute" }, ` ${q.frames_done}/${q.frames.length} frames · ${q.policy}`)),
    el("div", { class: "strip" }, ...cells));
}

// ---- tonemapping panel --------------------------------------------------------------------

// The query parameters of preview.png / image.png per kernel (LuxRender's film parameter names),
// with the slider ranges offered here; the server validates the values.
const TM_PARAMS = {
  reinhard_prescale: { label: "prescale", min: 0.01, max: 10, log: true },
  reinhard_postscale: { label: "postscale", min: 0.01, max: 10, log: true },
  reinhard_burn: { label: "burn", min: 0.1, max: 20, log: true },
  linear_sensitivity: { label: "sensitivity (ISO)", min: 3, max: 12800, log: true },
  linear_exposure: { label: "exposure (s)", min: 1e-4, max: 100, log: true },
  linear_fstop: { label: "f-stop", min: 0.5, max: 64, log: true },
  linear_gamma: { label: "linear gamma", min: 0.1, max: 5, log: false },
  contrast_ywa: { label: "Ywa", min: 0.01, max: 1000, log: true },
  gamma: { label: "output gamma", min: 0.5, max: 4, log: false },
};
const TM_KERNELS = {
  reinhard: ["reinhard_prescale", "reinhard_postscale", "reinhard_burn"],
  linear: ["linear_sensitivity", "linear_exposure", "linear_fstop", "linear_gamma"],
  contrast: ["contrast_ywa"],
  maxwhite: [],
  autolinear: [],
  // offered only when the scene's Film uses it: its range (false_min, false_max) is the scene's
  falsecolors: [],
};
const SLIDER_STEPS = 1000;

function toSlider(p, v) {
  const f = p.log ? Math.log(v / p.min) / Math.log(p.max / p.min) : (v - p.min) / (p.max - p.min);
  return String(Math.round(Math.max(0, Math.min(1, f)) * SLIDER_STEPS));
}

function fromSlider(p, s) {
  const f = Number(s) / SLIDER_STEPS;
  const v = p.log ? p.min * Math.pow(p.max / p.min, f) : p.min + f * (p.max - p.min);
  return Number(v.toPrecision(3));
}

// The "Tonemapping" panel: kernel, its parameters and the output gamma. `onChange(query)` gets
// the query string for the image URLs ("" for the scene's own tonemapping), debounced.
function tonemapPanel(settings, onChange) {
  const { scene, defaults } = settings;
  const state = { kernel: scene.kernel, values: {} };
  const kernel = el("select", { id: "tm-kernel" },
    ...Object.keys(TM_KERNELS).filter((k) => k !== "falsecolors" || k === scene.kernel)
      .map((k) => el("option", { value: k }, k === scene.kernel ? `${k} (scene)` : k)));
  const params = el("div", { id: "tm-params", class: "tm-params" });
  const reset = el("button", { id: "tm-reset", type: "button", class: "secondary" }, "Scene default");
  const panel = el("section", { id: "tonemap", class: "panel" },
    el("div", { class: "panel-head" }, el("h3", {}, "Tonemapping"), reset),
    el("div", { class: "tm-row tm-kernel" }, el("label", { for: "tm-kernel" }, "kernel"), kernel), params);
  let debounce = null;
  const query = () => {
    const names = [...TM_KERNELS[state.kernel], "gamma"];
    const same = state.kernel === scene.kernel && names.every((n) => state.values[n] === scene[n]);
    if (same) return "";
    // the scene's kernel goes without `kernel=` (the server keeps it; falsecolors only so)
    const q = new URLSearchParams(state.kernel === scene.kernel ? {} : { kernel: state.kernel });
    for (const n of names) q.set(n, String(state.values[n]));
    return `?${q}`;
  };
  const changed = () => {
    clearTimeout(debounce);
    debounce = setTimeout(() => onChange(query()), 300);
  };
  const draw = () => {
    kernel.value = state.kernel;
    params.replaceChildren(...[...TM_KERNELS[state.kernel], "gamma"].map((n) => {
      const p = TM_PARAMS[n];
      const number = el("input", { id: `tm-${n}`, type: "number", step: "any", min: "0",
        value: String(state.values[n]), "aria-label": p.label });
      const slider = el("input", { id: `tm-range-${n}`, type: "range", min: "0", max: String(SLIDER_STEPS),
        value: toSlider(p, state.values[n]), "aria-label": `${p.label} slider` });
      slider.addEventListener("input", () => {
        state.values[n] = fromSlider(p, slider.value);
        number.value = String(state.values[n]);
        changed();
      });
      number.addEventListener("input", () => {
        if (number.value === "" || !isFinite(Number(number.value))) return;
        state.values[n] = Number(number.value);
        slider.value = toSlider(p, state.values[n]);
        changed();
      });
      return el("div", { class: "tm-row" }, el("label", { for: `tm-${n}` }, p.label), slider, number);
    }));
  };
  // Values of a kernel's parameters: the scene's for the scene's kernel, else LuxRender's.
  const start = (k) => {
    state.kernel = k;
    for (const n of TM_KERNELS[k]) state.values[n] = (k === scene.kernel ? scene : defaults)[n];
  };
  kernel.addEventListener("change", () => { start(kernel.value); draw(); changed(); });
  reset.addEventListener("click", () => { start(scene.kernel); state.values.gamma = scene.gamma; draw(); changed(); });
  start(scene.kernel);
  state.values.gamma = scene.gamma;
  draw();
  return panel;
}

// ---- job page -----------------------------------------------------------------------------

async function jobPage(my, id) {
  const img = el("img", { id: "preview", alt: "preview" });
  const info = el("dl", { id: "job-info" });
  const chart = el("canvas", { id: "chart", width: 600, height: 160 });
  const workers = el("table", { id: "job-workers" });
  const cancel = el("button", { id: "cancel", class: "danger", type: "button" }, "Cancel");
  const title = el("h2", {}, `Job ${id}`);
  const tmSlot = el("div", { id: "tonemap-slot", class: "job-tonemap" });
  const dl = (f, label) => el("a", { href: `${API}/jobs/${id}/${f}`, download: f, onclick: download, id: `dl-${f.replace(".", "-")}` }, label);
  const pngLink = dl("image.png", "PNG");
  const trade = tradePanel(id, my);
  main.replaceChildren(title, el("div", { class: "job" },
    el("div", { class: "preview" }, el("div", { class: "stack" }, img, trade.overlay)), tmSlot,
    el("div", { class: "job-side" }, info, el("p", { class: "actions" }, cancel,
      el("span", { class: "downloads" }, pngLink, dl("image.exr", "EXR"), dl("film.flm", "FLM")))),
    el("div", { class: "job-progress" }, trade.panel, el("h3", {}, "Progress"), chart, el("h3", {}, "Workers"),
      el("div", { class: "scroll" }, workers))));
  const history = [];
  let etag = null, url = null, job = null, query = "", fetchSeq = 0;
  let farmWorkers = new Map(); // worker id -> the master's view (samples/s, last heartbeat)
  cancel.addEventListener("click", async () => {
    if (!confirm(`Cancel job ${job ? job.name : id}?`)) return;
    try {
      job = await api(`/jobs/${id}`, { method: "DELETE" });
      drawInfo();
    } catch (e) { showError(e); }
  });
  const drawInfo = () => {
    title.textContent = `${job.name} `;
    title.append(stateBadge(job.state));
    const rows = [["state", job.state + (job.reason ? ` (${job.reason})` : "")],
      ["resolution", `${job.width}×${job.height}`], ["spp", progress(job.spp, job.haltspp, (x) => num(x, 1))],
      ["time", progress(job.elapsed, job.halttime, dur)], ["convergence", convergence(job)],
      ["samples/s", num(job.samples_per_sec)], ["ETA", dur(job.eta)], ["priority", String(job.priority)],
      ["seed", String(job.seed)]];
    info.replaceChildren(...rows.flatMap(([k, v]) => [el("dt", {}, k), el("dd", { "data-key": k }, v)]));
    info.dataset.state = job.state;
    cancel.disabled = ["done", "cancelled", "failed"].includes(job.state);
    workers.replaceChildren(el("tr", {}, el("th", {}, "worker"), el("th", {}, "samples"),
      el("th", {}, "samples/s"), el("th", {}, "last seen"), el("th", {}, "active")),
      ...job.workers.map((w) => {
        const live = farmWorkers.get(w.worker_id);
        const here = w.active && live && live.lease_id === w.lease_id;
        return el("tr", { "data-worker": w.worker_id }, el("td", {}, live ? live.name : w.worker_id),
          el("td", {}, num(w.samples)), el("td", {}, here ? num(live.samples_per_sec) : "–"),
          el("td", {}, live ? `${dur(live.last_seen_secs)} ago` : "–"), el("td", {}, w.active ? "yes" : "no"));
      }));
  };
  // Fetches the preview with the current tonemapping query; a response to an older query is
  // dropped so the image always shows the latest setting.
  const pollPreview = async () => {
    const seq = ++fetchSeq, q = query;
    const headers = authHeaders(etag ? { "If-None-Match": etag } : {});
    let resp;
    try { resp = await fetch(`${API}/jobs/${id}/preview.png${q}`, { headers }); } catch (e) { throw new ApiError(`network error: ${e.message}`); }
    if (seq !== fetchSeq || my !== page) return;
    if (resp.status === 304) return;
    if (resp.status === 503 || resp.status === 404 && job && job.samples === 0) return; // no film yet
    if (!resp.ok) throw await failure(resp);
    const blob = await resp.blob();
    if (seq !== fetchSeq) return;
    etag = resp.headers.get("ETag");
    if (url) URL.revokeObjectURL(url);
    url = URL.createObjectURL(blob);
    img.src = url;
    img.dataset.etag = etag || "";
    img.dataset.query = q;
    img.dataset.loads = String(Number(img.dataset.loads || 0) + 1);
  };
  const retone = async (q) => {
    if (my !== page || q === query) return;
    query = q;
    etag = null;
    pngLink.href = `${API}/jobs/${id}/image.png${q}`;
    try {
      if (job && job.samples > 0) await pollPreview();
      clearError();
    } catch (e) { showError(e); }
  };
  const refresh = async () => {
    try {
      const [j, ws] = await Promise.all([api(`/jobs/${id}`), api("/workers")]);
      job = j;
      farmWorkers = new Map(ws.map((w) => [w.id, w]));
      if (my !== page) return;
      history.push([job.elapsed, job.spp, job.samples_per_sec]);
      if (history.length > 600) history.shift();
      drawInfo();
      drawChart(chart, history);
      await trade.update(job);
      if (job.samples > 0) await pollPreview();
    } catch (e) { showError(e); }
  };
  api(`/jobs/${id}/tonemap`).then((tm) => {
    if (my === page) tmSlot.replaceChildren(tonemapPanel(tm, retone));
  }).catch(showError);
  await refresh();
  timer = setInterval(refresh, 2500);
}

// ---- speed / accuracy trade ----------------------------------------------------------------

// The "Error over time" panel of a job: the film's relative error and the convergence test's
// failing fraction against time (log–log inline SVG), with the projections to the job's
// haltthreshold (failing fraction) and to the relative error typed here, and the toggle of
// the convergence-map overlay on the preview. `update(job)` redraws from the job's view, or
// from /trade (?target= while a target is typed; an ended job's saved history).
function tradePanel(id, my) {
  const svg = document.createElementNS(SVG_NS, "svg");
  svg.setAttribute("id", "trade-chart");
  svg.setAttribute("viewBox", `0 0 ${TRADE_W} ${TRADE_H}`);
  svg.setAttribute("role", "img");
  svg.setAttribute("aria-label", "relative error and failing fraction against time, log–log");
  const text = el("div", { id: "trade-projection" }, "not enough data");
  const target = el("input", { id: "trade-target", type: "number", min: "0", max: "10", step: "any",
    placeholder: "e.g. 0.05", "aria-label": "target relative error" });
  const toggle = el("input", { id: "overlay-toggle", type: "checkbox" });
  const mapStatus = el("span", { id: "overlay-status", class: "mute" });
  const overlay = el("img", { id: "overlay", alt: "convergence map", hidden: "" });
  const panel = el("section", { id: "trade", class: "panel" },
    el("div", { class: "panel-head" }, el("h3", {}, "Error over time"),
      el("label", { class: "trade-target-label" }, "target relative error ", target)),
    svg, el("p", { class: "trade-legend mute" }, el("i", { class: "key key-rel" }), "relative error ",
      el("i", { class: "key key-fail" }), "failing fraction ", el("i", { class: "key key-proj" }), "projection"),
    text,
    el("label", { class: "overlay-toggle" }, toggle, " convergence map on the preview ", mapStatus));
  let job = null, url = null;
  const targetValue = () => {
    const v = Number(target.value);
    return target.value !== "" && isFinite(v) && v > 0 && v <= 10 ? v : null;
  };
  const pollOverlay = async () => {
    if (!toggle.checked) return;
    let resp;
    try { resp = await fetch(`${API}/jobs/${id}/convergence.png`, { headers: authHeaders() }); } catch (e) { throw new ApiError(`network error: ${e.message}`); }
    if (my !== page || !toggle.checked) return;
    if (resp.status === 503 || resp.status === 404) {
      const body = await resp.json().catch(() => ({}));
      mapStatus.textContent = `(${body.detail || "no convergence map"})`;
      return;
    }
    if (!resp.ok) throw await failure(resp);
    const blob = await resp.blob();
    if (url) URL.revokeObjectURL(url);
    url = URL.createObjectURL(blob);
    overlay.src = url;
    overlay.dataset.loads = String(Number(overlay.dataset.loads || 0) + 1);
    mapStatus.textContent = "";
  };
  const update = async (j) => {
    if (j) job = j;
    if (!job) return;
    let t = job.trade;
    const want = targetValue();
    // An ended job's view has no history: /trade reads the one saved with its checkpoint.
    const ended = ["done", "cancelled", "failed"].includes(job.state);
    if (want !== null || ended) t = await api(`/jobs/${id}/trade${want !== null ? `?target=${want}` : ""}`);
    if (my !== page) return;
    drawTrade(svg, t);
    const lines = [];
    if (t.target_projection) lines.push(el("p", { id: "trade-target-text", "data-status": t.target_projection.status }, projectionText(t, t.target_projection)));
    else lines.push(el("p", { class: "mute" }, "type a target relative error to project it"));
    if (t.threshold_projection) lines.push(el("p", { id: "trade-threshold-text", "data-status": t.threshold_projection.status }, projectionText(t, t.threshold_projection)));
    text.replaceChildren(...lines);
    const primary = t.target_projection || t.threshold_projection;
    text.dataset.status = primary ? primary.status : "no_target";
    await pollOverlay();
  };
  let debounce = null;
  target.addEventListener("input", () => {
    clearTimeout(debounce);
    debounce = setTimeout(() => update().catch(showError), 300);
  });
  toggle.addEventListener("change", () => {
    overlay.hidden = !toggle.checked;
    if (!toggle.checked) mapStatus.textContent = "";
    pollOverlay().catch(showError);
  });
  return { panel, overlay, update };
}

const SVG_NS = "http://www.w3.org/2000/svg";
const TRADE_W = 600, TRADE_H = 210, TRADE_PAD = 44;
// The value of a history point a metric reads.
const METRIC = { relative_error: (q) => q.estimate, failing_fraction: (q) => q.failing };

function projectionText(t, p) {
  const what = p.metric === "failing_fraction" ? `haltthreshold ${p.target} (failing fraction)` : `relative error ${p.target}`;
  switch (p.status) {
    case "projected":
      return `${what}: projected at ${dur(p.at_secs)}, in ${dur(p.remaining_secs)}` +
        ` (fit ∝ t^${p.fit.exponent.toFixed(2)} on ${p.fit.points} points)`;
    case "reached": return `${what}: reached`;
    case "no_trend": return `${what}: no downward trend yet`;
    case "noisy": return `${what}: too noisy to project`;
    case "unreachable": return `${what}: out of reach at the current rate`;
    default: return `${what}: not enough data${t.history.length ? "" : " (no convergence test yet)"}`;
  }
}

function svgEl(tag, attrs) {
  const n = document.createElementNS(SVG_NS, tag);
  for (const [k, v] of Object.entries(attrs)) n.setAttribute(k, String(v));
  return n;
}

// Log–log axes over both series (and the projections' ends), decade ticks, each series as a
// line, targets as dashed horizontal lines and projections as dashed segments.
function drawTrade(svg, t) {
  const series = Object.entries(METRIC).map(([metric, f]) => [metric,
    t.history.filter((q) => q.secs > 0 && f(q) > 0).map((q) => [q.secs, f(q)])]);
  const projections = [t.target_projection, t.threshold_projection].filter((p) => p && p.target > 0);
  const all = series.flatMap(([, pts]) => pts);
  if (!all.length) {
    const msg = svgEl("text", { x: TRADE_PAD, y: TRADE_H / 2, class: "trade-empty" });
    msg.textContent = "no error estimate yet (it starts with the second convergence test)";
    svg.replaceChildren(msg);
    svg.dataset.points = "0";
    return;
  }
  const xs = all.map((p) => p[0]), ys = all.map((p) => p[1]);
  for (const p of projections) {
    ys.push(p.target);
    if (p.status === "projected") xs.push(p.at_secs);
  }
  let x0 = Math.log10(Math.min(...xs)), x1 = Math.log10(Math.max(...xs));
  let y0 = Math.log10(Math.min(...ys)), y1 = Math.log10(Math.max(...ys));
  if (x1 - x0 < 0.3) { x0 -= 0.15; x1 += 0.15; }
  if (y1 - y0 < 0.3) { y0 -= 0.15; y1 += 0.15; }
  const left = TRADE_PAD, right = TRADE_W - 12, top = 14, bottom = TRADE_H - 30;
  const X = (secs) => left + (Math.log10(secs) - x0) / (x1 - x0) * (right - left);
  const Y = (v) => bottom - (Math.log10(v) - y0) / (y1 - y0) * (bottom - top);
  const kids = [svgEl("rect", { x: left, y: top, width: right - left, height: bottom - top, class: "trade-frame" })];
  const tick = (x, y, label, anchor) => {
    const l = svgEl("text", { x, y, class: "trade-tick", "text-anchor": anchor });
    l.textContent = label;
    kids.push(l);
  };
  for (let d = Math.ceil(x0); d <= Math.floor(x1); d++) {
    kids.push(svgEl("line", { x1: X(10 ** d), x2: X(10 ** d), y1: top, y2: bottom, class: "trade-grid" }));
    tick(X(10 ** d), bottom + 14, dur(10 ** d), "middle");
  }
  for (let d = Math.ceil(y0); d <= Math.floor(y1); d++) {
    kids.push(svgEl("line", { x1: left, x2: right, y1: Y(10 ** d), y2: Y(10 ** d), class: "trade-grid" }));
    tick(left - 4, Y(10 ** d) + 4, `1e${d}`, "end");
  }
  for (const [metric, pts] of series) {
    if (!pts.length) continue;
    kids.push(svgEl("polyline", { class: `trade-line trade-${metric}`, "data-metric": metric,
      points: pts.map(([s, v]) => `${X(s).toFixed(1)},${Y(v).toFixed(1)}`).join(" ") }));
    const [ls, lv] = pts[pts.length - 1];
    kids.push(svgEl("circle", { cx: X(ls), cy: Y(lv), r: 3, class: `trade-last trade-${metric}` }));
  }
  for (const p of projections) {
    kids.push(svgEl("line", { x1: left, x2: right, y1: Y(p.target), y2: Y(p.target),
      class: `trade-target trade-${p.metric}`, "data-metric": p.metric }));
    const pts = series.find(([m]) => m === p.metric)[1];
    if (p.status !== "projected" || !pts.length) continue;
    const ls = pts[pts.length - 1][0], f = p.fit;
    kids.push(svgEl("line", { class: "trade-projection", "data-metric": p.metric,
      x1: X(ls), y1: Y(f.coefficient * ls ** f.exponent), x2: X(p.at_secs), y2: Y(p.target) }));
  }
  tick(right, TRADE_H - 4, "time since the first lease (log)", "end");
  svg.replaceChildren(...kids);
  svg.dataset.points = String(t.history.length);
}

async function download(ev) {
  if (!token()) return; // plain link works without a token
  ev.preventDefault();
  const a = ev.currentTarget;
  try {
    const resp = await fetch(a.href, { headers: authHeaders() });
    if (!resp.ok) throw await failure(resp);
    const blob = await resp.blob();
    const tmp = el("a", { href: URL.createObjectURL(blob), download: a.getAttribute("download") });
    tmp.click();
    setTimeout(() => URL.revokeObjectURL(tmp.href), 10000);
  } catch (e) { showError(e); }
}

// spp (orange, left scale) and samples/s (blue, right scale) against elapsed time.
function drawChart(canvas, history) {
  const w = canvas.width, h = canvas.height, pad = 28;
  const g = canvas.getContext("2d");
  g.clearRect(0, 0, w, h);
  g.font = "11px system-ui";
  if (history.length < 2) { g.fillStyle = "#9aa0aa"; g.fillText("collecting…", pad, h / 2); return; }
  const t0 = history[0][0], t1 = Math.max(history[history.length - 1][0], t0 + 1e-6);
  const line = (idx, color, yLabelX) => {
    const max = Math.max(...history.map((p) => p[idx]), 1e-9);
    g.strokeStyle = color; g.lineWidth = 2; g.beginPath();
    history.forEach((p, i) => {
      const x = pad + (p[0] - t0) / (t1 - t0) * (w - 2 * pad), y = h - pad - p[idx] / max * (h - 2 * pad);
      i ? g.lineTo(x, y) : g.moveTo(x, y);
    });
    g.stroke(); g.fillStyle = color; g.fillText(num(max), yLabelX, pad - 8);
  };
  line(1, "#f2a33a", 2);
  line(2, "#4c8df6", w - pad - 10);
  g.fillStyle = "#9aa0aa";
  g.fillText("spp", pad, h - 8); g.fillText("samples/s", w / 2, h - 8); g.fillText(dur(t1), w - pad - 20, h - 8);
}

// ---- submit -------------------------------------------------------------------------------

function submitPage() {
  const field = (name, label, attrs = {}) => [el("label", { for: `f-${name}` }, label),
    el("input", { id: `f-${name}`, name, ...attrs })];
  const status = el("p", { id: "submit-status", class: "mute" });
  const form = el("form", { id: "submit-form", class: "grid" },
    ...field("file", "scene (.lxs, .igs, .lws, .mi, .zip, .tar)",
      { type: "file", required: "", accept: ".lxs,.igs,.lws,.mi,.zip,.tar" }),
    ...field("name", "name", { type: "text" }),
    ...field("haltspp", "haltspp", { type: "number", min: "0", step: "any" }),
    ...field("halttime", "halttime (s)", { type: "number", min: "0", step: "any" }),
    ...field("haltthreshold", "haltthreshold", { type: "number", min: "0", step: "any" }),
    ...field("priority", "priority", { type: "number", step: "1" }),
    el("span"), el("button", { type: "submit" }, "Submit"));
  form.addEventListener("submit", async (ev) => {
    ev.preventDefault();
    const data = new FormData(form);
    for (const [k, v] of [...data.entries()]) if (v === "") data.delete(k);
    status.textContent = "uploading…";
    try {
      const job = await api("/jobs", { method: "POST", body: data });
      clearError();
      location.hash = `#/job/${job.id}`;
    } catch (e) { status.textContent = ""; showError(e); }
  });
  main.replaceChildren(el("h2", {}, "Submit a scene"), form, status);
}

// ---- workers ------------------------------------------------------------------------------

async function workersPage(my) {
  const table = el("table", { id: "workers" });
  main.replaceChildren(el("h2", {}, "Workers"), el("div", { class: "scroll" }, table));
  const draw = (ws) => {
    const rows = ws.map((w) =>
      el("tr", { "data-id": w.id, "data-quarantined": w.quarantined ? "yes" : "no" }, el("td", {}, w.name),
        el("td", {}, stateBadge(w.quarantined ? "quarantined" : w.state)),
        el("td", {}, String(w.threads)), el("td", { "data-key": "samples_per_sec" }, num(w.samples_per_sec)),
        el("td", {}, w.job_id ? el("a", { href: `#/job/${w.job_id}` }, w.job_id) : "–"),
        el("td", {}, `${dur(w.last_seen_secs)} ago`), el("td", { class: "hide-narrow" }, num(w.samples)),
        el("td", { "data-key": "tags" }, (w.tags || []).join(", ") || "–"),
        el("td", { "data-key": "blocked", title: w.quarantined || "" }, (w.blocked_jobs || []).length ? `${w.blocked_jobs.length} job(s)` : "–")));
    if (!rows.length) rows.push(el("tr", {}, el("td", { colspan: 9, class: "mute" }, "no workers")));
    table.replaceChildren(el("tr", {}, ...["name", "state", "threads", "samples/s", "job", "heartbeat"].map((h) => el("th", {}, h)),
      el("th", { class: "hide-narrow" }, "samples"), el("th", {}, "tags"), el("th", {}, "blocked from")), ...rows);
  };
  const refresh = async () => {
    try {
      const ws = await api("/workers");
      if (my === page) draw(ws);
    } catch (e) { showError(e); }
  };
  follow((kind, data) => { if (my === page && kind === "workers") draw(data); }, refresh);
}

// ---- routing ------------------------------------------------------------------------------

function route() {
  clearInterval(timer);
  live.listener = null;
  page += 1;
  const my = page;
  const hash = location.hash || "#/jobs";
  for (const a of document.querySelectorAll("nav a")) a.classList.toggle("active", hash.startsWith(a.getAttribute("href")));
  const m = hash.match(/^#\/job\/([^/]+)$/);
  if (m) return jobPage(my, decodeURIComponent(m[1]));
  if (hash === "#/submit") return submitPage();
  if (hash === "#/workers") return workersPage(my);
  return jobsPage(my);
}

document.getElementById("error-close").addEventListener("click", clearError);
document.getElementById("token-button").addEventListener("click", showTokenForm);
document.getElementById("token-form").addEventListener("submit", (ev) => {
  ev.preventDefault();
  localStorage.setItem("luxfarm-token", document.getElementById("token-input").value.trim());
  document.getElementById("token-form").hidden = true;
  clearError();
  reconnectEvents();
  route();
});
window.addEventListener("hashchange", route);
connectEvents();
route();
