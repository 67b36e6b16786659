// Unit tests of the farm monitor's SQLite store and live table.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <tuple>

#include "deploy_dir.hpp"
#include "farm_state.hpp"
#include "farm_store.hpp"
#include "fault_report.hpp"
#include "process.hpp"
#include "yaml_config.hpp"

using namespace windfdi;
using namespace windfdi::farm;

namespace {

FaultEvent fault(const std::string& turbine, const std::string& component, const std::string& cls, double t,
                 bool raised = true) {
  FaultEvent e;
  e.t = t;
  e.turbine_id = turbine;
  e.source = "pitch_diag";
  e.component = component;
  e.fault = cls;
  e.raised = raised;
  e.severity = "critical";
  return e;
}

/// Injected faults (turbine, target, type, start) with the component and class a service should report.
std::vector<InjectedFault> injected_faults(
    std::initializer_list<std::tuple<const char*, const char*, const char*, double>> faults) {
  std::vector<InjectedFault> out;
  for (const auto& [turbine, target, type, start] : faults) {
    InjectedFault i{turbine, target, type, start, "", ""};
    std::tie(i.component, i.fault) = expected_detection(i.target, i.type);
    out.push_back(i);
  }
  return out;
}

TEST(FarmStore, ReplayedEventsAreStoredOnce) {
  const std::string db = test::temp_dir("farm1") + "/farm.sqlite";
  FarmStore s(db);
  // GIVEN a raised fault stored once
  EXPECT_TRUE(s.add_fault(fault("WT01", "pitch_actuator_3", "hydraulic_leakage", 12.0), 1000.0));
  // WHEN the same report arrives again (transient-local replay after a restart)
  EXPECT_FALSE(s.add_fault(fault("WT01", "pitch_actuator_3", "hydraulic_leakage", 12.0), 1005.0));
  // THEN it is not stored twice, while its clear is a new event
  EXPECT_TRUE(s.add_fault(fault("WT01", "pitch_actuator_3", "hydraulic_leakage", 20.0, false), 1010.0));
  EXPECT_EQ(s.count("fault_events"), 2);
  ConfigRecord c{1001.0, 12.1, "WT01", "primary", 3, "safe_stop", "strain_gauge", "normal", {"a/b/c: d"}};
  EXPECT_TRUE(s.add_config(c));
  EXPECT_FALSE(s.add_config(c));
}

TEST(FarmStore, HistoryFiltersByTurbineAndTime) {
  const std::string db = test::temp_dir("farm2") + "/farm.sqlite";
  FarmStore s(db);
  s.add_fault(fault("WT01", "pitch_actuator_1", "pump_wear", 1.0), 100.0);
  s.add_fault(fault("WT02", "pitch_actuator_2", "pump_wear", 1.0), 200.0);
  s.add_health({150.0, "WT01", "pitch_diag", "lost", "liveliness lost"});
  EXPECT_EQ(s.history("", 0.0).size(), 3u);
  const auto wt1 = s.history("WT01", 0.0);
  ASSERT_EQ(wt1.size(), 2u);
  EXPECT_EQ(wt1[0].kind, "fault");
  EXPECT_EQ(wt1[1].kind, "health");  // ordered by reception
  EXPECT_EQ(s.history("", 150.0).size(), 2u);
  EXPECT_EQ(s.history("WT03", 0.0).size(), 0u);
}

TEST(FarmStore, CommittedEventsSurviveKillMinus9) {
  // GIVEN a child process that stores an event and is then killed with SIGKILL before closing
  const std::string db = test::temp_dir("farm3") + "/farm.sqlite";
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    FarmStore s(db);
    s.add_fault(fault("WT07", "rotor", "ice_accretion", 5.0), 50.0);
    kill(getpid(), SIGKILL);
    _exit(0);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status));
  // WHEN the database is reopened THEN the event is there, and the picture rebuilt from it says so
  FarmStore s(db);
  const auto latest = s.latest_faults();
  ASSERT_EQ(latest.size(), 1u);
  EXPECT_EQ(latest[0].turbine_id, "WT07");
  EXPECT_TRUE(latest[0].raised);
}

TEST(FarmStore, UnopenableDatabaseIsAConfigError) {
  EXPECT_THROW(FarmStore("/nonexistent/dir/farm.sqlite"), ConfigError);
}

