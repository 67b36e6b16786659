// The tests on each blade's residual channels (Stotsky 2014: a t-test per sample for outliers, a
// moving-window mean test for drift), their confirmation and single-blade isolation, and the fault classes
// they raise.
#pragma once

#include <array>
#include <deque>
#include <string>
#include <vector>

#include "episode_classifier.hpp"
#include "fault_event.hpp"
#include "healthy_channels.hpp"
#include "noise_follower.hpp"
#include "residual_channels.hpp"

namespace windfdi::blade_load {

enum class Witness { kOff, kConfirm, kSensors };

/// Detection (Stotsky 2014: t-test per sample for outliers, moving-window mean test for drift).
struct DetectionConfig {
  // The two tests.
  double significance = 1e-8;        ///< two-sided level of the outlier t-test per 10 Hz sample (0..0.1)
  double drift_significance = 1e-8;  ///< two-sided level of the moving-window mean test per revolution
  /// A second, looser level on the mean-load channels (kMean, kRawMean), the ones a drift moves (a constant
  /// added to a gauge leaves its first harmonic alone), for a window-mean shift of at least min_drift_share
  /// that the other mean-load channel shares.
  double mean_drift_significance = 1e-5;
  /// Least window-mean shift, as a share of the rotor's mean blade load, that the looser level acts on: the
  /// healthy 10-revolution means stay below 1.4 % (0.1 % of them above 1 %), while the t statistic alone
  /// passes 1e-5 on shifts of 0.3 % where the healthy spread is narrow (20 m/s).
  double min_drift_share = 0.01;
  /// A drift on a mean-load channel is raised only once its window mean has moved by min_drift_share, at
  /// either level (the strict one fires on t alone and counts its revolutions meanwhile). At 8 m/s the t
  /// statistic reached 9.3 against 7.5 on a healthy 10-revolution excursion of 0.6-0.8 % (healthy suite set
  /// 185, benchmark turbine, TI 0.121, 235 s after learning), whose peak was 0.94 %. false: t alone
  bool drift_raise_needs_share = true;
  int drift_window = 10;  ///< revolutions in the moving-window mean
  /// A drift moves the window's median, not only its mean: the median of the window's revolutions, on the
  /// channel it fires on, must carry this share of the window mean's shift, in its direction (0: off). A
  /// ramp's and an offset's median carries about its mean; a burst of one or two revolutions moves the mean
  /// for ten revolutions and the median not at all: judged suite set 191 (medium-speed rotor, 10.1 m/s), an
  /// intermittent gauge's first 6 s burst came in a lull, which holds the outlier test, and was raised as
  /// sensor_drift 11 s after it had ended.
  double drift_median_share = 0.5;
  /// Consecutive revolutions the moving-window test must fire on the same channel and sign before it raises
  /// (1: at once). A drift keeps growing past the critical value; a slow excursion of the LIDAR model's
  /// error or of the cross-blade mean touches it and falls back.
  int drift_confirm_revolutions = 4;
  /// The two mean-load channels (kMean, kRawMean) count as one for those consecutive revolutions: a drift
  /// moves both by the same share, and which is the larger t flips with the noise. Counted per channel, each
  /// flip restarted the count (a synthetic ramp raised 3 revolutions later). false: as before stop 64
  bool mean_channels_count_as_one = true;
  // Confirmation of an outlier run.
  double confirm_time = 1.0;  ///< s of continuous same-sign exceedance of one channel to raise (0.1..600)
  /// And at least this many revolutions (0..20): a single-revolution transient stays in the one-revolution
  /// window for exactly one revolution.
  double confirm_revolutions = 1.1;
  double onset_ratio = 0.5;  ///< a run of exceedance starts above this share of the critical value (0.1..1)
  /// A raised fault stays evidenced by a run above the onset level only in the direction it was raised in
  /// (the gauge reading high or low): after a drift's end a healthy gauge's runs past half the critical value
  /// the other way, and the wind's either way, kept a drift raised 665 s. false: any run, as before stop 49
  bool hold_in_raised_direction = true;
  double fast_ratio = 1.25;        ///< a large step: above this multiple of the critical value (0: off) ...
  double fast_confirm_time = 1.0;  ///< ... continuously for this long (s) raises before confirm_revolutions
  /// The fast path skips the revolution's persistence, so it takes only evidence no wind structure gives:
  /// the other (unraised) blades' LIDAR residuals below the onset level, and on a mean-load channel the
  /// gauges' own cross-blade mean isolating the blade too. Healthy rotors, a gust the two beams did not see
  /// for about a revolution, raised sensor_abrupt at 1.4-1.6 times the critical value: judged suite set 207
  /// (benchmark, 20 m/s; the gauges' own means put blade 3 with blade 1), set 201 (6 MW example, 12 m/s;
  /// another blade's LIDAR residual at 0.78 of its critical value). false: as before stop 62
  bool fast_needs_clean_witnesses = true;
  // Isolation: the other blades as witnesses.
  double isolation_ratio = 0.5;  ///< cross-blade channels: the other two blades must agree with each other,
                                 ///< |x_o1 - x_o2| <= this * |x_b - mean(x_o)| (a single-sensor fault, 0..2)
  /// While another blade's gauge fault is raised, a new cross-blade raise needs this blade's own LIDAR
  /// residual beyond the onset level and above the unraised other blade's (none without the LIDAR): one
  /// witness is left, and a load change on it reads as this blade's opposite excursion. false: as before
  /// stop 48
  bool second_fault_model_witness = true;
  /// The cross-blade mean-load ratio (kMean, normalised by each blade's LIDAR model) raises nothing while an
  /// unraised other blade's LIDAR residual is beyond mean_model_witness_ratio of its critical value: the
  /// model does not explain the wind on that blade, and its mean is as wrong (a failed gauge moves only its
  /// own blade's residuals). Healthy suite seeds 133, 134 and 142: 5 false gauge reports at 12-17.4 m/s,
  /// turbulence 0.14-0.16 -> 0 (README)
  bool mean_model_witness = true;
  /// That other blade's LIDAR residual, as a share of its critical value. 0.5 (the onset level) put a pitch
  /// bias's secondary drift 11.7 s later with 2 % of the samples lost (tests/reliability/lost_samples.py
  /// allows 10 s; passes from 0.7); seed 134's false drift returns from 1.0
  double mean_model_witness_ratio = 0.8;
  /// The cross-blade mean-load ratio (kMean) raises an outlier only while the gauges' own cross-blade mean
  /// (kRawMean) shares its excursion from healthy: same sign, at least mean_gauge_witness_share of it. A
  /// failed gauge moves its mean against the other gauges as much as against the LIDAR model (a gain g: by
  /// 3(g-1)/(g+2) and g-1); the model's error on one blade moves only the ratio. Healthy suite set 185
  /// (medium-speed rotor, 12 m/s, TI 0.133): the ratio at +2.5 % for 5 s, the gauges' mean below half of
  /// it, raised sensor_abrupt at 1.003 times the critical value. 0: off
  double mean_gauge_witness_share = 0.5;
  /// The drift test's agreement between the two mean-load channels (kMean and kRawMean) needs the witness
  /// channel to isolate the blade as well, not only to share its shift: a failed gauge moves its blade on
  /// both channels and each other blade by about half as much the other way. On a healthy 6 MW rotor (8 m/s,
  /// TI 0.148, shear 0.30; judged suite set 237) blade 1's ratio stood at +1.3 to +1.6 % for ten
  /// revolutions and the gauges' own mean at +0.9 to +1.2 %, but that channel put blade 2 at -1.7 % and
  /// blade 3 at +0.3 %: the wind on blade 2, not blade 1's gauge. It raised sensor_drift. false: as before
  /// stop 64
  bool mean_witness_isolates = true;
  /// kConfirm: the LIDAR residual counts only if the cross-blade model residual agrees (sign and
  /// witness_significance); kSensors: and the gauges' own cross-blade amplitude is beyond the same test's
  /// critical value, in the same direction; kOff: the paper's LIDAR residual alone.
  Witness witness = Witness::kSensors;
  double witness_significance = 1e-2;  ///< two-sided level of that agreement
  bool mean_test = true;  ///< cross-blade mean-load test (the only one that sees an offset or drift)
  // Class of a confirmed outlier: abrupt or drift.
  double abrupt_ratio =
      0.25;  ///< abrupt if before detection the mean t (signed along the excursion) was below
             ///< this share of the critical value (the residual stepped), else drift (it ramped)
  int abrupt_lookback = 2;   ///< revolutions back where that mean starts (a step is confirmed within ~1.1)
  int abrupt_span = 4;       ///< revolutions in that mean (a step leaves it at 0 +- 0.5 in t units)
  int ramp_revolutions = 2;  ///< a confirmed outlier is a drift too when each of this many revolutions before
                             ///< the newest reached abrupt_ratio of the critical value (0: off)
  /// A confirmed outlier is abrupt, whatever the two rules above say, when a revolution of the span stood
  /// beyond the critical value and the two before the newest are back below the onset level (signed along
  /// the excursion): a ramp only grows, and that is an earlier episode that ended (an intermittent gauge's
  /// burst unseen in a lull, which read as a ramp and named the next burst sensor_drift). false: as before
  bool step_after_quiet = true;
  /// step_after_quiet with only the one revolution before the newest back below the onset level, when the
  /// earlier revolution stood at this multiple of the critical value (0: off). Between an intermittent
  /// gauge's bursts 14 s apart, rotors of 4.5-5.6 s a revolution (the 1.5 and 6 MW examples) have one quiet
  /// revolution, the ones either side holding the bursts' edges; their bursts stood at 2.4 and 6.4 times the
  /// critical value, a ramp's noisy revolutions at up to 1.2 before a dip below the onset level.
  double quiet_step_strength = 2.0;
  double held_step_share = 0.06;  ///< when most of those revolutions were held (a pitch or speed fault): a
                                  ///< step if the excursion is at least this share of the other blades'
                                  ///< reading (the smallest specified step is a 10 % gain), else a drift
                                  ///< (1.5 %/min through a 2-minute hold is 3 %)
};

/// The tests of the three blades of one turbine, with the healthy statistics they compare with. Time and the
/// channel values come in; raised and cleared classes go out as FaultEvents.
class ResidualTests {
 public:
  ResidualTests(const DetectionConfig& detection, const LearningConfig& learning,
                const EpisodeConfig& episode);

