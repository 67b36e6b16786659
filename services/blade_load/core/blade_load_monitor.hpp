// Blade-root moment sensor monitoring of one turbine (Stotsky 2014): its configuration, the per-sample
// orchestration of the first harmonic from each strain gauge and from the LIDAR load model, the residual
// tests and the load-table adaptation, its 10 Hz estimate and the state a restart keeps.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "episode_classifier.hpp"
#include "fault_event.hpp"
#include "frame_sample.hpp"
#include "harmonic_ls.hpp"
#include "healthy_channels.hpp"
#include "input_context.hpp"
#include "input_validity.hpp"
#include "load_model.hpp"
#include "residual_channels.hpp"
#include "residual_tests.hpp"
#include "statistics.hpp"
#include "surface_gate.hpp"
#include "suspect_inputs.hpp"
#include "table_adaptation.hpp"
#include "turbine_params.hpp"
#include "yaml_config.hpp"

namespace windfdi::blade_load {

/// The `blade_load` configuration. The YAML keys are flat (deploy/config/blade_load.yaml); here they are
/// grouped by the part of the monitor that reads them.
struct MonitorConfig {
  HarmonicConfig harmonic;       ///< sensor and model estimators (eqs 3-8)
  LoadModelConfig model;         ///< LIDAR load model (eqs 1, 9)
  double estimate_rate = 10.0;   ///< Hz, estimates and the per-sample outlier test
  double min_rotor_speed = 0.5;  ///< rad/s; below it (standstill, idling) nothing is estimated
  double max_bridged_gap = 0.5;  ///< s: a hole of lost samples at most this long leaves the gauge windows
                                 ///< running (they fit by azimuth); a longer one restarts every window
  ValidityConfig validity;       ///< max_moment, invalid_time (input_validity.hpp)
  DetectionConfig detection;  ///< the outlier and drift tests, confirmation, isolation (residual_tests.hpp)
  LearningConfig learning;    ///< the healthy statistics and the noise level (healthy_channels.hpp)
  GateConfig gate;            ///< the steep-surface gate (surface_gate.hpp)
  LullConfig lull;            ///< the lull hold (surface_gate.hpp)
  SuspectInputConfig suspect_inputs;  ///< speed and pitch redundancy, context hold (suspect_inputs.hpp)
  EpisodeConfig episode;        ///< return_time, intermittent_window, clear_time (episode_classifier.hpp)
  AdaptationConfig adaptation;  ///< the load table in uniform wind (table_adaptation.hpp)
};

/// Loads the `blade_load` keys (unknown keys and out-of-range values are ConfigErrors naming file and key).
MonitorConfig load_monitor_config(const YamlSection& section, const TurbineParams& turbine);

/// The 10 Hz estimate (the replay columns and BladeLoadEstimate).
struct BladeLoadOutput {
  double t = 0.0;
  std::array<double, 3> a1_sensor{kNaN, kNaN, kNaN};  ///< N m
  std::array<double, 3> a1_model{kNaN, kNaN, kNaN};   ///< N m
  std::array<double, 3> delta_a{kNaN, kNaN, kNaN};    ///< a1_model - a1_sensor (N m)
  std::array<bool, 3> valid{false, false, false};
  bool lidar_ok = false;
  double shear = kNaN;  ///< LIDAR shear exponent (-)
};

/// What a restart keeps: the learned table correction and the healthy statistics.
struct MonitorState {
  std::vector<double> table_factors;  ///< LoadTable::factors()
  int n_lambda = 0, n_pitch = 0;
  BladeHealthy healthy{};
};
/// Writes atomically (a temporary file beside it, then rename). Throws ConfigError on failure.
void save_state(const MonitorState& s, const std::string& path);
/// Reads a state file; false when it does not exist. A malformed file is a ConfigError.
bool load_state(const std::string& path, MonitorState& s);

/// Orchestrates one turbine's monitoring per sample: input validity, the two estimators of each blade, the
/// revolution and the estimate rate, the gate, the tests and the table adaptation.
class BladeLoadMonitor {
 public:
  BladeLoadMonitor(const MonitorConfig& config, LoadTable table);

