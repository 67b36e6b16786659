// Blade-root moment sensor monitoring of one turbine (Stotsky 2014): first harmonic from each strain gauge
// and from the LIDAR load model, t-tests on their difference with the other blades as a second witness, fault
// classes, load-table adaptation in uniform wind, and the state a restart keeps.
#pragma once

#include <array>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "episode_classifier.hpp"
#include "fault_event.hpp"
#include "frame_sample.hpp"
#include "harmonic_ls.hpp"
#include "input_context.hpp"
#include "load_model.hpp"
#include "statistics.hpp"
#include "turbine_params.hpp"
#include "yaml_config.hpp"

namespace windfdi::blade_load {

enum class Witness { kOff, kConfirm };

struct MonitorConfig {
  HarmonicConfig harmonic;       ///< sensor and model estimators (eqs 3-8)
  LoadModelConfig model;         ///< LIDAR load model (eqs 1, 9)
  double estimate_rate = 10.0;   ///< Hz, estimates and the per-sample outlier test
  double min_rotor_speed = 0.5;  ///< rad/s; below it (standstill, idling) nothing is estimated
  double max_moment = 5e7;       ///< N m, |blade moment| above it is out of range (sensor_invalid)
  double invalid_time = 1.0;     ///< s a blade moment or the LIDAR must stay invalid before sensor_invalid
  // Detection (Stotsky 2014: t-test per sample for outliers, moving-window mean test for drift).
  double significance = 1e-8;        ///< two-sided level of the outlier t-test per 10 Hz sample (0..0.1)
  double drift_significance = 1e-8;  ///< two-sided level of the moving-window mean test per revolution
  int drift_window = 10;             ///< revolutions in the moving-window mean
  double learn_time = 200.0;  ///< s of healthy start-up from which each residual's distribution is learned
                              ///< (robust: median and MAD of one value per revolution)
  int min_learn_revolutions = 20;    ///< and at least this many revolutions
  double healthy_adapt_time = 3600;  ///< s, time constant of the slow healthy-statistics update (0: frozen);
                                     ///< applied only while nothing is raised on the turbine
  double confirm_time = 1.0;  ///< s of continuous same-sign exceedance of one channel to raise (0.1..600)
  double confirm_revolutions =
      1.1;                   ///< and at least this many revolutions (0..20): a single-revolution transient
                             ///< stays in the one-revolution window for exactly one revolution
  double onset_ratio = 0.5;  ///< a run of exceedance starts above this share of the critical value (0.1..1)
  double noise_revolutions = 20.0;  ///< revolutions over which each residual's present noise level is
                                    ///< followed (0: off): its t-values are divided by max(1, that level /
                                    ///< the learned one), read from the quietest of the three pairs of
                                    ///< blades, which one fault leaves alone
  double fast_ratio = 1.25;         ///< a large step: above this multiple of the critical value (0: off) ...
  double fast_confirm_time = 1.0;   ///< ... continuously for this long (s) raises before confirm_revolutions
  // Steep-surface gate: where k_M(lambda, pitch) changes by more than gate_max_sensitivity (relative) within
  // +/- gate_pitch_margin deg of a blade's (low-passed) measured pitch, neither the table (0.5 deg nodes) nor
  // the pitch measurement (0.2 deg noise) determines the load: the plant's Heier Cp is singular at -1 deg
  // (beta^3 + 1 = 0), where the thrust drops from ~0.5 to 0 within 0.3 deg. Every window that holds such a
  // sample is not tested (and not learned); an episode in progress is held, neither confirmed nor quiet.
  double gate_pitch_margin = 0.25;     ///< deg (0: no gate)
  double gate_max_sensitivity = 0.25;  ///< (max - min) / max of k_M over pitch +/- margin
  double gate_pitch_filter = 0.2;      ///< s, low-pass of the measured pitch for the gate (noise 0.2 deg)
  // Inputs the load model relies on (rotor speed for lambda, each blade's pitch for k_M): while one is
  // suspect no window is tested or learned (the steep-surface gate's hold), and an episode in progress is
  // held.
  double gear_ratio = 0.0;       ///< N (turbine file): the generator speed / N is the rotor speed's twin
  double speed_mismatch = 0.05;  ///< relative |omega_r - omega_g / N| / omega_r (0.5 s low-pass) above which
                                 ///< the two speed sensors disagree: lambda is not known (0..1, 0: off)
  double pitch_mismatch = 3.0;  ///< deg, |pitch_i - pitch_ref_i| (0.5 s low-pass) above which blade i's pitch
                                ///< reading or its actuator is not what the model assumes (0: off; healthy
                                ///< lag 1 deg at 10 deg/s)
  double context_hold = 10.0;   ///< s held after another service raised or cleared a fault on an input the
                                ///< model uses (a speed or pitch sensor, an actuator), or the arbiter
                                ///< reconfigured the controller; held as long as such a fault stays raised
  double isolation_ratio = 0.5;  ///< cross-blade channels: the other two blades must agree with each other,
                                 ///< |x_o1 - x_o2| <= this * |x_b - mean(x_o)| (a single-sensor fault, 0..2)
  double robust_clip = 3.0;      ///< healthy adaptation: a value's deviation is clipped at this many sd
  double abrupt_ratio = 0.5;     ///< abrupt if two revolutions before detection |t| was below this share of
                                 ///< the critical value (the residual stepped), else drift (it ramped)
  int abrupt_lookback = 2;       ///< revolutions back for that comparison
  EpisodeConfig episode;         ///< return_time, intermittent_window, clear_time (episode_classifier.hpp)
  Witness witness = Witness::kConfirm;  ///< kConfirm: the LIDAR residual counts only if the cross-blade
                                        ///< amplitude residual agrees (sign and witness_significance)
  double witness_significance = 1e-2;   ///< two-sided level of that agreement
  bool mean_test = true;  ///< cross-blade mean-load test (the only one that sees an offset or drift)
  // Load-table adaptation in uniform wind (Stotsky 2014, last section).
  bool adapt = true;
  double uniform_shear = 0.04;      ///< |LIDAR shear exponent| below which the wind is uniform
  int adapt_revolutions = 20;       ///< consecutive uniform revolutions averaged for one update
  double adapt_gain = 0.2;          ///< share of the way to the measured ratio per update (0..1)
  double adapt_bound = 0.15;        ///< largest correction of the shipped table, +/- share
  double adapt_sigma_lambda = 0.5;  ///< tip-speed-ratio width of an update on the surface
  double adapt_sigma_pitch = 1.5;   ///< deg, pitch width of an update
  double adapt_max_lambda_spread =
      0.5;  ///< operating point must stay within this lambda range while averaging
  double adapt_max_pitch_spread = 2.0;  ///< and within this pitch range (deg)
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

/// Residual channels per blade, each with its own healthy distribution.
/// kModel: (A_model - A_sensor) / mean load (the paper's delta_A). kWitness: the same residual minus the
/// other two blades' (a common LIDAR-model error cancels). kMean: the sensor/model mean-load ratio minus the
/// other blades' (an offset or drift). kRawWitness, kRawMean: the sensors alone against each other, when the
/// LIDAR is missing.
enum Channel {
  kModelChannel = 0,
  kWitnessChannel,
  kMeanChannel,
  kRawWitnessChannel,
  kRawMeanChannel,
  kChannels
};
/// One value per blade and residual channel.
using BladeChannels = std::array<std::array<double, kChannels>, 3>;
const char* channel_name(int c);

/// What a restart keeps: the learned table correction and the healthy statistics.
struct MonitorState {
  std::vector<double> table_factors;  ///< LoadTable::factors()
  int n_lambda = 0, n_pitch = 0;
  std::array<std::array<HealthyStats, kChannels>, 3> healthy{};
};
/// Writes atomically (a temporary file beside it, then rename). Throws ConfigError on failure.
void save_state(const MonitorState& s, const std::string& path);
/// Reads a state file; false when it does not exist. A malformed file is a ConfigError.
bool load_state(const std::string& path, MonitorState& s);

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
  const HealthyStats& healthy(int blade, int channel) const { return healthy_[blade][channel]; }
  bool learned() const;
  /// Largest |outlier t| / critical value seen per channel after learning (a healthy run's margin).
  double max_ratio(int channel) const { return max_ratio_[channel]; }
  /// The factor a channel's t-values are divided by now (>= 1; noise_revolutions).
  double noise_scale(int channel) const { return noise_[channel].scale; }
  /// The class raised on a blade ("" when none).
  const std::string& raised(int blade) const { return blades_[blade].raised; }
  int adaptations() const { return adaptations_; }
  const HarmonicEstimator& sensor_estimator(int blade) const { return *sensor_[blade]; }
  const HarmonicEstimator& model_estimator(int blade) const { return *model_[blade]; }
  const LidarLoadModel& load_model() const { return lidar_; }
  uint64_t rejected() const { return rejected_; }
  /// Samples on which the steep-surface gate closed (a blade's pitch where k_M is steep), and revolutions
  /// that were not tested because of it.
  uint64_t gated_samples() const { return gated_samples_; }
  uint64_t gated_revolutions() const { return gated_revolutions_; }
  /// Samples held because an input of the load model was suspect (speed_mismatch, pitch_mismatch, context).
  uint64_t suspect_samples() const { return suspect_samples_; }
  /// The inputs' context (input_context.hpp) from sample time t on.
  void set_context(const InputContext& context, double t) { suspects_.set(context, t); }
  /// Relative spread of k_M over pitch +/- gate_pitch_margin at (lambda, pitch) (0 when k_M is 0 there).
  double model_sensitivity(double lambda, double pitch_deg) const;
  /// The last revolution's channel values of a blade (NaN: not available).
  const std::array<double, kChannels>& last_revolution(int blade) const { return last_x_[blade]; }

