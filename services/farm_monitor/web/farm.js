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
  document.getElementById("turbine-view").hidden = false;
  document.getElementById("turbine-name").textContent = id;
  await refreshTurbine();
}

async function refreshTurbine() {
  if (!selected) return;
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
    document.body.dataset.updated = String(Date.now());
    setStatus("updated " + new Date().toLocaleTimeString());
  } catch (e) {
    setStatus("farm monitor unreachable: " + e.message, true);
  }
  setTimeout(poll, 1000);
}
poll();
