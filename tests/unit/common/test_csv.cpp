// Unit tests of the CSV and replay-format reader/writer: round trip (plain and gzip), malformed rows.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "csv.hpp"
#include "fault_event.hpp"
#include "jsonl.hpp"
#include "process.hpp"
#include "replay_csv.hpp"
#include "yaml_config.hpp"

using namespace windfdi;

namespace {

FrameSample sample(uint64_t k) {
  FrameSample s;
  s.sequence = k;
  s.t = 0.01 * static_cast<double>(k);
  s.rotor_speed = 1.26 + 1e-3 * std::sin(0.1 * static_cast<double>(k));
  s.generator_speed = 95.0 * s.rotor_speed;
  s.gen_torque = 31e3 + static_cast<double>(k);
  s.gen_torque_ref = 31e3;
  s.power = 4.8e6 / 3.0;
  s.wind_hub = 11.3;
  s.azimuth = std::fmod(0.1 * static_cast<double>(k), 2 * M_PI);
  s.pitch = {1.0 / 3.0, 2.0, 3.5};
  s.pitch_ref = {1.0, 2.0, 3.0};
  s.blade_moment = {1.1e6, 1.2e6, 0.9e6};
  s.lidar_v_upper = 12.0;
  s.lidar_v_lower = 10.5;
  return s;
}

void expect_same(const FrameSample& a, const FrameSample& b) {
  EXPECT_EQ(a.sequence, b.sequence);
  EXPECT_EQ(a.t, b.t);  // exact: numbers are written in their shortest round-trip form
  EXPECT_EQ(a.rotor_speed, b.rotor_speed);
  EXPECT_EQ(a.azimuth, b.azimuth);
  EXPECT_EQ(a.pitch, b.pitch);
  EXPECT_EQ(a.blade_moment, b.blade_moment);
  EXPECT_EQ(a.lidar_v_lower, b.lidar_v_lower);
}

class ReplayRoundTrip : public ::testing::TestWithParam<std::string> {};

TEST_P(ReplayRoundTrip, WrittenSamplesReadBackExactly) {
  // GIVEN 500 samples of two turbines written in the replay format (plain or gzip)
  const std::string path = test::temp_dir("csv") + "/frames.csv" + GetParam();
  {
    FrameCsvWriter w(path, {"true_inertia"});
    for (uint64_t k = 0; k < 500; ++k) {
      w.write("WT01", sample(k), {4.3e6});
      w.write("WT02", sample(k), {4.4e6});
    }
  }
  // WHEN read back THEN every value is identical and the turbine ids alternate
  FrameCsvReader r(path);
  EXPECT_TRUE(r.has_column("true_inertia"));
  FrameSample s;
  std::string id;
  for (uint64_t k = 0; k < 500; ++k) {
    ASSERT_TRUE(r.next(s, id));
    EXPECT_EQ(id, "WT01");
    expect_same(s, sample(k));
    ASSERT_TRUE(r.next(s, id));
    EXPECT_EQ(id, "WT02");
  }
  EXPECT_FALSE(r.next(s, id));
}

INSTANTIATE_TEST_SUITE_P(PlainAndGzip, ReplayRoundTrip, ::testing::Values("", ".gz"));

std::string write_text(const std::string& text) {
  const std::string path = test::temp_dir("csvbad") + "/bad.csv";
  std::ofstream(path) << text;
  return path;
}

TEST(ReplayCsv, NonNumericFieldNamesFileLineAndColumn) {
  const std::string path = write_text("t,rotor_speed,pitch_1\n0,1.2,3\n0.01,fast,3\n");
  FrameCsvReader r(path);
  FrameSample s;
  std::string id;
  ASSERT_TRUE(r.next(s, id));
  try {
    r.next(s, id);
    FAIL() << "malformed row accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.key(), "rotor_speed");
  }
}

TEST(ReplayCsv, WrongFieldCountIsAnError) {
  FrameCsvReader r(write_text("t,rotor_speed\n0,1.2,7\n"));
  FrameSample s;
  std::string id;
  try {
    r.next(s, id);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.line(), 2);
  }
}

TEST(ReplayCsv, MissingTimeColumnIsAnError) {
  EXPECT_THROW(FrameCsvReader(write_text("rotor_speed\n1\n")), ConfigError);
  EXPECT_THROW(FrameCsvReader(write_text("")), ConfigError);
  EXPECT_THROW(FrameCsvReader("/nonexistent/frames.csv"), ConfigError);
}

TEST(ReplayCsv, NanAndMissingColumnsAreInvalidSamplesNotErrors) {
  // GIVEN a file with a NaN pitch, an empty field and unknown / missing columns
  FrameCsvReader r(write_text("t,pitch_1,rotor_speed,unknown_column\n0,nan,,7\n"));
  FrameSample s;
  std::string id;
  ASSERT_TRUE(r.next(s, id));
  // THEN the values are NaN with their valid bits cleared, and sequence numbers start at 0
  EXPECT_TRUE(std::isnan(s.pitch[0]));
  EXPECT_TRUE(std::isnan(s.rotor_speed));
  EXPECT_FALSE(s.valid_mask & kValidPitch1);
  EXPECT_FALSE(s.valid_mask & kValidRotorSpeed);
  EXPECT_FALSE(s.valid_mask & kValidBladeMoment1);  // column absent
  EXPECT_EQ(s.sequence, 0u);
  EXPECT_EQ(id, "WT01");
}

TEST(ReplayCsv, FormatNumberIsShortestExact) {
  EXPECT_EQ(format_number(0.1), "0.1");
  EXPECT_EQ(format_number(std::nan("")), "nan");
  EXPECT_EQ(format_number(-INFINITY), "-inf");
  EXPECT_EQ(std::stod(format_number(1.0 / 3.0)), 1.0 / 3.0);
}

TEST(Jsonl, FaultEventRoundTrip) {
  const std::string path = test::temp_dir("jsonl") + "/events.jsonl";
  FaultEvent e;
  e.t = 12.5;
  e.turbine_id = "WT03";
  e.source = "pitch_diag";
  e.component = "pitch_actuator_2";
  e.fault = "hydraulic_leakage";
  e.statistic = 3.2;
  e.detail = "omega_n 3.42 rad/s";
  {
    JsonlWriter w(path);
    w.write(to_json(e));
    e.raised = false;
    w.write(to_json(e));
  }
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  const auto j = nlohmann::json::parse(line);
  for (const char* key :
       {"t", "turbine_id", "source", "component", "fault", "state", "severity", "statistic", "detail"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["state"], "raised");
  const FaultEvent back = fault_event_from_json(j);
  EXPECT_EQ(back.component, "pitch_actuator_2");
  EXPECT_TRUE(back.raised);
  std::getline(in, line);
  EXPECT_FALSE(fault_event_from_json(nlohmann::json::parse(line)).raised);
}

}  // namespace
