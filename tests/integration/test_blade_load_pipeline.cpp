// windfdi-blade-load as a process: the replay contract on plant recordings of every blade-moment scenario
// (abrupt, drift, intermittent, invalid, a healthy farm hour), and end to end on DDS (plant -> blade_load ->
// arbiter and farm monitor): a blade-moment sensor fault switches the IPC to the LIDAR load model.
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "process.hpp"
#include "test_util.hpp"

using namespace windfdi::test;
using nlohmann::json;

namespace {

const std::string kDeploy = WINDFDI_SOURCE_DEPLOY_DIR;

// The shipped configuration with absolute table paths and the state file in this test's own temporary
// directory, so learned statistics never leak from one run (or test) into another.
std::string private_config(const std::string& dir) {
  std::string text = read_file(kDeploy + "/config/blade_load.yaml");
  for (std::size_t p = text.find("../turbine/"); p != std::string::npos; p = text.find("../turbine/", p))
    text.replace(p, 11, kDeploy + "/turbine/");
  const std::string key = "state_file: \"\"";
  const std::size_t p = text.find(key);
  EXPECT_NE(p, std::string::npos) << "blade_load.yaml has no empty state_file";
  if (p != std::string::npos) text.replace(p, key.size(), "state_file: \"" + dir + "/state/{turbine}.yaml\"");
  const std::string path = dir + "/blade_load.yaml";
  std::ofstream(path) << text;
  return path;
}

struct Replay {
  std::string dir, header;
  int rows = 0;
  std::vector<json> events;
};

Replay replay(const std::string& scenario) {
  Replay r;
  r.dir = temp_dir("blade_load_replay");
  ChildProcess plant({bin("windfdi-plant"), "--scenario", kDeploy + "/scenarios/" + scenario, "--offline",
                      "--record", r.dir + "/frames.csv.gz"},
                     {}, "plant");
  EXPECT_EQ(plant.wait(std::chrono::seconds(60)), 0) << plant.stderr_text();
  ChildProcess diag(
      {bin("windfdi-blade-load"), "--replay", r.dir + "/frames.csv.gz", "--estimates", r.dir + "/est.csv",
       "--events", r.dir + "/events.jsonl", "--config", private_config(r.dir)},
      {}, "blade_load_replay");
  EXPECT_EQ(diag.wait(std::chrono::seconds(60)), 0) << diag.stderr_text();
  std::stringstream est(read_file(r.dir + "/est.csv"));
  std::getline(est, r.header);
  for (std::string line; std::getline(est, line);) ++r.rows;
  r.events = json_lines(read_file(r.dir + "/events.jsonl"));
  return r;
}

const char* kColumns =
    "t,turbine_id,a1_sensor_1,a1_sensor_2,a1_sensor_3,a1_model_1,a1_model_2,a1_model_3,delta_a_1,delta_a_2,"
    "delta_a_3,valid_1,valid_2,valid_3,lidar_ok";

// The first raised event on a component (nullptr: none).
const json* first_raised(const std::vector<json>& events, const std::string& component) {
  for (const auto& e : events)
    if (e["component"] == component && e["state"] == "raised") return &e;
  return nullptr;
}

TEST(BladeLoadReplay, AbruptGainRaisedOnBlade2AfterTheOnset) {
  // GIVEN sensor_abrupt.yaml: blade 2's gain +10 % at 250 s, 16 m/s
  const Replay r = replay("sensor_abrupt.yaml");
  // THEN the contract's columns at 10 Hz (400 s: about 4000 rows)
  EXPECT_EQ(r.header, kColumns);
  EXPECT_NEAR(r.rows, 4000, 20);
  // AND sensor_abrupt is raised on blade_moment_sensor_2 after 250 s and within 10 s, nothing else
  const json* e = first_raised(r.events, "blade_moment_sensor_2");
  ASSERT_NE(e, nullptr) << r.events.size();
  EXPECT_EQ((*e)["fault"], "sensor_abrupt");
  EXPECT_EQ((*e)["source"], "blade_load");
  EXPECT_EQ((*e)["turbine_id"], "WT01");
  EXPECT_GT((*e)["t"].get<double>(), 250.0);
  EXPECT_LT((*e)["t"].get<double>(), 260.0);
  for (const auto& x : r.events) EXPECT_EQ(x["component"], "blade_moment_sensor_2") << x.dump();
  // AND the state file was written in the private directory (at exit)
  EXPECT_TRUE(std::filesystem::exists(r.dir + "/state/WT01.yaml"));
}

TEST(BladeLoadReplay, DriftRaisedOnBlade1BeforeFivePercent) {
  // GIVEN sensor_drift.yaml: 1 % of the mean load per minute on blade 1 from 300 s
  const Replay r = replay("sensor_drift.yaml");
  EXPECT_EQ(r.header, kColumns);
  const json* e = first_raised(r.events, "blade_moment_sensor_1");
  ASSERT_NE(e, nullptr);
  // THEN sensor_drift, before 5 % (300 s after the onset)
  EXPECT_EQ((*e)["fault"], "sensor_drift");
  EXPECT_GT((*e)["t"].get<double>(), 300.0);
  EXPECT_LT((*e)["t"].get<double>(), 600.0);
  for (const auto& x : r.events) EXPECT_EQ(x["component"], "blade_moment_sensor_1") << x.dump();
}

TEST(BladeLoadReplay, IntermittentIsReclassifiedOnTheSecondEpisode) {
  // GIVEN sensor_intermittent.yaml: blade 3 gain 1.3 for 6 s of every 20 s from 250 s
  const Replay r = replay("sensor_intermittent.yaml");
  EXPECT_EQ(r.header, kColumns);
  // THEN: sensor_abrupt raised, later cleared together with sensor_intermittent raised, and no event storm
  std::vector<std::string> seq;
  for (const auto& x : r.events) {
    EXPECT_EQ(x["component"], "blade_moment_sensor_3") << x.dump();
    seq.push_back(x["fault"].get<std::string>() + "/" + x["state"].get<std::string>());
  }
  const std::vector<std::string> want = {"sensor_abrupt/raised", "sensor_abrupt/cleared",
                                         "sensor_intermittent/raised"};
  EXPECT_EQ(seq, want);
  if (r.events.size() == 3) {
    EXPECT_GT(r.events[0]["t"].get<double>(), 250.0);
    EXPECT_GT(r.events[2]["t"].get<double>(), 270.0);  // the second episode starts at 270 s
    EXPECT_LT(r.events[2]["t"].get<double>(), 300.0);
  }
}

TEST(BladeLoadReplay, InvalidSensorRaisedAndCleared) {
  // GIVEN sensor_invalid.yaml: blade 3's moment is NaN from 100 s to 200 s
  const Replay r = replay("sensor_invalid.yaml");
  EXPECT_EQ(r.header, kColumns);
  ASSERT_EQ(r.events.size(), 2u);
  EXPECT_EQ(r.events[0]["fault"], "sensor_invalid");
  EXPECT_EQ(r.events[0]["component"], "blade_moment_sensor_3");
  EXPECT_EQ(r.events[0]["state"], "raised");
  EXPECT_NEAR(r.events[0]["t"].get<double>(), 101.0, 0.5);  // invalid_time 1 s
  EXPECT_EQ(r.events[1]["state"], "cleared");
  EXPECT_NEAR(r.events[1]["t"].get<double>(), 200.0, 0.5);
}

// WT02 (14 m/s) used to raise at 1340 s and 1803 s: a blade's pitch swept through -1 deg, where the plant's
// k_M is singular, while the IPC faded out (the steep-surface gate, README).
TEST(BladeLoadReplay, HealthyFarmHourRaisesNothing) {
  // GIVEN healthy.yaml: three turbines at 8, 14 and 20 m/s for an hour
  const Replay r = replay("healthy.yaml");
  EXPECT_EQ(r.header, kColumns);
  EXPECT_NEAR(r.rows, 3 * 36000, 60);
  // THEN no blade-moment sensor fault on any turbine
  for (const auto& e : r.events) EXPECT_NE(e["state"], "raised") << e.dump();
}

TEST(BladeLoadReplay, MalformedRecordingExitsWithCode2NamingFileAndLine) {
  const auto r = replay_malformed("windfdi-blade-load",
                                  "t,azimuth,rotor_speed,blade_moment_1,blade_moment_2,blade_moment_3\n0,0,1."
                                  "2,1,1,1\n0.01,abc,1.2,1,1,1\n");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.stderr_text.find(r.file + ":3"), std::string::npos) << r.stderr_text;
}

