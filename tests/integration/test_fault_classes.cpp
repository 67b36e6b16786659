// End to end on DDS, one run per fault class of the canonical list (generated from one table over the
// shipped scenarios): the plant runs the class's scenario faster than real time, the diagnostic service
// reports, and the farm monitor must store the right FaultReport (component, class, source) within the
// class's target while the arbiter reacts as its decision table says. Plus the healthy scenario with every
// service, and a killed diagnostic service.
#include <gtest/gtest.h>

#include <algorithm>
#include <csignal>
#include <filesystem>
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

const std::string kDeploy = WINDFDI_SOURCE_DEPLOY_DIR;

/// A farm on a private domain: farm monitor, arbiter, a peer printing every configuration, and services.
struct Farm {
  int domain;
  std::map<std::string, std::string> env;
  std::string dir, db;
  std::vector<std::unique_ptr<ChildProcess>> processes;
  ChildProcess* configs = nullptr;
  ChildProcess* arbiter = nullptr;

  explicit Farm(int salt) : domain(private_domain(salt)), env(dds_env(domain)) {
    dir = temp_dir("fault_classes_" + std::to_string(domain));
    db = dir + "/farm.sqlite";
    start({bin("windfdi-farm"), "--db", db, "--table-period", "0"}, "farm");
    arbiter = &start({bin("windfdi-arbiter"), "--config", kDeploy + "/config/arbiter.yaml"}, "arbiter");
    configs = &start({bin("windfdi-test-peer"), "configs", "--timeout", "600"}, "configs");
  }
  ~Farm() {
    processes.clear();
    remove_stale_shm(domain);
  }
  ChildProcess& start(const std::vector<std::string>& argv, const std::string& name) {
    processes.push_back(std::make_unique<ChildProcess>(argv, env, name));
    return *processes.back();
  }
  /// A diagnostic service with its shipped configuration (windfdi-pitch-diag: config/pitch_diag.yaml).
  ChildProcess& service(const std::string& exe) {
    std::string name = exe.substr(std::string("windfdi-").size());
    std::replace(name.begin(), name.end(), '-', '_');
    return start({bin(exe), "--config", kDeploy + "/config/" + name + ".yaml"}, exe);
  }
  std::vector<json> history() const { return farm_history(db, env); }
  std::vector<json> configurations() const {
    std::vector<json> out;
    for (auto& j : json_lines(configs->stdout_text()))
      if (j.contains("revision")) out.push_back(j);
    return out;
  }
  std::string logs() const {
    std::string s;
    for (const auto& p : processes) s += p->stderr_text().substr(0, 4000);
    return s;
  }
};

struct FaultClass {
  const char* name;
  const char* scenario;
  const char* service;  ///< executable
  const char* source;   ///< its service name in the reports
  const char* component;
  const char* fault;
  double onset;   ///< s, the scenario's fault start
  double target;  ///< s from the onset within which the report must be raised
  double rate;    ///< plant speed-up
  std::function<bool(const json& config)> reaction;  ///< the arbiter's reaction, per its decision table
  /// Samples per frame (the plant's --block). The ice scenarios run 25 minutes of turbine at 30x: in blocks
  /// of 10 a reader's 8-block history is 27 ms of wall time, and five of them at once on 2 cores lost
  /// 10-200 samples a few times a second (one shedding never raised, an accretion 100 s late); blocks of 32
  /// make it 85 ms. The services see the same samples.
  int block = 10;
};

// The class's name stands for the row in test names and messages.
void PrintTo(const FaultClass& c, std::ostream* os) { *os << c.name; }

class FaultClassPipeline : public ::testing::TestWithParam<FaultClass> {};