  /// Once per revolution, at time t (s) with the revolution time (s) and the revolution's channel values
  /// (NaN: not available; all NaN on a window the gate holds): follows the noise level, learns and adapts
  /// the healthy statistics, runs the moving-window mean test. `lidar_ok`: the LIDAR channels may judge.
  void revolution(double t, double revolution_time, const BladeChannels& x, bool lidar_ok);
  /// At the estimate rate on a window the gate holds: no run continues through it, an episode is held as it
  /// is.
  void hold();
  /// At the estimate rate: the outlier test of each blade on the channel values `x` of the estimates `e`,
  /// its confirmation, the classes raised and cleared (in `events`).
  void tick(double t, double revolution_time, const BladeChannels& x, const BladeEstimates& e, bool lidar_ok,
            std::vector<FaultEvent>& events);

  const HealthyChannels& healthy() const { return healthy_; }
  /// Restores saved healthy statistics and the critical values that follow from them.
  void restore(const BladeHealthy& s);
  /// Largest |outlier t| / critical value seen per channel after learning (a healthy run's margin).
  double max_ratio(int channel) const { return max_ratio_[channel]; }
  /// The factor a channel's t-values are divided by now (>= 1; noise_revolutions).
  double noise_scale(int channel) const { return noise_.scale(channel); }
  /// The class raised on a blade ("" when none).
  const std::string& raised(int blade) const { return blades_[blade].raised; }
  bool any_raised() const;
  /// Some channel of the blade is above its threshold now (or, raised, above its onset level).
  bool exceeding(int blade) const { return blades_[blade].exceeding; }

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
    int drift_revolutions = 0;  // consecutive revolutions the drift test fired on drift_channel, same sign
    double drift_shift = 0.0;   // largest firing mean-load shift from healthy, drift_t's sign (share of load)
    bool drift_spread = false;  // the window's median carries drift_channel's shift (drift_median_share)
    std::string raised;         // class raised, "" none (mirrors the classifier)
    int raised_direction = 0;   // +1: raised on the gauge reading high, -1: low (0: none, or unknown)
    EpisodeClassifier episode;
  };