TEST(FarmState, TableShowsModesFaultsAndLostServices) {
  FarmState st;
  st.on_config({0, 0, "WT02", "primary", 4, "safe_stop", "lidar_model", "normal", {}});
  st.on_fault(fault("WT02", "pitch_actuator_3", "hydraulic_leakage", 1.0));
  st.on_fault(fault("WT01", "pitch_actuator_1", "pump_wear", 1.0));
  st.on_fault(fault("WT01", "pitch_actuator_1", "pump_wear", 9.0, false));  // cleared
  st.on_service("WT01", "ice_detect", "ok");
  st.on_service_lost("WT01", "ice_detect");
  EXPECT_EQ(st.active_faults("WT01"), (std::vector<std::string>{"ice_detect service_lost"}));
  EXPECT_EQ(st.active_faults("WT02"),
            (std::vector<std::string>{"pitch_actuator_3 hydraulic_leakage (critical)"}));
  const std::string table = st.render();
  EXPECT_NE(table.find("safe_stop"), std::string::npos) << table;
  EXPECT_NE(table.find("lidar_model"), std::string::npos) << table;
  EXPECT_NE(table.find("ice_detect:lost"), std::string::npos) << table;
  // AND six healthy services fit the column as a count
  for (const char* s : {"arbiter", "blade_load", "ice_detect", "pitch_diag", "plant", "sensor_bias"})
    st.on_service("WT03", s, "ok");
  EXPECT_NE(st.render().find("6 ok"), std::string::npos) << st.render();
}

}  // namespace

namespace {

TEST(FarmStateIsolation, TheLiveTableMarksAReportAnotherExplainsAsSecondary) {
  using namespace windfdi::farm;
  FarmState st;
  // GIVEN a stuck rotor-speed sensor at 1500.2 s and a blade-moment report 1 s later on the same turbine
  FaultEvent speed = fault("WT01", "rotor_speed_sensor", "sensor_bias", 1501.0);
  speed.source = "sensor_bias";
  speed.t_detected = 1500.2;
  FaultEvent blade = fault("WT01", "blade_moment_sensor_2", "sensor_abrupt", 1502.0);
  blade.source = "blade_load";
  blade.t_detected = 1501.2;
  st.on_fault(speed);
  st.on_fault(blade);
  // THEN the blade report is shown as the speed fault's echo, the speed fault as a root
  const auto faults = st.active_faults("WT01");
  ASSERT_EQ(faults.size(), 2u);
  EXPECT_NE(
      std::find(faults.begin(), faults.end(),
                "blade_moment_sensor_2 sensor_abrupt (critical), secondary: explained by rotor_speed_sensor "
                "sensor_bias"),
      faults.end());
  EXPECT_NE(std::find(faults.begin(), faults.end(), "rotor_speed_sensor sensor_bias (critical)"),
            faults.end());
}

TEST(FaultReportTable, MatchesInjectedFaultsWithDetectionsAndReactions) {
  using namespace windfdi::farm;
  // GIVEN a leak injected at 120 s and a blade gain at 90 s, and a history with the leak detected at 126.5 s
  const auto injected = injected_faults({{"WT02", "pitch_actuator_3", "hydraulic_leakage", 120.0},
                                         {"WT01", "blade_moment_2", "gain", 90.0},
                                         {"WT01", "wind_hub", "bias", 50.0}});
  EXPECT_EQ(injected[1].component, "blade_moment_sensor_2");
  EXPECT_EQ(injected[1].fault, "sensor_abrupt");
  EXPECT_EQ(injected[2].component, "");  // no service watches the anemometer
  // The benchmark's converter and drive-train faults are drive_train's classes.
  EXPECT_EQ(expected_detection("converter", "torque_offset"),
            std::make_pair(std::string("converter"), std::string("torque_offset")));
  EXPECT_EQ(expected_detection("drive_train", "efficiency"),
            std::make_pair(std::string("drive_train"), std::string("efficiency_loss")));
  FaultEvent e = fault("WT02", "pitch_actuator_3", "hydraulic_leakage", 127.0);
  e.t_detected = 126.5;
  std::vector<HistoryRow> history = {
      {1000.0, "fault", "WT02", to_json(e)},
      {1000.2,
       "config",
       "WT02",
       {{"mode", "safe_stop"}, {"ipc_source", "strain_gauge"}, {"ice_mode", "normal"}}}};
  // WHEN matched
  const auto rows = match(injected, history);
  // THEN the leak is detected with its class, 6.5 s after onset, and the arbiter's safe stop is its reaction
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_TRUE(rows[0].detected);
  EXPECT_EQ(rows[0].detected_fault, "hydraulic_leakage");
  EXPECT_DOUBLE_EQ(rows[0].delay, 6.5);
  EXPECT_NE(rows[0].reaction.find("safe_stop"), std::string::npos);
  EXPECT_FALSE(rows[1].detected);  // nothing reported on blade 2
  const std::string table = render_report(rows, history);
  EXPECT_NE(table.find("MISSED"), std::string::npos) << table;
  EXPECT_NE(table.find("1 of 2 covered faults"), std::string::npos) << table;
}

TEST(FaultReportTable, ShowsAReclassificationAndCountsItApart) {
  using namespace windfdi::farm;
  // GIVEN a leak at 120 s first reported as pump wear (122 s), then as hydraulic leakage (125 s)
  const auto injected = injected_faults({{"WT02", "pitch_actuator_3", "hydraulic_leakage", 120.0}});
  FaultEvent first = fault("WT02", "pitch_actuator_3", "pump_wear", 122.0);
  first.t_detected = 122.0;
  FaultEvent second = fault("WT02", "pitch_actuator_3", "hydraulic_leakage", 125.0);
  second.t_detected = 125.0;
  const std::vector<HistoryRow> history = {{1000.0, "fault", "WT02", to_json(first)},
                                           {1003.0, "fault", "WT02", to_json(second)}};
  const auto rows = match(injected, history);
  // THEN the row shows both classes in order, the delay is the first report's, and the summary does not count
  // it as right first but as right after a re-classification
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].detected_fault, "pump_wear");
  ASSERT_EQ(rows[0].reclassified.size(), 1u);
  EXPECT_EQ(rows[0].reclassified[0], "hydraulic_leakage");
  EXPECT_DOUBLE_EQ(rows[0].delay, 2.0);
  const std::string table = render_report(rows, history);
  EXPECT_NE(table.find("pump_wear (!) > hydraulic_leakage"), std::string::npos) << table;
  EXPECT_NE(
      table.find(
          "0 of 1 covered faults detected with the right class first, 1 more after a re-classification"),
      std::string::npos)
      << table;
}

