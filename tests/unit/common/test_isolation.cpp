// The fault-signature table row by row, the precedence of two reports that explain each other, and the
// common cause on every blade.
#include <gtest/gtest.h>

#include "isolation.hpp"

using namespace windfdi::isolation;

namespace {

Report report(const std::string& source, const std::string& component, const std::string& fault, double t) {
  return {source, component, fault, t};
}

// A concrete root and responder for each row of the table (blade 2 where a row binds blades).
struct RowCase {
  const char* name;
  Report root, responder;
};
void PrintTo(const RowCase& c, std::ostream* os) { *os << c.name; }

class SignatureRow : public ::testing::TestWithParam<RowCase> {};

TEST_P(SignatureRow, RootExplainsItsResponderAndNotTheOtherWayRound) {
  const RowCase& k = GetParam();
  // GIVEN the root detected first and the responder 2 s later
  const auto v = isolate({k.root, k.responder});
  // THEN the responder is secondary, explained by the root, and the root is not
  EXPECT_FALSE(v[0].secondary) << k.name;
  ASSERT_TRUE(v[1].secondary) << k.name;
  EXPECT_EQ(v[1].explained_by, k.root.component + " " + k.root.fault);
  EXPECT_FALSE(v[1].why.empty());
  // AND a responder detected long (beyond any row's lead) before the root is its own root
  Report early = k.responder;
  early.t_detected = k.root.t_detected - longest_lead() - 60.0;
  EXPECT_FALSE(isolate({k.root, early})[1].secondary) << k.name;
}

INSTANTIATE_TEST_SUITE_P(
    Table, SignatureRow,
    ::testing::Values(
        RowCase{"rotor_speed_blade_load", report("sensor_bias", "rotor_speed_sensor", "sensor_bias", 10),
                report("blade_load", "blade_moment_sensor_1", "sensor_drift", 12)},
        RowCase{"rotor_speed_pitch_diag", report("sensor_bias", "rotor_speed_sensor", "sensor_bias", 10),
                report("pitch_diag", "pitch_actuator_3", "hydraulic_leakage", 12)},
        RowCase{"rotor_speed_pitch_sensor", report("sensor_bias", "rotor_speed_sensor", "sensor_bias", 10),
                report("sensor_bias", "pitch_sensor_2", "sensor_bias", 12)},
        RowCase{"rotor_speed_ice", report("sensor_bias", "rotor_speed_sensor", "sensor_bias", 10),
                report("ice_detect", "rotor", "ice_accretion", 12)},
        RowCase{"generator_speed_blade_load",
                report("sensor_bias", "generator_speed_sensor", "sensor_bias", 10),
                report("blade_load", "blade_moment_sensor_2", "sensor_abrupt", 12)},
        RowCase{"generator_speed_pitch_diag",
                report("sensor_bias", "generator_speed_sensor", "sensor_bias", 10),
                report("pitch_diag", "pitch_actuator_2", "hydraulic_leakage", 12)},
        RowCase{"generator_speed_pitch_sensor",
                report("sensor_bias", "generator_speed_sensor", "sensor_bias", 10),
                report("sensor_bias", "pitch_sensor_1", "sensor_bias", 12)},
        RowCase{"generator_speed_ice", report("sensor_bias", "generator_speed_sensor", "sensor_bias", 10),
                report("ice_detect", "rotor", "ice_shedding", 12)},
        RowCase{"generator_speed_drive_train",
                report("sensor_bias", "generator_speed_sensor", "sensor_gain", 10),
                report("drive_train", "drive_train", "efficiency_loss", 12)},
        RowCase{"generator_speed_rotor_speed",
                report("sensor_bias", "generator_speed_sensor", "sensor_bias", 10),
                report("sensor_bias", "rotor_speed_sensor", "sensor_bias", 12)},
        RowCase{"pitch_sensor_actuator", report("sensor_bias", "pitch_sensor_2", "sensor_bias", 10),
                report("pitch_diag", "pitch_actuator_2", "hydraulic_leakage", 12)},
        RowCase{"pitch_sensor_blade_load", report("sensor_bias", "pitch_sensor_2", "sensor_bias", 10),
                report("blade_load", "blade_moment_sensor_2", "sensor_abrupt", 12)},
        // (a pitch-sensor report within 30 s of its actuator's is the root either way: the reverse row)
        RowCase{"pitch_actuator_sensor", report("pitch_diag", "pitch_actuator_2", "hydraulic_leakage", 10),
                report("sensor_bias", "pitch_sensor_2", "sensor_bias", 45)},
        RowCase{"pitch_actuator_blade_load", report("pitch_diag", "pitch_actuator_2", "pump_wear", 10),
                report("blade_load", "blade_moment_sensor_2", "sensor_drift", 12)},
        RowCase{"ice_blade_load", report("ice_detect", "rotor", "ice_accretion", 10),
                report("blade_load", "blade_moment_sensor_2", "sensor_drift", 12)},
        RowCase{"ice_drive_train", report("ice_detect", "rotor", "ice_accretion", 10),
                report("drive_train", "drive_train", "efficiency_loss", 12)}),
    [](const ::testing::TestParamInfo<RowCase>& row) { return std::string(row.param.name); });

TEST(Isolation, EveryTableRowHasACase) {
  // The parameterised cases above cover each row once; a new row needs a new case.
  EXPECT_EQ(signature_table().size(), 16u);
}

TEST(Isolation, ARotorSpeedFaultExplainsWhatRespondedWhileItsTypeWasWeighed) {
  // GIVEN a blade-moment report 70 s before the rotor-speed report (sensor_bias weighs gain against offset
  // for up to 60 s after the threshold is crossed)
  const auto v = isolate({report("blade_load", "blade_moment_sensor_1", "sensor_drift", 1000),
                          report("sensor_bias", "rotor_speed_sensor", "sensor_gain", 1070)});
  // THEN the blade-moment report is the rotor speed's echo (the rotor rows' own lead, 80 s)
  EXPECT_TRUE(v[0].secondary);
  // AND a generator-speed root (below rated it weighs for up to 20 s) explains one 30 s before it ...
  EXPECT_TRUE(isolate({report("blade_load", "blade_moment_sensor_1", "sensor_drift", 1000),
                       report("sensor_bias", "generator_speed_sensor", "sensor_gain", 1030)})[0]
                  .secondary);
  // ... but not 70 s before (its rows' lead, 40 s)
  EXPECT_FALSE(isolate({report("blade_load", "blade_moment_sensor_1", "sensor_drift", 1000),
                        report("sensor_bias", "generator_speed_sensor", "sensor_gain", 1070)})[0]
                   .secondary);
}

TEST(Isolation, IceExplainsAnEfficiencyLossTheEnergyBalanceSawMinutesBefore) {
  // GIVEN an efficiency loss raised 10 min before ice_detect weighed the ice
  const auto v = isolate({report("drive_train", "drive_train", "efficiency_loss", 1000),
                          report("ice_detect", "rotor", "ice_accretion", 1600)});
  // THEN the efficiency loss is the ice's echo, and the ice the root
  EXPECT_TRUE(v[0].secondary);
  EXPECT_FALSE(v[1].secondary);
  // AND an efficiency loss 20 min before is a fault of its own
  EXPECT_FALSE(isolate({report("drive_train", "drive_train", "efficiency_loss", 400),
                        report("ice_detect", "rotor", "ice_accretion", 1600)})[0]
                   .secondary);
  EXPECT_GE(longest_lead(), 900.0);
}

TEST(Isolation, AnEfficiencyLossRaisedAfterItsRootsTrailIsTheDriveTrainsOwn) {
  // GIVEN each root reported at 1000 s, an efficiency loss raised soon after it (still its echo) and one
  // raised after the row's trail
  struct Case {
    Report root;
    double echo_t, own_t;
  };
  const Case cases[] = {
      // The generator speed: from its report the balance takes the rotor's sensor and judges again only after
      // a minute of new blocks; fault suite set 170, scenario 06: a real loss 70 s into a stuck generator
      // speed.
      {report("sensor_bias", "generator_speed_sensor", "sensor_stuck", 1000), 1020, 1065},
      // Ice: once weighed, the balance weighs the rotor iced and raises only a clean step; fault suite set
      // 241, scenario 04: a real loss on the iced medium-speed rotor 163 s after the ice report.
      {report("ice_detect", "rotor", "ice_accretion", 1000), 1030, 1163},
  };
  const auto loss = [](double t) { return report("drive_train", "drive_train", "efficiency_loss", t); };
  for (const Case& c : cases) {
    // THEN the first is the root's echo, and the second a root, as is the root
    EXPECT_TRUE(isolate({c.root, loss(c.echo_t)})[1].secondary) << c.root.component;
    const auto v = isolate({c.root, loss(c.own_t)});
    EXPECT_FALSE(v[0].secondary) << c.root.component;
    EXPECT_FALSE(v[1].secondary) << c.root.component;
  }
  // AND a row without a trail keeps its responder an echo while both stand: a blade-moment report 10 min
  // after a generator-speed report
  EXPECT_TRUE(isolate({report("sensor_bias", "generator_speed_sensor", "sensor_stuck", 1000),
                       report("blade_load", "blade_moment_sensor_2", "sensor_drift", 1600)})[1]
                  .secondary);
}

TEST(Isolation, APitchActuatorFaultRaisedLongAfterASpeedSensorsReportIsTheActuatorsOwn) {
  // GIVEN a speed sensor's report at 1000 s (the arbiter switches the controller to the corrected speed)
  for (const char* sensor : {"generator_speed_sensor", "rotor_speed_sensor"}) {
    const Report speed = report("sensor_bias", sensor, "sensor_bias", 1000);
    // THEN an actuator report 10 s after it is still its echo (the switch's transient) ...
    EXPECT_TRUE(isolate({speed, report("pitch_diag", "pitch_actuator_2", "pump_wear", 1010)})[1].secondary)
        << sensor;
    // ... one before it too (the wrong speed moved the pitch) ...
    EXPECT_TRUE(isolate({speed, report("pitch_diag", "pitch_actuator_2", "pump_wear", 990)})[1].secondary)
        << sensor;
    // ... and one 116 s after it (fault suite set 170, scenario 06: air in blade 3's oil 116 s into a stuck
    // generator speed) is a root, as is the speed sensor
    const auto v = isolate({speed, report("pitch_diag", "pitch_actuator_3", "high_air_content", 1116)});
    EXPECT_FALSE(v[0].secondary) << sensor;
    EXPECT_FALSE(v[1].secondary) << sensor;
  }
}

TEST(Isolation, BladeBoundRowsDoNotCrossBlades) {
  // A pitch sensor fault on blade 1 does not explain an actuator fault on blade 3.
  const auto v = isolate({report("sensor_bias", "pitch_sensor_1", "sensor_bias", 10),
                          report("pitch_diag", "pitch_actuator_3", "pump_wear", 12)});
  EXPECT_FALSE(v[0].secondary);
  EXPECT_FALSE(v[1].secondary);
}

TEST(Isolation, APitchSensorReportIsTheRootOfItsActuatorsReportWithin30sEitherWay) {
  const Report sensor = report("sensor_bias", "pitch_sensor_1", "sensor_bias", 1663.56);
  Report actuator = report("pitch_diag", "pitch_actuator_1", "hydraulic_leakage", 1667.0);
  // a sensor fault first: the actuator report is its echo
  auto v = isolate({sensor, actuator});
  EXPECT_FALSE(v[0].secondary);
  EXPECT_TRUE(v[1].secondary);
  // the actuator seen first (suite seed 60: a 1.06 deg bias read as a leak at its onset, the bias confirmed
  // 13.4 s later): sensor_bias confirms only a static offset, which no actuator fault of Table 1 makes, so
  // the sensor is still the root
  actuator.t_detected = 1650.2;
  v = isolate({sensor, actuator});
  EXPECT_FALSE(v[0].secondary);
  ASSERT_TRUE(v[1].secondary);
  EXPECT_EQ(v[1].explained_by, "pitch_sensor_1 sensor_bias");
  // ... and so at a tie
  actuator.t_detected = sensor.t_detected;
  EXPECT_TRUE(isolate({sensor, actuator})[1].secondary);
  // an actuator fault over 30 s before the sensor's report is its own root, and the sensor report its echo
  actuator.t_detected = sensor.t_detected - 31.0;
  v = isolate({sensor, actuator});
  EXPECT_TRUE(v[0].secondary);
  EXPECT_FALSE(v[1].secondary);
  EXPECT_EQ(v[0].explained_by, "pitch_actuator_1 hydraulic_leakage");
}

TEST(Isolation, ARotorSpeedReportBesideAGeneratorSpeedFaultIsItsEcho) {
  // The drive-train observer cannot tell every generator-speed error from a rotor-speed one: a rotor report
  // beside a generator report is its echo (the arbiter corrects the generator speed only). The benchmark's
  // 1000 s fault (both gains at once) is still detected on both components; the report counts both.
  const auto v = isolate({report("sensor_bias", "rotor_speed_sensor", "sensor_bias", 1000.2),
                          report("sensor_bias", "generator_speed_sensor", "sensor_bias", 1000.1)});
  EXPECT_TRUE(v[0].secondary);
  EXPECT_FALSE(v[1].secondary);
  // and not the other way round: a generator report beside a rotor fault is its own root
  const auto w = isolate({report("sensor_bias", "rotor_speed_sensor", "sensor_bias", 1000.0),
                          report("sensor_bias", "generator_speed_sensor", "sensor_bias", 1000.5)});
  EXPECT_FALSE(w[1].secondary);
}

TEST(Isolation, TheSameResidualOnEveryBladeIsACommonCause) {
  std::vector<Report> r = {report("blade_load", "blade_moment_sensor_1", "sensor_abrupt", 1087),
                           report("blade_load", "blade_moment_sensor_2", "sensor_drift", 1103)};
  // two blades: two sensor faults as far as isolation can tell
  for (const auto& v : isolate(r)) EXPECT_FALSE(v.secondary);
  // the third within common_window: one common cause
  r.push_back(report("blade_load", "blade_moment_sensor_3", "sensor_abrupt", 1102));
  for (const auto& v : isolate(r)) {
    EXPECT_TRUE(v.secondary);
    EXPECT_EQ(v.explained_by, "common cause on every blade");
  }
  // the third long after: no common cause
  r.back().t_detected = 1200;
  EXPECT_FALSE(isolate(r)[2].secondary);
  // pitch actuators are not a sensor family: a fault on all three is three actuator reports
  const auto a = isolate({report("pitch_diag", "pitch_actuator_1", "pump_wear", 10),
                          report("pitch_diag", "pitch_actuator_2", "pump_wear", 11),
                          report("pitch_diag", "pitch_actuator_3", "pump_wear", 12)});
  for (const auto& v : a) EXPECT_FALSE(v.secondary);
}

}  // namespace
