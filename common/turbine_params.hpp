// The benchmark turbine's parameters and aerodynamic model (Cp, thrust, flapwise blade-root moment),
// shared by the plant and every service that needs an aerodynamic model.
#pragma once

#include <string>
#include <vector>

#include "yaml_config.hpp"

namespace windfdi {

/// The 4.8 MW FDI/FTC benchmark turbine (Odgaard, Stoustrup, Kinnaert 2009); drive train and pitch values
/// as Witczak et al. Table I. Loaded from deploy/turbine/benchmark_4.8MW.yaml.
struct TurbineParams {
  double rotor_radius = 57.5;             ///< m
  double hub_height = 87.6;               ///< m
  double air_density = 1.225;             ///< kg/m^3
  double gear_ratio = 95.0;               ///< N_g (-)
  double rotor_inertia = 55e6;            ///< J_r (kg m^2)
  double generator_inertia = 390.0;       ///< J_g (kg m^2)
  double drive_train_stiffness = 2.7e9;   ///< K_dt (N m/rad)
  double drive_train_damping = 775.49;    ///< B_dt (N m s/rad)
  double rotor_friction = 7.11;           ///< B_r (N m s/rad)
  double generator_friction = 45.6;       ///< B_g (N m s/rad)
  double drive_train_efficiency = 0.97;   ///< eta_dt (-)
  double generator_efficiency = 0.98;     ///< eta_g: electrical power = eta_g * omega_g * T_g
  double converter_time_constant = 0.02;  ///< s, first-order converter
  double rated_power = 4.8e6;             ///< W, electrical
  double rated_generator_speed = 162.0;   ///< rad/s
  double pitch_omega_n = 11.11;           ///< rad/s, healthy hydraulic pitch actuator
  double pitch_zeta = 0.6;                ///< -, healthy damping ratio
  double pitch_rate_limit = 10.0;         ///< deg/s
  double pitch_min = -2.0;                ///< deg
  double pitch_max = 90.0;                ///< deg
  /// deg; the blade angle taken when the turbine's data carries no pitch at all (a fixed-pitch or
  /// stall-regulated rotor, or a recording without pitch columns)
  double fixed_pitch = 0.0;
  double ice_radius = 40.0;   ///< m, radius at which accreted ice mass adds inertia (m r^2)
  double ice_cp_loss = 0.02;  ///< relative Cp loss per tonne of ice (-/t)
  double load_radius = 0.7;   ///< effective radius of a blade's wind, share of the rotor radius

  double rotor_area() const;  ///< m^2
  /// Lumped inertia referred to the generator side, (J_r + N^2 J_g) / N^2 (Stotsky & Egardt 2013, errata in
  /// docs/papers.md), kg m^2.
  double lumped_inertia(double extra_rotor_inertia = 0.0) const;
  /// N m, the generator torque at rated power and rated generator speed, P / (eta_g omega_g): the scale of
  /// torque levels that must hold on any turbine
  double rated_generator_torque() const;
  double rated_rotor_speed() const;  ///< rad/s, rated_generator_speed / N_g
};

/// Reads a turbine file; unknown keys and out-of-range values are ConfigErrors naming file and key.
TurbineParams load_turbine_params(const YamlSection& section);
TurbineParams load_turbine_params_file(const std::string& path);
/// The turbine file a scenario names (`turbine_file` of `scenario`, read from `scenario_file`; default the
/// benchmark turbine's): a relative path beside the scenario when it is there, else under `deploy_dir`. A
/// file that does not exist is a ConfigError naming the key.
std::string scenario_turbine_file(const YamlSection& scenario, const std::string& scenario_file,
                                  const std::string& deploy_dir);
/// The turbine file a service's or the arbiter's configuration names in `turbine_file` (relative: beside the
/// configuration), else the shipped benchmark turbine's (deploy_dir()/turbine/benchmark_4.8MW.yaml).
std::string configured_turbine_file(const YamlSection& config);
/// The turbine of that file.
TurbineParams configured_turbine(const YamlSection& config);

/// Aerodynamics: the Heier/Slootweg analytic power coefficient
///   Cp = c1 (c2/li - c3 beta - c4) exp(-c5/li) + c6 lambda,  1/li = 1/(lambda + 0.08 beta) - 0.035/(beta^3 +
///   1)
/// with max(beta, 0) in the cubic term (the fit is singular at beta = -1 deg, which IPC reaches below fine
/// pitch) (c = 0.5176, 116, 0.4, 5, 21, 0.0068; max Cp 0.48 at lambda 8.1, beta 0), and thrust from momentum
/// theory: the axial induction a with Cp = 4a(1-a)^2 (a <= 1/3) gives Ct = 4a(1-a). A blade's flapwise
/// root moment is its third of the thrust at 2/3 of the radius: M = Ct q A (2R/3) / 3, q = rho v^2 / 2.
class AeroModel {
 public:
  explicit AeroModel(const TurbineParams& p);

  static double power_coefficient(double lambda, double pitch_deg);
  static double thrust_coefficient(double lambda, double pitch_deg);
  /// The tip-speed ratio of the largest Cp at zero pitch (about 8.1, Cp 0.48), searched once in steps of
  /// 0.01.
  static double optimal_tip_speed_ratio();
  /// A blade's root moment per thrust coefficient and (m/s)^2 of wind, q A (2R/3) / 3 per v^2 (N m s^2/m^2).
  static double moment_scale(const TurbineParams& p);
  /// Tip-speed ratio omega R / v (0 for v <= 0.1 m/s).
  double tip_speed_ratio(double wind, double rotor_speed) const;
  /// Aerodynamic torque on the rotor (N m); `cp_scale` < 1 for an iced rotor.
  double aero_torque(double wind, double rotor_speed, double pitch_deg, double cp_scale = 1.0) const;
  double aero_power(double wind, double rotor_speed, double pitch_deg, double cp_scale = 1.0) const;
  /// kM(lambda, beta) such that a blade's flapwise root moment is kM * v^2 (N m per (m/s)^2),
  /// interpolated in a precomputed table (lambda 0..20, beta -5..90 deg).
  double moment_coefficient(double lambda, double pitch_deg) const;
  /// The same coefficient computed directly (for building tables).
  double moment_coefficient_exact(double lambda, double pitch_deg) const;

  static constexpr double kLambdaMax = 20.0, kLambdaStep = 0.1, kPitchMin = -5.0, kPitchMax = 90.0,
                          kPitchStep = 0.5;

 private:
  TurbineParams p_;
  double moment_scale_;  // q A (2R/3) / 3 per Ct per v^2
  int n_lambda_, n_pitch_;
  std::vector<double> table_;  // kM, row-major over (lambda, pitch)
};

/// The pitch (deg) at which the turbine, at rated rotor speed in `wind` (m/s), gives rated power: beyond
/// the one it needs past cut-out the rotor is feathering (0 when the wind does not reach rated power). The
/// services judge no sample pitched further (the power model of a feathering rotor does not hold).
double feathering_pitch(const TurbineParams& turbine, double wind);

}  // namespace windfdi
