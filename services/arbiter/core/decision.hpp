// The fault-tolerant control arbiter's decision function: one turbine's faults, estimates and service
// health in, its control configuration (with reasons) out. No DDS; time is an argument.
#pragma once

#include <array>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "control_modes.hpp"
#include "fault_event.hpp"
#include "isolation.hpp"
#include "yaml_config.hpp"

namespace windfdi::arbiter {

// Ordered (common/control_modes.hpp): a higher value is more conservative, and the most conservative demand
// wins.
using Mode = control::OperatingMode;
using control::IceMode;
using control::IpcSource;
using control::to_string;
/// When a cause stops acting: once it has been clear for `clear_hold`, or only after an operator's ack.
enum class ClearCondition { kWhenClear, kOnAck };

struct ArbiterConfig {
  double clear_hold = 30.0;          ///< s a cause must stay clear before its action is withdrawn (0..3600)
  double nominal_pitch_rate = 10.0;  ///< deg/s, pitch rate limit of a healthy blade (1..30)
  double derated_pitch_rate = 5.0;   ///< deg/s, limit for pump wear / high air content (0.5..30)
  double rotor_speed_bias_limit = 0.1;  ///< rad/s; a larger rotor speed bias is not trusted (degraded mode)
  double generator_speed_bias_limit = 10.0;  ///< rad/s; likewise for the generator speed
  double pitch_bias_limit = 3.0;             ///< deg; likewise for a pitch sensor
  bool has_lidar = true;                     ///< the turbine carries a LIDAR (IPC can fall back to its model)
  /// Relative change of the inertia estimate that re-tunes the ice-adapted controller (0..0.5). Each 1 Hz
  /// estimate used to be a new configuration: 30 revisions a second at 30x, a controller re-tuned on noise.
  double inertia_step = 0.02;
  /// s a fault of a class that warrants a safe stop must hold its stop severity (critical) with its
  /// class unchanged before the turbine is stopped (0..600). A stop costs production and is latched until
  /// an operator acknowledges it, so a pressure drop that passes is no cause: the FDI/FTC benchmark's leak
  /// (30 s ramp in, 40 s at full size, 30 s ramp out) reads critical for 38 s and is carried on the
  /// reversible derate; one that holds 90 s stops.
  double stop_confirm_time = 90.0;
  /// s after another class was raised on the same component during which its class is uncertain (0..3600):
  /// "high_air_content or hydraulic_leakage" gets the most conservative reversible action, never a stop.
  double class_settle_time = 30.0;
  /// Relative drive-train efficiency loss (drive_train's estimate) from which the turbine runs degraded: the
  /// gearbox turns the lost power into heat (0..1; 0.1: 0.97 -> 0.87).
  double efficiency_derate_drop = 0.1;
  /// Largest converter torque offset (N m) the arbiter compensates in the torque command (0: never).
  double max_torque_compensation = 2000.0;
  isolation::IsolationConfig isolation;  ///< keys isolation_lead, isolation_common_window (s)
};

/// Reads the `arbiter` keys of a YAML file (unknown keys and out-of-range values are ConfigErrors).
ArbiterConfig load_arbiter_config(const YamlSection& section);

/// Why one part of the configuration is what it is.
struct Reason {
  std::string source;  ///< service that reported (or "arbiter" for its own conclusions)
  std::string component;
  std::string fault;   ///< canonical fault class
  std::string action;  ///< e.g. "ipc_source=lidar_model"
  bool operator==(const Reason& o) const {
    return source == o.source && component == o.component && fault == o.fault && action == o.action;
  }
};

struct Configuration {
  Mode mode = Mode::kNormal;
  IpcSource ipc_source = IpcSource::kStrainGauge;
  bool use_corrected_rotor_speed = false;
  bool use_corrected_generator_speed = false;
  std::array<bool, 3> use_corrected_pitch{false, false, false};
  std::array<double, 3> pitch_rate_limit{10.0, 10.0, 10.0};  ///< deg/s
  IceMode ice_mode = IceMode::kNormal;
  double inertia = 0.0;              ///< kg m^2 for the adapted controller (0: nominal)
  double torque_compensation = 0.0;  ///< N m taken off the converter's torque command (a converter offset)
  std::vector<Reason> reasons;       ///< sorted
  /// Same control content and reasons (the revision is the node's business).
  bool operator==(const Configuration& o) const;
  bool operator!=(const Configuration& o) const { return !(*this == o); }
};

/// One turbine's arbiter. Feed it what arrives, then ask for the configuration at a time.
class Arbiter {
 public:
  explicit Arbiter(const ArbiterConfig& config = {});

  /// A FaultReport. Returns false (and counts it) for a component or class that is not canonical or does
  /// not belong together: such a report is never acted on.
  bool on_fault(const FaultEvent& event, double now);
  /// An operator acknowledgement; `fault` "none" acknowledges every class on the component.
  void on_ack(const std::string& component, const std::string& fault, double now);
  /// A diagnostic service's liveliness (from wt/health).
  void on_service_alive(const std::string& service, bool alive, double now);
  /// The latest inertia estimate (kg m^2, generator side), for the ice-adapted controller.
  /// Only a change beyond inertia_step counts (the controller is not re-tuned on estimator noise).
  void on_inertia(double inertia) {
    if (inertia > 0.0 && (inertia_ <= 0.0 || std::fabs(inertia / inertia_ - 1.0) > config_.inertia_step))
      inertia_ = inertia;
  }

  /// The configuration every active (or held, or latched) cause demands at `now`.
  Configuration evaluate(double now);

  uint64_t rejected_reports() const { return rejected_; }
  /// Causes currently acting, for display: "source/component/fault" (secondary ones included).
  std::vector<std::string> active_causes(double now) const;

 private:
  struct Cause {
    FaultEvent event;  ///< the latest report of this (source, component, fault)
    bool raised = false;
    double cleared_at = 0.0;      ///< arbiter time of the clear
    double severity_since = 0.0;  ///< arbiter time from which the report has held its present severity
    bool latched = false;         ///< a confirmed stop (or critical fault): acts until acknowledged
    bool secondary = false;       ///< at the last evaluation, explained by another report
    double primary_since = 0.0;   ///< arbiter time from which it has not been secondary
    /// Arbiter time from which it has held its severity as a root cause: the clock of a stop.
    double settled_since() const { return std::max(severity_since, primary_since); }
  };
  bool acting(const Cause& c, double now) const;
  void apply(Cause& c, double now, Configuration& cfg);
  /// Other classes raised on the cause's (source, component) within class_settle_time: empty when settled.
  std::vector<std::string> rival_classes(const Cause& c, double now) const;
  void note_class(const FaultEvent& e, double now);  ///< a class raised or cleared on its source/component
  void apply_service_lost(const std::string& service, Configuration& cfg) const;

  ArbiterConfig config_;
  std::map<std::string, Cause> causes_;  // key source/component/fault
  // source/component -> (time, class) of each class raised there, newest last (pruned to class_settle_time)
  std::map<std::string, std::vector<std::pair<double, std::string>>> class_history_;
  std::map<std::string, double> lost_services_;  // service -> time lost (or time it came back, see below)
  std::map<std::string, double> recovered_services_;
  double inertia_ = 0.0;
  uint64_t rejected_ = 0;
};

}  // namespace windfdi::arbiter
