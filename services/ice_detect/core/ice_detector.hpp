// Ice accretion and shedding on one turbine's rotor from its estimated inertia (Stotsky & Egardt 2013).
#pragma once

#include <cmath>
#include <deque>
#include <string>
#include <vector>

#include "fault_event.hpp"
#include "frame_sample.hpp"
#include "inertia_drop_test.hpp"
#include "inertia_estimator.hpp"
#include "input_context.hpp"
#include "turbine_params.hpp"
#include "yaml_config.hpp"

namespace windfdi::ice_detect {

struct DetectorConfig {
  EstimatorConfig estimator;
  double wind_window = 0.5;      ///< s, centred average of the anemometer before the power model (0: none)
  double clean_inertia = 0.0;    ///< kg m^2 generator side, J0; 0: the turbine's lumped inertia
  double learn_time = 0.0;       ///< s; > 0: learn J0 as the median estimate over this time instead
  double median_estimates = 61;  ///< 1 Hz estimates in the running median that is reported
  double ice_radius = 40.0;      ///< m, radius of gyration of the ice (m r^2 of rotor inertia)
  double gear_ratio = 95.0;      ///< N, to refer the rotor inertia to the generator side
  // Ice levels as a rise of the inertia over the clean rotor's J0, so that they hold on any turbine; on the
  // 4.8 MW benchmark rotor (J0 6484 kg m^2 generator side, ice at 40 m) 1 % is 366 kg of ice.
  double warning_rise = 0.0465;   ///< ice_accretion warning (1700 kg on the benchmark rotor)
  double fault_rise = 0.0684;     ///< severity fault (2500 kg)
  double critical_rise = 0.1230;  ///< severity critical, the arbiter stops the turbine (4500 kg)
  double critical_margin = 0.2;   ///< the stop level needs an estimate this share above critical_rise: the
                                  ///< estimate's error (1-4 % of inertia) must not stop a rotor below it
  double critical_confirm_time = 60.0;  ///< s of fresh (excited) estimates above it before critical is raised
  /// Those seconds are weighed by the regression's excitation as the first warning's are (first_excitation),
  /// with this k: full from k times min_excitation. 1: every fresh second counts fully, as before stop 50
  double critical_excitation = 2.0;
  double confirm_time = 10.0;  ///< s of fresh estimates, from a half-full median, above a level to raise it
  /// s of them above the warning level before a rotor with no ice reported gets its first report, always the
  /// warning (further levels then take confirm_time each)
  double first_confirm_time = 60.0;
  /// The first warning also needs this much evidence: the fresh seconds' rise above the warning level,
  /// summed, each second below taking its shortfall back (share of J0 times s; 0: first_confirm_time alone)
  double first_evidence = 1.0;
  /// A fresh second counts fully toward the first warning's time and evidence once the regression's
  /// excitation is this many times min_excitation; nearer the gate it counts ((e/g)^2 - 1) / (k^2 - 1) of a
  /// second (the estimate's variance falls as the excitation squared). 1: every fresh second counts fully
  double first_excitation = 1.5;
  /// The first warning also needs a rise of this many standard deviations of the clean rotor's estimate,
  /// learned from its fall below J0 (ice only raises the inertia, so that half is the estimator's error
  /// alone); 0: warning_rise alone
  double warning_sigmas = 3.5;
  double warning_noise_time = 1800.0;  ///< s of fresh estimates remembered for it; used after a third of it
  double clear_time = 30.0;            ///< s below the clear level before a raised level clears
  double clear_ratio = 0.7;            ///< a level clears below this share of its threshold (hysteresis)
  double shed_power_step =
      0.01;  ///< rise of the power model's calibration in one step that is shedding (0: off)
  /// s in a row the balance since such a step must hold shed_power_keep of the step before it is shedding
  /// (0: at once); a step the wind made leaves with the wind
  double shed_power_confirm = 10.0;
  double shed_power_keep = 0.5;  ///< share of the step as first seen the seconds after it must hold
  double ice_cp_loss = 0.02;     ///< share of Cp an iced rotor loses per tonne (sizes a shedding from its Cp)
  DropTestConfig drop_test;      ///< the inertia's own witness of a shedding (reference and windows)
  double shed_sigmas = 4.0;  ///< the fall of the inertia over its learned standard deviation that is shedding
  double shed_confirm = 5.0;     ///< s (tested seconds in a row) the fall must stand out
  double shed_min_drop = 0.025;  ///< share of J0: a smaller fall is no shedding however clear
  /// On a rotor whose ice takes Cp: the share of the Cp a fall's mass took (ice_cp_loss) that the calibration
  /// must have given back over the fall's window before the inertia's witness is shedding (0: off)
  double shed_inertia_cp_share = 0.2;
  double shed_min_rise = 0.0137;  ///< inertia rise (500 kg on the benchmark rotor) that must be estimated,
                                  ///< with ice_accretion raised, to shed
  double shed_hold = 60.0;        ///< s an ice_shedding report stays raised
  double min_generator_speed = 30.0;  ///< rad/s below which the estimator is not fed (standstill)
  double min_gen_torque = 3000.0;     ///< N m; below it the turbine is not producing (stopping): not fed
  /// m/s; samples pitched beyond what the turbine needs for rated power at rated speed in this wind
  /// (feathering, stopping: the power model is not trusted) are not fed
  double max_pitch_wind = 28.0;
  double max_pitch = 30.0;  ///< deg, that pitch: the loaded configuration takes it from the turbine
  /// s: samples lost over at most this long are bridged (the estimators fed the straight line between the
  /// samples either side) instead of restarting a regression of `window` s (0: every gap restarts it)
  double max_bridged_gap = 0.5;
  double speed_mismatch =
      0.05;  ///< relative |omega_g / N - omega_r| / omega_r (0.5 s low-pass) above which the
             ///< speed sensors disagree: the generator speed is suspect, not fed (0: off)
  /// While drive_train reports efficiency_loss, the shedding test takes no balance (and forgets those since
  /// the loss began): the balance divides by the turbine file's efficiency, and its step read as an inertia
  /// fall (false ice_shedding). The inertia regression goes on.
  bool efficiency_loss_holds = true;
};

/// Loads the `ice_detect` keys (unknown keys and out-of-range values are ConfigErrors).
DetectorConfig load_detector_config(const YamlSection& section, const TurbineParams& turbine);

/// The 1 Hz estimate.
struct InertiaOutput {
  double t = 0.0;
  double inertia = 0.0;        ///< kg m^2 generator side (median of the last estimates), 0 before any
  double inertia_clean = 0.0;  ///< J0
  double ice_mass = 0.0;       ///< kg
  bool excited = false;
};

/// One turbine: samples in (with their aerodynamic power), estimates and fault events out.
class IceDetector {
 public:
  IceDetector(const DetectorConfig& config, const TurbineParams& turbine);

