// Plant scenarios (YAML).
#include "scenario.hpp"

#include <algorithm>
#include <set>

namespace windfdi::plant {

const std::vector<std::string>& sensor_channels() {
  static const std::vector<std::string> c = {
      "rotor_speed",    "generator_speed", "gen_torque",    "power",          "wind_hub",
      "pitch_1",        "pitch_2",         "pitch_3",       "blade_moment_1", "blade_moment_2",
      "blade_moment_3", "lidar_v_upper",   "lidar_v_lower", "lidar"};
  return c;
}

std::vector<std::string> fault_types_for(const std::string& target) {
  const auto& ch = sensor_channels();
  if (std::find(ch.begin(), ch.end(), target) != ch.end())
    return {"bias", "bias_paper", "gain", "offset", "drift", "stuck", "intermittent", "invalid"};
  if (target.rfind("pitch_actuator_", 0) == 0 && target.size() == 16 && target[15] >= '1' &&
      target[15] <= '3')
    return {"pump_wear", "hydraulic_leakage", "high_air_content"};
  if (target == "rotor") return {"ice_accretion", "ice_shedding"};
  if (target == "converter") return {"torque_offset"};
  if (target == "drive_train") return {"efficiency"};
  return {};
}

std::vector<FaultSpec> Scenario::faults_of(const std::string& id) const {
  std::vector<FaultSpec> out;
  for (const auto& f : faults)
    if (f.turbine == id) out.push_back(f);
  return out;
}

namespace {

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

WindConfig load_wind(const YamlSection& w) {
  w.require_known_keys({"mean", "turbulence_intensity", "length_scale", "shear_exponent", "shear_variation",
                        "shear_time_constant", "tower_shadow", "lidar_distance", "lidar_rate",
                        "lidar_noise"});
  WindConfig c;
  c.mean = w.require_number("mean", 0.5, 40.0);
  c.turbulence_intensity = w.get_number("turbulence_intensity", c.turbulence_intensity, 0.0, 0.5);
  c.length_scale = w.get_number("length_scale", c.length_scale, 1.0, 5000.0);
  c.shear_exponent = w.get_number("shear_exponent", c.shear_exponent, -0.5, 1.0);
  c.shear_variation = w.get_number("shear_variation", c.shear_variation, 0.0, 0.5);
  c.shear_time_constant = w.get_number("shear_time_constant", c.shear_time_constant, 1.0, 1e5);
  c.tower_shadow = w.get_number("tower_shadow", c.tower_shadow, 0.0, 0.9);
  c.lidar_distance = w.get_number("lidar_distance", c.lidar_distance, 1.0, 1000.0);
  c.lidar_rate = w.get_number("lidar_rate", c.lidar_rate, 0.1, 100.0);
  c.lidar_noise = w.get_number("lidar_noise", c.lidar_noise, 0.0, 5.0);
  return c;
}

FaultSpec load_fault(const YamlSection& f, const std::set<std::string>& turbine_ids, double duration) {
  f.require_known_keys({"turbine", "target", "type", "start", "end", "value", "gain", "rate", "amplitude",
                        "period", "duty", "ramp_in", "ramp_out", "hold", "alpha", "fraction"});
  FaultSpec s;
  s.turbine = f.require<std::string>("turbine");
  if (!turbine_ids.count(s.turbine)) {
    std::vector<std::string> ids(turbine_ids.begin(), turbine_ids.end());
    throw f.error("turbine",
                  "'" + s.turbine + "' is not a turbine of this scenario (turbines: " + join(ids) + ")");
  }
  s.target = f.require<std::string>("target");
  const auto types = fault_types_for(s.target);
  if (types.empty())
    throw f.error("target", "'" + s.target + "' is not a fault target (channels: " + join(sensor_channels()) +
                                "; components: pitch_actuator_1..3, rotor, converter, drive_train)");
  s.type = f.require<std::string>("type");
  if (std::find(types.begin(), types.end(), s.type) == types.end())
    throw f.error("type",
                  "'" + s.type + "' is not a fault type of " + s.target + " (valid: " + join(types) + ")");
  s.start = f.require_number("start", 0.0, duration);
  s.end = f.get_number("end", 1e300, s.start, 1e300);
  s.has_value = f.has("value");
  s.value = f.get_number("value", 0.0, -1e9, 1e9);
  s.gain = f.get_number("gain", s.type == "intermittent" ? 1.3 : 1.0, -10.0, 10.0);
  s.rate = f.get_number("rate", 0.0, -1e7, 1e7);
  s.amplitude = f.get_number("amplitude", 0.02, 0.0, 1.0);
  s.period = f.get_number("period", s.period, 0.02, 1e5);
  s.duty = f.get_number("duty", s.duty, 0.0, 1.0);
  s.ramp_in = f.get_number("ramp_in", 0.0, 0.0, 1e5);
  s.ramp_out = f.get_number("ramp_out", 0.0, 0.0, 1e5);
  if (f.has("hold")) s.end = s.start + s.ramp_in + f.require_number("hold", 0.0, 1e5);
  s.alpha = f.get_number("alpha", 1.0, 0.0, 1.0);
  s.fraction = f.get_number("fraction", 1.0, 0.0, 1.0);
  const bool needs_value = s.type == "bias" || s.type == "offset" || s.type == "torque_offset" ||
                           s.type == "efficiency" || s.type == "ice_accretion";
  if (needs_value && !s.has_value) throw f.error("value", "fault type " + s.type + " needs a 'value'");
  if (s.type == "gain" && !f.has("gain")) throw f.error("gain", "fault type gain needs a 'gain'");
  if (s.type == "drift" && !f.has("rate")) throw f.error("rate", "fault type drift needs a 'rate'");
  if (s.type == "efficiency" && (s.value <= 0.0 || s.value > 1.0))
    throw f.error("value", "an efficiency must be in (0, 1]");
  if (s.type == "ice_accretion" && s.value < 0.0) throw f.error("value", "an ice mass cannot be negative");
  return s;
}

}  // namespace

Scenario load_scenario(const std::string& path, const std::string& deploy_dir) {
  const YamlSection root = YamlSection::load_file(path);
  root.require_known_keys(
      {"duration", "seed", "sample_rate", "turbine_file", "turbines", "faults", "description"});
  Scenario sc;
  sc.file = path;
  sc.duration = root.require_number("duration", 0.01, 1e7);
  sc.seed = root.get<uint64_t>("seed", 1);
  sc.sample_rate = root.get_number("sample_rate", 100.0, 1.0, 10000.0);
  sc.turbine_file = scenario_turbine_file(root, path, deploy_dir);
  sc.turbine = load_turbine_params_file(sc.turbine_file);
  std::set<std::string> ids;
  for (const auto& t : root.sequence("turbines")) {
    t.require_known_keys({"id", "wind", "ice_mass"});
    TurbineScenario ts;
    ts.id = t.require<std::string>("id");
    if (ts.id.empty() || !ids.insert(ts.id).second)
      throw t.error("id", "turbine ids must be unique and non-empty");
    if (!t.has("wind")) throw t.error("wind", "required key is missing");
    ts.wind = load_wind(t.section("wind"));
    ts.ice_mass = t.get_number("ice_mass", 0.0, 0.0, 1e5);
    sc.turbines.push_back(ts);
  }
  if (sc.turbines.empty()) throw root.error("turbines", "a scenario needs at least one turbine");
  for (const auto& f : root.sequence("faults")) sc.faults.push_back(load_fault(f, ids, sc.duration));
  return sc;
}

}  // namespace windfdi::plant
