// What the rest of the system says about one turbine's measured inputs: faults other services have raised
// on them, and the arbiter's reconfigurations. Diagnostic cores use it to hold judgement on spoiled inputs.
#pragma once

#include <array>
#include <limits>
#include <map>
#include <string>

#include "fault_event.hpp"

namespace windfdi {

/// The suspect inputs of one turbine (deploy/arbiter/DECISION_TABLE.md "Isolation", first layer): a core that
/// relies on a suspect input uses a redundant value or holds its judgement instead of raising a fault of its
/// own.
struct InputContext {
  bool rotor_speed_suspect = false;
  bool generator_speed_suspect = false;
  std::array<bool, 3> pitch_sensor_suspect{};    ///< measured pitch of blade i
  std::array<bool, 3> pitch_actuator_suspect{};  ///< the actuator of blade i (its measured pitch is true)
  /// drive_train reports the drive train's efficiency (efficiency_loss): a torque balance that takes the
  /// turbine file's efficiency does not hold. No controller switches anything on it, so it is no transient.
  bool drive_train_suspect = false;
  bool turbine_stopped =
      false;  ///< the arbiter holds the turbine in safe stop: its actuators are parked at feather
  /// deg/s, the pitch rate limit the arbiter commands per blade (infinite: none seen)
  std::array<double, 3> pitch_rate_limit{kNoLimit, kNoLimit, kNoLimit};
  static constexpr double kNoLimit = std::numeric_limits<double>::infinity();
  /// Valid bits (frame_sample.hpp) of the channels the turbine's data does not carry at all (a recording
  /// without those columns, a gateway that never sends them): a core does without them, or takes what the
  /// configuration says for them, and does not count their absence as rejected samples.
  uint32_t absent = 0;
  /// Counts the changes a transient follows: a suspect set that changed (the controller may switch to a
  /// corrected measurement) or a new control configuration from the arbiter.
  uint64_t transitions = 0;

  bool speed_suspect() const { return rotor_speed_suspect || generator_speed_suspect; }
  /// Equal in what a transient follows: all but drive_train_suspect.
  bool same_transient_inputs(const InputContext& o) const {
    InputContext a = *this;
    a.drive_train_suspect = o.drive_train_suspect;
    return a == o;
  }
  bool operator==(const InputContext& o) const {
    return rotor_speed_suspect == o.rotor_speed_suspect &&
           generator_speed_suspect == o.generator_speed_suspect &&
           pitch_sensor_suspect == o.pitch_sensor_suspect &&
           pitch_actuator_suspect == o.pitch_actuator_suspect &&
           drive_train_suspect == o.drive_train_suspect && turbine_stopped == o.turbine_stopped &&
           pitch_rate_limit == o.pitch_rate_limit && absent == o.absent && transitions == o.transitions;
  }
};

/// Builds a turbine's InputContext from other services' fault reports and the arbiter's configurations.
class InputContextTracker {
 public:
  /// `own_service`: the tracking service's own reports are not context (they are its judgement).
  explicit InputContextTracker(std::string own_service) : own_(std::move(own_service)) {}
  /// A raised or cleared FaultReport of any service. Returns true when the context changed.
  bool on_fault(const FaultEvent& e);
  /// The arbiter published a configuration that differs from the last one (new control content); `stopped`:
  /// its mode is safe stop.
  void on_reconfiguration(bool stopped = false,
                          const std::array<double, 3>& pitch_rate_limit = {
                              InputContext::kNoLimit, InputContext::kNoLimit, InputContext::kNoLimit}) {
    ++context_.transitions;
    context_.turbine_stopped = stopped;
    context_.pitch_rate_limit = pitch_rate_limit;
  }
  const InputContext& context() const { return context_; }

 private:
  void rebuild();
  std::string own_;
  std::map<std::string, bool> raised_;  // source/component/fault -> raised
  InputContext context_;
};

/// The suspect-input hold every core applies the same way: judgement is held while an input it relies on is
/// suspect and for `hold_time` seconds of sample time after the context last changed (the transient a
/// reconfiguration or a switch to corrected values causes is not a new fault).
class SuspectHold {
 public:
  explicit SuspectHold(double hold_time = 10.0) : hold_time_(hold_time) {}
  /// The context in force from sample time `t` on.
  void set(const InputContext& c, double t) {
    if (!c.same_transient_inputs(context_)) last_change_ = t;
    context_ = c;
  }
  const InputContext& context() const { return context_; }
  /// True within hold_time of the last change of the context.
  bool in_transient(double t) const { return t - last_change_ < hold_time_; }

 private:
  double hold_time_;
  double last_change_ = -std::numeric_limits<double>::infinity();
  InputContext context_;
};

}  // namespace windfdi