TEST_P(FaultClassPipeline, RightReportReachesTheFarmInTimeAndTheArbiterReacts) {
  const FaultClass& c = GetParam();
  Farm farm(30);
  farm.service(c.service);
  std::this_thread::sleep_for(std::chrono::seconds(2));
  // GIVEN the class's scenario on the plant
  auto& plant =
      farm.start({bin("windfdi-plant"), "--scenario", kDeploy + "/scenarios/" + c.scenario, "--rate",
                  std::to_string(c.rate), "--block", std::to_string(c.block), "--progress", "0"},
                 "plant");
  // THEN the farm stores the report raised by the service on the component, within the target
  json report;
  const auto stored = [&] {
    for (const auto& r : farm.history())
      if (r["kind"] == "fault" && r["data"]["component"] == c.component && r["data"]["fault"] == c.fault &&
          r["data"]["source"] == c.source && r["data"]["state"] == "raised") {
        report = r["data"];
        return true;
      }
    return false;
  };
  const double wall_budget = (c.onset + c.target) / c.rate + 40.0;
  ASSERT_TRUE(wait_until(stored, std::chrono::seconds(static_cast<int>(wall_budget)))) << farm.logs();
  const double delay = report["t"].get<double>() - c.onset;
  EXPECT_GT(delay, 0.0) << report.dump();
  EXPECT_LE(delay, c.target) << report.dump();
  std::cout << "[ measured ] " << c.name << ": " << c.component << " " << c.fault << " raised " << delay
            << " s after the onset\n";
  // AND nothing was raised on another component (on this one an earlier class may precede the expected one:
  // an intermittent fault is first raised abrupt, and shedding needs the accretion that was there)
  for (const auto& r : farm.history())
    if (r["kind"] == "fault" && r["data"]["state"] == "raised" && r["data"]["component"] != c.component)
      ADD_FAILURE() << "raised on another component: " << r["data"].dump();
  // AND the arbiter's configuration reacts as its decision table says
  const auto reacted = [&] {
    for (const auto& j : farm.configurations())
      if (c.reaction(j)) return true;
    return false;
  };
  EXPECT_TRUE(wait_until(reacted, std::chrono::seconds(15)))
      << farm.configs->stdout_text() << farm.arbiter->stderr_text();
  plant.stop(SIGTERM);
}

bool derated(const json& c, int blade) {
  return c["pitch_rate_limit"][blade].get<double>() < 10.0 && c["mode"] == 0;
}

