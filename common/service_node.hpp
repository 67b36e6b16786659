// The DDS side every diagnostic service shares: frames in (per-turbine filter), sequence gaps, fault
// reports and health out. A service adds its core and its estimate writer.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>

#include "ControlConfiguration.h"
#include "FaultReport.h"
#include "LidarFrame.h"
#include "TurbineFrame.h"
#include "app.hpp"
#include "dds/endpoints.hpp"
#include "fault_event.hpp"
#include "frame_sample.hpp"
#include "health.hpp"
#include "hop_trace.hpp"
#include "input_context.hpp"
#include "replay.hpp"
#include "turbine_limit.hpp"

namespace windfdi {

class DiagnosticNode {
 public:
  /// The largest sample time taken (s): 300 years, so seconds since the Unix epoch pass.
  static constexpr double kMaxSampleTime = 1e10;
  /// Per-sample callback: false when the core rejected the sample; `gap` when samples were lost before it.
  using SampleFn = std::function<bool(const std::string& turbine_id, const FrameSample& sample, bool gap)>;
  using LidarFn = std::function<void(const std::string& turbine_id, const windfdi::LidarFrame& frame)>;

  DiagnosticNode(const CommonOptions& options, const std::string& service);

  bus::Participant& participant() { return participant_; }
  HealthReporter& health() { return health_; }
  const std::string& service() const { return service_; }

  /// Also follow wt/lidar (must be called before run()).
  void subscribe_lidar(LidarFn on_lidar);

  /// Runs until SIGINT/SIGTERM: every sample goes to `process` in order. Health is published once a
  /// second, with what DDS reports of the streams (deadlines missed, samples lost, incompatible QoS).
  void run(const SampleFn& process);

  /// What other services and the arbiter say about a turbine's inputs (empty context before anything).
  const InputContext& context(const std::string& turbine_id);

  /// Publishes a raised or cleared fault (FaultReport) and logs it. An event with a non-canonical
  /// class is logged and counted, never published.
  void publish(const FaultEvent& event);

 private:
  std::string service_;
  std::vector<std::string> turbines_;
  bus::Participant participant_;
  bus::Wakeup wakeup_;
  bus::Reader<windfdi::TurbineFrame> frames_;
  bus::Writer<windfdi::FaultReport> faults_;
  HealthReporter health_;
  std::unique_ptr<bus::Reader<windfdi::LidarFrame>> lidar_;
  // Other services' faults and the arbiter's configurations: the inputs' context (input_context.hpp).
  bus::Reader<windfdi::FaultReport> other_faults_;
  bus::Reader<windfdi::ControlConfiguration> configurations_;
  // Every map below and the service's own per-turbine state hold admitted turbines only.
  TurbineLimit limit_;
  ForeignReports foreign_reports_;
  std::map<std::string, InputContextTracker> contexts_;
  std::map<std::string, std::string> last_control_;  // turbine -> the control content last seen
  void take_context();
  LidarFn on_lidar_;
  std::map<std::string, SequenceTracker> sequence_;
  std::map<std::string, SampleTimeTracker> sample_times_;
  HopTrace trace_;
  // The frame being processed (its write, reception and take times): a report's decisive frame.
  bus::SampleMeta frame_meta_;
  double frame_woke_ = 0.0, frame_taken_ = 0.0;
};

}  // namespace windfdi
