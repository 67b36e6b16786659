// windfdi-pitch-diag as a process: the replay contract on a plant recording, and end to end on DDS (plant ->
// pitch_diag -> arbiter and farm monitor) for a hydraulic leak (safe stop) and pump wear (blade derated).
#include <gtest/gtest.h>

#include <csignal>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "process.hpp"

using namespace windfdi::test;
using nlohmann::json;

namespace {

const std::string kDeploy = WINDFDI_SOURCE_DEPLOY_DIR;

bool wait_until(const std::function<bool()>& pred, std::chrono::seconds timeout) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < end) {
    if (pred()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  return pred();
}

std::vector<json> json_lines(const std::string& text) {
  std::vector<json> out;
  std::stringstream ss(text);
  for (std::string line; std::getline(ss, line);)
    if (!line.empty() && line[0] == '{') out.push_back(json::parse(line));
  return out;
}

std::string read_file(const std::string& path) {
  std::ifstream f(path);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

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
  const std::string dir = temp_dir("pitch_replay_bad");
  std::ofstream(dir + "/bad.csv") << "t,pitch_1,pitch_ref_1\n0,1,1\n0.01,abc,1\n";
  ChildProcess diag({bin("windfdi-pitch-diag"), "--replay", dir + "/bad.csv", "--estimates", dir + "/e.csv",
                     "--events", dir + "/e.jsonl"},
                    {}, "pitch_bad");
  EXPECT_EQ(diag.wait(std::chrono::seconds(20)), 2);
  EXPECT_NE(diag.stderr_text().find(dir + "/bad.csv:3"), std::string::npos) << diag.stderr_text();
}

// Plant at 20x real time with pitch_diag, the arbiter and the farm monitor on a private domain.
void run_pipeline(const std::string& scenario, const std::string& component, const std::string& fault,
                  const std::function<bool(const json& config)>& reaction) {
  const int domain = private_domain(5);
  const auto env = dds_env(domain);
  const std::string dir = temp_dir("pitch_pipeline");
  const std::string db = dir + "/farm.sqlite";
  ChildProcess farm({bin("windfdi-farm"), "--db", db, "--table-period", "0"}, env, "farm");
  ChildProcess arbiter({bin("windfdi-arbiter")}, env, "arbiter");
  ChildProcess configs({bin("windfdi-test-peer"), "configs", "--timeout", "120"}, env, "configs");
  ChildProcess diag({bin("windfdi-pitch-diag"), "--config", kDeploy + "/config/pitch_diag.yaml"}, env,
                    "pitch_diag");
  std::this_thread::sleep_for(std::chrono::seconds(2));
  // GIVEN the plant running the scenario at 20x real time
  ChildProcess plant({bin("windfdi-plant"), "--scenario", kDeploy + "/scenarios/" + scenario, "--rate", "20"},
                     env, "plant");
  // THEN the farm stores the fault raised by pitch_diag on the right component
  const auto stored = [&] {
    ChildProcess h({bin("windfdi-farm"), "--db", db, "history", "--json"}, env, "history");
    if (h.wait(std::chrono::seconds(20)) != 0) return false;
    for (const auto& j : json_lines(h.stdout_text()))
      if (j["kind"] == "fault" && j["data"]["component"] == component && j["data"]["fault"] == fault &&
          j["data"]["source"] == "pitch_diag" && j["data"]["state"] == "raised")
        return true;
    return false;
  };
  EXPECT_TRUE(wait_until(stored, std::chrono::seconds(60))) << diag.stderr_text() << farm.stderr_text();
  // AND the arbiter's configuration reacts as its decision table says
  const auto reacted = [&] {
    for (const auto& j : json_lines(configs.stdout_text()))
      if (j.contains("revision") && reaction(j)) return true;
    return false;
  };
  EXPECT_TRUE(wait_until(reacted, std::chrono::seconds(20)))
      << configs.stdout_text() << arbiter.stderr_text();
  // AND no other pitch fault was raised
  EXPECT_EQ(diag.stderr_text().find("pump_wear on pitch_actuator_2"), std::string::npos);
  plant.stop(SIGTERM);
  remove_stale_shm(domain);
}

TEST(PitchPipeline, HydraulicLeakReachesTheFarmAndTheArbiterStopsTheTurbine) {
  run_pipeline("hydraulic_leakage.yaml", "pitch_actuator_3", "hydraulic_leakage",
               [](const json& c) { return c["mode"] == 2; });
}

TEST(PitchPipeline, PumpWearReachesTheFarmAndTheArbiterDeratesTheBlade) {
  run_pipeline("pump_wear.yaml", "pitch_actuator_1", "pump_wear", [](const json& c) {
    return c.contains("pitch_rate_limit") && c["pitch_rate_limit"][0].get<double>() < 10.0 && c["mode"] == 0;
  });
}

}  // namespace
