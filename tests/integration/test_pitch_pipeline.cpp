// windfdi-pitch-diag as a process: the replay contract on a plant recording (end to end on DDS: every pitch
// fault class in test_fault_classes.cpp).
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "process.hpp"
#include "test_util.hpp"

using namespace windfdi::test;
using nlohmann::json;

namespace {

const std::string kDeploy = WINDFDI_SOURCE_DEPLOY_DIR;

TEST(PitchReplay, PlantRecordingGivesTheContractFilesAndTheLeak) {
  // GIVEN a plant recording (gzip) of hydraulic_leakage.yaml: blade 3's actuator leaks from 150 s
  const std::string dir = temp_dir("pitch_replay");
  ChildProcess plant({bin("windfdi-plant"), "--scenario", kDeploy + "/scenarios/hydraulic_leakage.yaml",
                      "--offline", "--record", dir + "/frames.csv.gz"},
                     {}, "plant");
  ASSERT_EQ(plant.wait(std::chrono::seconds(60)), 0) << plant.stderr_text();
  // WHEN windfdi-pitch-diag replays it
  ChildProcess diag(
      {bin("windfdi-pitch-diag"), "--replay", dir + "/frames.csv.gz", "--estimates", dir + "/est.csv",
       "--events", dir + "/events.jsonl", "--config", kDeploy + "/config/pitch_diag.yaml"},
      {}, "pitch_replay");
  ASSERT_EQ(diag.wait(std::chrono::seconds(60)), 0) << diag.stderr_text();
  // THEN the estimates have the contract's columns at 10 Hz (300 s: about 3000 rows)
  std::stringstream est(read_file(dir + "/est.csv"));
  std::string header;
  std::getline(est, header);
  EXPECT_EQ(header.rfind(
                "t,turbine_id,omega_n_1,omega_n_2,omega_n_3,zeta_1,zeta_2,zeta_3,class_1,class_2,class_3", 0),
            0u)
      << header;
  int rows = 0;
  for (std::string line; std::getline(est, line);) ++rows;
  EXPECT_NEAR(rows, 3000, 20);
  // AND the first event raises hydraulic_leakage on pitch_actuator_3 after the onset, nothing on other blades
  const auto events = json_lines(read_file(dir + "/events.jsonl"));
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events[0]["component"], "pitch_actuator_3");
  EXPECT_EQ(events[0]["fault"], "hydraulic_leakage");
  EXPECT_EQ(events[0]["state"], "raised");
  EXPECT_EQ(events[0]["source"], "pitch_diag");
  EXPECT_EQ(events[0]["turbine_id"], "WT01");
  EXPECT_GT(events[0]["t"].get<double>(), 150.0);
  for (const auto& e : events) EXPECT_EQ(e["component"], "pitch_actuator_3") << e.dump();
}

TEST(PitchReplay, MalformedRecordingExitsWithCode2NamingFileAndLine) {
  const auto r = replay_malformed("windfdi-pitch-diag", "t,pitch_1,pitch_ref_1\n0,1,1\n0.01,abc,1\n");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.stderr_text.find(r.file + ":3"), std::string::npos) << r.stderr_text;
}

}  // namespace
