// The input context a diagnostic service builds from other services' fault reports, and its hold.
#include <gtest/gtest.h>

#include "input_context.hpp"

using namespace windfdi;

namespace {

FaultEvent report(const std::string& source, const std::string& component, bool raised) {
  FaultEvent e;
  e.source = source;
  e.component = component;
  e.fault = "sensor_bias";
  e.raised = raised;
  return e;
}

TEST(InputContextTracker, OtherServicesReportsMakeTheirComponentsSuspect) {
  InputContextTracker tracker("pitch_diag");
  // GIVEN sensor_bias raising pitch_sensor_2 and the rotor-speed sensor
  EXPECT_TRUE(tracker.on_fault(report("sensor_bias", "pitch_sensor_2", true)));
  EXPECT_TRUE(tracker.on_fault(report("sensor_bias", "rotor_speed_sensor", true)));
  const InputContext& c = tracker.context();
  EXPECT_TRUE(c.pitch_sensor_suspect[1]);
  EXPECT_FALSE(c.pitch_sensor_suspect[0]);
  EXPECT_TRUE(c.rotor_speed_suspect);
  EXPECT_TRUE(c.speed_suspect());
  EXPECT_EQ(c.transitions, 2u);
  // WHEN the same report arrives again (transient-local replay) THEN nothing changes
  EXPECT_FALSE(tracker.on_fault(report("sensor_bias", "pitch_sensor_2", true)));
  EXPECT_EQ(tracker.context().transitions, 2u);
  // WHEN it clears THEN the pitch is trusted again, and the change counts as a transition
  EXPECT_TRUE(tracker.on_fault(report("sensor_bias", "pitch_sensor_2", false)));
  EXPECT_FALSE(tracker.context().pitch_sensor_suspect[1]);
  EXPECT_EQ(tracker.context().transitions, 3u);
  // AND a reconfiguration by the arbiter is a transition too, a safe stop holds until the next one
  tracker.on_reconfiguration(true);
  EXPECT_EQ(tracker.context().transitions, 4u);
  EXPECT_TRUE(tracker.context().turbine_stopped);
  EXPECT_TRUE(tracker.on_fault(report("sensor_bias", "pitch_sensor_1", true)));
  EXPECT_TRUE(tracker.context().turbine_stopped);  // a fault report does not release the stop
  tracker.on_reconfiguration(false);
  EXPECT_FALSE(tracker.context().turbine_stopped);
}

TEST(InputContextTracker, TheServicesOwnReportsAreNotContext) {
  InputContextTracker tracker("pitch_diag");
  EXPECT_FALSE(tracker.on_fault(report("pitch_diag", "pitch_actuator_1", true)));
  EXPECT_FALSE(tracker.context().pitch_actuator_suspect[0]);
  // another service clearing what it never raised is nothing either
  EXPECT_FALSE(tracker.on_fault(report("blade_load", "pitch_actuator_1", false)));
  EXPECT_TRUE(tracker.on_fault(report("other", "pitch_actuator_1", true)));
  EXPECT_TRUE(tracker.context().pitch_actuator_suspect[0]);
}

TEST(SuspectHold, HoldsForItsTimeAfterEachChangeOfTheContext) {
  SuspectHold hold(10.0);
  EXPECT_FALSE(hold.in_transient(0.0));  // nothing has changed yet
  InputContext c;
  c.transitions = 1;
  hold.set(c, 100.0);
  EXPECT_TRUE(hold.in_transient(100.0));
  EXPECT_TRUE(hold.in_transient(109.9));
  EXPECT_FALSE(hold.in_transient(110.0));
  hold.set(c, 200.0);  // the same context again: no new transient
  EXPECT_FALSE(hold.in_transient(200.0));
}

TEST(InputContextTracker, ADriveTrainEfficiencyReportIsSuspectButNoTransient) {
  InputContextTracker tracker("ice_detect");
  SuspectHold hold(10.0);
  // GIVEN drive_train raising efficiency_loss (its component drive_train)
  FaultEvent e = report("drive_train", "drive_train", true);
  e.fault = "efficiency_loss";
  // THEN the drive train is suspect (a torque balance with the turbine file's efficiency does not hold) and
  // the service hears of it
  EXPECT_TRUE(tracker.on_fault(e));
  EXPECT_TRUE(tracker.context().drive_train_suspect);
  EXPECT_FALSE(tracker.context().speed_suspect());
  // BUT it is no transition: no controller switches on it, so no service holds its judgement for it
  EXPECT_EQ(tracker.context().transitions, 0u);
  hold.set(tracker.context(), 50.0);
  EXPECT_FALSE(hold.in_transient(50.0));
  // AND when it clears the drive train is trusted again, still without a transition
  e.raised = false;
  EXPECT_TRUE(tracker.on_fault(e));
  EXPECT_FALSE(tracker.context().drive_train_suspect);
  EXPECT_EQ(tracker.context().transitions, 0u);
  hold.set(tracker.context(), 80.0);
  EXPECT_FALSE(hold.in_transient(80.0));
  // (a speed sensor's report still is one)
  EXPECT_TRUE(tracker.on_fault(report("sensor_bias", "rotor_speed_sensor", true)));
  EXPECT_EQ(tracker.context().transitions, 1u);
  hold.set(tracker.context(), 90.0);
  EXPECT_TRUE(hold.in_transient(90.0));
}

}  // namespace
