// A farm over a network: three hosts as network namespaces (two turbine hosts, one farm host) joined by a
// bridge over veth, UDP only, discovery through a Fast DDS discovery server on the farm host. Each turbine
// host runs its plant and its pitch_diag; the farm host runs the discovery server, the arbiter and the farm
// monitor, which must see both turbines' faults.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "process.hpp"
#include "test_util.hpp"

using namespace windfdi::test;
using nlohmann::json;

namespace {

const char* const kIp = "/bin/ip";  // ChildProcess execs without a PATH search

int sh(const std::string& command) { return std::system((command + " >/dev/null 2>&1").c_str()); }

class FarmNetwork : public ::testing::Test {
 protected:
  void SetUp() override {
    const int id = static_cast<int>(getpid() % 200);
    prefix = "wf" + std::to_string(id);
    net = "10.213." + std::to_string(id);
    if (geteuid() != 0 || sh("ip netns add " + prefix + "f") != 0)
      GTEST_SKIP() << "network namespaces need root and iproute2 (ip netns add failed)";
    created = true;
    // The farm host holds the bridge; each turbine host is a veth pair away from it.
    const std::string f = "ip -n " + prefix + "f ";
    ASSERT_EQ(sh(f + "link set lo up"), 0);
    ASSERT_EQ(sh(f + "link add br0 type bridge"), 0);
    ASSERT_EQ(sh(f + "link set br0 up"), 0);
    ASSERT_EQ(sh(f + "addr add " + net + ".1/24 dev br0"), 0);
    int address = 2;
    for (const char* host : {"a", "b"}) {
      const std::string ns = prefix + host, inside = prefix + host + "0", outside = prefix + host + "1";
      ASSERT_EQ(sh("ip netns add " + ns), 0);
      ASSERT_EQ(sh("ip -n " + ns + " link set lo up"), 0);
      ASSERT_EQ(sh("ip link add " + inside + " type veth peer name " + outside), 0);
      ASSERT_EQ(sh("ip link set " + inside + " netns " + ns), 0);
      ASSERT_EQ(sh("ip link set " + outside + " netns " + prefix + "f"), 0);
      ASSERT_EQ(sh(f + "link set " + outside + " master br0"), 0);
      ASSERT_EQ(sh(f + "link set " + outside + " up"), 0);
      ASSERT_EQ(
          sh("ip -n " + ns + " addr add " + net + "." + std::to_string(address++) + "/24 dev " + inside), 0);
      ASSERT_EQ(sh("ip -n " + ns + " link set " + inside + " up"), 0);
    }
  }
  void TearDown() override {
    processes.clear();  // stops every process before its namespace goes
    if (!created) return;
    for (const char* host : {"f", "a", "b"}) sh("ip netns del " + prefix + host);
    remove_stale_shm(domain);
  }
  ChildProcess& start(const std::string& host, std::vector<std::string> argv, const std::string& name) {
    argv.insert(argv.begin(), {kIp, "netns", "exec", prefix + host});
    auto env = dds_env(domain);
    env["WINDFDI_PARTICIPANT_PROFILE"] = "windfdi_participant_udp";  // UDP only, across the bridge
    env["ROS_DISCOVERY_SERVER"] = net + ".1:11811";                  // clients of the farm host's server
    processes.push_back(std::make_unique<ChildProcess>(argv, env, name));
    return *processes.back();
  }

  std::string prefix, net;
  bool created = false;
  int domain = private_domain(9);
  std::vector<std::unique_ptr<ChildProcess>> processes;
};

TEST_F(FarmNetwork, TwoTurbineHostsAndAFarmHostOverUdpWithADiscoveryServer) {
  const std::string dir = temp_dir("farm_network");
  // GIVEN a leak on WT01's blade 3 (host a) and pump wear on WT02's blade 1 (host b), both at 60 s
  std::ofstream(dir + "/wt01.yaml")
      << "duration: 200\nseed: 3\nturbines:\n  - {id: WT01, wind: {mean: 17.0}}\n"
         "faults:\n  - {turbine: WT01, target: pitch_actuator_3, type: "
         "hydraulic_leakage, start: 60}\n";
  std::ofstream(dir + "/wt02.yaml")
      << "duration: 200\nseed: 4\nturbines:\n  - {id: WT02, wind: {mean: 17.0}}\n"
         "faults:\n  - {turbine: WT02, target: pitch_actuator_1, type: pump_wear, "
         "start: 60}\n";
  const std::string db = dir + "/farm.sqlite";
  start("f", {"fast-discovery-server", "-i", "0", "-l", net + ".1", "-p", "11811"}, "discovery");
  auto& farm = start("f", {bin("windfdi-farm"), "--db", db, "--table-period", "0"}, "farm");
  auto& arbiter = start("f", {bin("windfdi-arbiter")}, "arbiter");
  start("a", {bin("windfdi-pitch-diag"), "--turbine", "WT01"}, "pitch_a");
  start("b", {bin("windfdi-pitch-diag"), "--turbine", "WT02"}, "pitch_b");
  std::this_thread::sleep_for(std::chrono::seconds(2));
  auto& plant_a =
      start("a", {bin("windfdi-plant"), "--scenario", dir + "/wt01.yaml", "--rate", "10"}, "plant_a");
  auto& plant_b =
      start("b", {bin("windfdi-plant"), "--scenario", dir + "/wt02.yaml", "--rate", "10"}, "plant_b");
  // THEN the farm host stores both turbines' faults, raised by their own hosts' pitch_diag
  const auto history = [&] { return farm_history(db, dds_env(domain)); };
  const auto has = [&](const std::vector<json>& rows, const char* turbine, const char* component,
                       const char* fault) {
    for (const auto& r : rows)
      if (r["kind"] == "fault" && r["data"]["turbine_id"] == turbine && r["data"]["component"] == component &&
          r["data"]["fault"] == fault && r["data"]["state"] == "raised")
        return true;
    return false;
  };
  // The arbiter's configurations follow the faults by a few ms: wait for all four, then say which is missing.
  const auto config_seen = [](const std::vector<json>& rows, const char* turbine, bool (*want)(const json&)) {
    for (const auto& r : rows)
      if (r["kind"] == "config" && r["data"]["turbine_id"] == turbine && want(r["data"])) return true;
    return false;
  };
  const auto safe_stop = [](const json& c) { return c["mode"] == "safe_stop"; };
  const auto derating = [](const json& c) { return c["mode"] == "normal" && !c["reasons"].empty(); };
  std::vector<json> rows;
  bool both = false, stopped = false, derated = false;
  wait_until(
      [&] {
        rows = history();
        both = has(rows, "WT01", "pitch_actuator_3", "hydraulic_leakage") &&
               has(rows, "WT02", "pitch_actuator_1", "pump_wear");
        stopped = config_seen(rows, "WT01", safe_stop);
        derated = config_seen(rows, "WT02", derating);
        return both && stopped && derated;
      },
      std::chrono::seconds(60));
  EXPECT_TRUE(both) << farm.stderr_text() << plant_a.stderr_text() << plant_b.stderr_text();
  // AND the arbiter on the farm host stopped WT01 (mode 2) and derated WT02, and the plants applied it
  EXPECT_TRUE(stopped) << arbiter.stderr_text();
  EXPECT_TRUE(derated) << arbiter.stderr_text();
  EXPECT_NE(plant_a.stderr_text().find("mode 2"), std::string::npos) << plant_a.stderr_text();
}

}  // namespace