TEST(FaultReportTable, AReportOfALaterFaultOnTheSameGaugeIsThatFaultsNotARenaming) {
  using namespace windfdi::farm;
  // GIVEN a gain on blade 2's gauge at 887 s and its signal lost at 1019 s while the gain lasts (fault set
  // 386), and on blade 1 a drift from 2067 s never raised before that gauge's signal was lost at 2221 s
  const auto injected = injected_faults({{"WT01", "blade_moment_2", "gain", 887.0},
                                         {"WT01", "blade_moment_2", "invalid", 1019.0},
                                         {"WT02", "blade_moment_1", "drift", 2067.0},
                                         {"WT02", "blade_moment_1", "invalid", 2221.0}});
  FaultEvent gain = fault("WT01", "blade_moment_sensor_2", "sensor_abrupt", 888.9);
  FaultEvent lost = fault("WT01", "blade_moment_sensor_2", "sensor_invalid", 1020.0);
  FaultEvent lost_1 = fault("WT02", "blade_moment_sensor_1", "sensor_invalid", 2222.0);
  for (FaultEvent* e : {&gain, &lost, &lost_1}) e->t_detected = e->t;
  const std::vector<HistoryRow> history = {{888.9, "fault", "WT01", to_json(gain)},
                                           {1020.0, "fault", "WT01", to_json(lost)},
                                           {2222.0, "fault", "WT02", to_json(lost_1)}};
  const auto rows = match(injected, history);
  ASSERT_EQ(rows.size(), 4u);
  // THEN the gain is named once, the lost signal is the second fault's own report
  EXPECT_EQ(rows[0].detected_fault, "sensor_abrupt");
  EXPECT_TRUE(rows[0].reclassified.empty());
  EXPECT_EQ(rows[1].detected_fault, "sensor_invalid");
  // AND the drift was missed, not named sensor_invalid
  EXPECT_FALSE(rows[2].detected);
  EXPECT_EQ(rows[3].detected_fault, "sensor_invalid");
  // BUT the same raise with no later fault behind it is a renaming of the gain
  const auto alone = match(injected_faults({{"WT01", "blade_moment_2", "gain", 887.0}}), history);
  ASSERT_EQ(alone[0].reclassified.size(), 1u);
  EXPECT_EQ(alone[0].reclassified[0], "sensor_invalid");
}