  void critical_values();
  bool standalone(int channel, bool lidar_ok) const;  // may decide alone now
  // The LIDAR residual's t confirmed by the witnesses (crit: the test's critical values).
  bool witnessed(const BladeChannels& t, int blade, const std::array<double, kChannels>& crit) const;
  // Channel c of blade b differs from each other blade's, in the direction of its own excursion, by at
  // least isolation_ratio of its distance to their mean (x: values or window means).
  bool isolated(const BladeChannels& x, int b, int c) const;
  // A new raise on a cross-blade channel while another blade's gauge is raised: its own LIDAR residual
  // (t, beyond the onset level of model_crit) must say it is this blade, more than the unraised other's.
  bool second_fault_witnessed(const BladeChannels& t, int blade, double model_crit, bool lidar_ok) const;
  // Another blade than `blade` (with `only_unraised`, one with no raised gauge) has its LIDAR residual's t
  // beyond `level`: the model misses the wind there.
  bool other_model_residual_beyond(const BladeChannels& t, int blade, double level, bool only_unraised) const;
  double t_value(int blade, int channel, double x) const;  // NaN when not learned or x is not available
  void follow_noise(const BladeChannels& x);
  // The blades whose gauge is raised, when the noise followers hold their pairs (noise_holds_raised).
  std::array<bool, 3> noise_held() const;
  void drift_test(bool lidar_ok);
  // `known`: some test could judge blade b now (false while its windows refill).
  void blade_decision(int b, double t, bool active, bool confirmed, double stat, double crit, int channel,
                      double size, const BladeEstimates& e, bool lidar_ok, bool known,
                      std::vector<FaultEvent>& events);

  DetectionConfig c_;
  HealthyChannels healthy_;
  std::array<BladeState, 3> blades_;
  std::array<double, kChannels> max_ratio_{};
  std::array<double, kChannels> crit_{}, drift_crit_{};
  std::array<double, kChannels> mean_drift_crit_{};  // at mean_drift_significance (mean-load channels)
  double witness_crit_ = 0.0;
  NoiseFollower noise_;        // of the one-revolution values
  NoiseFollower drift_noise_;  // of the drift test's window means
  bool noise_holds_raised_;
};

}  // namespace windfdi::blade_load
