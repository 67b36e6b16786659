// The farm monitor's HTTP API without the socket.
#include "farm_api.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "fault_report.hpp"
#include "names.hpp"
#include "yaml_config.hpp"

namespace windfdi::farm {

using nlohmann::json;

namespace {

ApiResponse json_response(const json& j, int status = 200) { return {status, "application/json", j.dump()}; }

// A query parameter as a number; throws a 400 message naming it when it is not one (or out of range).
double number_param(const ApiRequest& r, const std::string& key, double fallback, double lo, double hi) {
  const auto it = r.params.find(key);
  if (it == r.params.end() || it->second.empty()) return fallback;
  std::size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(it->second, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != it->second.size() || !std::isfinite(v) || v < lo || v > hi) {
    char range[96];
    std::snprintf(range, sizeof range, "a number in [%g, %g]", lo, hi);
    throw std::invalid_argument("query parameter '" + key + "' must be " + range + ", not '" + it->second +
                                "'");
  }
  return v;
}

std::string text_param(const ApiRequest& r, const std::string& key) {
  const auto it = r.params.find(key);
  return it == r.params.end() ? "" : it->second;
}

// A name parameter that must be one of `names` when given.
std::string name_param(const ApiRequest& r, const std::string& key, const std::vector<std::string>& names) {
  const std::string v = text_param(r, key);
  if (!v.empty() && name_index(names, v) < 0)
    throw std::invalid_argument("query parameter '" + key + "': '" + v + "' is not a known name");
  return v;
}

// The query every history request starts with: one turbine or all, received since, at most limit rows.
struct RowQuery {
  std::string turbine;
  double since = 0.0;
  std::size_t limit = 200;
};

RowQuery row_query(const ApiRequest& r, double limit = 200, double max_limit = 5000) {
  return {text_param(r, "turbine"), number_param(r, "since", 0.0, 0.0, 1e12),
          static_cast<std::size_t>(number_param(r, "limit", limit, 1, max_limit))};
}

json fault_json(const FaultEvent& e) {
  json j = to_json(e);
  j["turbine_id"] = e.turbine_id;
  return j;
}

// Prometheus label values: backslash, quote and newline escaped.
std::string label(const std::string& v) {
  std::string out;
  for (char c : v) {
    if (c == '\\' || c == '"')
      out += '\\', out += c;
    else if (c == '\n')
      out += "\\n";
    else
      out += c;
  }
  return out;
}

}  // namespace

bool is_loopback(const std::string& addr) {
  return addr == "::1" || addr.rfind("127.", 0) == 0 || addr.rfind("::ffff:127.", 0) == 0;
}

ApiResponse api_error(int status, const std::string& message) {
  return json_response({{"error", message}}, status);
}

FarmApi::FarmApi(const std::string& db, std::string token, AckPublisher ack, std::string scenario)
    : token_(std::move(token)),
      ack_(std::move(ack)),
      scenario_(std::move(scenario)),
      store_(std::make_unique<FarmStore>(db)) {
  if (!scenario_.empty()) read_injected(scenario_);  // a scenario that cannot be read is an error at start
}

void FarmApi::update(const FarmState& state, const std::map<std::string, ServiceMetrics>& services) {
  auto next = std::make_shared<const Picture>(Picture{state, services});  // the copy, outside the lock
  std::lock_guard<std::mutex> lock(picture_mutex_);
  picture_ = std::move(next);
}

std::shared_ptr<const FarmApi::Picture> FarmApi::picture() const {
  std::lock_guard<std::mutex> lock(picture_mutex_);
  return picture_;
}

ApiResponse FarmApi::handle(const ApiRequest& r) {
  // Access: the token opens everything; without one, reading from this machine only. A wrong token is
  // refused even on localhost (a script with a stale token must learn it).
  const bool writes = r.method == "POST";
  const std::string bearer = "Bearer ";
  const bool has_token = r.authorization.rfind(bearer, 0) == 0;
  if (has_token && (token_.empty() || r.authorization.substr(bearer.size()) != token_))
    return api_error(403, "the token is not this farm monitor's");
  if (!has_token) {
    if (writes) return api_error(401, "an operator token is needed (Authorization: Bearer <token>)");
    if (!is_loopback(r.remote_addr))
      return api_error(401, "remote access needs the operator token (Authorization: Bearer <token>)");
  }
  // Each resource once: its path, its method and what answers it.
  const struct {
    const char* path;
    const char* method;
    std::function<ApiResponse()> answer;
  } routes[] = {{"/api/turbines", "GET", [&] { return turbines(); }},
                {"/api/faults", "GET", [&] { return faults(r); }},
                {"/api/history", "GET", [&] { return history(r); }},
                {"/api/estimates", "GET", [&] { return estimates(r); }},
                {"/api/ack", "POST", [&] { return ack(r); }},
                {"/api/report", "GET", [&] { return report(); }},
                {"/metrics", "GET", [&] { return metrics(); }}};
  for (const auto& route : routes) {
    if (r.path != route.path) continue;
    if (r.method != route.method) return api_error(405, "method " + r.method + " not allowed on " + r.path);
    try {
      return route.answer();
    } catch (const std::invalid_argument& e) {
      return api_error(400, e.what());
    } catch (const ConfigError& e) {
      return api_error(400, e.what());
    } catch (const std::exception& e) {
      return api_error(500, e.what());
    }
  }
  return api_error(404, "no such resource: " + r.path);
}

ApiResponse FarmApi::turbines() const {
  const auto p = picture();
  json out = json::array();
  for (const auto& [id, t] : p->state.turbines()) {
    // The same isolation as the live table: a report another one explains is marked secondary.
    json faults = json::array();
    for (const auto& [e, verdict] : p->state.raised(id)) {
      json f = fault_json(*e);
      f["secondary"] = verdict.secondary;
      f["explained_by"] = verdict.explained_by;
      faults.push_back(f);
    }
    json services = json::object();
    for (const auto& [name, state] : t.services) services[name] = state;
    out.push_back({{"turbine_id", id},
                   {"mode", t.mode},
                   {"ipc_source", t.ipc_source},
                   {"ice_mode", t.ice_mode},
                   {"revision", t.revision},
                   {"arbiter_id", t.arbiter_id},
                   {"services", services},
                   {"active_faults", faults}});
  }
  return json_response({{"turbines", out}});
}

std::vector<HistoryRow> FarmApi::stored(const std::string& turbine, double since) {
  std::lock_guard<std::mutex> lock(store_mutex_);
  return store_->history(turbine, since);
}

ApiResponse FarmApi::faults(const ApiRequest& r) {
  const RowQuery q = row_query(r);
  const std::string component = name_param(r, "component", component_names());
  const std::string fault = name_param(r, "fault", fault_class_names());
  const std::string severity = name_param(r, "severity", severity_names());
  const std::string state = name_param(r, "state", {"raised", "cleared"});
  const std::vector<HistoryRow> rows = stored(q.turbine, q.since);
  json out = json::array();
  for (auto it = rows.rbegin(); it != rows.rend() && out.size() < q.limit; ++it) {
    if (it->kind != "fault") continue;
    const json& d = it->data;
    if ((!component.empty() && d.value("component", "") != component) ||
        (!fault.empty() && d.value("fault", "") != fault) ||
        (!severity.empty() && d.value("severity", "") != severity) ||
        (!state.empty() && d.value("state", "") != state))
      continue;
    json f = d;
    f["received_at"] = it->received_at;
    out.push_back(f);
  }
  return json_response({{"faults", out}});  // newest first
}

ApiResponse FarmApi::history(const ApiRequest& r) {
  const RowQuery q = row_query(r);
  const std::string kind = name_param(r, "kind", {"fault", "config", "health"});
  const std::vector<HistoryRow> rows = stored(q.turbine, q.since);
  json out = json::array();
  for (auto it = rows.rbegin(); it != rows.rend() && out.size() < q.limit; ++it)
    if (kind.empty() || it->kind == kind)
      out.push_back({{"received_at", it->received_at}, {"kind", it->kind}, {"data", it->data}});
  return json_response({{"history", out}});  // newest first
}

ApiResponse FarmApi::estimates(const ApiRequest& r) {
  const RowQuery q = row_query(r, 3600, 86400);  // a day of 1 Hz estimates at most
  const std::string service = name_param(r, "service", service_names());
  if (q.turbine.empty() || service.empty())
    throw std::invalid_argument("query parameters 'turbine' and 'service' are needed");
  std::vector<EstimateRecord> rows;
  {
    std::lock_guard<std::mutex> lock(store_mutex_);
    rows = store_->estimates(q.turbine, service, q.since, q.limit);
  }
  json out = json::array();
  for (const auto& e : rows) {
    json row = e.fields.is_object() ? e.fields : json::object();
    row["t"] = e.t;
    row["received_at"] = e.received_at;
    out.push_back(row);
  }
  return json_response(
      {{"turbine_id", q.turbine}, {"service", service}, {"estimates", out}});  // oldest first
}

ApiResponse FarmApi::ack(const ApiRequest& r) {
  const json body = json::parse(r.body, nullptr, false);
  if (body.is_discarded() || !body.is_object()) return api_error(400, "the body must be a JSON object");
  for (const char* key : {"turbine_id", "component"})
    if (!body.contains(key) || !body[key].is_string() || body[key].get<std::string>().empty())
      return api_error(400, std::string("'") + key + "' (a string) is needed");
  const auto text = [&](const char* key, const char* fallback) {
    return body.contains(key) && body[key].is_string() ? body[key].get<std::string>() : std::string(fallback);
  };
  const std::string turbine = text("turbine_id", ""), component = text("component", "");
  const std::string fault = text("fault", "none"), who = text("operator", "web");
  if (!is_component(component)) return api_error(400, "'" + component + "' is not a component");
  if (fault != "none" && name_index(fault_class_names(), fault) < 0)
    return api_error(400, "'" + fault + "' is not a fault class");
  const int arbiters = ack_ ? ack_(turbine, component, fault, who) : 0;
  if (arbiters == 0) return api_error(503, "no arbiter received the acknowledgement");
  return json_response({{"acknowledged", true}, {"arbiters", arbiters}});
}

ApiResponse FarmApi::report() {
  if (scenario_.empty())
    return api_error(404, "the farm monitor was not given a scenario (--report-scenario)");
  const std::vector<HistoryRow> history = stored("", 0.0);
  json out = report_json(match(read_injected(scenario_), history), history);
  out["scenario"] = scenario_;
  return json_response(out);
}

ApiResponse FarmApi::metrics() const {
  const auto p = picture();
  std::ostringstream m;
  m << "# HELP windfdi_faults_active Raised fault reports per turbine and severity.\n"
       "# TYPE windfdi_faults_active gauge\n";
  for (const auto& [id, t] : p->state.turbines()) {
    std::map<std::string, int> by_severity;
    for (const auto& name : severity_names()) by_severity[name] = 0;
    for (const auto& [key, e] : t.faults)
      if (e.raised) ++by_severity[e.severity];
    for (const auto& [severity, n] : by_severity)
      m << "windfdi_faults_active{turbine=\"" << label(id) << "\",severity=\"" << label(severity) << "\"} "
        << n << "\n";
  }
  m << "# HELP windfdi_configuration_revision The arbiter's latest configuration revision per turbine.\n"
       "# TYPE windfdi_configuration_revision counter\n";
  for (const auto& [id, t] : p->state.turbines())
    m << "windfdi_configuration_revision{turbine=\"" << label(id) << "\"} " << t.revision << "\n";
  m << "# HELP windfdi_safe_stop 1 while the arbiter holds the turbine in safe stop.\n"
       "# TYPE windfdi_safe_stop gauge\n";
  for (const auto& [id, t] : p->state.turbines())
    m << "windfdi_safe_stop{turbine=\"" << label(id) << "\"} " << (t.mode == "safe_stop" ? 1 : 0) << "\n";
  // Per service and turbine (a farm-wide instance has turbine "*"), from its last ServiceHealth.
  struct Counter {
    const char* name;
    const char* help;
    const char* type;
    std::function<double(const ServiceMetrics&)> value;
  };
  const Counter counters[] = {
      {"windfdi_service_up", "1 while the service is alive (not lost).", "gauge",
       [](const ServiceMetrics& s) { return s.state == "lost" ? 0.0 : 1.0; }},
      {"windfdi_samples_in_total", "Samples the service took in since its start.", "counter",
       [](const ServiceMetrics& s) { return static_cast<double>(s.samples_in); }},
      {"windfdi_samples_rejected_total", "NaN, infinite, out-of-range or malformed samples rejected.",
       "counter", [](const ServiceMetrics& s) { return static_cast<double>(s.samples_rejected); }},
      {"windfdi_sequence_gaps_total", "Samples found missing from the sequence numbers.", "counter",
       [](const ServiceMetrics& s) { return static_cast<double>(s.sequence_gaps); }},
      {"windfdi_deadlines_missed_total", "Input streams silent past their deadline.", "counter",
       [](const ServiceMetrics& s) { return static_cast<double>(s.deadlines_missed); }},
      {"windfdi_lag_seconds", "Wall-clock age of the newest processed sample.", "gauge",
       [](const ServiceMetrics& s) { return s.lag; }},
  };
  for (const auto& c : counters) {
    m << "# HELP " << c.name << " " << c.help << "\n# TYPE " << c.name << " " << c.type << "\n";
    for (const auto& [key, s] : p->services) {
      const auto slash = key.find('/');
      char value[64];
      std::snprintf(value, sizeof value, "%.17g", c.value(s));
      m << c.name << "{turbine=\"" << label(key.substr(0, slash)) << "\",service=\""
        << label(key.substr(slash + 1)) << "\"} " << value << "\n";
    }
  }
  return {200, "text/plain; version=0.0.4", m.str()};
}

}  // namespace windfdi::farm
