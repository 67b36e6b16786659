// Two-process DDS test: one process publishes TurbineFrames for 3 turbines, others receive them.
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <thread>
#include <utility>

#include "process.hpp"
#include "test_util.hpp"

using namespace windfdi::test;

namespace {

nlohmann::json last_json_line(const std::string& text) {
  const auto end = text.find_last_not_of('\n');
  if (end == std::string::npos) return {};
  const auto start = text.rfind('\n', end);
  return nlohmann::json::parse(text.substr(start == std::string::npos ? 0 : start + 1, end + 1));
}

int count_domain_shm(int domain) {
  int n = 0;
  for (const auto& e : std::filesystem::directory_iterator("/dev/shm")) {
    const std::string name = e.path().filename().string();
    for (int offset = 0; offset < 250; ++offset)
      if (name.find("fastrtps_port" + std::to_string(7400 + 250 * domain + offset)) != std::string::npos) ++n;
  }
  return n;
}

bool wait_ready(ChildProcess& p, std::chrono::seconds timeout) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < end) {
    if (p.stdout_text().find("\"ready\"") != std::string::npos) return true;
    if (!p.running()) return false;  // it died: say so now rather than after the timeout
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

class DdsFrames : public ::testing::Test {
 protected:
  void TearDown() override { remove_stale_shm(domain); }
  /// A writer of sensor_bias estimates for WT01-WT03 as fast as it can for `hold` s (estimate_reliable),
  /// ready; nullptr when it did not start.
  std::unique_ptr<ChildProcess> start_flood(const std::string& hold) {
    auto flood =
        std::make_unique<ChildProcess>(std::vector<std::string>{bin("windfdi-test-peer"), "flood", "--ids",
                                                                "WT01,WT02,WT03", "--hold", hold},
                                       dds_env(domain), "flood");
    if (wait_ready(*flood, std::chrono::seconds(20))) return flood;
    ADD_FAILURE() << "the estimate writer did not start: " << flood->stderr_text();
    return nullptr;
  }
  int domain = private_domain(1);
};

TEST_F(DdsFrames, ARangeSelectsItsTurbinesOnTopicsFilteredAtTheReaderToo) {
  // GIVEN a health reader given the range WT01..WT03 (wt/health is filtered in the reader, not the writer)
  const auto env = dds_env(domain);
  ChildProcess range({bin("windfdi-test-peer"), "health", "--turbine", "WT01..WT03", "--timeout", "12"}, env,
                     "health-range");
  ASSERT_TRUE(wait_ready(range, std::chrono::seconds(20))) << range.stderr_text();
  // WHEN services report health for WT02 and for WT09
  std::vector<std::unique_ptr<ChildProcess>> services;
  for (const char* id : {"WT02", "WT09"})
    services.push_back(std::make_unique<ChildProcess>(
        std::vector<std::string>{bin("windfdi-test-peer"), "fault", "--source", "pitch_diag", "--turbine-id",
                                 id, "--hold", "6"},
        env, std::string("service-") + id));
  ASSERT_EQ(range.wait(std::chrono::seconds(30)), 0) << range.stderr_text();
  // THEN the reader has WT02's health and not WT09's (before the fix it had none: the range was compared
  // as one id)
  std::set<std::string> seen;
  for (const auto& line : json_lines(range.stdout_text()))
    if (line.contains("turbine_id")) seen.insert(line["turbine_id"].get<std::string>());
  EXPECT_EQ(seen, std::set<std::string>{"WT02"}) << range.stdout_text();
}

TEST_F(DdsFrames, FilteredAndUnfilteredReadersGetExactlyTheirTurbines) {
  // GIVEN a reader of every turbine, one filtered to WT02 and one to the range WT02..WT03, on a private
  // domain
  const auto env = dds_env(domain);
  const int blocks = 50, block = 10;
  ChildProcess all(
      {bin("windfdi-test-peer"), "listen", "--expect", std::to_string(3 * blocks * block), "--timeout", "40"},
      env, "listen-all");
  ChildProcess one({bin("windfdi-test-peer"), "listen", "--turbine", "WT02", "--expect",
                    std::to_string(blocks * block), "--timeout", "40"},
                   env, "listen-wt02");
  ChildProcess range({bin("windfdi-test-peer"), "listen", "--turbine", "WT02..WT03", "--expect",
                      std::to_string(2 * blocks * block), "--timeout", "40"},
                     env, "listen-range");
  for (ChildProcess* reader : {&all, &one, &range})
    ASSERT_TRUE(wait_ready(*reader, std::chrono::seconds(20))) << reader->stderr_text();

  // WHEN a publisher in a fourth process sends 50 blocks of 10 samples for WT01, WT02 and WT03
  ChildProcess pub({bin("windfdi-test-peer"), "publish", "--ids", "WT01,WT02,WT03", "--blocks",
                    std::to_string(blocks), "--block", std::to_string(block), "--readers", "3"},
                   env, "publish");
  ASSERT_EQ(pub.wait(std::chrono::seconds(60)), 0) << pub.stderr_text();
  for (ChildProcess* reader : {&all, &one, &range})
    ASSERT_EQ(reader->wait(std::chrono::seconds(45)), 0) << reader->stdout_text() << reader->stderr_text();

  // THEN the unfiltered reader has every sample of every turbine, in sequence
  const auto a = last_json_line(all.stdout_text());
  EXPECT_EQ(a["total"].get<int>(), 3 * blocks * block);
  for (const char* id : {"WT01", "WT02", "WT03"}) EXPECT_EQ(a["counts"][id].get<int>(), blocks * block) << id;
  EXPECT_TRUE(a["gaps"].empty()) << a.dump();
  // AND the filtered reader has WT02's samples and nothing else
  const auto o = last_json_line(one.stdout_text());
  EXPECT_EQ(o["total"].get<int>(), blocks * block);
  EXPECT_EQ(o["counts"].size(), 1u) << o.dump();
  EXPECT_EQ(o["counts"]["WT02"].get<int>(), blocks * block);
  // AND the range's reader has WT02's and WT03's and not WT01's
  const auto r = last_json_line(range.stdout_text());
  EXPECT_EQ(r["total"].get<int>(), 2 * blocks * block);
  EXPECT_EQ(r["counts"].size(), 2u) << r.dump();
  EXPECT_FALSE(r["counts"].contains("WT01")) << r.dump();
}

TEST_F(DdsFrames, ABusyWriterSurvivesFilteredReadersComingAndGoing) {
  // GIVEN a writer of estimates for three turbines that writes as fast as it can (Fast DDS 2.9 evaluated
  // remote readers' filters in write() unlocked against their arrival and departure: such a writer crashed)
  const auto env = dds_env(domain);
  // (it stays alive longer than the churn may take, 200 s below: with a 120 s hold it left on its own while a
  // loaded CI machine's churn was at 123 s, which read as a crash)
  const auto flood_process = start_flood("300");
  ASSERT_TRUE(flood_process);
  ChildProcess& flood = *flood_process;

  // WHEN a reader with a DDS content filter on WT02 is created and deleted 20 times in another process (each
  // waits up to 5 s for its first sample: on the stop-50 machine a cycle took 6 s even unloaded, 3 of 5
  // matched in time, and 60 cycles outlasted the 200 s below)
  ChildProcess churn({bin("windfdi-test-peer"), "churn", "--turbine-id", "WT02", "--cycles", "20"}, env,
                     "churn");
  int churn_exit = -1;
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(200);
  while (churn_exit == -1 && flood.running() && std::chrono::steady_clock::now() < end)
    churn_exit = churn.wait(std::chrono::milliseconds(500));

  // THEN the writer is still running and stops cleanly
  ASSERT_TRUE(flood.running()) << "the writer died: " << flood.stderr_text();
  ASSERT_EQ(churn_exit, 0) << churn.stderr_text();
  EXPECT_EQ(flood.stop(SIGTERM), 0) << flood.stderr_text();
  // AND every reader got WT02's estimates and nothing else (the writer leaves the filter to the reader)
  const auto c = last_json_line(churn.stdout_text());
  // (a reader that matched late sees nothing in its 5 s; a quarter must have seen estimates, so that the
  // writer evaluated the filters of readers coming and going)
  EXPECT_GE(c["cycles"].get<int>(), 5) << c.dump();
  EXPECT_EQ(c["foreign"].get<int>(), 0) << c.dump();
}

TEST_F(DdsFrames, EveryTopicCarriesTheInstancesOfAThousandTurbineFarm) {
  // GIVEN a farm-wide reader of the per-turbine topics, health and faults in one process (the sizes of
  // deploy/qos/windfdi_qos.xml: at 240 turbines the 1024 health instances of before showed 58 turbines)
  const auto env = dds_env(domain);
  ChildProcess count({bin("windfdi-test-peer"), "count", "--farm", "1000", "--timeout", "100"}, env, "count");
  ASSERT_TRUE(wait_ready(count, std::chrono::seconds(20))) << count.stderr_text();
  // WHEN another process writes every instance of 1000 turbines once: a frame block, a sensor-bias estimate
  // and a configuration per turbine, the health of 8 processes and 16 fault instances per turbine
  ChildProcess writer(
      {bin("windfdi-test-peer"), "instances", "--farm", "1000", "--readers", "1", "--hold", "120"}, env,
      "instances");
  const int rc = count.wait(std::chrono::seconds(120));
  EXPECT_EQ(writer.stop(SIGTERM), 0) << writer.stderr_text();
  // THEN every instance arrived, none was refused at the writer
  ASSERT_EQ(rc, 0) << count.stdout_text() << count.stderr_text();
  const auto c = last_json_line(count.stdout_text());
  EXPECT_EQ(c["frame"].get<int>(), 1000);
  EXPECT_EQ(c["estimate"].get<int>(), 1000);
  EXPECT_EQ(c["control"].get<int>(), 1000);
  EXPECT_EQ(c["health"].get<int>(), 8000);
  EXPECT_EQ(c["fault"].get<int>(), 16000);
  const auto w = nlohmann::json::parse(writer.stdout_text().substr(0, writer.stdout_text().find('\n')));
  for (const auto& [topic, failed] : w["failures"].items()) EXPECT_EQ(failed.get<int>(), 0) << topic;
}

TEST_F(DdsFrames, ThePlantsBestEffortReaderHearsTheReliableBiasEstimates) {
  // GIVEN sensor_bias's reliable estimate writer for three turbines (estimate_reliable)
  const auto env = dds_env(domain);
  const auto flood = start_flood("60");
  ASSERT_TRUE(flood);
  // WHEN the plant's reader (estimate_newest: best effort, keep last 1, filtered to two turbines) listens
  ChildProcess reader({bin("windfdi-test-peer"), "newest", "--ids", "WT01,WT03", "--timeout", "30"}, env,
                      "newest");
  const int rc = reader.wait(std::chrono::seconds(45));
  EXPECT_EQ(flood->stop(SIGTERM), 0) << flood->stderr_text();
  // THEN the QoS match and it hears both of its turbines and no other
  ASSERT_EQ(rc, 0) << reader.stdout_text() << reader.stderr_text();
  const auto r = last_json_line(reader.stdout_text());
  EXPECT_EQ(r["incompatible_qos"].get<int>(), 0);
  EXPECT_EQ(r["counts"].size(), 2u) << r.dump();
  EXPECT_GT(r["counts"]["WT01"].get<int>(), 0);
  EXPECT_GT(r["counts"]["WT03"].get<int>(), 0);
}

TEST_F(DdsFrames, ABusyLoopAssertsItsHealthLivelinessTenTimesASecondAndStaysAlive) {
  // GIVEN a reader of wt/health following its writers' liveliness (lease 3 s), as the farm monitor does
  const auto env = dds_env(domain);
  ChildProcess reader({bin("windfdi-test-peer"), "health", "--timeout", "8"}, env, "health");
  ASSERT_TRUE(wait_ready(reader, std::chrono::seconds(20))) << reader.stderr_text();
  // WHEN a service's health writer asserts its liveliness every 0.2 ms for 4 s (a loop passing for every
  // frame block: each assertion went out as a heartbeat to every reader)
  ChildProcess busy({bin("windfdi-test-peer"), "busy-health", "--turbine-id", "WT01", "--hold", "4"}, env,
                    "busy");
  ASSERT_EQ(busy.wait(std::chrono::seconds(30)), 0) << busy.stderr_text();
  EXPECT_EQ(reader.wait(std::chrono::seconds(30)), 0) << reader.stderr_text();
  // THEN at most one assertion in 100 ms goes out (41 in 4 s) of the thousands of calls
  const auto b = last_json_line(busy.stdout_text());
  EXPECT_GE(b["calls"].get<int>(), 1000) << b.dump();
  EXPECT_GE(b["asserted"].get<int>(), 1) << b.dump();
  EXPECT_LE(b["asserted"].get<int>(), 41) << b.dump();
  // AND the reader got its health sample and never saw the writer lost while it ran
  std::istringstream lines(reader.stdout_text());
  std::string line;
  int health = 0, alive = 0, lost_while_running = 0;
  while (std::getline(lines, line)) {
    const auto j = nlohmann::json::parse(line);
    if (j.contains("service")) ++health;
    if (!j.contains("liveliness")) continue;
    if (j["liveliness"].get<bool>())
      ++alive;
    else if (j["t"].get<double>() < b["end"].get<double>())
      ++lost_while_running;
  }
  EXPECT_EQ(health, 1) << reader.stdout_text();
  EXPECT_GE(alive, 1) << reader.stdout_text();
  EXPECT_EQ(lost_while_running, 0) << reader.stdout_text();
}

TEST_F(DdsFrames, AServicesPlaceholderHealthLeavesTheHistoryOnceItNamesATurbine) {
  // GIVEN a farm-wide service's health writer heard by a reader from its start: "*" (no turbine seen yet)
  const auto env = dds_env(domain);
  ChildProcess early({bin("windfdi-test-peer"), "health", "--timeout", "6"}, env, "early");
  ASSERT_TRUE(wait_ready(early, std::chrono::seconds(20))) << early.stderr_text();
  ChildProcess service({bin("windfdi-test-peer"), "health-reporter", "--turbine-id", "WT07", "--hold", "14"},
                       env, "service");
  ASSERT_TRUE(wait_ready(service, std::chrono::seconds(20))) << service.stderr_text();
  // WHEN it names its first turbine (2 s later) and a reader joins after that (transient local: it gets
  // what the writer's history holds)
  EXPECT_EQ(early.wait(std::chrono::seconds(30)), 0) << early.stderr_text();
  ChildProcess late({bin("windfdi-test-peer"), "health", "--timeout", "3"}, env, "late");
  EXPECT_EQ(late.wait(std::chrono::seconds(30)), 0) << late.stderr_text();
  EXPECT_EQ(service.stop(SIGTERM), 0) << service.stderr_text();
  const auto turbines = [](const std::string& out) {
    std::set<std::string> ids;
    for (const auto& j : json_lines(out))
      if (j.contains("turbine_id")) ids.insert(j["turbine_id"].get<std::string>());
    return ids;
  };
  // THEN the first reader heard "*" and WT07, and the late one only WT07: the "*" sample is no longer kept
  // (kept, it stayed the writer's oldest sample, and every heartbeat carried a GAP over all reports since)
  EXPECT_EQ(turbines(early.stdout_text()), (std::set<std::string>{"*", "WT07"})) << early.stdout_text();
  EXPECT_EQ(turbines(late.stdout_text()), (std::set<std::string>{"WT07"})) << late.stdout_text();
}

TEST_F(DdsFrames, AHealthSampleLeavesItsWritersHistoryAfterItsLifespan) {
  // GIVEN a health writer that wrote one sample 0.5 s after a reader joined, then only asserts its liveliness
  const auto env = dds_env(domain);
  ChildProcess early({bin("windfdi-test-peer"), "health", "--timeout", "4"}, env, "early");
  ASSERT_TRUE(wait_ready(early, std::chrono::seconds(20))) << early.stderr_text();
  ChildProcess writer({bin("windfdi-test-peer"), "health-once", "--turbine-id", "WT07", "--hold", "16"}, env,
                      "writer");
  ASSERT_TRUE(wait_ready(writer, std::chrono::seconds(20))) << writer.stderr_text();
  EXPECT_EQ(early.wait(std::chrono::seconds(30)), 0) << early.stderr_text();
  // WHEN a reader joins 7 s after the write (the health profile's lifespan is 5 s; every service rewrites
  // each of its instances every second)
  std::this_thread::sleep_for(std::chrono::seconds(4));
  ChildProcess late({bin("windfdi-test-peer"), "health", "--timeout", "3"}, env, "late");
  EXPECT_EQ(late.wait(std::chrono::seconds(30)), 0) << late.stderr_text();
  EXPECT_EQ(writer.stop(SIGTERM), 0) << writer.stderr_text();
  const auto heard = [](const std::string& out) {
    int samples = 0;
    bool alive = false;
    for (const auto& j : json_lines(out)) {
      samples += j.contains("turbine_id");
      alive = alive || (j.contains("liveliness") && j["liveliness"].get<bool>());
    }
    return std::make_pair(samples, alive);
  };
  // THEN the first reader got the sample and the late one none, though it hears the writer alive: a sample
  // never rewritten does not stay the writer's oldest. Kept (a Fast DDS 2.9 writer whose participant also
  // reads wt/health kept one of its first samples for good), every heartbeat carried a GAP over every report
  // since, which each reader walked number by number: the arbiters' CPU grew for hours in the 24-hour soak.
  EXPECT_EQ(heard(early.stdout_text()).first, 1) << early.stdout_text();
  EXPECT_EQ(heard(late.stdout_text()), std::make_pair(0, true)) << late.stdout_text();
}

TEST_F(DdsFrames, ListenerGivesUpWithoutPublisherAndSaysSo) {
  // GIVEN a reader expecting samples WHEN nobody publishes THEN it exits 1 after its timeout, not hangs
  ChildProcess lone({bin("windfdi-test-peer"), "listen", "--expect", "10", "--timeout", "2"}, dds_env(domain),
                    "lone");
  EXPECT_EQ(lone.wait(std::chrono::seconds(20)), 1) << lone.stderr_text();
  EXPECT_EQ(last_json_line(lone.stdout_text())["total"].get<int>(), 0);
}

TEST_F(DdsFrames, SigtermExitsCleanlyAndLeavesNoSharedMemory) {
  // GIVEN a running DDS participant on a private domain
  ChildProcess p({bin("windfdi-test-peer"), "listen", "--expect", "1000000", "--timeout", "60"},
                 dds_env(domain), "sigterm");
  ASSERT_TRUE(wait_ready(p, std::chrono::seconds(20))) << p.stderr_text();
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  ASSERT_GT(count_domain_shm(domain), 0) << "the participant should hold shared-memory port files";
  // WHEN it receives SIGTERM
  const int rc = p.stop(SIGTERM, std::chrono::seconds(10));
  // THEN it exits 0 and its domain's shared-memory port files are gone
  EXPECT_EQ(rc, 0) << p.stderr_text();
  EXPECT_EQ(count_domain_shm(domain), 0);
}

TEST_F(DdsFrames, TheArbiterKeepsOffSharedMemoryUnlessAsked) {
  // GIVEN the arbiter with its defaults on a private domain WHEN it runs THEN it holds no shared-memory port
  // (a stopped and resumed arbiter lost its ports to its peers' watchdog; services/arbiter/README.md)
  const std::string config = std::string(WINDFDI_SOURCE_DEPLOY_DIR) + "/config/arbiter.yaml";
  {
    ChildProcess arbiter({bin("windfdi-arbiter"), "--config", config}, dds_env(domain), "arbiter");
    std::this_thread::sleep_for(std::chrono::seconds(2));
    ASSERT_TRUE(arbiter.running()) << arbiter.stderr_text();
    EXPECT_EQ(count_domain_shm(domain), 0) << arbiter.stderr_text();
    EXPECT_EQ(arbiter.stop(SIGTERM, std::chrono::seconds(10)), 0) << arbiter.stderr_text();
  }
  // AND with --shared-memory it takes the profile's shared-memory transport
  ChildProcess arbiter({bin("windfdi-arbiter"), "--config", config, "--shared-memory"}, dds_env(domain),
                       "arbiter-shm");
  std::this_thread::sleep_for(std::chrono::seconds(2));
  ASSERT_TRUE(arbiter.running()) << arbiter.stderr_text();
  EXPECT_GT(count_domain_shm(domain), 0) << arbiter.stderr_text();
  EXPECT_EQ(arbiter.stop(SIGTERM, std::chrono::seconds(10)), 0) << arbiter.stderr_text();
}

}  // namespace
