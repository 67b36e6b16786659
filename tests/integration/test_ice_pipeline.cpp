// windfdi-ice-detect as a process: end to end on DDS (plant with an iced rotor -> ice_detect -> arbiter and
// farm monitor), and the replay contract on a plant recording with an accretion and a shedding.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "process.hpp"
#include "test_util.hpp"

using namespace windfdi::test;

namespace {

TEST(IcePipeline, IcedRotorReachesTheFarmAndTheArbiterAdaptsTheController) {
  const int domain = private_domain(4);
  const auto env = dds_env(domain);
  const std::string dir = temp_dir("ice_pipeline");
  const std::string deploy = WINDFDI_SOURCE_DEPLOY_DIR;
  ChildProcess farm({bin("windfdi-farm"), "--db", dir + "/farm.sqlite", "--table-period", "0"}, env, "farm");
  ChildProcess arbiter({bin("windfdi-arbiter")}, env, "arbiter");
  ChildProcess ice({bin("windfdi-ice-detect"), "--config", deploy + "/config/ice_detect.yaml"}, env, "ice");
  std::this_thread::sleep_for(std::chrono::seconds(2));
  // GIVEN a plant whose rotor carries 3 t of ice, at 20x real time
  ChildProcess plant(
      {bin("windfdi-plant"), "--scenario", deploy + "/scenarios/iced_rotor.yaml", "--rate", "20"}, env,
      "plant");
  // THEN the plant applies an ice-adapted configuration (ice mode 1) from the arbiter
  const bool adapted = wait_until(
      [&] {
        return plant.stderr_text().find("applying configuration") != std::string::npos &&
               farm.stderr_text().find("ice adapted") != std::string::npos;
      },
      std::chrono::seconds(60));
  // AND the farm stored ice_accretion on rotor from ice_detect
  const auto rows = farm_history(dir + "/farm.sqlite", env);
  ASSERT_FALSE(rows.empty()) << farm.stderr_text();
  bool stored = false;
  for (const auto& j : rows)
    if (j["kind"] == "fault" && j["data"]["component"] == "rotor" && j["data"]["fault"] == "ice_accretion" &&
        j["data"]["source"] == "ice_detect" && j["data"]["state"] == "raised")
      stored = true;
  EXPECT_TRUE(stored) << rows.size() << " events; " << ice.stderr_text();
  EXPECT_TRUE(adapted) << farm.stderr_text() << arbiter.stderr_text();
  plant.stop(SIGTERM);
  remove_stale_shm(domain);
}

// The scenario's true ice mass (kg) at t: 2500 kg accreting over [500, 1700) s, half of it shed at 2000 s.
double scenario_ice(double t) {
  const double accreted = 2500.0 * std::clamp((t - 500.0) / 1200.0, 0.0, 1.0);
  return t < 2000.0 ? accreted : 0.5 * accreted;
}

TEST(IceReplay, PlantRecordingTracksTheAccretionAndFlagsTheShedding) {
  // GIVEN a plant recording (gzip) at 10 m/s, 12 % turbulence: 2.5 t of ice accrete over 20 minutes from
  // 500 s, and half of it falls off at 2000 s
  const std::string dir = temp_dir("ice_replay");
  std::ofstream(dir + "/scenario.yaml")
      << "duration: 2300\nseed: 41\n"
         "turbines:\n  - {id: WT01, wind: {mean: 10.0, turbulence_intensity: 0.12}}\n"
         "faults:\n"
         "  - {turbine: WT01, target: rotor, type: ice_accretion, value: 2500, ramp_in: 1200, start: 500}\n"
         "  - {turbine: WT01, target: rotor, type: ice_shedding, fraction: 0.5, start: 2000}\n";
  ChildProcess plant({bin("windfdi-plant"), "--scenario", dir + "/scenario.yaml", "--offline", "--record",
                      dir + "/frames.csv.gz"},
                     {}, "plant");
  ASSERT_EQ(plant.wait(std::chrono::seconds(60)), 0) << plant.stderr_text();
  // WHEN windfdi-ice-detect replays it with the shipped configuration (the recording has no aerodynamic
  // power, as a real turbine's: the model on the anemometer gives it)
  ChildProcess ice({bin("windfdi-ice-detect"), "--replay", dir + "/frames.csv.gz", "--estimates",
                    dir + "/est.csv", "--events", dir + "/events.jsonl", "--config",
                    std::string(WINDFDI_SOURCE_DEPLOY_DIR) + "/config/ice_detect.yaml"},
                   {}, "ice_replay");
  ASSERT_EQ(ice.wait(std::chrono::seconds(60)), 0) << ice.stderr_text();
  // THEN the estimates carry the contract's columns, once a second
  std::stringstream es(read_file(dir + "/est.csv"));
  std::string line;
  std::getline(es, line);
  EXPECT_EQ(line, "t,turbine_id,inertia,ice_mass,excited");
  int rows = 0, during = 0;
  double sum_sq = 0.0, worst_after = 0.0;
  while (std::getline(es, line)) {
    ++rows;
    std::stringstream ls(line);
    std::string t, id, inertia, mass;
    std::getline(ls, t, ',');
    std::getline(ls, id, ',');
    std::getline(ls, inertia, ',');
    std::getline(ls, mass, ',');
    const double time = std::stod(t), ice_mass = std::stod(mass);
    // AND the ice mass follows the ramp a window and half a median late (90 s; measured rms 380-610 kg over
    // seeds 41-43), and is right after the shedding once the window holds none of what fell: a window and
    // half a median (150 s) after the step in the power model's balance is seen, 2035-2041 s (the later
    // since stop 65, whose step threshold is as wide as the balance's wander learned within 3 of its RMS)
    if (time >= 900.0 && time < 2000.0) {
      sum_sq += std::pow(ice_mass - scenario_ice(time - 90.0), 2);
      ++during;
    }
    if (time >= 2195.0) worst_after = std::max(worst_after, std::fabs(ice_mass - scenario_ice(time)));
  }
  EXPECT_GE(rows, 2290);
  ASSERT_GT(during, 1000);
  EXPECT_LT(std::sqrt(sum_sq / during), 600.0) << "kg rms";
  EXPECT_LT(worst_after, 700.0) << "kg";
  // AND ice_accretion is raised during the accretion or soon after its end (measured 1765 s: a clean rotor's
  // first report needs first_confirm_time, 60 s, of fresh estimates above the warning, and the median was
  // held 1685-1735 s; 1649 s with 10 s), and ice_shedding within a minute of the drop
  double accretion = -1, shedding = -1;
  for (const auto& e : json_lines(read_file(dir + "/events.jsonl"))) {
    EXPECT_EQ(e["component"], "rotor") << e.dump();
    EXPECT_EQ(e["source"], "ice_detect");
    if (e["state"] != "raised") continue;
    if (e["fault"] == "ice_accretion" && accretion < 0) accretion = e["t"].get<double>();
    if (e["fault"] == "ice_shedding" && shedding < 0) shedding = e["t"].get<double>();
  }
  EXPECT_GT(accretion, 500.0);
  EXPECT_LT(accretion, 1800.0);
  EXPECT_GE(shedding, 2000.0);
  EXPECT_LT(shedding, 2060.0);
}

TEST(IceReplay, MalformedRecordingExitsWithCode2NamingFileAndLine) {
  const auto r =
      replay_malformed("windfdi-ice-detect", "t,generator_speed,gen_torque\n0,152,30000\n0.01,152,torque\n");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.stderr_text.find(r.file + ":3"), std::string::npos) << r.stderr_text;
}

}  // namespace
