// Unit tests of the farm monitor's HTTP API handlers (no socket): access rules, queries, errors, metrics.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "farm_api.hpp"
#include "process.hpp"

using namespace windfdi;
using namespace windfdi::farm;
using nlohmann::json;

namespace {

FaultEvent fault(const std::string& turbine, const std::string& source, const std::string& component,
                 const std::string& cls, const std::string& severity, double t, bool raised = true) {
  FaultEvent e;
  e.t = e.t_detected = t;
  e.turbine_id = turbine;
  e.source = source;
  e.component = component;
  e.fault = cls;
  e.raised = raised;
  e.severity = severity;
  e.detail = "test";
  return e;
}

ApiRequest get(const std::string& path, std::map<std::string, std::string> params = {},
               const std::string& from = "127.0.0.1") {
  ApiRequest r;
  r.method = "GET";
  r.path = path;
  r.params = std::move(params);
  r.remote_addr = from;
  return r;
}

ApiRequest post_ack(const std::string& body, const std::string& authorization) {
  ApiRequest r;
  r.method = "POST";
  r.path = "/api/ack";
  r.body = body;
  r.remote_addr = "127.0.0.1";
  r.authorization = authorization;
  return r;
}

// A farm of two turbines: WT01 with a critical leak (stored raised, then cleared, then raised again) and a
// pitch-sensor bias on the same blade, WT02 with nothing; the API on the same database.
class FarmApiTest : public ::testing::Test {
 protected:
  void SetUp() override {
    db = test::temp_dir("farm_api") + "/farm.sqlite";
    FarmStore store(db);
    const FaultEvent events[] = {
        fault("WT01", "pitch_diag", "pitch_actuator_3", "hydraulic_leakage", "critical", 10.0),
        fault("WT01", "pitch_diag", "pitch_actuator_3", "hydraulic_leakage", "critical", 20.0, false),
        fault("WT01", "pitch_diag", "pitch_actuator_3", "hydraulic_leakage", "critical", 30.0),
        fault("WT01", "sensor_bias", "pitch_sensor_3", "sensor_bias", "fault", 31.0),
        fault("WT02", "ice_detect", "rotor", "ice_accretion", "warning", 40.0, false),
    };
    double received = 1000.0;
    for (const auto& e : events) {
      store.add_fault(e, received += 1.0);
      state.on_fault(e);
    }
    ConfigRecord c;
    c.received_at = 1010.0;
    c.turbine_id = "WT01";
    c.arbiter_id = "primary";
    c.revision = 7;
    c.mode = "safe_stop";
    c.ipc_source = "strain_gauge";
    c.ice_mode = "normal";
    c.reasons = {"pitch_diag/pitch_actuator_3/hydraulic_leakage: mode=safe_stop"};
    store.add_config(c);
    state.on_config(c);
    // Estimates of pitch_diag on WT01 received at 1001..1010 (one a second), and one of ice_detect.
    std::vector<EstimateRecord> batch;
    for (int i = 1; i <= 10; ++i)
      batch.push_back(
          {1000.0 + i, 100.0 + i, "WT01", "pitch_diag", json{{"omega_n", {11.0, 11.1, 7.3 + i}}}});
    batch.push_back({1005.0, 105.0, "WT01", "ice_detect", json{{"inertia", 6500.0}}});
    store.add_estimates(batch);
    store.add_estimates({batch[0]});  // again (a replay): stored once
    state.on_service("WT01", "pitch_diag", "ok");
    services["WT01/pitch_diag"] = {"ok", 1200, 3, 0, 0, 0.004};
    services["WT01/ice_detect"] = {"lost", 900, 0, 1, 0, 0.0};
  }
  std::unique_ptr<FarmApi> api(const std::string& token = "s3cret") {
    auto a = std::make_unique<FarmApi>(
        db, token,
        [this](const std::string& t, const std::string& c, const std::string& f, const std::string& who) {
          acks.push_back(t + " " + c + " " + f + " " + who);
          return arbiters;
        });
    a->update(state, services);
    return a;
  }
  std::string db;
  FarmState state;
  std::map<std::string, ServiceMetrics> services;
  std::vector<std::string> acks;
  int arbiters = 1;
};

TEST(Access, LoopbackAddresses) {
  EXPECT_TRUE(is_loopback("127.0.0.1"));
  EXPECT_TRUE(is_loopback("127.1.2.3"));
  EXPECT_TRUE(is_loopback("::1"));
  EXPECT_TRUE(is_loopback("::ffff:127.0.0.1"));
  EXPECT_FALSE(is_loopback("10.0.0.7"));
  EXPECT_FALSE(is_loopback("::ffff:10.0.0.7"));
  EXPECT_FALSE(is_loopback(""));
}

TEST_F(FarmApiTest, TurbinesCarryModeServicesAndActiveFaultsWithTheirIsolation) {
  const ApiResponse r = api()->handle(get("/api/turbines"));
  ASSERT_EQ(r.status, 200) << r.body;
  const json j = json::parse(r.body);
  ASSERT_EQ(j["turbines"].size(), 2u);
  const json& wt01 = j["turbines"][0];
  EXPECT_EQ(wt01["turbine_id"], "WT01");
  EXPECT_EQ(wt01["mode"], "safe_stop");
  EXPECT_EQ(wt01["revision"], 7);
  EXPECT_EQ(wt01["services"]["pitch_diag"], "ok");
  // Both raised reports are there; the isolation core names one of them (a leak explains no pitch-sensor bias
  // and the other way round: neither is secondary here).
  ASSERT_EQ(wt01["active_faults"].size(), 2u);
  for (const auto& f : wt01["active_faults"]) {
    EXPECT_TRUE(f.contains("secondary"));
    EXPECT_EQ(f["state"], "raised");
  }
  EXPECT_TRUE(j["turbines"][1]["active_faults"].empty());  // WT02's accretion is cleared
}

TEST_F(FarmApiTest, FaultsAreFilteredNewestFirstAndLimited) {
  auto a = api();
  json j =
      json::parse(a->handle(get("/api/faults", {{"turbine", "WT01"}, {"fault", "hydraulic_leakage"}})).body);
  ASSERT_EQ(j["faults"].size(), 3u);
  EXPECT_EQ(j["faults"][0]["t"], 30.0);  // newest first
  EXPECT_EQ(j["faults"][1]["state"], "cleared");
  j = json::parse(a->handle(get("/api/faults", {{"state", "raised"}, {"limit", "2"}})).body);
  ASSERT_EQ(j["faults"].size(), 2u);
  EXPECT_EQ(j["faults"][0]["component"], "pitch_sensor_3");
  j = json::parse(a->handle(get("/api/faults", {{"severity", "warning"}})).body);
  ASSERT_EQ(j["faults"].size(), 1u);
  EXPECT_EQ(j["faults"][0]["turbine_id"], "WT02");
  j = json::parse(a->handle(get("/api/faults", {{"since", "1004.5"}})).body);
  EXPECT_EQ(j["faults"].size(), 1u);  // received at 1005 only
}

TEST_F(FarmApiTest, HistoryOfOneKind) {
  const json j =
      json::parse(api()->handle(get("/api/history", {{"turbine", "WT01"}, {"kind", "config"}})).body);
  ASSERT_EQ(j["history"].size(), 1u);
  EXPECT_EQ(j["history"][0]["data"]["mode"], "safe_stop");
  EXPECT_EQ(j["history"][0]["data"]["reasons"][0],
            "pitch_diag/pitch_actuator_3/hydraulic_leakage: mode=safe_stop");
}

TEST_F(FarmApiTest, EstimatesOfOneServiceOldestFirstSinceAndLimited) {
  auto a = api();
  json j =
      json::parse(a->handle(get("/api/estimates", {{"turbine", "WT01"}, {"service", "pitch_diag"}})).body);
  ASSERT_EQ(j["estimates"].size(), 10u);
  EXPECT_EQ(j["estimates"][0]["t"], 101.0);  // oldest first: a plot's order
  EXPECT_EQ(j["estimates"][9]["omega_n"][2], 17.3);
  // The newest 3 since 1004.5 (received 1005..1010).
  j = json::parse(
      a->handle(get("/api/estimates",
                    {{"turbine", "WT01"}, {"service", "pitch_diag"}, {"since", "1004.5"}, {"limit", "3"}}))
          .body);
  ASSERT_EQ(j["estimates"].size(), 3u);
  EXPECT_EQ(j["estimates"][0]["t"], 108.0);
  EXPECT_EQ(j["estimates"][2]["received_at"], 1010.0);
  // Both names needed, and a known service.
  EXPECT_EQ(a->handle(get("/api/estimates", {{"turbine", "WT01"}})).status, 400);
  EXPECT_EQ(a->handle(get("/api/estimates", {{"service", "pitch_diag"}})).status, 400);
  EXPECT_EQ(a->handle(get("/api/estimates", {{"turbine", "WT01"}, {"service", "weather"}})).status, 400);
}

TEST_F(FarmApiTest, TheRunIsJudgedAgainstTheScenarioWhenOneIsKnown) {
  EXPECT_EQ(api()->handle(get("/api/report")).status, 404);  // no scenario given
  const std::string scenario = test::temp_dir("farm_api_report") + "/scenario.yaml";
  std::ofstream(scenario)
      << "duration: 60\nseed: 1\nturbines:\n  - {id: WT01, wind: {mean: 12.0}}\nfaults:\n"
         "  - {turbine: WT01, target: pitch_actuator_3, type: hydraulic_leakage, start: 8}\n";
  FarmApi with(db, "tok", nullptr, scenario);
  const ApiResponse r = with.handle(get("/api/report"));
  ASSERT_EQ(r.status, 200) << r.body;
  const json j = json::parse(r.body);
  ASSERT_EQ(j["faults"].size(), 1u);
  EXPECT_EQ(j["faults"][0]["first"], "hydraulic_leakage");
  EXPECT_EQ(j["faults"][0]["delay"], 2.0);  // raised at 10 s
  // The leak's raise, clear and raise again are one fault; the pitch-sensor bias no injected fault explains.
  ASSERT_EQ(j["extra"].size(), 1u);
  EXPECT_EQ(j["extra"][0]["component"], "pitch_sensor_3");
  // A scenario that cannot be read is an error at start, naming it.
  EXPECT_THROW(FarmApi(db, "tok", nullptr, scenario + ".missing"), std::exception);
}

TEST(FarmStoreEstimates, PrunedBeforeTheRetention) {
  FarmStore store(test::temp_dir("farm_estimates") + "/farm.sqlite");
  std::vector<EstimateRecord> batch;
  for (int i = 0; i < 5; ++i)
    batch.push_back({100.0 + i, double(i), "WT03", "ice_detect", json{{"inertia", 1.0}}});
  store.add_estimates(batch);
  EXPECT_EQ(store.prune_estimates(102.0), 2);  // received at 100 and 101
  EXPECT_EQ(store.estimates("WT03", "ice_detect", 0.0, 100).size(), 3u);
}

TEST(FarmStoreEstimates, PruningFindsTheOldEstimatesByTheirIndexNotByReadingTheTable) {
  // GIVEN a store (its schema as the farm monitor opens it)
  const std::string path = test::temp_dir("farm_estimates_index") + "/farm.sqlite";
  { FarmStore store(path); }
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  // WHEN SQLite plans the pruning's delete
  sqlite3_stmt* plan = nullptr;
  ASSERT_EQ(sqlite3_prepare_v2(db, "EXPLAIN QUERY PLAN DELETE FROM estimates WHERE received_at < 100.0", -1,
                               &plan, nullptr),
            SQLITE_OK);
  std::string details;
  while (sqlite3_step(plan) == SQLITE_ROW)
    details += std::string(reinterpret_cast<const char*>(sqlite3_column_text(plan, 3))) + "; ";
  sqlite3_finalize(plan);
  sqlite3_close(db);
  // THEN it searches the index on received_at (a scan of a 20-turbine farm's 1 million estimates took
  // 0.3-0.5 s of a core at each pruning, and the soak's services lost samples to it)
  EXPECT_NE(details.find("USING INDEX estimates_received"), std::string::npos) << details;
}

TEST_F(FarmApiTest, MalformedQueriesAreRefusedWithAJsonErrorNamingTheParameter) {
  auto a = api();
  for (const auto& [key, value] : std::vector<std::pair<std::string, std::string>>{{"since", "abc"},
                                                                                   {"since", "-1"},
                                                                                   {"since", "nan"},
                                                                                   {"limit", "0"},
                                                                                   {"limit", "1e9"},
                                                                                   {"limit", "5x"},
                                                                                   {"fault", "rust"},
                                                                                   {"component", "blade_9"},
                                                                                   {"state", "maybe"}}) {
    const ApiResponse r = a->handle(get("/api/faults", {{key, value}}));
    EXPECT_EQ(r.status, 400) << key << "=" << value;
    const json j = json::parse(r.body);
    EXPECT_NE(j["error"].get<std::string>().find(key), std::string::npos) << r.body;
  }
  EXPECT_EQ(a->handle(get("/api/history", {{"kind", "everything"}})).status, 400);
  EXPECT_EQ(a->handle(get("/api/nothing")).status, 404);
  ApiRequest wrong_method = get("/api/turbines");
  wrong_method.method = "POST";
  wrong_method.authorization = "Bearer s3cret";
  EXPECT_EQ(a->handle(wrong_method).status, 405);
}

TEST_F(FarmApiTest, ReadingNeedsTheTokenFromAnotherMachineOnly) {
  auto a = api();
  EXPECT_EQ(a->handle(get("/api/turbines", {}, "127.0.0.1")).status, 200);
  EXPECT_EQ(a->handle(get("/api/turbines", {}, "::1")).status, 200);
  EXPECT_EQ(a->handle(get("/api/turbines", {}, "10.1.2.3")).status, 401);
  EXPECT_EQ(a->handle(get("/metrics", {}, "10.1.2.3")).status, 401);
  ApiRequest remote = get("/api/turbines", {}, "10.1.2.3");
  remote.authorization = "Bearer s3cret";
  EXPECT_EQ(a->handle(remote).status, 200);
  remote.authorization = "Bearer stale";
  EXPECT_EQ(a->handle(remote).status, 403);
  // A wrong token is refused on localhost too.
  ApiRequest local = get("/api/turbines");
  local.authorization = "Bearer stale";
  EXPECT_EQ(a->handle(local).status, 403);
}

TEST_F(FarmApiTest, AcknowledgementNeedsTheTokenAndNamesAKnownComponentAndClass) {
  auto a = api();
  const std::string body =
      R"({"turbine_id":"WT01","component":"pitch_actuator_3","fault":"hydraulic_leakage"})";
  // Without a token, with a wrong one: refused, nothing published.
  EXPECT_EQ(a->handle(post_ack(body, "")).status, 401);
  EXPECT_EQ(a->handle(post_ack(body, "Bearer stale")).status, 403);
  EXPECT_TRUE(acks.empty());
  // Malformed bodies and unknown names: 400, nothing published.
  for (const std::string& bad :
       {std::string("not json"), std::string("[1,2]"), std::string(R"({"turbine_id":"WT01"})"),
        std::string(R"({"turbine_id":"WT01","component":"pitch_actuator_9"})"),
        std::string(R"({"turbine_id":"WT01","component":"rotor","fault":"rust"})"),
        std::string(R"({"turbine_id":5,"component":"rotor"})")})
    EXPECT_EQ(a->handle(post_ack(bad, "Bearer s3cret")).status, 400) << bad;
  EXPECT_TRUE(acks.empty());
  // With the token: published once, with the operator defaulted.
  const ApiResponse r = a->handle(post_ack(body, "Bearer s3cret"));
  ASSERT_EQ(r.status, 200) << r.body;
  ASSERT_EQ(acks.size(), 1u);
  EXPECT_EQ(acks[0], "WT01 pitch_actuator_3 hydraulic_leakage web");
  // No arbiter heard it: the operator is told.
  arbiters = 0;
  EXPECT_EQ(a->handle(post_ack(body, "Bearer s3cret")).status, 503);
  // A farm monitor without a token accepts no acknowledgement at all.
  EXPECT_EQ(api("")->handle(post_ack(body, "Bearer s3cret")).status, 403);
}

TEST_F(FarmApiTest, MetricsInThePrometheusTextFormat) {
  const ApiResponse r = api()->handle(get("/metrics"));
  ASSERT_EQ(r.status, 200);
  EXPECT_EQ(r.content_type.rfind("text/plain", 0), 0u);
  for (const char* line :
       {"windfdi_faults_active{turbine=\"WT01\",severity=\"critical\"} 1",
        "windfdi_faults_active{turbine=\"WT01\",severity=\"fault\"} 1",
        "windfdi_faults_active{turbine=\"WT02\",severity=\"warning\"} 0",
        "windfdi_configuration_revision{turbine=\"WT01\"} 7", "windfdi_safe_stop{turbine=\"WT01\"} 1",
        "windfdi_service_up{turbine=\"WT01\",service=\"ice_detect\"} 0",
        "windfdi_samples_in_total{turbine=\"WT01\",service=\"pitch_diag\"} 1200",
        "windfdi_samples_rejected_total{turbine=\"WT01\",service=\"pitch_diag\"} 3",
        "windfdi_sequence_gaps_total{turbine=\"WT01\",service=\"ice_detect\"} 1",
        "# TYPE windfdi_lag_seconds gauge"})
    EXPECT_NE(r.body.find(std::string(line) + "\n"), std::string::npos) << line << "\n" << r.body;
  // Every sample line is "name{labels} value".
  std::istringstream lines(r.body);
  for (std::string l; std::getline(lines, l);)
    if (!l.empty() && l[0] != '#') {
      EXPECT_NE(l.find("} "), std::string::npos) << l;
    }
}

}  // namespace
