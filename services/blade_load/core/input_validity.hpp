// Which of a sample's inputs are usable (blade moments, pitch readings, the delayed LIDAR speeds), and
// sensor_invalid on a blade-moment gauge or the LIDAR that stays unusable.
#pragma once

#include <array>
#include <vector>

#include "fault_event.hpp"
#include "frame_sample.hpp"

namespace windfdi::blade_load {

struct ValidityConfig {
  double max_moment = 5e7;    ///< N m, |blade moment| above it is out of range (sensor_invalid)
  double invalid_time = 1.0;  ///< s a blade moment or the LIDAR must stay invalid before sensor_invalid
};

class InputValidity {
 public:
  explicit InputValidity(const ValidityConfig& c) : c_(c) {}

  /// Each blade's moment is usable: finite, within max_moment and its validity bit set. One that stays
  /// unusable for invalid_time raises sensor_invalid (its `lost` entry is then true: the blade's window
  /// restarts); a usable one clears it.
  std::array<bool, 3> moments(const FrameSample& s, std::vector<FaultEvent>& events,
                              std::array<bool, 3>& lost);
  /// Each blade's pitch (deg), a missing reading replaced by the mean of the others (the last such mean when
  /// none is there).
  std::array<double, 3> pitch(const FrameSample& s);
  /// The LIDAR model had delayed speeds at time t (`model_ok`) or not. Returns true when the LIDAR is lost
  /// now (none for invalid_time after it was there): monitoring falls back to the sensor-only channels and
  /// `lidar` sensor_invalid (warning) is raised; it clears when the speeds are back.
  bool lidar(double t, bool model_ok, std::vector<FaultEvent>& events);
  /// The LIDAR channels are in use (delayed speeds are there, or were lost for less than invalid_time).
  bool lidar_ok() const { return lidar_ok_; }
  /// The LIDAR history restarted (the sample time stepped) or has a hole (samples lost): for `grace` s of
  /// sample time from `t` (its D / V and the allowed age) no delayed speed can be found, which is no loss. A
  /// LIDAR still silent after that is one; a raised loss stays raised until the LIDAR serves again.
  void restart_lidar(double t, double grace) {
    lidar_bad_since_ = -1.0;
    lidar_grace_until_ = t + grace;
  }

 private:
  ValidityConfig c_;
  std::array<double, 3> invalid_since_{-1.0, -1.0, -1.0};  // start of a blade's unusable spell (-1: none)
  std::array<bool, 3> invalid_raised_{};
  double last_pitch_mean_ = 0.0;
  bool lidar_ok_ = false;
  double lidar_bad_since_ = -1.0;
  double lidar_grace_until_ = -1e300;
  bool lidar_raised_ = false;
};

}  // namespace windfdi::blade_load
