// The steep-surface gate: no test, learning or adaptation on a window whose load the model does not determine
// (a blade's pitch where k_M(lambda, pitch) is steep, Stotsky 2014 eq 9) or whose model inputs are suspect.
// The lull hold: no outlier test on a window whose mean blade load has fallen well below the usual one.
#pragma once

#include <array>
#include <cstdint>

#include "frame_sample.hpp"
#include "load_model.hpp"

namespace windfdi::blade_load {

/// Steep-surface gate (YAML keys `gate_pitch_margin`, `gate_max_sensitivity`, `gate_pitch_filter`): where
/// k_M(lambda, pitch) changes by more than max_sensitivity (relative) within +/- pitch_margin deg of a
/// blade's (low-passed) measured pitch, neither the table (0.5 deg nodes) nor the pitch measurement (0.2 deg
/// noise) determines the load: the plant's Heier Cp is singular at -1 deg (beta^3 + 1 = 0), where the thrust
/// drops from ~0.5 to 0 within 0.3 deg. Every window that holds such a sample is not tested (and not
/// learned); an episode in progress is held, neither confirmed nor quiet.
struct GateConfig {
  double pitch_margin = 0.25;     ///< deg (0: no gate)
  double max_sensitivity = 0.25;  ///< (max - min) / max of k_M over pitch +/- margin
  double pitch_filter = 0.2;      ///< s, low-pass of the measured pitch for the gate (noise 0.2 deg)
};

class SurfaceGate {
 public:
  /// `dt`: the sample period (s).
  SurfaceGate(const GateConfig& c, double dt) : c_(c), dt_(dt) {}
  /// Relative spread of k_M over pitch +/- pitch_margin at (lambda, pitch) (0 when k_M is 0 there).
  double sensitivity(const LoadTable& table, double lambda, double pitch_deg) const;
  /// One sample: each blade's pitch (deg) at the tip-speed ratio of the last delayed LIDAR value (0: none
  /// yet). The gate closes on it when a blade is on a steep part of the table or `suspect` (an input of the
  /// model is suspect).
  void update(const LoadTable& table, double lambda, const std::array<double, 3>& pitch, bool suspect);
  /// The last `window` samples hold one the gate closed on.
  bool holds(uint64_t window) const { return since_closed_ < window; }
  /// Samples on which the gate closed.
  uint64_t closed_samples() const { return closed_samples_; }

 private:
  GateConfig c_;
  double dt_;
  std::array<double, 3> pitch_lp_{kNaN, kNaN, kNaN};
  uint64_t since_closed_ = UINT64_MAX / 2;  // samples since the last sample the gate closed on
  uint64_t closed_samples_ = 0;
};

/// The lull hold (YAML keys `lull_load_share`, `lull_memory`). Every residual channel is a ratio to a mean
/// load, but what makes it noisy (the beams' wind against the rotor's, one blade's eddy against another's)
/// is a load: as the wind drops in a lull the mean load falls, and the channels' spread grows as its inverse
/// (measured: at 8 m/s and 15.9 % turbulence the wind fell from 7.5 to 3-4 m/s for half a minute, the loads
/// from 2.2 to 0.5 MN m, and one blade's cross-blade mean ratio stood at 6.6 %, beyond its critical value).
/// On a window whose mean blade load is below load_share of the rotor's usual one the outlier test is held as
/// on a steep one.
struct LullConfig {
  double load_share = 0.6;  ///< of the usual mean blade load, below which a window is a lull (0: no hold)
  double memory = 600.0;    ///< s over which the usual mean blade load is followed (a lasting change of wind
                            ///< becomes the usual within about as long)
};

class LullHold {
 public:
  explicit LullHold(const LullConfig& c) : c_(c) {}
  /// Once per revolution: the revolution's mean blade load (window_load, N m; NaN: none) and its time (s).
  void follow(double load, double revolution_time);
  /// A window with mean blade load `load` (N m) is in a lull (never while the usual load is not known).
  bool holds(double load) const;
  /// The rotor's usual mean blade load (N m; < 0: not known yet).
  double usual_load() const { return usual_load_; }

 private:
  LullConfig c_;
  double usual_load_ = -1.0;
};

}  // namespace windfdi::blade_load
