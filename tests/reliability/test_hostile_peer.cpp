// Reliability: a hostile peer on an unsecured domain (10 000 made-up turbines, NaN and 1e308 samples, foreign
// reports and health, huge strings) is refused and counted, and costs the processes bounded memory.
#include <gtest/gtest.h>

#include <csignal>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <thread>

#include "process.hpp"
#include "test_util.hpp"

using namespace windfdi::test;
using nlohmann::json;

namespace {

const std::string kDeploy = WINDFDI_SOURCE_DEPLOY_DIR;

// Resident memory of a process (MB), from /proc.
double resident_mb(int pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return -1.0;
}

TEST(HostilePeer, MadeUpTurbinesForeignReportsAndHugeStringsAreRefusedAndCostBoundedMemory) {
  // GIVEN pitch_diag, blade_load, the arbiter and the farm monitor on an unsecured domain, each told the farm
  // has at most 5 turbines
  const int domain = private_domain(13);
  const auto env = dds_env(domain);
  const std::string db = temp_dir("hostile_" + std::to_string(domain)) + "/farm.sqlite";
  const std::vector<std::string> limit = {"--max-turbines", "5"};
  auto with_limit = [&](std::vector<std::string> argv) {
    argv.insert(argv.end(), limit.begin(), limit.end());
    return argv;
  };
  std::vector<std::pair<std::string, std::unique_ptr<ChildProcess>>> processes;
  for (const auto& [argv, name] : std::vector<std::pair<std::vector<std::string>, std::string>>{
           {{bin("windfdi-farm"), "--db", db, "--table-period", "0"}, "farm"},
           {{bin("windfdi-arbiter"), "--config", kDeploy + "/config/arbiter.yaml"}, "arbiter"},
           {{bin("windfdi-pitch-diag"), "--config", kDeploy + "/config/pitch_diag.yaml"}, "pitch_diag"},
           {{bin("windfdi-blade-load"), "--config", kDeploy + "/config/blade_load.yaml"}, "blade_load"}})
    processes.emplace_back(name, std::make_unique<ChildProcess>(with_limit(argv), env, name));
  std::this_thread::sleep_for(std::chrono::seconds(3));
  std::map<std::string, double> before;
  for (auto& [name, p] : processes) before[name] = resident_mb(p->pid());

  // WHEN a peer floods frames for 10 000 unknown turbines and NaN / 1e308 samples for WT03, and sends
  // reports and health with unknown components, services and turbines, ids of 200 bytes and strings of 1 MB
  ChildProcess peer({bin("windfdi-test-peer"), "hostile", "--farm", "10000", "--huge", "1048576", "--hold",
                     "15", "--turbine-id", "WT03"},
                    env, "hostile");
  ASSERT_EQ(peer.wait(std::chrono::seconds(120)), 0) << peer.stderr_text();
  std::this_thread::sleep_for(std::chrono::seconds(3));

  // THEN every process runs, its resident memory grew by less than 64 MB
  std::string logs;
  for (auto& [name, p] : processes) {
    EXPECT_TRUE(p->running()) << name << " ended: " << p->stderr_text().substr(0, 3000);
    const double after = resident_mb(p->pid());
    std::cout << "[ measured ] " << name << " resident " << before[name] << " -> " << after << " MB\n";
    EXPECT_LT(after - before[name], 64.0) << name;
    logs += p->stderr_text();
  }
  // AND the services and the arbiter said that they refused turbines past the limit, and the arbiter and the
  // farm monitor that they ignored foreign reports
  for (const char* said : {"pitch_diag: ", "blade_load: ", "arbiter: "})
    EXPECT_NE(logs.find(std::string(said) + "10 messages refused for turbines past --max-turbines 5"),
              std::string::npos)
        << said << "\n"
        << logs.substr(0, 6000);
  EXPECT_NE(logs.find("ignoring a FaultReport (1 so far): its component is not a canonical one"),
            std::string::npos);
  // AND the farm store holds at most 5 turbines, none with an id over 64 bytes, and no foreign report
  std::set<std::string> turbines;
  for (const auto& r : farm_history(db, env)) {
    const std::string id = r["data"].value("turbine_id", std::string("*"));
    if (id != "*") turbines.insert(id);
    EXPECT_LE(id.size(), 64u);
    if (r["kind"] == "fault") {
      EXPECT_NE(r["data"]["component"], "flux_capacitor");
    }
  }
  EXPECT_LE(turbines.size(), 5u);
  for (auto& [name, p] : processes) p->stop(SIGTERM);
  remove_stale_shm(domain);
}

}  // namespace
