// The arbiter's configuration as the plant applies it, with the clock passed in: it holds while the arbiter
// that wrote it is alive and for a lease after that; then the defaults, except that a safe stop stays
// stopped.
#pragma once

#include <array>
#include <cmath>

#include "turbine_sim.hpp"

namespace windfdi::plant {

/// The settings of a ControlConfiguration the plant acts on, whoever carries them (the DDS sample, or the
/// arbiter's own Configuration in the closed-loop replay).
struct ControlSettings {
  OperatingMode mode = OperatingMode::kNormal;
  IpcSource ipc_source = IpcSource::kStrainGauge;
  control::IceMode ice_mode = control::IceMode::kNormal;
  std::array<double, 3> pitch_rate_limit{10.0, 10.0, 10.0};  ///< deg/s per blade
  bool use_corrected_generator_speed = false;
  double inertia = 0.0;              ///< kg m^2 generator side (0: nominal)
  double torque_compensation = 0.0;  ///< N m off the converter's torque command
};

/// What the controller is asked to do: a rate limit that is not finite and positive is the actuator's own
/// 10 deg/s, an inertia that is not is the nominal one, and ice mode "stop" is a safe stop.
inline ControlInput control_input(const ControlSettings& s) {
  ControlInput in;
  in.mode = s.ice_mode == control::IceMode::kStop ? OperatingMode::kSafeStop : s.mode;
  in.ipc_source = s.ipc_source;
  for (std::size_t i = 0; i < 3; ++i) {
    const double r = s.pitch_rate_limit[i];
    in.pitch_rate_limit[i] = std::isfinite(r) && r > 0.0 ? r : 10.0;
  }
  in.use_corrected_generator_speed = s.use_corrected_generator_speed;
  in.inertia = std::isfinite(s.inertia) && s.inertia > 0.0 ? s.inertia : 0.0;
  in.torque_compensation = std::isfinite(s.torque_compensation) ? s.torque_compensation : 0.0;
  return in;
}

class ConfigurationLease {
 public:
  /// `lease`: s a configuration holds after its writer was lost or fell silent. `corrected_max_age`: s a
  /// bias-corrected measurement is used after it arrived (sensor_bias alive).
  explicit ConfigurationLease(double lease, double corrected_max_age = 1.0)
      : lease_(lease), corrected_max_age_(corrected_max_age) {}

  /// A configuration arrived at wall time `now` from a live writer.
  void received(const ControlInput& input, double now) {
    input_ = input;
    last_ = now;
    writer_alive_ = true;
  }
  /// The writer's liveliness changed (its 2 s lease in DDS): while it is alive the configuration holds
  /// however long its samples take, so a sample delayed under load cannot end a live arbiter's
  /// configuration.
  void writer_liveliness(bool alive) { writer_alive_ = alive; }
  /// A bias-corrected generator speed arrived (rad/s).
  void corrected_generator_speed(double speed, double now) {
    corrected_speed_ = speed;
    corrected_at_ = now;
  }

  /// The control input at wall time `now`. Sets `expired` when the lease ran out at this call (the defaults
  /// are back; a safe stop stays one).
  ControlInput input(double now, bool* expired = nullptr) {
    if (expired) *expired = false;
    if (writer_alive_ && last_ >= 0.0) last_ = now;
    if (last_ >= 0.0 && now - last_ > lease_) {
      const bool stopped = input_.mode == OperatingMode::kSafeStop;
      input_ = ControlInput{};
      if (stopped) input_.mode = OperatingMode::kSafeStop;
      last_ = -1.0;
      if (expired) *expired = true;
    }
    ControlInput in = input_;
    in.corrected_generator_speed = now - corrected_at_ < corrected_max_age_ ? corrected_speed_ : kNaN;
    return in;
  }
  /// True when the applied configuration is a safe stop.
  bool stopped() const { return input_.mode == OperatingMode::kSafeStop; }
  double lease() const { return lease_; }

 private:
  double lease_, corrected_max_age_;
  ControlInput input_;
  double last_ = -1.0;  // wall time the configuration was last known current, < 0: none (defaults)
  bool writer_alive_ = false;
  double corrected_speed_ = kNaN, corrected_at_ = -1e300;
};

}  // namespace windfdi::plant
