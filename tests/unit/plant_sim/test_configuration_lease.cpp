// The plant's rule for the arbiter's configuration, on a hand-advanced clock: it holds while its writer is
// alive and for the lease after; then the defaults, except that a safe stop stays stopped.
#include <gtest/gtest.h>

#include <cmath>

#include "configuration_lease.hpp"

using namespace windfdi;
using namespace windfdi::plant;

namespace {
ControlInput degraded_derated() {
  ControlInput in;
  in.mode = OperatingMode::kDegraded;
  in.ipc_source = IpcSource::kLidarModel;
  in.pitch_rate_limit = {10.0, 5.0, 10.0};
  return in;
}
}  // namespace

TEST(ConfigurationLease, HoldsWhileTheArbiterLivesAndForTheLeaseAfter) {
  ConfigurationLease lease(5.0);
  // Before any configuration: the defaults
  EXPECT_EQ(lease.input(0.0).mode, OperatingMode::kNormal);
  // GIVEN a configuration from a live arbiter at t = 10 s
  lease.received(degraded_derated(), 10.0);
  // THEN it holds however long no sample comes while the writer lives (a delayed sample under load)
  bool expired = true;
  EXPECT_EQ(lease.input(100.0, &expired).mode, OperatingMode::kDegraded);
  EXPECT_FALSE(expired);
  // WHEN the arbiter's liveliness is lost at 100 s
  lease.writer_liveliness(false);
  // THEN it holds for the lease (5 s) ...
  EXPECT_EQ(lease.input(104.9, &expired).ipc_source, IpcSource::kLidarModel);
  EXPECT_FALSE(expired);
  // ... and then the defaults are back, said once
  const ControlInput after = lease.input(105.1, &expired);
  EXPECT_TRUE(expired);
  EXPECT_EQ(after.mode, OperatingMode::kNormal);
  EXPECT_EQ(after.ipc_source, IpcSource::kStrainGauge);
  EXPECT_DOUBLE_EQ(after.pitch_rate_limit[1], 10.0);
  lease.input(200.0, &expired);
  EXPECT_FALSE(expired);
}

TEST(ConfigurationLease, ASafeStopStaysStoppedWhenTheArbiterIsLost) {
  ConfigurationLease lease(5.0);
  ControlInput stop = degraded_derated();
  stop.mode = OperatingMode::kSafeStop;
  lease.received(stop, 0.0);
  lease.writer_liveliness(false);
  bool expired = false;
  const ControlInput after = lease.input(6.0, &expired);
  EXPECT_TRUE(expired);
  EXPECT_EQ(after.mode, OperatingMode::kSafeStop);
  EXPECT_EQ(after.ipc_source, IpcSource::kStrainGauge);  // the rest is the defaults
  EXPECT_TRUE(lease.stopped());
}

TEST(ConfigurationLease, ACorrectedSpeedIsUsedOnlyWhileFresh) {
  ConfigurationLease lease(5.0, 1.0);
  EXPECT_TRUE(std::isnan(lease.input(0.0).corrected_generator_speed));
  lease.corrected_generator_speed(150.0, 10.0);
  EXPECT_DOUBLE_EQ(lease.input(10.5).corrected_generator_speed, 150.0);
  EXPECT_TRUE(std::isnan(lease.input(11.1).corrected_generator_speed));  // sensor_bias silent for 1.1 s
}

TEST(ControlSettings, IceStopIsASafeStopAndInvalidLimitsAndInertiaAreTheDefaults) {
  // GIVEN a configuration with ice mode stop, a NaN and a negative rate limit and a NaN inertia
  ControlSettings s;
  s.mode = OperatingMode::kDegraded;
  s.ice_mode = control::IceMode::kStop;
  s.pitch_rate_limit = {kNaN, -1.0, 4.0};
  s.inertia = kNaN;
  s.use_corrected_generator_speed = true;
  const ControlInput in = control_input(s);
  // THEN the turbine stops, the bad limits are the actuator's own 10 deg/s, the good one holds, and the
  // controller keeps its nominal inertia
  EXPECT_EQ(in.mode, OperatingMode::kSafeStop);
  EXPECT_EQ(in.pitch_rate_limit, (std::array<double, 3>{10.0, 10.0, 4.0}));
  EXPECT_EQ(in.inertia, 0.0);
  EXPECT_TRUE(in.use_corrected_generator_speed);
  // AND without the ice stop the mode is the configuration's own
  s.ice_mode = control::IceMode::kAdapted;
  s.inertia = 4.2e6;
  EXPECT_EQ(control_input(s).mode, OperatingMode::kDegraded);
  EXPECT_EQ(control_input(s).inertia, 4.2e6);
}