INSTANTIATE_TEST_SUITE_P(EveryClass, FaultClassPipeline,
                         ::testing::
                             Values(
                                 FaultClass{"pump_wear", "pump_wear.yaml", "windfdi-pitch-diag", "pitch_diag",
                                            "pitch_actuator_1", "pump_wear", 150, 10, 20,
                                            [](const json& c) { return derated(c, 0); }},
                                 FaultClass{"hydraulic_leakage", "hydraulic_leakage.yaml",
                                            "windfdi-pitch-diag", "pitch_diag", "pitch_actuator_3",
                                            "hydraulic_leakage", 150, 10, 20,
                                            [](const json& c) { return c["mode"] == 2; }},
                                 FaultClass{"high_air_content", "high_air_content.yaml", "windfdi-pitch-diag",
                                            "pitch_diag", "pitch_actuator_2", "high_air_content", 150, 10, 20,
                                            [](const json& c) { return derated(c, 1); }},
                                 FaultClass{"sensor_abrupt", "sensor_abrupt.yaml", "windfdi-blade-load",
                                            "blade_load", "blade_moment_sensor_2", "sensor_abrupt", 250, 10,
                                            10, [](const json& c) { return c["ipc_source"] == 1; }},
                                 FaultClass{"sensor_drift", "sensor_drift.yaml", "windfdi-blade-load",
                                            "blade_load", "blade_moment_sensor_1", "sensor_drift", 300, 300,
                                            20, [](const json& c) { return c["ipc_source"] == 1; }},
                                 FaultClass{"sensor_intermittent", "sensor_intermittent.yaml",
                                            "windfdi-blade-load", "blade_load", "blade_moment_sensor_3",
                                            "sensor_intermittent", 250, 120, 20,
                                            [](const json& c) { return c["ipc_source"] == 1; }},
                                 FaultClass{"sensor_invalid", "sensor_invalid.yaml", "windfdi-blade-load",
                                            "blade_load", "blade_moment_sensor_3", "sensor_invalid", 100, 5,
                                            10, [](const json& c) { return c["ipc_source"] == 1; }},
                                 FaultClass{
                                     "sensor_bias_rotor_speed", "sensor_bias_rotor_speed.yaml",
                                     "windfdi-sensor-bias", "sensor_bias", "rotor_speed_sensor",
                                     // reported once gain and offset are told apart: up to 60 s
                                     "sensor_bias", 150, 62, 10,
                                     [](const json& c) { return c["use_corrected_rotor_speed"] == true; }},
                                 FaultClass{"sensor_bias_generator_speed", "sensor_bias_generator_speed.yaml",
                                            "windfdi-sensor-bias", "sensor_bias", "generator_speed_sensor",
                                            "sensor_bias", 150, 5, 10,
                                            [](const json& c) {
                                              return c["use_corrected_generator_speed"] == true;
                                            }},
                                 FaultClass{"sensor_gain_generator_speed", "sensor_gain_generator_speed.yaml",
                                            "windfdi-sensor-bias", "sensor_bias", "generator_speed_sensor",
                                            "sensor_gain", 150, 6, 10,
                                            [](const json& c) {
                                              return c["use_corrected_generator_speed"] == true;
                                            }},
                                 FaultClass{
                                     "sensor_bias_pitch", "sensor_bias_pitch.yaml", "windfdi-sensor-bias",
                                     "sensor_bias", "pitch_sensor_2", "sensor_bias", 150, 5,
                                     10, [](const json& c) { return c["use_corrected_pitch"][1] == true; }},
                                 FaultClass{"ice_accretion", "ice_accretion.yaml", "windfdi-ice-detect",
                                            "ice_detect", "rotor", "ice_accretion", 600, 900,
                                            30, [](const json& c) { return c["ice_mode"] == 1; }, 32},
                                 FaultClass{"ice_shedding", "ice_shedding.yaml", "windfdi-ice-detect",
                                            "ice_detect", "rotor", "ice_shedding", 700, 300, 30,
                                            [](const json& c) { return c["reasons"].get<int>() > 0; }, 32},
                                 FaultClass{"torque_offset",
                                            "converter_torque_offset.yaml", "windfdi-drive-train",
                                            "drive_train", "converter", "torque_offset", 150, 1, 10,
                                            [](const json& c) {
                                              const double comp = c["torque_compensation"].get<double>();
                                              return comp > 70.0 && comp < 130.0 && c["mode"] == 0;
                                            }},
                                 FaultClass{
                                     "efficiency_loss", "drive_train_efficiency.yaml", "windfdi-drive-train",
                                     "drive_train", "drive_train", "efficiency_loss", 260, 60, 10,
                                     [](const json& c) {
                                       return c["reasons"].get<int>() > 0 && c["mode"] == 0;
                                     }}),
                         [](const auto& i) { return std::string(i.param.name); });

// One fault through the whole system (every service, the arbiter closing the loop on the plant): one right
// report, nothing on the components its residuals touch, and no stop (deploy/arbiter/DECISION_TABLE.md).
struct Chain {
  const char* name;
  const char* scenario;
  const char* component;  ///< the one report expected
  const char* fault;
  std::vector<std::string> quiet_prefixes;  ///< components on which nothing may be raised
};
void PrintTo(const Chain& c, std::ostream* os) { *os << c.name; }

class IsolationChain : public ::testing::TestWithParam<Chain> {};

