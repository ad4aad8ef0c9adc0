// targetacq explorer: a form posted to the JSON API, its ranges as a table, its curves as SVG.
"use strict";

const SVG_NS = "http://www.w3.org/2000/svg";
const TASKS = ["detection", "recognition", "identification"];
const DASHES = { detection: "", recognition: "7 4", identification: "2 3" };
const COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"];
const LIVE_COLOUR = "#222222";
const MAX_COMPARED = 4;
// Keys of a DRI row that are not the sweep's own options.
const ROW_KEYS = new Set(["task", "probability", "threshold", "threshold_unit", "range_m", "reached"]);

const form = document.getElementById("case-form");
const statusBox = document.getElementById("status");
let liveCurves = null; // the /curves answer for the form as it is
let liveOptions = {};
let compared = []; // [{options, curves, colour}]
let latestRequest = 0;
let latestScenario = 0; // the last scenario sent: an earlier upload's late answer is dropped
let timer = null;
let scenarioText = null;
let scenarioName = "scenario";
let liveReport = null; // the /dri answer for the form as it is (the table)
let targetDimensions = {}; // a named target's critical dimension [m], from /registries

// ---------- small helpers ----------

function svgEl(tag, attrs) {
  const el = document.createElementNS(SVG_NS, tag);
  for (const [key, value] of Object.entries(attrs || {})) el.setAttribute(key, value);
  return el;
}

function setStatus(text) {
  statusBox.textContent = text || "";
  statusBox.classList.toggle("shown", Boolean(text));
}

// The options the form sends: a disabled field (the critical dimension of a named target) is shown, not sent.
function formOptions() {
  const options = {};
  for (const el of form.elements) {
    if (el.name && !el.disabled && el.value.trim() !== "") options[el.name] = el.value.trim();
  }
  return options;
}

// ---------- the form's state in the URL ----------

// The page's address carries the form's options (?pitch=17um&focal_length=50mm...): copy it to share the case.
function writeURL(options) {
  const query = new URLSearchParams(options).toString();
  const address = query ? `${location.pathname}?${query}` : location.pathname;
  if (address !== `${location.pathname}${location.search}`) history.replaceState(null, "", address);
}

// The form as an address gives it: every field from the query (a field it leaves out is empty);
// false, with the form untouched, when the address names no field.
function readURL() {
  const params = new URLSearchParams(location.search);
  const fields = [...form.elements].filter((el) => el.name);
  if (!fields.some((el) => params.has(el.name))) return false;
  for (const el of fields) el.value = params.get(el.name) ?? "";
  return true;
}

function describe(options) {
  return Object.entries(options)
    .filter(([key]) => key !== "probability")
    .map(([key, value]) => `${key.replace(/_/g, " ")} ${value}`)
    .join(", ");
}

function post(url, body) {
  return fetch(url, { method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(body) });
}

async function readJSON(response) {
  const data = await response.json().catch(() => null);
  return { ok: response.ok, status: response.status, data };
}

async function postJSON(url, body) {
  return readJSON(await post(url, body));
}

// The field a 422's location names (its last element), and the message.
function problems(data) {
  const detail = data && Array.isArray(data.detail) ? data.detail : [];
  return detail.map((d) => ({
    loc: Array.isArray(d.loc) ? d.loc : [],
    field: Array.isArray(d.loc) && d.loc.length ? String(d.loc[d.loc.length - 1]) : "",
    msg: d.msg || String(d),
  }));
}

// A problem as "where: what", its location without the leading "body" (the request itself).
function located(p) {
  const where = p.loc.filter((part) => part !== "body").join(".");
  return where ? `${where}: ${p.msg}` : p.msg;
}

// The server's message for a failed answer, whatever the shape of its detail.
function errorText(result) {
  const detail = result.data && result.data.detail;
  if (typeof detail === "string") return result.status ? `${result.status}: ${detail}` : detail;
  const list = problems(result.data);
  if (list.length) return `${result.status}: ${list.map(located).join("; ")}`;
  if (result.status === 413) return "413: the request is too large";
  return `${result.status}: the request failed`;
}

// ---------- registries ----------