  /// Feeds one sample whose aerodynamic power is `aero_power` (W; the node computes it from the aerodynamic
  /// model or takes the recording's column). Returns false for a rejected sample (NaN, infinite, out of
  /// range): counted, never fed. `gap`: samples were lost (or the clock stepped): a hole of at most
  /// max_bridged_gap between two fed samples is bridged, any other restarts the regression.
  bool update(const FrameSample& s, double aero_power, bool gap, std::vector<FaultEvent>& events);
  /// True once per second of sample time, with the estimate in `out`.
  bool estimate_due(InertiaOutput& out);

  uint64_t rejected() const { return rejected_; }
  /// Samples not fed because an input was suspect (speed_mismatch, or another service's fault on a speed or
  /// pitch sensor): the estimate is held instead.
  uint64_t suspect_samples() const { return suspect_samples_; }
  void set_context(const InputContext& context) { context_ = context; }
  const InertiaEstimator& estimator() const { return estimator_; }
  const InertiaDropTest& drop_test() const { return drop_test_; }

 private:
  void second(double t, std::vector<FaultEvent>& events);
  void level_events(double t, std::vector<FaultEvent>& events);

  DetectorConfig cfg_;
  double mass_per_inertia_;  // kg of ice per kg m^2 of generator-side inertia
  /// kg of ice that raises the clean inertia by `rise` (a share of J0).
  double ice_mass_at(double rise) const { return rise * j0_ * mass_per_inertia_; }
  InertiaEstimator estimator_;     // the reported inertia (long window)
  InertiaDropTest drop_test_;      // per-second balances: sees a shedding within a minute or two
  int shed_confirmed_ = 0;         // tested seconds in a row the fall stood out
  double shed_first_at_ = -1.0;    // the first of them
  double cp_candidate_ = 0.0;      // a step up of the calibration with ice reported, not yet kept (0: none)
  double cp_candidate_at_ = -1.0;  // when it was seen
  int cp_kept_ = 0;                // seconds in a row since, the balance since the step held the step
  std::size_t cp_counted_ = 0;     // the last second of balance since the step counted in cp_kept_
  std::deque<double> scale_history_;  // the calibration at each of the last seconds (the drop test's windows)
  /// s before a fall's onset the Cp it gives back is counted from (the calibration's step window lags it)
  static constexpr double kCpLead = 30.0;
  /// Entries of scale_history_ (not empty) `seconds` back from its newest, at most all of it.
  std::size_t history_back(double seconds) const;
  /// The calibration's relative rise over the last `seconds`.
  double cp_rise(double seconds) const;
  /// The calibration's relative distance below its highest of the last `seconds` (<= 0).
  double cp_below_highest(double seconds) const;
  double step_settled_at_ = -1.0;  // the calibration of the aerodynamics after its last step is known then
  double iced_at_ = -1.0;          // the last second ice was reported (-1: never)
  std::deque<double> ice_recent_;  // kg of ice reported in each of the last seconds (0: none reported)
  double below_square_ = 0.0;      // mean of min(rise, 0)^2 of fresh estimates while no ice is reported
  double below_learned_ = 0.0;     // s of it (warning_noise_time memory)
  /// The clean rotor's estimate's standard deviation (share of J0): twice the lower half's mean square.
  double clean_sd() const { return std::sqrt(2.0 * below_square_); }
  /// The rise the first warning needs.
  double first_warning_rise() const;
  /// The share of a second this second's estimate counts toward the first warning (first_excitation).
  double first_warning_weight() const;
  /// The share of a second an estimate at this excitation counts, full from k times min_excitation.
  double excitation_weight(double k) const;
  double calibrated_at_ = -1.0;  // time the power model was first calibrated
  double next_second_ = -1.0;
  bool due_ = false;
  InertiaOutput out_;
  std::deque<double> recent_;  // last raw estimates (1 Hz, excited only)
  std::vector<double> learning_;
  double j0_;
  // Accretion: the raised severity level (0 none, 1 warning, 2 fault, 3 critical) and its timers.
  int raised_level_ = 0;
  double above_since_ = -1.0, below_since_ = -1.0;
  double above_fresh_ =
      0.0;  // fresh seconds above the next level since above_since_ (from a half-full median)
  double critical_evidence_ = 0.0;  // s of fresh estimates above the stop level in the current run
  double first_evidence_ = 0.0;     // a clean rotor's rise above the warning level, summed (first_evidence)
  bool fresh_ = false;              // this second's estimate entered the median
  double shed_raised_at_ = -1.0;
  uint64_t power_changes_seen_ = 0;
  InputContext context_;
  bool fed_ = false;        // the last sample was fed to the estimators
  bool drop_held_ = false;  // the shedding test took no balance (drive train suspect)
  struct Fed {
    uint64_t sequence = 0;
    double t = 0, generator_speed = 0, power = 0, gen_torque = 0;
  } last_fed_;  // that sample
  // Feeds the estimators the straight line from last_fed_ to `s` over the samples lost between them; false
  // (nothing fed) when the hole is not whole samples of at most max_bridged_gap.
  bool bridge(const FrameSample& s, double power);
  double resumed_at_ = -1e300;  // sample time the estimators were last fed again after a reset
  double speed_mismatch_lp_ = 0.0;
  uint64_t suspect_samples_ = 0;
  uint64_t rejected_ = 0;
};

}  // namespace windfdi::ice_detect