TEST_P(IsolationChain, OneFaultGivesOneReportAndNoStop) {
  const Chain& c = GetParam();
  Farm farm(33);
  for (const char* exe : {"windfdi-blade-load", "windfdi-sensor-bias", "windfdi-pitch-diag",
                          "windfdi-ice-detect", "windfdi-drive-train"})
    farm.service(exe);
  std::this_thread::sleep_for(std::chrono::seconds(2));
  // GIVEN the chain's scenario (fault at 300 s, after blade_load has learned) at 20x real time, closed loop
  auto& plant = farm.start({bin("windfdi-plant"), "--scenario", kDeploy + "/scenarios/" + c.scenario,
                            "--rate", "20", "--progress", "0"},
                           "plant");
  ASSERT_EQ(plant.wait(std::chrono::seconds(120)), 0) << plant.stderr_text();
  std::this_thread::sleep_for(std::chrono::seconds(3));
  const auto history = farm.history();
  // THEN the fault's own report was raised
  bool found = false;
  for (const auto& r : history)
    found |= r["kind"] == "fault" && r["data"]["state"] == "raised" &&
             r["data"]["component"] == c.component && r["data"]["fault"] == c.fault;
  EXPECT_TRUE(found) << c.component << " " << c.fault << " not raised\n" << farm.logs();
  // AND nothing on the components its residuals touch
  for (const auto& r : history) {
    if (r["kind"] != "fault" || r["data"]["state"] != "raised") continue;
    const std::string component = r["data"]["component"].get<std::string>();
    for (const auto& p : c.quiet_prefixes)
      if (component.rfind(p, 0) == 0) ADD_FAILURE() << "raised on " << component << ": " << r["data"].dump();
  }
  // AND the turbine was never stopped
  for (const auto& cfg : farm.configurations()) EXPECT_NE(cfg["mode"], 2) << cfg.dump();
}

INSTANTIATE_TEST_SUITE_P(Chains, IsolationChain,
                         ::testing::Values(Chain{"rotor_speed_stuck_raises_no_blade_or_pitch_report",
                                                 "chain_rotor_speed_stuck.yaml",
                                                 "rotor_speed_sensor",
                                                 "sensor_stuck",
                                                 {"blade_moment_sensor_", "pitch_sensor_",
                                                  "pitch_actuator_"}},
                                           Chain{"stuck_pitch_sensor_is_no_actuator_fault",
                                                 "chain_pitch_stuck.yaml",
                                                 "pitch_sensor_1",
                                                 "sensor_stuck",
                                                 {"pitch_actuator_"}},
                                           Chain{"high_air_content_at_18_never_stops",
                                                 "chain_high_air_content_18.yaml",
                                                 "pitch_actuator_2",
                                                 "high_air_content",
                                                 {"pitch_sensor_", "blade_moment_sensor_"}},
                                           Chain{"generator_speed_bias_raises_no_actuator_fault",
                                                 "chain_generator_speed_bias.yaml",
                                                 "generator_speed_sensor",
                                                 "sensor_bias",
                                                 {"pitch_actuator_"}}),
                         [](const auto& i) { return std::string(i.param.name); });

// A restart of pitch_diag on a running turbine, `down_ms` of wall time after a kill -9 (at 5x: 5 turbine
// seconds per wall second). The health lease is 3 s: a shorter restart is not seen as a loss at all.
struct Restart {
  const char* name;
  int down_ms;
  bool loss_noticed;
};

class RestartedService : public ::testing::TestWithParam<Restart> {};

