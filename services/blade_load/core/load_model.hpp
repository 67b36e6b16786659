// The LIDAR-driven blade load model of Stotsky 2014 (eq 1, eq 9): look-up table k_M(lambda, beta), expected
// blade winds from two delayed LIDAR speeds (frozen turbulence), and the table's bounded adaptation in
// uniform wind.
#pragma once

#include <array>
#include <deque>
#include <string>
#include <vector>

#include "turbine_params.hpp"

namespace windfdi::blade_load {

/// k_M(lambda, beta) on a regular grid, with a learned multiplicative correction per node (the adaptation).
/// A blade's flapwise root moment is k_M(lambda, beta) * v^2 with v its wind at the load radius (eq 9).
class LoadTable {
 public:
  LoadTable() = default;
  LoadTable(double lambda0, double lambda_step, int n_lambda, double pitch0, double pitch_step, int n_pitch,
            std::vector<double> k);

  /// Reads the shipped CSV: '#' comment lines, a header `lambda\pitch_deg,<pitch values...>`, then one row
  /// per tip-speed ratio: lambda, k_M at each pitch (N m per (m/s)^2). A malformed file is a ConfigError.
  static LoadTable load_csv(const std::string& path);
  /// The table of a turbine's own aerodynamic model (AeroModel::moment_coefficient_exact): lambda 0..20 step
  /// 0.25, pitch -5..45 deg step 0.5, the operating range with margin. What windfdi-blade-load-table writes.
  static LoadTable from_turbine(const TurbineParams& turbine);
  void save_csv(const std::string& path, const std::string& comment) const;

  /// k_M with the learned correction, bilinear, clamped to the grid.
  double k(double lambda, double pitch_deg) const;
  /// The learned correction (1 = as shipped) interpolated at a point.
  double factor(double lambda, double pitch_deg) const;
  /// Moves the correction near (lambda, pitch) toward `target_factor` by `gain` (0..1) with Gaussian weights
  /// of width (sigma_lambda, sigma_pitch), each node bounded to 1 +/- bound (Stotsky 2014, "Adaptation").
  void adapt(double lambda, double pitch_deg, double target_factor, double gain, double sigma_lambda,
             double sigma_pitch, double bound);

  bool empty() const { return k_.empty(); }
  int n_lambda() const { return nl_; }
  int n_pitch() const { return np_; }
  const std::vector<double>& factors() const { return f_; }
  std::vector<double>& factors() { return f_; }

 private:
  double bilinear(const std::vector<double>& v, double lambda, double pitch_deg) const;
  double l0_ = 0, dl_ = 1, p0_ = 0, dp_ = 1;
  int nl_ = 0, np_ = 0;
  std::vector<double> k_, f_;
};

struct LoadModelConfig {
  double hub_height = 87.6;       ///< m, H
  double rotor_radius = 57.5;     ///< m, R
  double load_radius = 0.7;       ///< share of R at which a blade's wind acts (the plant's effective radius)
  double lidar_distance = 100.0;  ///< m, D upstream
  double lidar_half_span = 0.5;   ///< beams at H +/- this * R (Figure 1: half the blade length)
  double tower_shadow = 0.1;      ///< relative wind deficit in front of the tower (azimuth pi); 0: none
  double shadow_width = 0.25;     ///< rad, Gaussian half-width of the shadow in azimuth
  double advection_time =
      600.0;                   ///< s, low-pass of the LIDAR hub speed: the mean flow carrying the turbulence
  double max_lidar_age = 1.0;  ///< s a delayed LIDAR value may be older than wanted
  double max_delay = 60.0;     ///< s, longest D / V kept (LIDAR history)
};

/// Expected moments of the three blades now from the LIDAR speeds measured D / V ago.
class LidarLoadModel {
 public:
  LidarLoadModel(const LoadModelConfig& c, const LoadTable* table);

  /// Stores a LIDAR measurement (NaN or out of range: ignored). A time before the newest stored one, or
  /// kLidarHistoryMaxStep after it, restarts the history: then it returns true.
  bool add_lidar(double t, double v_upper, double v_lower);
  /// s: a jump of the sample time this long is a stepped clock, not a LIDAR that held its value.
  static constexpr double kLidarHistoryMaxStep = 60.0;
  /// Expected flapwise moments of the three blades at time t (false: no delayed LIDAR value).
  bool moments(double t, double rotor_speed, double azimuth, const std::array<double, 3>& pitch,
               std::array<double, 3>& m);
  void reset();

  /// From the last moments() call: shear exponent, hub wind and tip-speed ratio of the delayed wind.
  double shear() const { return alpha_; }
  double v_hub() const { return v_hub_; }
  double lambda() const { return lambda_; }
  double advection_speed() const { return v_adv_; }
  /// s, D / V: how long after a restart of the history (or a hole in it) no delayed speed can be found.
  double delay() const { return have_adv_ ? c_.lidar_distance / std::max(v_adv_, 1.0) : c_.max_delay; }
  /// Time of the newest stored LIDAR measurement (-inf: none).
  double last_lidar_time() const { return history_.empty() ? -1e300 : history_.back()[0]; }

 private:
  LoadModelConfig c_;
  const LoadTable* table_;
  std::deque<std::array<double, 3>> history_;  // (t, upper, lower)
  double v_adv_ = 0.0, t_adv_ = 0.0, t_adv0_ = 0.0;
  bool have_adv_ = false;
  double alpha_ = 0.0, v_hub_ = 0.0, lambda_ = 0.0;
};

}  // namespace windfdi::blade_load
