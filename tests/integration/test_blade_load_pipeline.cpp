// windfdi-blade-load as a process: the replay contract on plant recordings of every blade-moment scenario
// (abrupt, drift, intermittent, invalid, a healthy farm hour), and end to end on DDS (plant -> blade_load ->
// arbiter and farm monitor): a blade-moment sensor fault switches the IPC to the LIDAR load model.
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
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

// Every row of the WINDFDI_TRACE files in `dir`: hop -> key -> wall time (the turbine is WT01 throughout).
std::map<std::string, std::map<std::string, double>> trace_rows(const std::string& dir) {
  std::map<std::string, std::map<std::string, double>> rows;
  for (const auto& f : std::filesystem::directory_iterator(dir)) {
    if (f.path().extension() != ".csv") continue;
    std::stringstream in(read_file(f.path().string()));
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line, "hop,turbine_id,key,wall_time") << f.path();
    while (std::getline(in, line)) {
      std::vector<std::string> cell;
      std::stringstream row(line);
      for (std::string c; std::getline(row, c, ',');) cell.push_back(c);
      if (cell.size() == 4) rows[cell[0]][cell[2]] = std::stod(cell[3]);
    }
  }
  return rows;
}

TEST(BladeLoadPipeline, TheTraceFollowsAFaultHopByHopFromItsFrameToThePlantsControlStep) {
  const int domain = private_domain(8);
  auto env = dds_env(domain);
  const std::string dir = temp_dir("hop_trace");
  env["WINDFDI_TRACE"] = dir;
  // GIVEN plant, blade_load and the arbiter with WINDFDI_TRACE, and the blade-2 gauge's abrupt fault
  ChildProcess arbiter({bin("windfdi-arbiter")}, env, "arbiter");
  ChildProcess diag({bin("windfdi-blade-load"), "--config", private_config(dir)}, env, "blade_load");
  std::this_thread::sleep_for(std::chrono::seconds(2));
  ChildProcess plant(
      {bin("windfdi-plant"), "--scenario", kDeploy + "/scenarios/sensor_abrupt.yaml", "--rate", "20"}, env,
      "plant");
  // THEN the arbiter links the report to the configuration it decided, and the plant applies that revision
  std::string report, revision;
  const auto applied = [&] {
    const auto rows = trace_rows(dir);
    if (!rows.count("report_config") || !rows.count("config_apply")) return false;
    for (const auto& [link, t] : rows.at("report_config")) {
      const std::size_t gt = link.rfind('>');
      if (link.rfind("blade_moment_sensor_2/sensor_abrupt/", 0) == 0 &&
          rows.at("config_apply").count(link.substr(gt + 1))) {
        report = link.substr(0, gt);
        revision = link.substr(gt + 1);
        return true;
      }
    }
    return false;
  };
  ASSERT_TRUE(wait_until(applied, std::chrono::seconds(40)))
      << diag.stderr_text() << arbiter.stderr_text() << plant.stderr_text();
  plant.stop(SIGTERM);
  // AND every hop of it is stamped, in the order of the way (one clock on one host)
  auto rows = trace_rows(dir);
  const std::vector<std::pair<std::string, std::string>> way = {
      {"frame_write", report},    {"frame_receive", report},    {"frame_take", report},
      {"report_write", report},   {"report_receive", report},   {"report_take", report},
      {"config_write", revision}, {"config_receive", revision}, {"config_apply", revision}};
  double before = 0.0;
  for (const auto& [hop, key] : way) {
    ASSERT_TRUE(rows[hop].count(key)) << hop << " " << key;
    const double t = rows[hop][key];
    std::printf("[measured] %-15s %+.3f ms\n", hop.c_str(), before > 0 ? 1e3 * (t - before) : 0.0);
    EXPECT_GE(t, before - 1e-6) << hop << " stamped before the hop ahead of it";
    before = t;
  }
  // AND tests/perf/hop_table.py makes the table of it
  ChildProcess table({"/usr/bin/python3", kDeploy + "/../tests/perf/hop_table.py", dir}, {}, "hop_table");
  ASSERT_EQ(table.wait(std::chrono::seconds(30)), 0) << table.stderr_text();
  EXPECT_NE(table.stdout_text().find("| config: DDS receive -> plant control step | control period | "),
            std::string::npos)
      << table.stdout_text();
  remove_stale_shm(domain);
}

}  // namespace