TEST_P(RestartedService, ARestartOnARunningTurbineRaisesNothingAndTheRealFaultIsFound) {
  const Restart& r = GetParam();
  // GIVEN pitch_diag, the shipped arbiter and the farm on hydraulic_leakage.yaml (blade 3 leaks from 150 s)
  // at 5x
  Farm farm(r.loss_noticed ? 35 : 34);
  auto diag = std::make_unique<ChildProcess>(
      std::vector<std::string>{bin("windfdi-pitch-diag"), "--config", kDeploy + "/config/pitch_diag.yaml"},
      farm.env, "pitch_diag");
  std::this_thread::sleep_for(std::chrono::seconds(2));
  auto& plant = farm.start({bin("windfdi-plant"), "--scenario", kDeploy + "/scenarios/hydraulic_leakage.yaml",
                            "--rate", "5", "--progress", "0"},
                           "plant");
  // WHEN pitch_diag is killed at about 70 s and restarted, on a running turbine
  std::this_thread::sleep_for(std::chrono::milliseconds(14000));
  diag->stop(SIGKILL);
  std::this_thread::sleep_for(std::chrono::milliseconds(r.down_ms));
  diag = std::make_unique<ChildProcess>(
      std::vector<std::string>{bin("windfdi-pitch-diag"), "--config", kDeploy + "/config/pitch_diag.yaml"},
      farm.env, "pitch_diag_restarted");
  ASSERT_EQ(plant.wait(std::chrono::seconds(120)), 0) << plant.stderr_text();
  std::this_thread::sleep_for(std::chrono::seconds(3));
  // THEN nothing was raised on the healthy actuators, and the leak on blade 3 was, only after its onset
  bool leak = false;
  for (const auto& h : farm.history()) {
    if (h["kind"] != "fault" || h["data"]["state"] != "raised") continue;
    const auto& d = h["data"];
    if (d["component"] == "pitch_actuator_3" && d["t_detected"].get<double>() >= 150.0) {
      leak |= d["fault"] == "hydraulic_leakage";
    } else {
      ADD_FAILURE() << "raised: " << d.dump();
    }
  }
  EXPECT_TRUE(leak) << diag->stderr_text();
  // AND the lost-service fallback (every blade derated) came only for a loss the lease noticed, and was
  // withdrawn once the restarted service had been back for the arbiter's clear_hold, before the leak.
  // It once stayed for good: the restarted writer was seen before the old one's lease ran out, and the old
  // writer's loss then marked the running service lost (the false leak warning on blade 1 came of that).
  bool derated = false, normal_again = false, stopped = false;
  for (const auto& c : farm.configurations()) {
    const double t = c["t"].get<double>();
    if (t < 150.0) {
      if (c["mode"] == 1) derated = true;
      if (derated && c["mode"] == 0) normal_again = true;
    }
    if (c["mode"] != 2) continue;
    // AND no stop came before the leak (the restart itself is harmless), one came after it
    if (!stopped) std::cout << "[ measured ] safe stop at t = " << t << " s\n";
    stopped = true;
    EXPECT_GE(t, 150.0) << c.dump();
  }
  // A restart 0.8 s after the kill is usually seen before the old writer's 3 s lease runs out (no derate at
  // all), but not always on a loaded machine (CI once saw the loss first): then the derate must be withdrawn
  // as after any loss. The defect this guards against left it on for good.
  std::cout << "[ measured ] loss seen by the arbiter: " << (derated ? "yes" : "no") << "\n";
  if (r.loss_noticed) {
    EXPECT_TRUE(derated) << farm.configs->stdout_text();
  }
  EXPECT_EQ(normal_again, derated) << farm.configs->stdout_text();
  EXPECT_TRUE(stopped) << farm.configs->stdout_text() << farm.logs();
}

INSTANTIATE_TEST_SUITE_P(Restarts, RestartedService,
                         ::testing::Values(Restart{"within_the_health_lease", 800, false},
                                           Restart{"after_the_loss_is_noticed", 4500, true}),
                         [](const auto& i) { return std::string(i.param.name); });

