// windfdi farm monitor page: polls the farm monitor's JSON API once a second and draws tiles and alarms.
"use strict";

const severityRank = { info: 1, warning: 2, fault: 3, critical: 4 };
let selected = null;  // the turbine whose view is open

function escapeHtml(s) {
  return String(s).replace(/[&<>"']/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;", "'": "&#39;" }[c]));
}

// The operator token lives in this tab only (sessionStorage), never in the page's address.
const tokenInput = document.getElementById("token");
tokenInput.value = sessionStorage.getItem("windfdi-token") || "";
tokenInput.addEventListener("change", () => sessionStorage.setItem("windfdi-token", tokenInput.value));

async function api(path, options = {}) {
  const headers = Object.assign({}, options.headers || {});
  if (tokenInput.value) headers["Authorization"] = "Bearer " + tokenInput.value;
  const response = await fetch(path, Object.assign({}, options, { headers }));
  const body = await response.json();
  if (!response.ok) throw new Error(body.error || response.statusText);
  return body;
}

function worstSeverity(faults) {
  let worst = "";
  for (const f of faults)
    if (!f.secondary && (severityRank[f.severity] || 0) > (severityRank[worst] || 0)) worst = f.severity;
  return worst;
}

function drawFarm(turbines) {
  document.getElementById("turbine-count").textContent = "(" + turbines.length + ")";
  const tiles = turbines.map((t) => {
    const services = Object.entries(t.services);
    const ok = services.filter(([, s]) => s === "ok").length;
    const lost = services.filter(([, s]) => s === "lost").map(([n]) => n);
    const faults = t.active_faults.map((f) =>
      `<li class="fault sev-${escapeHtml(f.severity)}${f.secondary ? " secondary" : ""}"` +
      ` data-component="${escapeHtml(f.component)}" data-fault="${escapeHtml(f.fault)}">` +
      `${escapeHtml(f.component)} ${escapeHtml(f.fault)}${f.secondary ? " (secondary)" : ""}</li>`).join("");
    return `<div class="tile" id="tile-${escapeHtml(t.turbine_id)}" data-turbine="${escapeHtml(t.turbine_id)}"` +
      ` data-mode="${escapeHtml(t.mode)}" data-severity="${worstSeverity(t.active_faults)}"` +
      ` data-lost="${lost.length > 0}">` +
      `<div class="id">${escapeHtml(t.turbine_id)}</div>` +
      `<div>mode ${escapeHtml(t.mode)} · IPC ${escapeHtml(t.ipc_source)} · ice ${escapeHtml(t.ice_mode)}</div>` +
      `<div>services ${ok} ok${lost.length ? ", lost: " + lost.map(escapeHtml).join(", ") : ""}</div>` +
      (faults ? `<ul>${faults}</ul>` : "") + "</div>";
  });
  const farm = document.getElementById("farm");
  farm.innerHTML = tiles.join("");
  for (const tile of farm.querySelectorAll(".tile"))
    tile.addEventListener("click", () => openTurbine(tile.dataset.turbine));
}

function drawAlarms(turbines) {
  const rows = [];
  for (const t of turbines)
    for (const f of t.active_faults)
      rows.push(`<tr class="${f.secondary ? "secondary" : ""}"><td>${escapeHtml(t.turbine_id)}</td>` +
        `<td>${escapeHtml(f.component)}</td><td>${escapeHtml(f.fault)}</td>` +
        `<td class="sev-${escapeHtml(f.severity)}">${escapeHtml(f.severity)}</td><td>${escapeHtml(f.source)}</td>` +
        `<td>${Number(f.t_detected).toFixed(1)}</td>` +
        `<td>${escapeHtml(f.secondary ? "explained by " + f.explained_by : f.detail)}</td>` +
        `<td><button class="ack" data-turbine="${escapeHtml(t.turbine_id)}" data-component="${escapeHtml(f.component)}"` +
        ` data-fault="${escapeHtml(f.fault)}">acknowledge</button></td></tr>`);
  const body = document.querySelector("#alarms tbody");
  body.innerHTML = rows.join("");
  for (const button of body.querySelectorAll("button.ack"))
    button.addEventListener("click", () => acknowledge(button.dataset));
}

