// End to end on DDS: plant with an iced rotor -> windfdi-ice-detect -> arbiter (ice-adapted control) and
// farm monitor (the FaultReport stored).
#include <gtest/gtest.h>

#include <csignal>
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
  ChildProcess plant({bin("windfdi-plant"), "--scenario", deploy + "/scenarios/iced_rotor.yaml", "--rate", "20"}, env,
                     "plant");
  // THEN the plant applies an ice-adapted configuration (ice mode 1) from the arbiter
  const bool adapted = wait_until(
      [&] { return plant.stderr_text().find("applying configuration") != std::string::npos &&
                   farm.stderr_text().find("ice adapted") != std::string::npos; },
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

}  // namespace