async function loadRegistries() {
  let registries;
  try {
    const response = await fetch("/registries");
    registries = await response.json();
  } catch (err) {
    setStatus(`Could not load the registries: ${err}`);
    return;
  }
  for (const target of registries.targets || []) {
    if (Number.isFinite(target.critical_dimension_m)) targetDimensions[target.name] = target.critical_dimension_m;
  }
  for (const select of form.querySelectorAll("select[data-registry]")) {
    // Choices written into the page (the visibility conventions) stand until the registry lists its own.
    select.sources = {};
    for (const option of select.options) {
      if (option.value) select.sources[option.value] = { name: option.value, description: option.title };
    }
    const listed = registries[select.dataset.registry];
    if (!Array.isArray(listed)) {
      showSource(select);
      continue;
    }
    if (listed.length) {
      for (const option of [...select.options]) if (option.value !== "") option.remove();
      select.sources = {};
    }
    for (const item of listed) {
      const entry = typeof item === "string" ? { name: item } : item;
      // An obscurant's levels are choices of their own (haze:low), as on the CLI.
      for (const name of [entry.name, ...(entry.levels || []).map((level) => `${entry.name}:${level}`)]) {
        const option = document.createElement("option");
        option.value = option.textContent = name;
        option.title = entry.description || "";
        select.appendChild(option);
        select.sources[name] = entry;
      }
    }
    showSource(select);
  }
}

// What a registry says of a choice: its description, band limits, levels and source.
function showSource(select) {
  const box = form.querySelector(`[data-source-for="${select.id}"]`);
  const entry = select.sources && select.sources[select.value];
  if (!box) return;
  const parts = [];
  if (entry && entry.description) parts.push(entry.description);
  if (entry && Array.isArray(entry.limits_m)) parts.push(entry.limits_m.map((m) => +(m * 1e6).toPrecision(4)).join("–") + " µm");
  if (entry && entry.levels) parts.push(`levels: ${entry.levels.join(", ")}`);
  if (entry && entry.source) parts.push(`Source: ${entry.source}`);
  box.textContent = parts.join(". ");
}

// ---------- the range case ----------

function schedule() {
  clearTimeout(timer);
  timer = setTimeout(update, 250);
}

function showFieldErrors(list) {
  for (const span of form.querySelectorAll(".error")) span.textContent = "";
  const unplaced = [];
  for (const p of list) {
    const span = form.querySelector(`.error[data-for="${CSS.escape(p.field)}"]`);
    if (span) span.textContent = span.textContent ? `${span.textContent}; ${p.msg}` : p.msg;
    else unplaced.push(`${p.loc.join(".")}: ${p.msg}`);
  }
  return unplaced;
}

// A request that failed to reach the server reads as an answer with no status.
function unanswered(err) {
  return { ok: false, status: 0, data: { detail: `the server did not answer: ${err}` } };
}

async function update() {
  const request = ++latestRequest;
  const options = formOptions();
  writeURL(options);
  // The table needs only /dri: a failed /curves (a transform for detection only, say) costs the curves alone.
  const [dri, curves] = await Promise.all([
    postJSON("/dri", options).catch(unanswered),
    postJSON("/curves", options).catch(unanswered),
  ]);
  if (request !== latestRequest) return; // a newer request is under way
  const results = document.getElementById("results");
  results.classList.toggle("stale", !dri.ok);
  if (!dri.ok) {
    if (dri.status === 422 && dri.data && Array.isArray(dri.data.detail)) {
      const unplaced = showFieldErrors(problems(dri.data));
      setStatus(unplaced.join("\n"));
    } else {
      showFieldErrors([]);
      setStatus(errorText(dri));
    }
    return;
  }
  showFieldErrors([]);
  liveOptions = options;
  liveReport = dri.data;
  renderTable(dri.data);
  if (curves.ok && curves.data && Array.isArray(curves.data.range_m)) {
    liveCurves = curves.data;
    const note = typeof liveCurves.note === "string" ? liveCurves.note : "";
    if (TASKS.some((task) => Array.isArray(liveCurves[task]))) setStatus(note);
    else setStatus(`No curves: ${note || "this case gives no probability against range."}`);
  } else {
    liveCurves = null;
    setStatus(curves.ok ? "No curves: the server gave none." : `No curves: ${errorText(curves)}`);
  }
  drawCurves();
  setCaseDownloads();
  results.dataset.shown = JSON.stringify(options); // the case the table and curves show
}