TEST(FaultReportTable, ASheddingRaisedOnIceThatStaysIsUnexpectedNotTheAccretionsLaterName) {
  using namespace windfdi::farm;
  // GIVEN ice accreting from 900 s on two rotors (it never ends) and a shedding injected on WT02 at 1500 s
  const auto injected = injected_faults({{"WT01", "rotor", "ice_accretion", 900.0},
                                         {"WT02", "rotor", "ice_accretion", 900.0},
                                         {"WT02", "rotor", "ice_shedding", 1500.0}});
  auto ice = [](const std::string& turbine, const std::string& cls, double t, bool raised = true) {
    FaultEvent e = fault(turbine, "rotor", cls, t, raised);
    e.source = "ice_detect";
    e.t_detected = t;
    return HistoryRow{t, "fault", turbine, to_json(e)};
  };
  // and both accretions reported at 1100 s, WT02's shedding 20 s after it, and two sheddings nothing injected
  // (each held 60 s): on WT01, whose ice stays, and on WT02 900 s after its shedding
  const std::vector<HistoryRow> history = {
      ice("WT01", "ice_accretion", 1100.0), ice("WT02", "ice_accretion", 1100.0),
      ice("WT02", "ice_shedding", 1520.0),  ice("WT02", "ice_shedding", 1580.0, false),
      ice("WT01", "ice_shedding", 1600.0),  ice("WT01", "ice_shedding", 1660.0, false),
      ice("WT02", "ice_shedding", 2400.0)};
  // THEN each accretion is named right and never re-classified as a shedding, the shedding is found in 20 s
  const auto rows = match(injected, history);
  ASSERT_EQ(rows.size(), 3u);
  for (int k : {0, 1}) {
    EXPECT_EQ(rows[k].detected_fault, "ice_accretion");
    EXPECT_TRUE(rows[k].reclassified.empty()) << rows[k].reclassified[0];
  }
  EXPECT_EQ(rows[2].detected_fault, "ice_shedding");
  EXPECT_DOUBLE_EQ(rows[2].delay, 20.0);
  // ... and the two others are unexpected reports of their own (until stop 55 both were the accretions'
  // later names and counted nowhere)
  const auto extra = extra_reports(injected, history);
  ASSERT_EQ(extra.size(), 2u);
  EXPECT_EQ(extra[0].turbine, "WT01");
  EXPECT_DOUBLE_EQ(extra[0].t_detected, 1600.0);
  EXPECT_EQ(extra[1].turbine, "WT02");
  EXPECT_DOUBLE_EQ(extra[1].t_detected, 2400.0);
  for (const auto& x : extra) {
    EXPECT_EQ(x.fault, "ice_shedding");
    EXPECT_FALSE(x.secondary);
  }
}

}  // namespace

TEST(FaultReportStops, AStopIsWarrantedByALeakOrByIceAtItsStopLevelShortlyBefore) {
  using namespace windfdi::farm;
  auto stop_at = [](const std::string& turbine, double t) {
    return HistoryRow{t, "config", turbine, {{"t", t}, {"mode", "safe_stop"}}};
  };
  auto normal_at = [](const std::string& turbine, double t) {
    return HistoryRow{t, "config", turbine, {{"t", t}, {"mode", "normal"}}};
  };
  InjectedFault leak{"WT01", "pitch_actuator_3", "hydraulic_leakage", 100.0, "", ""};
  leak.end = 200.0;
  // 2500 kg ramped over 600 s, 54 % of it shed, then 4000 kg over 300 s (5150 kg), 63 % of that shed at 5172
  // s
  auto ice = [](double value, double ramp, double start) {
    InjectedFault i{"WT02", "rotor", "ice_accretion", start, "", ""};
    i.value = value;
    i.ramp_in = ramp;
    return i;
  };
  auto shed = [](double fraction, double start) {
    InjectedFault i{"WT02", "rotor", "ice_shedding", start, "", ""};
    i.fraction = fraction;
    return i;
  };
  const std::vector<InjectedFault> injected = {leak, ice(2500, 600, 3075), shed(0.54, 4029),
                                               ice(4000, 300, 4459), shed(0.63, 5172)};
  EXPECT_NEAR(injected_ice(injected, "WT02", 5170.0), 2500 * 0.46 + 4000, 1e-6);
  const auto s = stops(injected, {stop_at("WT01", 150.0), normal_at("WT01", 160.0), stop_at("WT01", 1000.0),
                                  stop_at("WT02", 4600.0), normal_at("WT02", 4700.0), stop_at("WT02", 5174.3),
                                  normal_at("WT02", 5200.0), stop_at("WT02", 5400.0)});
  // THEN stops with the leak active or just over are warranted, one 800 s after it is not
  ASSERT_EQ(s.size(), 5u);
  EXPECT_TRUE(s[0].warranted);
  EXPECT_FALSE(s[1].warranted);
  // AND ice: not while it is still growing below the level (4600 s: 1150 + 2107 kg), yes 2 s after a
  // shedding that came once it had been above it, no longer 228 s after that shedding
  EXPECT_FALSE(s[2].warranted);
  EXPECT_TRUE(s[3].warranted);
  EXPECT_FALSE(s[4].warranted);
}