async function acknowledge(d) {
  try {
    const r = await api("/api/ack", { method: "POST", headers: { "Content-Type": "application/json" },
      body: JSON.stringify({ turbine_id: d.turbine, component: d.component, fault: d.fault }) });
    setStatus(`acknowledged ${d.component} ${d.fault} on ${d.turbine} (${r.arbiters} arbiter(s))`);
  } catch (e) {
    setStatus("acknowledgement refused: " + e.message, true);
  }
}

function time(s) { return new Date(s * 1000).toLocaleTimeString(); }

async function openTurbine(id) {
  selected = id;
  history.replaceState(null, "", "#turbine=" + encodeURIComponent(id));
  document.getElementById("turbine-view").hidden = false;
  document.getElementById("turbine-name").textContent = id;
  await refreshTurbine();
}

// The paper's Table 1 (Wu & Li): omega_n (rad/s) and zeta of the healthy actuator and of each fault.
const table1 = { healthy: [11.11, 0.6], pump_wear: [7.27, 0.75], hydraulic_leakage: [3.42, 0.9],
  high_air_content: [5.73, 0.45] };
const graphs = {};

// One plot: rows [Date, v1, v2, ...]; `dashed` names the reference series.
function plot(id, labels, rows, dashed = []) {
  const div = document.getElementById(id);
  div.dataset.points = String(rows.length);
  if (typeof Dygraph === "undefined") {
    div.textContent = "plots need Debian's libjs-dygraphs on the farm monitor's host";
    return;
  }
  if (rows.length === 0) {
    if (graphs[id]) { graphs[id].destroy(); delete graphs[id]; }
    div.textContent = "no estimate stored yet";
    return;
  }
  const series = {};
  for (const name of dashed) series[name] = { strokePattern: Dygraph.DASHED_LINE, strokeWidth: 1 };
  const options = { labels: ["time", ...labels], title: div.dataset.title, series, legend: "follow",
    titleHeight: 20, axisLabelFontSize: 11 };
  if (graphs[id]) graphs[id].updateOptions(Object.assign({ file: rows }, options));
  else { div.textContent = ""; graphs[id] = new Dygraph(div, rows, options); }
}

const blades = [1, 2, 3];
async function refreshEstimates() {
  const since = Date.now() / 1000 - Number(document.getElementById("window").value);
  const get = (service) => api(`/api/estimates?turbine=${encodeURIComponent(selected)}&service=${service}` +
    `&since=${since}`).then((r) => r.estimates);
  const [pitch, bias, ice, blade] = await Promise.all(["pitch_diag", "sensor_bias", "ice_detect", "blade_load"].map(get));
  const when = (e) => new Date(e.received_at * 1000);
  const refs = (i) => Object.values(table1).map((v) => v[i]);
  const refNames = Object.keys(table1);
  plot("plot-pitch-omega", [...blades.map((b) => "blade " + b), ...refNames],
    pitch.map((e) => [when(e), ...e.omega_n, ...refs(0)]), refNames);
  plot("plot-pitch-zeta", [...blades.map((b) => "blade " + b), ...refNames],
    pitch.map((e) => [when(e), ...e.zeta, ...refs(1)]), refNames);
  plot("plot-bias-pitch", blades.map((b) => "pitch " + b), bias.map((e) => [when(e), ...e.bias_pitch]));
  plot("plot-bias-bound", ["bound ratio", "threshold"], bias.map((e) => [when(e), e.bound_ratio, 1.0]), ["threshold"]);
  // The levels ice_detect is configured with on this turbine (its estimate carries them).
  const levels = ["warning", "fault", "critical"];
  plot("plot-inertia", ["inertia", "clean J0", ...levels],
    // No estimate yet (0): a gap, not a value.
    ice.map((e) => [when(e), e.inertia > 0 ? e.inertia : null, e.inertia_clean,
      ...levels.map((l) => e.inertia_clean * (1 + e[l + "_rise"]))]), ["clean J0", ...levels]);
  plot("plot-blade", [...blades.map((b) => "gauge " + b), ...blades.map((b) => "LIDAR model " + b)],
    blade.map((e) => [when(e), ...e.a1_sensor.map((v) => v / 1e3), ...e.a1_model.map((v) => v / 1e3)]));
}

