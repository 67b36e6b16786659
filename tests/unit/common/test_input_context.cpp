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

}  // namespace