 private:
  struct BladeState {
    std::deque<std::array<double, kChannels>> history;    // per-revolution values
    std::deque<std::array<double, kChannels>> t_history;  // per-revolution outlier t
    std::array<double, kChannels>
        run_start{};  // start of the channel's continuous same-sign exceedance (-1 none)
    std::array<int, kChannels> run_sign{};
    std::array<double, kChannels> fast_start{};  // start of the run's stretch above fast_ratio (-1 none)
    bool exceeding = false;                      // any eligible channel above its threshold now
    bool drift_firing = false;
    double drift_t = 0.0;
    int drift_channel = -1;
    std::string raised;  // class raised, "" none (mirrors the classifier)
    EpisodeClassifier episode;
    double invalid_since = -1.0;
    bool invalid_raised = false;
  };

  void reset_windows();
  void tick(double t, std::vector<FaultEvent>& events);        // estimate rate
  void revolution(double t, std::vector<FaultEvent>& events);  // once per revolution
  void channel_values(BladeChannels& x) const;
  void blade_decision(int b, double t, bool active, bool confirmed, double stat, double crit, int channel,
                      double size, std::vector<FaultEvent>& events);
  void maybe_adapt(double t);
  FaultEvent event(double t, const std::string& component, const std::string& fault, bool raised) const;
  double crit(int channel) const;
  bool standalone(int channel) const;  // may decide alone now
  bool any_raised() const;

