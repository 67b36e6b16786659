// One measured turbine sample as every core sees it: plain C++, no DDS (the replay format's columns).
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <string>

namespace windfdi {

constexpr int kBlades = 3;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Bits of FrameSample::valid_mask: a cleared bit means the gateway marked that channel invalid.
enum ValidBit : uint32_t {
  kValidRotorSpeed = 1u << 0,
  kValidGeneratorSpeed = 1u << 1,
  kValidGenTorque = 1u << 2,
  kValidPower = 1u << 3,
  kValidWindHub = 1u << 4,
  kValidAzimuth = 1u << 5,
  kValidPitch1 = 1u << 6,         ///< pitch_1..3 are bits 6..8
  kValidPitchRef1 = 1u << 9,      ///< pitch_ref_1..3 are bits 9..11
  kValidBladeMoment1 = 1u << 12,  ///< blade_moment_1..3 are bits 12..14
  kValidLidar = 1u << 15,
  kValidAll = (1u << 16) - 1,
};

/// A sample of one turbine at one instant. Units are SI except pitch (deg), as in the replay contract.
struct FrameSample {
  uint64_t sequence = 0;                                ///< consecutive per turbine; a gap means lost samples
  double t = 0.0;                                       ///< measurement time (s)
  double rotor_speed = kNaN;                            ///< rad/s
  double generator_speed = kNaN;                        ///< rad/s
  double gen_torque = kNaN;                             ///< measured generator torque (N m)
  double gen_torque_ref = kNaN;                         ///< generator torque reference (N m)
  double power = kNaN;                                  ///< electrical power (W)
  double wind_hub = kNaN;                               ///< hub wind speed, nacelle anemometer (m/s)
  double azimuth = kNaN;                                ///< rotor azimuth of blade 1 (rad, 0 = up)
  std::array<double, kBlades> pitch{kNaN, kNaN, kNaN};  ///< measured pitch angle (deg)
  std::array<double, kBlades> pitch_ref{kNaN, kNaN, kNaN};     ///< pitch reference (deg)
  std::array<double, kBlades> blade_moment{kNaN, kNaN, kNaN};  ///< flapwise blade-root moment (N m)
  double lidar_v_upper = kNaN;  ///< LIDAR upwind speed at hub height + R/2 (m/s)
  double lidar_v_lower = kNaN;  ///< LIDAR upwind speed at hub height - R/2 (m/s)
  double aero_torque = kNaN;    ///< replay only: aerodynamic torque when the recording has it (N m)
  double aero_power = kNaN;     ///< replay only: aerodynamic power when the recording has it (W)
  uint32_t valid_mask = kValidAll;
  bool lidar_lost_on_the_way =
      false;  ///< DDS only: LIDAR frames were lost in transport since the last sample
};

/// Samples lost between two received ones of a turbine, from their sequence numbers (0 when consecutive,
/// repeated or out of order).
inline uint64_t samples_lost(uint64_t last_sequence, uint64_t sequence) {
  return sequence > last_sequence + 1 ? sequence - last_sequence - 1 : 0;
}

/// Whether a service bridges the samples lost between two it received of one turbine (sequence and time of
/// the last one, then of this one) instead of restarting: some were lost, time went forward, and the hole,
/// the time between the two less one sample period (the period read from the two themselves, so that no
/// service needs a configured rate), is at most max_bridged_gap (s). One rule for every service: a loss is
/// bridged by all of them or by none (they had differed by a sample at the boundary).
inline bool bridgeable_hole(uint64_t last_sequence, double last_t, uint64_t sequence, double t,
                            double max_bridged_gap) {
  const double lost = static_cast<double>(samples_lost(last_sequence, sequence));
  if (lost == 0.0 || !(t > last_t)) return false;
  return (t - last_t) * lost / (lost + 1.0) <= max_bridged_gap + 1e-6;
}

}  // namespace windfdi