TEST(BladeLoadPipeline, AbruptFaultReachesTheFarmAndTheArbiterSwitchesIpcToTheLidarModel) {
  const int domain = private_domain(7);
  const auto env = dds_env(domain);
  const std::string dir = temp_dir("blade_load_pipeline");
  const std::string db = dir + "/farm.sqlite";
  ChildProcess farm({bin("windfdi-farm"), "--db", db, "--table-period", "0"}, env, "farm");
  ChildProcess arbiter({bin("windfdi-arbiter")}, env, "arbiter");
  ChildProcess configs({bin("windfdi-test-peer"), "configs", "--timeout", "120"}, env, "configs");
  ChildProcess diag({bin("windfdi-blade-load"), "--config", private_config(dir)}, env, "blade_load");
  std::this_thread::sleep_for(std::chrono::seconds(2));
  // GIVEN the plant running sensor_abrupt.yaml (fault at 250 s) at 20x real time: about 13 s of wall time
  ChildProcess plant(
      {bin("windfdi-plant"), "--scenario", kDeploy + "/scenarios/sensor_abrupt.yaml", "--rate", "20"}, env,
      "plant");
  // THEN the farm stores sensor_abrupt raised by blade_load on blade_moment_sensor_2
  const auto stored = [&] {
    for (const auto& j : farm_history(db, env))
      if (j["kind"] == "fault" && j["data"]["component"] == "blade_moment_sensor_2" &&
          j["data"]["fault"] == "sensor_abrupt" && j["data"]["source"] == "blade_load" &&
          j["data"]["state"] == "raised")
        return true;
    return false;
  };
  EXPECT_TRUE(wait_until(stored, std::chrono::seconds(40))) << diag.stderr_text() << farm.stderr_text();
  // AND the arbiter switches the IPC to the LIDAR load model (ipc_source 1, DECISION_TABLE.md)
  const auto reacted = [&] {
    for (const auto& j : json_lines(configs.stdout_text()))
      if (j.contains("revision") && j["ipc_source"] == 1) return true;
    return false;
  };
  EXPECT_TRUE(wait_until(reacted, std::chrono::seconds(15)))
      << configs.stdout_text() << arbiter.stderr_text();
  // AND no fault on another blade
  EXPECT_EQ(diag.stderr_text().find("blade_moment_sensor_1"), std::string::npos) << diag.stderr_text();
  EXPECT_EQ(diag.stderr_text().find("blade_moment_sensor_3"), std::string::npos) << diag.stderr_text();
  plant.stop(SIGTERM);
  remove_stale_shm(domain);
}

}  // namespace