async function refreshTurbine() {
  if (!selected) return;
  await refreshEstimates();
  const q = "turbine=" + encodeURIComponent(selected);
  const [faults, configs] = await Promise.all([api("/api/faults?limit=50&" + q),
    api("/api/history?kind=config&limit=20&" + q)]);
  document.querySelector("#turbine-faults tbody").innerHTML = faults.faults.map((f) =>
    `<tr><td>${time(f.received_at)}</td><td>${escapeHtml(f.component)}</td><td>${escapeHtml(f.fault)}</td>` +
    `<td>${escapeHtml(f.state)}</td><td class="sev-${escapeHtml(f.severity)}">${escapeHtml(f.severity)}</td>` +
    `<td>${escapeHtml(f.source)}</td><td>${escapeHtml(f.detail)}</td></tr>`).join("");
  document.querySelector("#turbine-configs tbody").innerHTML = configs.history.map((h) =>
    `<tr><td>${time(h.received_at)}</td><td>${h.data.revision}</td><td>${escapeHtml(h.data.mode)}</td>` +
    `<td>${escapeHtml(h.data.ipc_source)}</td><td>${escapeHtml(h.data.ice_mode)}</td>` +
    `<td>${escapeHtml((h.data.reasons || []).join("; "))}</td></tr>`).join("");
}

// The run judged against the scenario, when the farm monitor was given one (--report-scenario).
let reportAt = 0;
async function refreshReport() {
  if (Date.now() - reportAt < 10000) return;
  reportAt = Date.now();
  let r;
  try {
    r = await api("/api/report");
  } catch (e) {
    return;  // no scenario: no section
  }
  document.getElementById("report").hidden = false;
  const right = r.faults.filter((f) => f.expected && f.first === f.expected).length;
  const covered = r.faults.filter((f) => f.expected).length;
  document.getElementById("report-summary").textContent =
    `(${right} of ${covered} right first, ${r.extra.filter((x) => !x.secondary).length} unexpected, ` +
    `${r.stops.filter((x) => !x.warranted).length} unwarranted stops)`;
  document.querySelector("#report-faults tbody").innerHTML = r.faults.map((f) =>
    `<tr><td>${escapeHtml(f.turbine)}</td><td>${escapeHtml(f.target + ":" + f.type)}</td><td>${f.start}</td>` +
    `<td>${escapeHtml(f.expected ? f.component + " " + f.expected : "not covered")}</td>` +
    `<td>${escapeHtml(f.first || "-")}${f.then.length ? " (" + escapeHtml(f.then.join(", ")) + ")" : ""}</td>` +
    `<td>${f.delay === null ? "-" : Number(f.delay).toFixed(1)}</td><td>${f.while_active ? "yes" : "no"}</td></tr>`).join("");
}

function setStatus(text, error = false) {
  const s = document.getElementById("status");
  s.textContent = text;
  s.style.color = error ? "#ff8080" : "";
}

async function poll() {
  try {
    const r = await api("/api/turbines");
    drawFarm(r.turbines);
    drawAlarms(r.turbines);
    await refreshTurbine();
    await refreshReport();
    document.body.dataset.updated = String(Date.now());
    setStatus("updated " + new Date().toLocaleTimeString());
  } catch (e) {
    setStatus("farm monitor unreachable: " + e.message, true);
  }
  setTimeout(poll, 1000);
}
// A link to one turbine's view: /#turbine=WT01.
const linked = new URLSearchParams(location.hash.slice(1)).get("turbine");
if (linked) openTurbine(linked);
document.getElementById("window").addEventListener("change", refreshTurbine);
poll();