  MonitorConfig cfg_;
  LoadTable table_;
  LidarLoadModel lidar_;
  std::array<std::unique_ptr<HarmonicEstimator>, 3> sensor_, model_;
  std::array<bool, 3> sensor_valid_{}, model_valid_{};
  std::array<double, 3> a_sensor_{}, a_model_{}, mean_sensor_{}, mean_model_{};
  bool lidar_ok_ = false;
  double lidar_bad_since_ = -1.0;
  bool lidar_raised_ = false;
  double next_tick_ = -1.0;
  double rev_angle_ = 0.0, last_azimuth_ = kNaN;
  bool due_ = false;
  BladeLoadOutput out_;
  std::array<BladeState, 3> blades_;
  std::array<std::array<HealthyLearner, kChannels>, 3> learners_;
  std::array<std::array<HealthyStats, kChannels>, 3> healthy_{};
  std::array<double, kChannels> first_value_t_{-1, -1, -1, -1, -1};
  std::array<double, kChannels> max_ratio_{};
  double crit_[kChannels] = {};
  double witness_crit_ = 0.0, drift_crit_[kChannels] = {};
  // Each residual's present noise level, read from the three pairs of blades (the mean square of each pair's
  // difference over noise_revolutions), and the factor >= 1 the t-values are divided by.
  struct NoiseLevel {
    std::array<double, 3> pair_var{-1.0, -1.0,
                                   -1.0};  ///< mean square of each pair's difference; < 0: not started
    double scale = 1.0;
  };
  std::array<NoiseLevel, kChannels> noise_{},
      drift_noise_{};  // one-revolution values; the drift test's window means
  void follow_noise(const BladeChannels& deviation, const BladeChannels& unit,
                    std::array<NoiseLevel, kChannels>& level) const;
  double channel_t(int blade, int channel, double x) const;
  void update_noise(const BladeChannels& x);
  double rev_time_ = 0.0, last_rev_t_ = -1.0;
  // Adaptation accumulators.
  int adapt_n_ = 0;
  double adapt_sensor_ = 0, adapt_model_ = 0, adapt_lmin_ = 0, adapt_lmax_ = 0, adapt_pmin_ = 0,
         adapt_pmax_ = 0, adapt_lsum_ = 0, adapt_psum_ = 0;
  double shear_sum_ = 0.0, lambda_sum_ = 0.0, pitch_sum_ = 0.0;
  int op_n_ = 0;
  int adaptations_ = 0;
  uint64_t rejected_ = 0;
  double last_pitch_mean_ = 0.0;
  BladeChannels last_x_{};
  // Steep-surface gate.
  std::array<double, 3> pitch_lp_{kNaN, kNaN, kNaN};
  uint64_t since_steep_ = UINT64_MAX / 2;  // samples since the last sample with a blade on a steep k_M
  uint64_t gated_samples_ = 0, gated_revolutions_ = 0;
  bool gated() const;
  // Suspect inputs.
  bool inputs_suspect(const FrameSample& s);
  SuspectHold suspects_;
  double speed_mismatch_lp_ = 0.0;
  std::array<double, 3> pitch_mismatch_lp_{};
  uint64_t suspect_samples_ = 0;
};

}  // namespace windfdi::blade_load