  /// Feeds one sample. Returns false when it was rejected (rotor speed or azimuth missing, standstill).
  /// `gap`: samples were lost, the windows restart.
  bool update(const FrameSample& s, bool gap, std::vector<FaultEvent>& events);
  /// True at the estimate rate, with the estimate in `out`.
  bool estimate_due(BladeLoadOutput& out);

  MonitorState state() const;
  /// Restores a saved state (a table of another shape keeps the shipped table; statistics are still used).
  void restore(const MonitorState& s);

  // Introspection for tests, benchmarks and the README's measurements.
  const LoadTable& table() const { return table_; }
  const HealthyStats& healthy(int blade, int channel) const { return tests_.healthy().at(blade, channel); }
  bool learned() const;
  /// Largest |outlier t| / critical value seen per channel after learning (a healthy run's margin).
  double max_ratio(int channel) const { return tests_.max_ratio(channel); }
  /// The factor a channel's t-values are divided by now (>= 1; noise_revolutions).
  double noise_scale(int channel) const { return tests_.noise_scale(channel); }
  /// The class raised on a blade ("" when none).
  const std::string& raised(int blade) const { return tests_.raised(blade); }
  int adaptations() const { return adaptation_.adaptations(); }
  const HarmonicEstimator& sensor_estimator(int blade) const { return *sensor_[blade]; }
  const HarmonicEstimator& model_estimator(int blade) const { return *model_[blade]; }
  const LidarLoadModel& load_model() const { return lidar_; }
  uint64_t rejected() const { return rejected_; }
  /// Samples on which the steep-surface gate closed (a blade's pitch where k_M is steep, or a suspect input),
  /// and revolutions that were not tested because of it.
  uint64_t gated_samples() const { return gate_.closed_samples(); }
  uint64_t gated_revolutions() const { return gated_revolutions_; }
  /// Revolutions whose mean blade load was a lull's (their outlier test is held; lull_load_share).
  uint64_t lull_revolutions() const { return lull_revolutions_; }
  /// Samples held because an input of the load model was suspect (speed_mismatch, pitch_mismatch, context).
  uint64_t suspect_samples() const { return suspects_.suspect_samples(); }
  /// The inputs' context (input_context.hpp) from sample time t on.
  void set_context(const InputContext& context, double t) { suspects_.set_context(context, t); }
  /// Relative spread of k_M over pitch +/- gate_pitch_margin at (lambda, pitch) (0 when k_M is 0 there).
  double model_sensitivity(double lambda, double pitch_deg) const {
    return gate_.sensitivity(table_, lambda, pitch_deg);
  }
  /// The last revolution's channel values of a blade (NaN: not available).
  const std::array<double, kChannels>& last_revolution(int blade) const { return last_x_[blade]; }

 private:
  void reset_windows();
  bool gated() const;  // the windows hold a sample the gate closed on
  // `held`: gated() now.
  void revolution(double t, bool held);                             // once per revolution
  void tick(double t, bool held, std::vector<FaultEvent>& events);  // estimate rate

  MonitorConfig cfg_;
  LoadTable table_;
  LidarLoadModel lidar_;
  std::array<std::unique_ptr<HarmonicEstimator>, 3> sensor_, model_;
  BladeEstimates est_;  // of the last solve
  InputValidity validity_;
  SuspectInputs suspects_;
  SurfaceGate gate_;
  LullHold lull_;
  ResidualTests tests_;
  TableAdaptation adaptation_;
  double next_tick_ = -1.0;
  double rev_angle_ = 0.0, last_azimuth_ = kNaN;
  double last_t_ = kNaN;        // time of the last sample
  uint64_t last_sequence_ = 0;  // and its sequence
  double rev_time_ = 0.0, last_rev_t_ = -1.0;
  bool due_ = false;
  BladeLoadOutput out_;
  uint64_t rejected_ = 0;
  uint64_t gated_revolutions_ = 0, lull_revolutions_ = 0;
  BladeChannels last_x_{};
};

}  // namespace windfdi::blade_load
