// The benchmark turbine's parameters and aerodynamic model.
#include "turbine_params.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "deploy_dir.hpp"

namespace windfdi {

double TurbineParams::rotor_area() const { return M_PI * rotor_radius * rotor_radius; }

double TurbineParams::rated_generator_torque() const {
  return rated_power / (generator_efficiency * rated_generator_speed);
}

double TurbineParams::rated_rotor_speed() const { return rated_generator_speed / gear_ratio; }

double TurbineParams::lumped_inertia(double extra_rotor_inertia) const {
  const double n2 = gear_ratio * gear_ratio;
  return (rotor_inertia + extra_rotor_inertia + n2 * generator_inertia) / n2;
}

TurbineParams load_turbine_params(const YamlSection& s) {
  s.require_known_keys({"rotor_radius",
                        "hub_height",
                        "air_density",
                        "gear_ratio",
                        "rotor_inertia",
                        "generator_inertia",
                        "drive_train_stiffness",
                        "drive_train_damping",
                        "rotor_friction",
                        "generator_friction",
                        "drive_train_efficiency",
                        "generator_efficiency",
                        "converter_time_constant",
                        "rated_power",
                        "rated_generator_speed",
                        "pitch_omega_n",
                        "pitch_zeta",
                        "pitch_rate_limit",
                        "pitch_min",
                        "pitch_max",
                        "fixed_pitch",
                        "ice_radius",
                        "ice_cp_loss",
                        "load_radius"});
  TurbineParams p;
  p.rotor_radius = s.get_number("rotor_radius", p.rotor_radius, 1.0, 200.0);
  p.hub_height = s.get_number("hub_height", p.hub_height, p.rotor_radius + 1.0, 300.0);
  p.air_density = s.get_number("air_density", p.air_density, 0.5, 2.0);
  p.gear_ratio = s.get_number("gear_ratio", p.gear_ratio, 1.0, 500.0);
  p.rotor_inertia = s.get_number("rotor_inertia", p.rotor_inertia, 1e3, 1e10);
  p.generator_inertia = s.get_number("generator_inertia", p.generator_inertia, 1.0, 1e6);
  p.drive_train_stiffness = s.get_number("drive_train_stiffness", p.drive_train_stiffness, 1e5, 1e12);
  p.drive_train_damping = s.get_number("drive_train_damping", p.drive_train_damping, 0.0, 1e9);
  p.rotor_friction = s.get_number("rotor_friction", p.rotor_friction, 0.0, 1e6);
  p.generator_friction = s.get_number("generator_friction", p.generator_friction, 0.0, 1e6);
  p.drive_train_efficiency = s.get_number("drive_train_efficiency", p.drive_train_efficiency, 0.5, 1.0);
  p.generator_efficiency = s.get_number("generator_efficiency", p.generator_efficiency, 0.5, 1.0);
  p.converter_time_constant = s.get_number("converter_time_constant", p.converter_time_constant, 1e-4, 1.0);
  p.rated_power = s.get_number("rated_power", p.rated_power, 1e3, 1e8);
  p.rated_generator_speed = s.get_number("rated_generator_speed", p.rated_generator_speed, 1.0, 1000.0);
  p.pitch_omega_n = s.get_number("pitch_omega_n", p.pitch_omega_n, 0.1, 100.0);
  p.pitch_zeta = s.get_number("pitch_zeta", p.pitch_zeta, 0.05, 5.0);
  p.pitch_rate_limit = s.get_number("pitch_rate_limit", p.pitch_rate_limit, 0.1, 100.0);
  p.pitch_min = s.get_number("pitch_min", p.pitch_min, -10.0, 10.0);
  p.pitch_max = s.get_number("pitch_max", p.pitch_max, 20.0, 95.0);
  p.fixed_pitch = s.get_number("fixed_pitch", p.fixed_pitch, p.pitch_min, 30.0);
  p.ice_radius = s.get_number("ice_radius", p.ice_radius, 0.0, p.rotor_radius);
  p.ice_cp_loss = s.get_number("ice_cp_loss", p.ice_cp_loss, 0.0, 0.5);
  p.load_radius = s.get_number("load_radius", p.load_radius, 0.1, 1.0);
  return p;
}

TurbineParams load_turbine_params_file(const std::string& path) {
  return load_turbine_params(YamlSection::load_file(path));
}

std::string scenario_turbine_file(const YamlSection& scenario, const std::string& scenario_file,
                                  const std::string& deploy_dir) {
  namespace fs = std::filesystem;
  std::string tf = scenario.get<std::string>("turbine_file", "turbine/benchmark_4.8MW.yaml");
  if (fs::path(tf).is_relative()) {
    const fs::path beside = fs::path(scenario_file).parent_path() / tf;
    tf = fs::exists(beside) ? beside.string() : (fs::path(deploy_dir) / tf).string();
  }
  if (!fs::exists(tf)) throw scenario.error("turbine_file", "turbine file '" + tf + "' not found");
  return tf;
}

std::string configured_turbine_file(const YamlSection& config) {
  return config.get_path("turbine_file", deploy_dir() + "/turbine/benchmark_4.8MW.yaml");
}

TurbineParams configured_turbine(const YamlSection& config) {
  return load_turbine_params_file(configured_turbine_file(config));
}

double AeroModel::moment_scale(const TurbineParams& p) {
  return 0.5 * p.air_density * p.rotor_area() * (2.0 * p.rotor_radius / 3.0) / 3.0;
}

double AeroModel::optimal_tip_speed_ratio() {
  static const double best = [] {
    double lambda_opt = 8.0, cp_max = 0.0;
    for (int i = 400; i <= 1200; ++i) {
      const double l = 0.01 * i;
      if (power_coefficient(l, 0.0) > cp_max) cp_max = power_coefficient(l, 0.0), lambda_opt = l;
    }
    return lambda_opt;
  }();
  return best;
}

double AeroModel::power_coefficient(double lambda, double beta) {
  if (lambda <= 0.0) return 0.0;
  // Heier / Slootweg analytic Cp(lambda, beta). The fit is made for beta >= 0: its 0.035 / (beta^3 + 1) is
  // singular at beta = -1 deg, which individual pitch control reaches below fine pitch. Holding that term at
  // its beta = 0 value below 0 keeps Cp smooth (C2 at 0) and thrust rising towards stall, as pitching to
  // feather lowers it.
  const double beta_pos = std::max(beta, 0.0);
  const double inv_li = 1.0 / (lambda + 0.08 * beta) - 0.035 / (beta_pos * beta_pos * beta_pos + 1.0);
  const double cp = 0.5176 * (116.0 * inv_li - 0.4 * beta - 5.0) * std::exp(-21.0 * inv_li) + 0.0068 * lambda;
  return std::clamp(cp, 0.0, 16.0 / 27.0);
}

double AeroModel::thrust_coefficient(double lambda, double beta) {
  const double cp = power_coefficient(lambda, beta);
  // Momentum theory: Cp = 4a(1-a)^2 has one root in [0, 1/3] for Cp <= 16/27; Newton from a = cp/4.
  double a = cp / 4.0;
  for (int i = 0; i < 30; ++i) {
    const double f = 4.0 * a * (1.0 - a) * (1.0 - a) - cp;
    const double df = 4.0 * (1.0 - a) * (1.0 - 3.0 * a);
    if (std::fabs(df) < 1e-9) break;
    const double step = f / df;
    a = std::clamp(a - step, 0.0, 1.0 / 3.0);
    if (std::fabs(step) < 1e-12) break;
  }
  return 4.0 * a * (1.0 - a);
}

AeroModel::AeroModel(const TurbineParams& p)
    : p_(p),
      moment_scale_(moment_scale(p)),
      n_lambda_(static_cast<int>(std::lround(kLambdaMax / kLambdaStep)) + 1),
      n_pitch_(static_cast<int>(std::lround((kPitchMax - kPitchMin) / kPitchStep)) + 1) {
  table_.resize(static_cast<std::size_t>(n_lambda_ * n_pitch_));
  for (int i = 0; i < n_lambda_; ++i)
    for (int j = 0; j < n_pitch_; ++j)
      table_[static_cast<std::size_t>(i * n_pitch_ + j)] =
          moment_coefficient_exact(i * kLambdaStep, kPitchMin + j * kPitchStep);
}

double AeroModel::tip_speed_ratio(double wind, double rotor_speed) const {
  return wind > 0.1 ? rotor_speed * p_.rotor_radius / wind : 0.0;
}

double AeroModel::aero_power(double wind, double rotor_speed, double pitch_deg, double cp_scale) const {
  const double v = std::max(wind, 0.0);
  return 0.5 * p_.air_density * p_.rotor_area() * v * v * v * cp_scale *
         power_coefficient(tip_speed_ratio(v, rotor_speed), pitch_deg);
}

double AeroModel::aero_torque(double wind, double rotor_speed, double pitch_deg, double cp_scale) const {
  // At standstill use the torque limit P / omega -> Cp / lambda finite; guard the denominator.
  return aero_power(wind, rotor_speed, pitch_deg, cp_scale) / std::max(rotor_speed, 0.05);
}

double AeroModel::moment_coefficient_exact(double lambda, double pitch_deg) const {
  return moment_scale_ * thrust_coefficient(lambda, pitch_deg);
}

double AeroModel::moment_coefficient(double lambda, double pitch_deg) const {
  const double x = std::clamp(lambda, 0.0, kLambdaMax) / kLambdaStep;
  const double y = (std::clamp(pitch_deg, kPitchMin, kPitchMax) - kPitchMin) / kPitchStep;
  const int i = std::min(static_cast<int>(x), n_lambda_ - 2);
  const int j = std::min(static_cast<int>(y), n_pitch_ - 2);
  const double fx = x - i, fy = y - j;
  auto at = [&](int a, int b) { return table_[static_cast<std::size_t>(a * n_pitch_ + b)]; };
  return (1 - fx) * ((1 - fy) * at(i, j) + fy * at(i, j + 1)) +
         fx * ((1 - fy) * at(i + 1, j) + fy * at(i + 1, j + 1));
}

double feathering_pitch(const TurbineParams& turbine, double wind) {
  // Bisection: Cp falls as the pitch rises at a fixed tip-speed ratio above fine pitch.
  const AeroModel aero(turbine);
  const double rotor_speed = turbine.rated_generator_speed / turbine.gear_ratio;
  const double rated_aero =
      turbine.rated_power / (turbine.generator_efficiency * turbine.drive_train_efficiency);
  double low = 0.0, high = turbine.pitch_max;
  if (aero.aero_power(wind, rotor_speed, low) <= rated_aero) return low;
  for (int i = 0; i < 50; ++i) {
    const double mid = 0.5 * (low + high);
    (aero.aero_power(wind, rotor_speed, mid) > rated_aero ? low : high) = mid;
  }
  return low;
}

}  // namespace windfdi