TEST(HealthyFarm, EveryServiceOnTheHealthyScenarioRaisesNothing) {
  // GIVEN every diagnostic service and the arbiter on healthy.yaml (three turbines at 8, 14 and 20 m/s), the
  // first 15 minutes at 10x real time (whole hours per turbine are run by each service's own tests)
  Farm farm(31);
  for (const char* exe : {"windfdi-blade-load", "windfdi-sensor-bias", "windfdi-pitch-diag",
                          "windfdi-ice-detect", "windfdi-drive-train"})
    farm.service(exe);
  auto& health = farm.start({bin("windfdi-test-peer"), "health", "--timeout", "300"}, "health");
  std::this_thread::sleep_for(std::chrono::seconds(2));
  auto& plant = farm.start({bin("windfdi-plant"), "--scenario", kDeploy + "/scenarios/healthy.yaml", "--rate",
                            "10", "--duration", "900", "--progress", "0"},
                           "plant");
  ASSERT_EQ(plant.wait(std::chrono::seconds(150)), 0) << plant.stderr_text();
  std::this_thread::sleep_for(std::chrono::seconds(3));
  // THEN no fault was raised, and every configuration is the normal one
  for (const auto& r : farm.history())
    if (r["kind"] == "fault") ADD_FAILURE() << r["data"].dump();
  const auto configs = farm.configurations();
  EXPECT_FALSE(configs.empty());
  for (const auto& c : configs) {
    EXPECT_EQ(c["mode"], 0) << c.dump();
    EXPECT_EQ(c["ipc_source"], 0) << c.dump();
  }
  // AND every service diagnosed every turbine: 15 minutes of 100 Hz samples in, almost none rejected
  std::map<std::pair<std::string, std::string>, json> latest;  // (service, turbine) -> last health
  for (const auto& j : json_lines(health.stdout_text()))
    if (j.contains("service")) latest[{j["service"], j["turbine_id"]}] = j;
  for (const char* service : {"blade_load", "sensor_bias", "pitch_diag", "ice_detect", "drive_train"})
    for (const char* turbine : {"WT01", "WT02", "WT03"}) {
      const auto it = latest.find({service, turbine});
      ASSERT_NE(it, latest.end()) << service << " " << turbine << " sent no health";
      const auto in = it->second["samples_in"].get<uint64_t>();
      EXPECT_GT(in, 80000u) << it->second.dump();
      EXPECT_LT(it->second["samples_rejected"].get<uint64_t>(), in / 100) << it->second.dump();
    }
}

TEST(LaunchFarm, AScenariosTurbineFileIsEveryServicesAndTheArbiters) {
  // GIVEN a scenario on the 6 MW example turbine (turbine_file, relative to deploy/) run by the simulated
  // farm (launch_farm.sh: every service, the arbiter, the farm monitor and the plant on a private domain), 30
  // s at 10x
  const int domain = private_domain(41);
  auto env = dds_env(domain);
  env["WINDFDI_BIN"] = bin("");
  const std::string dir = temp_dir("launch_farm_" + std::to_string(domain));
  const std::string scenario = dir + "/six.yaml";
  {
    std::ofstream f(scenario);
    f << "duration: 30\nseed: 5\nturbine_file: turbine/example_6MW.yaml\nturbines:\n"
         "  - {id: WT01, wind: {mean: 12.0, turbulence_intensity: 0.1, shear_exponent: 0.2}}\nfaults: []\n";
  }
  {
    ChildProcess farm({kDeploy + "/scripts/launch_farm.sh", scenario, "--rate", "10", "--work", dir + "/work",
                       "--domain", std::to_string(domain), "--table-period", "0"},
                      env, "launch_farm");
    ASSERT_EQ(farm.wait(std::chrono::seconds(120)), 0) << farm.stderr_text();
  }
  remove_stale_shm(domain);
  // THEN every service's and the arbiter's configuration names that turbine file, as the plant's scenario
  // does
  const std::string six = kDeploy + "/turbine/example_6MW.yaml";
  for (const char* name :
       {"arbiter", "blade_load", "drive_train", "ice_detect", "pitch_diag", "sensor_bias"}) {
    const std::string config = read_file(dir + "/work/deploy/config/" + name + ".yaml");
    EXPECT_NE(config.find("turbine_file: " + std::filesystem::canonical(six).string()), std::string::npos)
        << name;
  }
  // AND sensor_bias designed its observers for that turbine at start (its relative gain files resolved)
  const std::string log = read_file(dir + "/work/logs/sensor-bias.log");
  EXPECT_NE(log.find("designed from design_drive_train_observer.yaml for it"), std::string::npos) << log;
  EXPECT_NE(log.find("example_6MW.yaml"), std::string::npos) << log;
  // AND the farm monitor stored the turbine's health
  EXPECT_FALSE(farm_history(dir + "/work/farm.sqlite", env).empty());
}