// ---------- downloads of the form's case ----------

function setCaseDownloads() {
  document.getElementById("download-dri-csv").disabled = !liveReport;
  document.getElementById("download-dri-json").disabled = !liveReport;
  const drawn = Boolean(liveCurves && TASKS.some((task) => Array.isArray(liveCurves[task])));
  document.getElementById("download-curves-csv").disabled = !drawn;
  document.getElementById("download-curves-svg").disabled = !drawn;
}

function save(text, type, name) {
  const link = document.createElement("a");
  link.href = URL.createObjectURL(new Blob([text], { type }));
  link.download = name;
  document.body.appendChild(link);
  link.click();
  link.remove();
  setTimeout(() => URL.revokeObjectURL(link.href), 1000);
}

function csvCell(value) {
  if (value === null || value === undefined) return "";
  const text = String(value);
  return /[",\n]/.test(text) ? `"${text.replace(/"/g, '""')}"` : text;
}

function csvText(columns, rows) {
  return [columns, ...rows].map((row) => row.map(csvCell).join(",")).join("\n") + "\n";
}

// The table as targetacq dri --format csv lays it out: a row per task and probability, the case's options first.
function driCSV(report) {
  const rows = report.ranges || [];
  const columns = [];
  for (const row of rows) for (const key of Object.keys(row)) if (!columns.includes(key)) columns.push(key);
  return csvText(columns, rows.map((row) => columns.map((key) => row[key])));
}

function curvesCSV(curves) {
  const tasks = TASKS.filter((task) => Array.isArray(curves[task]));
  const rows = curves.range_m.map((r, i) => [r, ...tasks.map((task) => curves[task][i])]);
  return csvText(["range_m", ...tasks.map((task) => `p_${task}`)], rows);
}

// The chart as a standalone SVG file: the page's drawing with the page's styles for it.
function curvesSVG() {
  const svg = document.getElementById("curves").cloneNode(true);
  svg.setAttribute("xmlns", SVG_NS);
  svg.setAttribute("width", "640");
  svg.setAttribute("height", "360");
  const rules = [];
  for (const sheet of document.styleSheets) {
    for (const rule of sheet.cssRules) if (/^svg\b/.test(rule.selectorText || "")) rules.push(rule.cssText);
  }
  const style = document.createElementNS(SVG_NS, "style");
  style.textContent = rules.join("\n");
  svg.insertBefore(style, svg.firstChild);
  return new XMLSerializer().serializeToString(svg);
}

function formatRange(row) {
  if (!row.reached || row.range_m === null || row.range_m === undefined) return "not reached";
  if (!Number.isFinite(row.range_m)) return "any";
  return row.range_m.toLocaleString("en-US", { maximumFractionDigits: 0 });
}

function renderTable(report) {
  const rows = (report && report.ranges) || [];
  const probabilities = [];
  const lines = new Map(); // a row per task (and per swept combination)
  for (const row of rows) {
    const p = row.probability === null ? "-" : String(row.probability);
    if (!probabilities.includes(p)) probabilities.push(p);
    const swept = Object.keys(row).filter((k) => !ROW_KEYS.has(k)).map((k) => `${k} ${row[k]}`);
    const key = [...swept, row.task].join(", ");
    if (!lines.has(key)) lines.set(key, { task: row.task, label: key, cells: {} });
    lines.get(key).cells[p] = row;
  }
  const table = document.getElementById("dri-table");
  const head = document.createElement("tr");
  head.appendChild(Object.assign(document.createElement("th"), { textContent: "task" }));
  for (const p of probabilities) {
    const th = document.createElement("th");
    th.textContent = p === "-" ? "range" : `P = ${Number(p).toFixed(2)}`;
    th.scope = "col";
    head.appendChild(th);
  }
  const body = document.createDocumentFragment();
  for (const line of lines.values()) {
    const tr = document.createElement("tr");
    tr.dataset.task = line.task;
    const th = Object.assign(document.createElement("th"), { textContent: line.label, scope: "row" });
    tr.appendChild(th);
    for (const p of probabilities) {
      const td = document.createElement("td");
      const row = line.cells[p];
      td.dataset.probability = p;
      if (row) {
        td.textContent = formatRange(row);
        td.dataset.rangeM = row.reached && row.range_m !== null ? String(row.range_m) : "";
        td.title = `${row.threshold} ${row.threshold_unit || ""}`.trim();
      }
      tr.appendChild(td);
    }
    body.appendChild(tr);
  }
  table.tHead.replaceChildren(head);
  table.tBodies[0].replaceChildren(body);
}

// ---------- charts ----------

const BOX = { left: 56, right: 620, top: 16, bottom: 310 }; // the plot area inside the viewBox

function niceStep(span, count) {
  const raw = span / count;
  const power = Math.pow(10, Math.floor(Math.log10(raw)));
  const scaled = raw / power;
  return power * (scaled < 1.5 ? 1 : scaled < 3.5 ? 2 : scaled < 7.5 ? 5 : 10);
}

// Axes, ticks and labels into svg; returns functions from data to picture coordinates.
function drawAxes(svg, xMax, xLabel, yLabel) {
  const x = (v) => BOX.left + (v / xMax) * (BOX.right - BOX.left);
  const y = (p) => BOX.bottom - p * (BOX.bottom - BOX.top);
  const axes = svgEl("g", { class: "axes" });
  const step = niceStep(xMax, 6);
  for (let v = 0; v <= xMax * 1.0001; v += step) {
    axes.appendChild(svgEl("line", { x1: x(v), x2: x(v), y1: BOX.top, y2: BOX.bottom, class: "grid" }));
    const label = svgEl("text", { x: x(v), y: BOX.bottom + 16, "text-anchor": "middle" });
    label.textContent = Number(v.toPrecision(6)).toString();
    axes.appendChild(label);
  }
  for (let p = 0; p <= 1.0001; p += 0.2) {
    axes.appendChild(svgEl("line", { x1: BOX.left, x2: BOX.right, y1: y(p), y2: y(p), class: "grid" }));
    const label = svgEl("text", { x: BOX.left - 6, y: y(p) + 4, "text-anchor": "end" });
    label.textContent = p.toFixed(1);
    axes.appendChild(label);
  }
  axes.appendChild(svgEl("rect", {
    x: BOX.left, y: BOX.top, width: BOX.right - BOX.left, height: BOX.bottom - BOX.top, class: "frame",
  }));
  const xText = svgEl("text", { x: (BOX.left + BOX.right) / 2, y: BOX.bottom + 36, "text-anchor": "middle", class: "axis-label" });
  xText.textContent = xLabel;
  const yText = svgEl("text", {
    x: 14, y: (BOX.top + BOX.bottom) / 2, "text-anchor": "middle", class: "axis-label",
    transform: `rotate(-90 14 ${(BOX.top + BOX.bottom) / 2})`,
  });
  yText.textContent = yLabel;
  axes.append(xText, yText);
  svg.appendChild(axes);
  return { x, y };
}

function pathData(xs, ys, scale) {
  let d = "";
  let pen = "M";
  for (let i = 0; i < xs.length; i++) {
    if (!Number.isFinite(xs[i]) || !Number.isFinite(ys[i])) {
      pen = "M";
      continue;
    }
    d += `${pen}${scale.x(xs[i]).toFixed(1)},${scale.y(ys[i]).toFixed(1)}`;
    pen = "L";
  }
  return d;
}

function drawCurves() {
  const svg = document.getElementById("curves");
  svg.replaceChildren();
  const cases = compared.map((c, i) => ({ id: `c${i + 1}`, ...c }));
  if (liveCurves) cases.push({ id: "live", options: liveOptions, curves: liveCurves, colour: LIVE_COLOUR });
  let xMax = 0;
  for (const c of cases) for (const r of c.curves.range_m || []) if (Number.isFinite(r)) xMax = Math.max(xMax, r / 1000);
  const scale = drawAxes(svg, xMax > 0 ? xMax : 1, "slant range [km]", "P");
  for (const c of cases) {
    const km = (c.curves.range_m || []).map((r) => r / 1000);
    for (const task of TASKS) {
      if (!Array.isArray(c.curves[task])) continue;
      const path = svgEl("path", {
        d: pathData(km, c.curves[task], scale), class: "curve", stroke: c.colour,
        "stroke-dasharray": DASHES[task], "data-case": c.id, "data-task": task,
      });
      const title = svgEl("title");
      title.textContent = `${c.id === "live" ? "current" : c.id}: ${task}`;
      path.appendChild(title);
      svg.appendChild(path);
    }
  }
  const legend = document.getElementById("legend");
  legend.replaceChildren();
  for (const c of cases) {
    const item = document.createElement("li");
    const swatch = Object.assign(document.createElement("span"), { className: "swatch" });
    swatch.style.background = c.colour;
    item.append(swatch, `${c.id === "live" ? "current" : c.id}: ${describe(c.options)}`);
    item.dataset.case = c.id;
    legend.appendChild(item);
  }
  const tasks = document.createElement("li");
  tasks.className = "tasks";
  tasks.textContent = "solid: detection, dashed: recognition, dotted: identification";
  legend.appendChild(tasks);
}

function addComparison() {
  if (!liveCurves) return;
  if (compared.length >= MAX_COMPARED) {
    setStatus(`At most ${MAX_COMPARED} configurations are compared: clear them first.`);
    return;
  }
  const used = new Set(compared.map((c) => c.colour));
  const colour = COLOURS.find((c) => !used.has(c));
  compared.push({ options: { ...liveOptions }, curves: liveCurves, colour });
  drawCurves();
}

function clearComparison() {
  compared = [];
  drawCurves();
}

// ---------- scenario ----------

function showScenarioErrors(lines) {
  const list = document.getElementById("scenario-errors");
  const items = document.createDocumentFragment(); // no spread: the list may be long
  for (const text of lines) items.appendChild(Object.assign(document.createElement("li"), { textContent: text }));
  list.replaceChildren(items);
}

// The scenario's plausibility warnings (a valid value no real sensor has: a unit slip?).
function showScenarioWarnings(lines) {
  const list = document.getElementById("scenario-warnings");
  const items = document.createDocumentFragment();
  for (const text of lines) items.appendChild(Object.assign(document.createElement("li"), { textContent: `warning: ${text}` }));
  list.replaceChildren(items);
}

function setDownloads(enabled) {
  for (const id of ["download-csv", "download-parquet", "download-report"]) {
    document.getElementById(id).disabled = !enabled;
  }
}

function clearTimeline() {
  document.getElementById("timeline").replaceChildren();
  document.getElementById("timeline-legend").replaceChildren();
}

async function evaluateScenario(text) {
  const request = ++latestScenario;
  scenarioText = text;
  setDownloads(false);
  clearTimeline();
  showScenarioErrors([]);
  showScenarioWarnings([]);
  let result;
  try {
    result = await postJSON("/evaluate", { scenario: text, format: "json" });
  } catch (err) {
    if (request === latestScenario) showScenarioErrors([`The server did not answer: ${err}`]);
    return;
  }
  if (request !== latestScenario) return; // a later upload's answer is the one shown
  if (!result.ok) {
    const list = problems(result.data);
    showScenarioErrors(list.length
      ? list.map((p) => `${p.loc.filter((part) => part !== "scenario" && part !== "body").join(".") || "scenario"}: ${p.msg}`)
      : [errorText(result)]);
    return;
  }
  showScenarioWarnings(Array.isArray(result.data.warnings) ? result.data.warnings : []);
  try {
    drawTimeline(result.data);
  } catch (err) {
    clearTimeline();
    showScenarioErrors([`Could not draw the timeline: ${err}`]);
    return;
  }
  setDownloads(true);
}

// The last finite time (times ascend); never Math.max(...times), which overflows the stack for long timelines.
function lastFinite(values) {
  for (let i = values.length - 1; i >= 0; i--) if (Number.isFinite(values[i])) return values[i];
  return NaN;
}

function drawTimeline(data) {
  const svg = document.getElementById("timeline");
  const times = data.time_s || [];
  const tMax = lastFinite(times);
  const scale = drawAxes(svg, Number.isFinite(tMax) && tMax > 0 ? tMax : 1, "time [s]", "fused P");
  const legend = document.getElementById("timeline-legend");
  (data.targets || []).forEach((target, i) => {
    const colour = COLOURS[i % COLOURS.length];
    const name = typeof target === "string" ? target : target.name;
    for (const task of TASKS) {
      const values = data[`fused_${task}`] && data[`fused_${task}`][i];
      if (!values) continue;
      const path = svgEl("path", {
        d: pathData(times, values, scale), stroke: colour, "stroke-dasharray": DASHES[task],
        class: task === "detection" ? "timeline" : "timeline-task", "data-target": name, "data-task": task,
      });
      svg.appendChild(path);
    }
    const item = document.createElement("li");
    const swatch = Object.assign(document.createElement("span"), { className: "swatch" });
    swatch.style.background = colour;
    item.append(swatch, name);
    legend.appendChild(item);
  });
  const title = document.createElement("li");
  title.className = "tasks";
  title.textContent = `${data.name || "scenario"}: sensors ${(data.sensors || []).join(", ")}; solid detection, dashed recognition, dotted identification`;
  legend.appendChild(title);
}

async function download(url, body, fallbackName) {
  let response;
  try {
    response = await post(url, body);
  } catch (err) {
    showScenarioErrors([`The server did not answer: ${err}`]);
    return;
  }
  if (!response.ok) {
    showScenarioErrors([errorText(await readJSON(response))]);
    return;
  }
  const disposition = response.headers.get("Content-Disposition") || "";
  const match = /filename="?([^";]+)"?/.exec(disposition);
  const link = document.createElement("a");
  link.href = URL.createObjectURL(await response.blob());
  link.download = match ? match[1] : fallbackName;
  document.body.appendChild(link);
  link.click();
  link.remove();
  setTimeout(() => URL.revokeObjectURL(link.href), 1000);
}

// ---------- wiring ----------

// A named target brings its own critical dimension: the field is disabled and shows the target's (from
// /registries; it is not sent) while one is chosen, and is given back its value when the choice returns to none.
function syncTarget() {
  const name = document.getElementById("target").value;
  const dimension = document.getElementById("critical_dimension");
  if (name !== "") {
    if (!dimension.disabled) dimension.dataset.kept = dimension.value;
    const metres = targetDimensions[name];
    dimension.value = Number.isFinite(metres) ? `${Number(metres.toPrecision(6))}m` : "";
  } else if (dimension.disabled) {
    dimension.value = dimension.dataset.kept ?? dimension.defaultValue;
  }
  dimension.disabled = name !== "";
}

form.addEventListener("input", schedule);
form.addEventListener("change", (event) => {
  if (event.target.tagName === "SELECT") showSource(event.target);
  if (event.target.id === "target") syncTarget();
  schedule();
});
form.addEventListener("submit", (event) => event.preventDefault());
document.getElementById("add-comparison").addEventListener("click", addComparison);
document.getElementById("clear-comparison").addEventListener("click", clearComparison);
document.getElementById("scenario-file").addEventListener("change", (event) => {
  const file = event.target.files[0];
  if (!file) return;
  scenarioName = file.name.replace(/\.toml$/i, "");
  const reader = new FileReader();
  reader.onload = () => evaluateScenario(String(reader.result));
  reader.onerror = () => showScenarioErrors([`Could not read ${file.name}`]);
  reader.readAsText(file);
});
document.getElementById("download-csv").addEventListener("click", () =>
  download("/evaluate", { scenario: scenarioText, format: "csv" }, `${scenarioName}.csv`));
document.getElementById("download-parquet").addEventListener("click", () =>
  download("/evaluate", { scenario: scenarioText, format: "parquet" }, `${scenarioName}.parquet`));
document.getElementById("download-report").addEventListener("click", () =>
  download("/report", { scenario: scenarioText }, `${scenarioName}-report.html`));
document.getElementById("download-dri-csv").addEventListener("click", () =>
  save(driCSV(liveReport), "text/csv", "dri.csv"));
document.getElementById("download-dri-json").addEventListener("click", () =>
  save(JSON.stringify(liveReport, null, 2) + "\n", "application/json", "dri.json"));
document.getElementById("download-curves-csv").addEventListener("click", () =>
  save(curvesCSV(liveCurves), "text/csv", "curves.csv"));
document.getElementById("download-curves-svg").addEventListener("click", () =>
  save(curvesSVG(), "image/svg+xml", "curves.svg"));

loadRegistries().then(() => {
  readURL(); // a shared address: its case
  for (const select of form.querySelectorAll("select[data-registry]")) showSource(select);
  syncTarget();
  return update();
});
