// The arbiter's configuration as the plant applies it, with the clock passed in: it holds while the arbiter
// that wrote it is alive and for a lease after that; then the defaults, except that a safe stop stays
// stopped.
#pragma once

#include "turbine_sim.hpp"

namespace windfdi::plant {

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
