// The arbiter's DDS node: faults, health (liveliness), inertia estimates and acks in; one
// ControlConfiguration per turbine out, on change and at 1 Hz, with exclusive-ownership strength.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "ControlConfiguration.h"
#include "FaultAck.h"
#include "FaultReport.h"
#include "ServiceHealth.h"
#include "app.hpp"
#include "dds/endpoints.hpp"
#include "decision.hpp"
#include "health.hpp"
#include "hop_trace.hpp"
#include "ice_detect_estimate_topic.hpp"
#include "pitch_diag_estimate_topic.hpp"
#include "service_liveliness.hpp"
#include "turbine_clock.hpp"
#include "turbine_limit.hpp"
#include "turbine_selection.hpp"

namespace windfdi::arbiter {

struct NodeOptions {
  std::string arbiter_id = "arbiter";  ///< shown in every configuration it publishes
  int strength = 100;                  ///< ownership strength: the highest live arbiter is followed
  double republish_period = 1.0;       ///< s between unchanged configurations
  /// Off by default: the arbiter speaks UDP alone. A stopped arbiter's shared-memory ports were torn down by
  /// its peers' port watchdog and not rebuilt in step when it went on, and it heard some services no more
  /// (README "Redundancy"; docs/fastdds.md "A stopped process").
  bool shared_memory = false;
};

windfdi::ControlConfiguration to_idl(const Configuration& c, const std::string& turbine_id, uint64_t revision,
                                     const std::string& arbiter_id, double t);

class ArbiterNode {
 public:
  ArbiterNode(const CommonOptions& common, const ArbiterConfig& config, const NodeOptions& options);
  /// Runs until SIGINT/SIGTERM.
  void run();

 private:
  struct Turbine {
    Arbiter arbiter;
    Configuration last;
    uint64_t revision = 0;
    double last_published = -1e300;
    TurbineClock clock;  ///< the decision's time base (sample time of the turbine's inputs)
    std::vector<std::string> traced_reports;  ///< reports taken since the last configuration (WINDFDI_TRACE)
    bool dirty = true;                        ///< an input came since it was last decided on
  };
  static constexpr double kFullPassPeriod =
      0.095;  ///< s between decisions on every turbine (the loop waits 0.1)
  double last_full_pass_ = -1e300;
  static constexpr double kStartupHold = 1.0;  ///< s after start before the first configuration
  double started_at_ = 1e300;                  ///< wall time run() began
  // A frozen arbiter (SIGSTOP for 10 s in the reliability campaign) saw every service's liveliness lapse when
  // it thawed, before the services' next assertions reached it, and published the lost-service fallback for
  // 8 s. Only a stall longer than the health lease (3 s) less its 1 s assertion period can lapse a lease by
  // itself; a loss seen within kStallGrace (two assertion periods) after one is acted on only if it still
  // holds then. The first try took 1 s loop gaps for stalls: a loaded CI machine makes those, and a real loss
  // was deferred past the 20 s the KilledService test allows.
  static constexpr double kStallGap = 2.0;    ///< s without a pass of the loop that is a stall
  static constexpr double kStallGrace = 2.0;  ///< s
  double last_pass_ = 0.0;                    ///< wall time the loop last ran
  double stalled_until_ = -1e300;
  std::set<std::pair<std::string, std::string>> deferred_losses_;  ///< (instance's turbine, service)
  /// The first revision of every turbine: the start time in ms since the Unix epoch, so that a restarted
  /// arbiter's revisions continue above the ones it published before (from 1 again, the farm store took
  /// them for ones it had stored, keyed by turbine, arbiter and revision, and dropped them).
  const uint64_t revision_base_ = static_cast<uint64_t>(wall_time() * 1000.0);
  Turbine& turbine(const std::string& id);
  /// Whether the turbine is this arbiter's: selected (--turbine) and within --max-turbines.
  bool serves(const std::string& id);
  void handle_inputs(double now);
  /// Tells the turbines an instance of `service` speaks for that it is alive or lost.
  void apply_liveliness(const std::string& instance_turbine, const std::string& service, bool alive,
                        double wall);
  void publish_configurations(double now);

  CommonOptions common_;
  TurbineSelection served_;  ///< common_.turbines, parsed once (serves() runs per sample)
  TurbineLimit limit_;
  ForeignReports foreign_reports_;
  ArbiterConfig config_;
  NodeOptions options_;
  bus::Participant participant_;
  bus::Wakeup wakeup_;
  // A fault report is decided on in the listener's thread when the loop is free (try_lock): the hand-off
  // to the loop thread cost 0.2 ms of the 0.9 ms from the decisive frame (README "Latency hop by hop").
  std::mutex step_mutex_;
  bool running_ = false;  // under step_mutex_: the node is whole and its loop runs
  bool report_arrived();
  bus::Wakeup report_wakeup_;
  bus::Reader<windfdi::FaultReport> faults_;
  bus::Reader<windfdi::ServiceHealth> health_in_;
  bus::Reader<windfdi::InertiaEstimate> inertia_;
  bus::Reader<windfdi::PitchActuatorEstimate> pitch_;  ///< 10 Hz: keeps the turbine clocks going (no wake-up)
  bus::Reader<windfdi::FaultAck> acks_;
  bus::Writer<windfdi::ControlConfiguration> config_out_;
  HealthReporter health_;
  std::map<std::string, Turbine> turbines_;
  ServiceLiveliness liveliness_;
  HopTrace trace_;
};

}  // namespace windfdi::arbiter
