// A test for a step fall of the rotor inertia (ice shedding) on the torque balance of each second.
//
// The one-mass model of Stotsky & Egardt 2013 (eq 2), integrated over one second k of filtered signals:
//   J (omega_end - omega_start) = s X_k - G_k + c,
// X_k the second's integral of P / omega, G_k that of the generator-side torque, s the power model's
// calibration (the one before its last step for the seconds before), c a torque error that stands still
// for minutes. Seconds are independent measurements of J
// (the accumulated regressor of eq 3 is not: its error is a random walk), so the inertia of the last m
// seconds and that of the reference seconds before them are two independent least-squares slopes, and their
// difference has a variance known from the reference seconds' own residuals. A shedding at the onset of the
// last m seconds is that difference standing out of its variance, for the m that fits best.
#pragma once

#include <array>
#include <cstddef>
#include <deque>

namespace windfdi::ice_detect {

struct DropTestConfig {
  double sample_time = 0.01;        ///< s
  double filter_time = 0.5;         ///< s, the low-pass of the inertia estimator (drive-train mode)
  double power_gain = 0.97;         ///< drive-train efficiency dividing the generator-side torques
  double friction = 45.6;           ///< N m s/rad, generator-side friction
  double reference_window = 600.0;  ///< s of balances before the candidate onset: the inertia before it
  double reference_min = 120.0;     ///< s; with fewer reference seconds nothing is tested
  double window_min = 20.0;         ///< s, the shortest time since a candidate onset that is tested
  double window_max = 180.0;        ///< s, the longest
  double noise_time = 1800.0;       ///< s, memory of each window's learned calibration
  double prior_ratio = 1.5;   ///< each window's calibration before it has learned (1.0-2.2 on the plant's
                              ///< anemometer, 0.5-1.2 with a clean power signal)
  double prior_time = 300.0;  ///< s of learning that prior is worth
};

class InertiaDropTest {
 public:
  /// The times since a candidate onset that are tested (s), those within [window_min, window_max].
  static constexpr std::array<int, 7> kWindows{20, 30, 45, 60, 90, 120, 180};

  explicit InertiaDropTest(const DropTestConfig& config = {});

  /// Feeds one sample (generator speed rad/s, aerodynamic power W, generator torque N m).
  void update(double omega, double power, double gen_torque);
  /// The next sample does not follow the last one (a hole, a stop): the second under way is dropped; the
  /// complete ones stay, each is a measurement of its own.
  void restart();
  /// Forgets every balance (the rotor and the power model may have changed unseen); the learned calibration
  /// stays.
  void forget();
  /// Keeps only the newest `seconds` balances (after a shedding, the reference must start after it).
  void keep_newest(std::size_t seconds);
  /// The power model's calibration stepped within the newest `seconds`: those balances are dropped (they mix
  /// the two), the ones before keep `scale_before`, the one they were taken with.
  void calibration_stepped(std::size_t seconds, double scale_before);

  struct Result {
    bool tested = false;  ///< a window was learned and had its reference
    double z = 0.0;       ///< the largest fall of at least min_drop over its learned deviation (0: none)
    double drop = 0.0;    ///< that fall of the inertia, share of J0
    double since = 0.0;   ///< s, its window: the onset was this long ago
  };
  /// Tests the balances, with the power model's calibration `power_scale` where no step froze another, for
  /// falls of at least `min_drop` of `j0` in windows of at least `min_window` s, once per balance completed
  /// since the last call (none: not tested); `learn`: nothing is under way, each window's calibration learns
  /// from this second.
  Result test(double power_scale, double j0, double min_drop, double min_window, bool learn);
  std::size_t balances() const { return balances_.size(); }
  /// Each window's learned ratio of squared falls to their predicted variance (kWindows' order).
  const std::array<double, kWindows.size()>& calibration() const { return calibration_; }

 private:
  struct Balance {
    double x, g, dw;  // the second's integrals of P / omega and of the generator-side torque (N m s), speed
                      // change (rad/s)
    double scale =
        0.0;  // the calibration before a step that followed it (0: none followed, the newest holds)
    double impulse(double newest) const { return (scale > 0.0 ? scale : newest) * x - g; }  // N m s: J dw + c
  };
  struct Slope {
    double inertia = 0.0;   // kg m^2
    double sxx = 0.0;       // sum of the centred speed changes squared
    double residual = 0.0;  // residual variance per second ((N m s)^2)
  };
  Slope slope(std::size_t from, std::size_t count, double power_scale) const;

  DropTestConfig cfg_;
  double alpha_;
  std::size_t samples_per_second_;
  bool started_ = false;
  double omega_f_ = 0.0, x_f_ = 0.0, g_f_ = 0.0;
  double x_sum_ = 0.0, g_sum_ = 0.0, omega_start_ = 0.0;
  std::size_t samples_ = 0;
  std::deque<Balance> balances_;
  double elevated_ = 0.0;  // recent share of tested seconds with a fall standing out (learning holds)
  bool untested_ = false;  // a balance completed since the last test
  std::array<double, kWindows.size()> calibration_{};  // learned mean of drop^2 / predicted variance
  std::array<double, kWindows.size()> learned_{};      // s of it, the prior's included
};

}  // namespace windfdi::ice_detect
