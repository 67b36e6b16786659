// Reliability: the turbine controller's clock steps forward and back by minutes (an NTP step) in a recording;
// every diagnostic service raises and clears on it what it raises and clears on the same recording without
// the steps (sample-time windows and confirmation timers must not read a step as time that passed).
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "process.hpp"
#include "test_util.hpp"

using namespace windfdi::test;
using nlohmann::json;

namespace {

const std::string kDeploy = WINDFDI_SOURCE_DEPLOY_DIR;

// A service's events as (turbine, component, class, state), in order: what it reported, not when.
std::vector<std::string> events_of(const std::string& service, const std::string& recording,
                                   const std::string& dir, const std::string& name) {
  const std::string exe = "windfdi-" + service;
  std::string file = service;
  for (auto& c : file)
    if (c == '-') c = '_';
  const std::string cfg = kDeploy + "/config/" + file + ".yaml";
  ChildProcess p({bin(exe), "--replay", recording, "--estimates", dir + "/" + name + ".csv", "--events",
                  dir + "/" + name + ".jsonl", "--config", cfg},
                 {}, name);
  EXPECT_EQ(p.wait(std::chrono::seconds(120)), 0) << p.stderr_text();
  std::vector<std::string> out;
  for (const auto& e : json_lines(read_file(dir + "/" + name + ".jsonl")))
    out.push_back(e["turbine_id"].get<std::string>() + " " + e["component"].get<std::string>() + " " +
                  e["fault"].get<std::string>() + " " + e["state"].get<std::string>());
  return out;
}

TEST(ClockStep, NoServiceRaisesOrClearsAnythingBecauseTheControllersClockStepped) {
  // GIVEN a plant recording of two turbines, one with a 1 deg pitch-sensor bias and pump wear from 60 s, one
  // healthy, once as it is and once with the controller's clock 5 minutes ahead from 200 s and 5 minutes
  // behind from 400 s (a step back of 10 minutes there)
  const std::string dir = temp_dir("clock_step");
  std::ofstream(dir + "/scenario.yaml")
      << "duration: 600\nseed: 21\nturbines:\n"
         "  - {id: WT01, wind: {mean: 16.0, turbulence_intensity: 0.1}}\n"
         "  - {id: WT02, wind: {mean: 11.0, turbulence_intensity: 0.1}}\n"
         "faults:\n"
         "  - {turbine: WT01, target: pitch_2, type: bias, value: 1.0, start: 60}\n"
         "  - {turbine: WT01, target: pitch_actuator_3, type: pump_wear, start: 60}\n";
  for (const auto& [name, steps] : std::vector<std::pair<std::string, std::vector<std::string>>>{
           {"plain", {}}, {"stepped", {"--clock-step", "200:300", "--clock-step", "400:-600"}}}) {
    std::vector<std::string> argv{bin("windfdi-plant"), "--scenario", dir + "/scenario.yaml",
                                  "--offline",          "--record",   dir + "/" + name + ".csv.gz"};
    argv.insert(argv.end(), steps.begin(), steps.end());
    ChildProcess plant(argv, {}, "plant_" + name);
    ASSERT_EQ(plant.wait(std::chrono::seconds(120)), 0) << plant.stderr_text();
  }
  // WHEN every diagnostic service replays both
  for (const char* service : {"blade-load", "sensor-bias", "pitch-diag", "ice-detect", "drive-train"}) {
    const auto plain = events_of(service, dir + "/plain.csv.gz", dir, std::string(service) + "_plain");
    const auto stepped = events_of(service, dir + "/stepped.csv.gz", dir, std::string(service) + "_stepped");
    // THEN it reports the same events on both
    std::string a, b;
    for (const auto& e : plain) a += e + "\n";
    for (const auto& e : stepped) b += e + "\n";
    EXPECT_EQ(stepped, plain) << service << "\nwithout the steps:\n" << a << "with them:\n" << b;
  }
}

}  // namespace