TEST(SilentPlant, AServiceReportsItsInputStreamsMissedDeadlinesInItsHealth) {
  // GIVEN windfdi-ice-detect diagnosing a turbine, and a peer printing every ServiceHealth
  Farm farm(33);
  farm.service("windfdi-ice-detect");
  auto& health = farm.start({bin("windfdi-test-peer"), "health", "--timeout", "120"}, "health");
  std::this_thread::sleep_for(std::chrono::seconds(2));
  // WHEN the plant publishes 30 s of frames (3 s at 10x) and then falls silent
  auto& plant = farm.start({bin("windfdi-plant"), "--scenario", kDeploy + "/scenarios/healthy.yaml", "--rate",
                            "10", "--duration", "30", "--progress", "0"},
                           "plant");
  ASSERT_EQ(plant.wait(std::chrono::seconds(60)), 0) << plant.stderr_text();
  // THEN the service's health says it had samples and that its frame stream missed its 1 s deadline
  const auto reported = [&] {
    for (const auto& j : json_lines(health.stdout_text()))
      if (j.value("service", "") == "ice_detect" && j.value("samples_in", 0) > 0 &&
          j.value("deadlines_missed", 0) > 0)
        return true;
    return false;
  };
  EXPECT_TRUE(wait_until(reported, std::chrono::seconds(15))) << health.stdout_text() << farm.logs();
}

TEST(KilledService, ARealDiagnosticServiceKilledBecomesServiceLostAndTheConservativeSetting) {
  // GIVEN windfdi-pitch-diag diagnosing a healthy turbine
  Farm farm(32);
  auto& diag = farm.service("windfdi-pitch-diag");
  std::this_thread::sleep_for(std::chrono::seconds(2));
  farm.start({bin("windfdi-plant"), "--scenario", kDeploy + "/scenarios/healthy.yaml", "--duration", "600",
              "--progress", "0"},
             "plant");
  const auto farm_knows = [&] {
    for (const auto& r : farm.history())
      if (r["kind"] == "health" && r["data"]["service"] == "pitch_diag" && r["data"]["event"] == "ok")
        return true;
    return false;
  };
  ASSERT_TRUE(wait_until(farm_knows, std::chrono::seconds(30))) << farm.logs();
  // WHEN it is killed without a goodbye
  diag.stop(SIGKILL);
  const auto killed = std::chrono::steady_clock::now();
  // THEN the farm records it lost, and the arbiter derates every blade and degrades the turbines
  const auto lost = [&] {
    for (const auto& r : farm.history())
      if (r["kind"] == "health" && r["data"]["service"] == "pitch_diag" && r["data"]["event"] == "lost")
        return true;
    return false;
  };
  EXPECT_TRUE(wait_until(lost, std::chrono::seconds(20))) << farm.logs();
  const auto conservative = [&] {
    for (const auto& c : farm.configurations())
      if (c["mode"] == 1 && c["pitch_rate_limit"][0].get<double>() < 10.0 &&
          c["pitch_rate_limit"][1].get<double>() < 10.0 && c["pitch_rate_limit"][2].get<double>() < 10.0)
        return true;
    return false;
  };
  EXPECT_TRUE(wait_until(conservative, std::chrono::seconds(20))) << farm.configs->stdout_text();
  std::cout << "[ measured ] pitch_diag killed -> service_lost and degraded configuration after "
            << std::chrono::duration<double>(std::chrono::steady_clock::now() - killed).count() << " s\n";
}

}  // namespace