TEST(FaultReportStops, TheIceThatWarrantsAStopIsTheTurbinesOwnCriticalLevel) {
  using namespace windfdi::farm;
  // GIVEN the benchmark turbine and the example 2 MW turbine (deploy/turbine/), and a 2 MW scenario with 1200
  // kg of ice grown by 900 s
  const std::string deploy = windfdi::deploy_dir();
  const TurbineParams big = load_turbine_params_file(deploy + "/turbine/benchmark_4.8MW.yaml");
  const TurbineParams two = load_turbine_params_file(deploy + "/turbine/example_2MW.yaml");
  // THEN the stop level is ice_detect's critical rise (12.3 % of the clean inertia) in kg of ice at the
  // file's ice radius: 4500 kg on the benchmark rotor, 12.3 % x (9e6 + 80^2 x 90) / 28^2 = 1503 kg on the 2
  // MW one
  EXPECT_NEAR(stop_ice_mass(big), 4500.0, 5.0);
  EXPECT_NEAR(stop_ice_mass(two), 0.123 * (9.0e6 + 6400.0 * 90.0) / (28.0 * 28.0), 1.0);
  const std::string dir = ::testing::TempDir() + "/stop_ice_" + std::to_string(getpid());
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/two.yaml")
      << "duration: 2000\nturbine_file: " << deploy
      << "/turbine/example_2MW.yaml\nturbines:\n  - {id: WT01, wind: {mean: 9}}\n"
      << "faults:\n  - {turbine: WT01, target: rotor, type: ice_accretion, value: "
         "1500, ramp_in: 300, start: 600}\n";
  const auto injected = read_injected(dir + "/two.yaml");
  ASSERT_EQ(injected.size(), 1u);
  EXPECT_NEAR(injected[0].stop_ice_mass, stop_ice_mass(two), 1e-9);
  // AND a stop with all 1500 kg on the 2 MW rotor is warranted (it would not be against 4500 kg)
  const auto s =
      stops(injected, {HistoryRow{1000.0, "config", "WT01", {{"t", 1000.0}, {"mode", "safe_stop"}}}});
  ASSERT_EQ(s.size(), 1u);
  EXPECT_TRUE(s[0].warranted);
  std::filesystem::remove_all(dir);
}

TEST(FaultReportTable, APowerPathFaultWhileTheTurbineIsStoppedIsMarkedStopped) {
  using namespace windfdi::farm;
  // GIVEN an efficiency change injected at 4000-4200 s on a turbine the arbiter has held in safe stop since
  // 3410 s, and one on a running turbine, neither detected
  std::vector<InjectedFault> injected = {{"WT01", "drive_train", "efficiency", 4000.0, "", ""},
                                         {"WT02", "drive_train", "efficiency", 4000.0, "", ""}};
  for (auto& i : injected) {
    std::tie(i.component, i.fault) = expected_detection(i.target, i.type);
    i.end = 4200.0;
  }
  std::vector<HistoryRow> history = {
      {3410.0,
       "config",
       "WT01",
       {{"t", 3410.0}, {"mode", "safe_stop"}, {"ipc_source", "off"}, {"ice_mode", "normal"}}},
      {3410.0,
       "config",
       "WT02",
       {{"t", 3410.0}, {"mode", "normal"}, {"ipc_source", "off"}, {"ice_mode", "normal"}}}};
  const std::string table = render_benchmark_table(match(injected, history), history);
  // THEN the stopped turbine's row says so and the running one's is a miss
  EXPECT_NE(table.find("WT01   drive_train:efficiency                    4000-4200  stopped"),
            std::string::npos)
      << table;
  EXPECT_NE(table.find("WT02   drive_train:efficiency                    4000-4200  no"), std::string::npos)
      << table;
  EXPECT_NE(table.find("1 fault(s) marked 'stopped'"), std::string::npos) << table;
}
