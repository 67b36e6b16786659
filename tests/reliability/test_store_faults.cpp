// Reliability: the farm store's disk fills up while faults keep coming; the farm monitor goes on, says so,
// and stores every event once the disk takes writes again; on a read-only disk (a real tmpfs; root) or a
// damaged store it does not start.
#include <gtest/gtest.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "process.hpp"
#include "test_util.hpp"

using namespace windfdi::test;
using nlohmann::json;

namespace {

int sh(const std::string& command) { return std::system((command + " >/dev/null 2>&1").c_str()); }

std::size_t occurrences(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

class StoreFaults : public ::testing::Test {
 protected:
  void SetUp() override {
    disk = temp_dir("store_faults_" + std::to_string(domain)) + "/disk";
    if (geteuid() != 0 || sh("mkdir -p " + disk + " && mount -t tmpfs -o size=4m windfdi-test " + disk) != 0)
      GTEST_SKIP() << "a disk of its own (tmpfs) needs root";
    mounted = true;
  }
  void TearDown() override {
    if (mounted) sh("umount -l " + disk);
    remove_stale_shm(domain);
  }
  // A peer that reports one fault event at once and stays (its writer keeps the report).
  std::unique_ptr<ChildProcess> report(const std::string& component, const std::string& state,
                                       const std::string& name) {
    auto p = std::make_unique<ChildProcess>(
        std::vector<std::string>{bin("windfdi-test-peer"), "fault", "--source", "pitch_diag", "--turbine-id",
                                 "WT01", "--script", "0:" + component + ":pump_wear:fault:" + state, "--hold",
                                 "120"},
        env, name);
    wait_until([&] { return p->stdout_text().find("\"sent\"") != std::string::npos; },
               std::chrono::seconds(20));
    return p;
  }
  int domain = private_domain(9);
  std::map<std::string, std::string> env = dds_env(domain);
  std::string disk;
  bool mounted = false;
};

TEST_F(StoreFaults, AFullDiskLosesNoEventAndTheFarmGoesOnAReadOnlyOneAtStartIsRefused) {
  const std::string db = disk + "/farm.sqlite";
  ChildProcess farm({bin("windfdi-farm"), "--db", db, "--table-period", "0.5"}, env, "farm");
  auto first = report("pitch_actuator_1", "raised", "peer1");
  auto stored_faults = [&] {
    std::vector<std::string> out;
    for (const auto& r : farm_history(db, env))
      if (r["kind"] == "fault")
        out.push_back(r["data"]["component"].get<std::string>() + " " +
                      r["data"]["state"].get<std::string>());
    return out;
  };
  ASSERT_TRUE(wait_until([&] { return stored_faults().size() == 1; }, std::chrono::seconds(20)))
      << farm.stderr_text();

  // WHEN the disk fills up and faults keep coming
  sh("dd if=/dev/zero of=" + disk + "/filler bs=64k");
  auto second = report("pitch_actuator_2", "raised", "peer2");
  // THEN the farm monitor says the store cannot write and goes on
  ASSERT_TRUE(wait_until([&] { return occurrences(farm.stderr_text(), "cannot write") >= 1; },
                         std::chrono::seconds(20)))
      << farm.stderr_text();
  EXPECT_TRUE(farm.running());
  // AND its live table shows the fault the store could not take
  EXPECT_TRUE(wait_until([&] { return farm.stdout_text().find("pitch_actuator_2") != std::string::npos; },
                         std::chrono::seconds(10)))
      << farm.stdout_text();
  auto second_clear = report("pitch_actuator_2", "cleared", "peer3");

  // WHEN the disk has room again
  sh("rm -f " + disk + "/filler");
  // THEN it writes what waited
  ASSERT_TRUE(wait_until([&] { return occurrences(farm.stderr_text(), "writing again") >= 1; },
                         std::chrono::seconds(20)))
      << farm.stderr_text();

  // AND a fault comes once it writes again (and holds the clear that came while it could not: a report of
  // another process may overtake it on a loaded machine, whose discovery came first, and the order compared
  // below is the order of arrival)
  ASSERT_TRUE(wait_until([&] { return stored_faults().size() == 3; }, std::chrono::seconds(20)))
      << farm.stderr_text();
  auto third = report("pitch_actuator_3", "raised", "peer4");
  ASSERT_TRUE(wait_until([&] { return stored_faults().size() == 4; }, std::chrono::seconds(20)))
      << farm.stderr_text();

  // THEN every fault event is stored once, in the order it came, and the farm monitor's own health says when
  // its store failed and came back
  int degraded = 0, ok_again = 0;
  for (const auto& r : farm_history(db, env)) {
    if (r["kind"] == "health" && r["data"]["service"] == "farm_monitor") {
      degraded += r["data"]["event"] == "degraded";
      ok_again += r["data"]["event"] == "ok";
    }
  }
  EXPECT_EQ(stored_faults(),
            (std::vector<std::string>{"pitch_actuator_1 raised", "pitch_actuator_2 raised",
                                      "pitch_actuator_2 cleared", "pitch_actuator_3 raised"}))
      << farm.stderr_text();
  EXPECT_EQ(degraded, 1);
  EXPECT_GE(ok_again, 1);
  EXPECT_EQ(farm.stop(SIGTERM), 0) << farm.stderr_text();

  // WHEN the farm monitor starts on a store whose filesystem is read-only (Linux refuses to remount a
  // filesystem read-only while a file on it is open for writing: this is the case a running farm monitor
  // meets as write errors, above)
  const std::string before = read_file(db);
  ASSERT_EQ(sh("mount -o remount,ro " + disk), 0);
  ChildProcess readonly({bin("windfdi-farm"), "--db", db, "--table-period", "0"}, env, "farm_ro");
  // THEN it refuses to start, naming the file, and leaves it as it was
  EXPECT_EQ(readonly.wait(std::chrono::seconds(20)), 2) << readonly.stderr_text();
  EXPECT_NE(readonly.stderr_text().find(db), std::string::npos) << readonly.stderr_text();
  EXPECT_EQ(sh("mount -o remount,rw " + disk), 0);
  EXPECT_EQ(read_file(db), before);
}

TEST(CorruptStore, AStoreThatIsNoDatabaseOrIsDamagedIsRefusedAtStartAndLeftAsItWas) {
  const int domain = private_domain(9);
  const auto env = dds_env(domain);
  const std::string dir = temp_dir("corrupt_store_" + std::to_string(domain));
  // GIVEN a store the farm monitor made (its tables, closed cleanly), a copy of it with its second page
  // garbled, header and all (the first table's root: an empty table's page garbled past its header is only
  // free space, which no check can tell), and a file that is no database at all
  const std::string good = dir + "/farm.sqlite", damaged = dir + "/damaged.sqlite",
                    garbage = dir + "/garbage.sqlite";
  {
    ChildProcess farm({bin("windfdi-farm"), "--db", good, "--table-period", "0"}, env, "farm");
    // (its tables are in the write-ahead log until it closes)
    ASSERT_TRUE(wait_until([&] { return farm.stderr_text().find("database") != std::string::npos; },
                           std::chrono::seconds(20)))
        << farm.stderr_text();
    ASSERT_EQ(farm.stop(SIGTERM), 0) << farm.stderr_text();
  }
  std::string bytes = read_file(good);
  ASSERT_GE(bytes.size(), 8192u);
  for (std::size_t i = 4096; i < 8192; ++i) bytes[i] = static_cast<char>(0x5a ^ (i & 0xff));
  std::ofstream(damaged, std::ios::binary) << bytes;
  std::ofstream(garbage, std::ios::binary) << std::string(3000, 'x');
  for (const auto& db : {damaged, garbage}) {
    const std::string before = read_file(db);
    // WHEN the farm monitor starts on it
    ChildProcess farm({bin("windfdi-farm"), "--db", db, "--table-period", "0"}, env, "farm_corrupt");
    // THEN it refuses with exit 2, naming the file, and leaves it as it was
    EXPECT_EQ(farm.wait(std::chrono::seconds(20)), 2) << db << ": " << farm.stderr_text();
    EXPECT_NE(farm.stderr_text().find(db), std::string::npos) << farm.stderr_text();
    EXPECT_EQ(read_file(db), before) << db;
  }
  // AND the intact store still opens
  ChildProcess again({bin("windfdi-farm"), "--db", good, "--table-period", "0"}, env, "farm_again");
  EXPECT_FALSE(wait_until([&] { return !again.running(); }, std::chrono::seconds(3))) << again.stderr_text();
  EXPECT_EQ(again.stop(SIGTERM), 0) << again.stderr_text();
  std::filesystem::remove_all(dir);
  remove_stale_shm(domain);
}

}  // namespace
