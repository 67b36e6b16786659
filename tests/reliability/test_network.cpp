// Reliability: the campaign's network emulation does what it says (WINDFDI_NETWORK_EMULATION): an outage
// carries nothing, not even discovery, and a lossy link still carries the reliable frame stream.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "process.hpp"
#include "test_util.hpp"

using namespace windfdi::test;

namespace {

class NetworkEmulation : public ::testing::Test {
 protected:
  void SetUp() override {
    std::filesystem::create_directories(dir);
    env["WINDFDI_NETWORK_EMULATION"] = file;
  }
  void TearDown() override {
    std::filesystem::remove_all(dir);
    remove_stale_shm(domain);
  }
  void set_network(const std::string& text) { std::ofstream(file) << text << "\n"; }
  /// A listener and a publisher of `blocks` blocks of 10 samples per turbine; the listener's last line.
  nlohmann::json exchange(const std::string& ids, int blocks, int turbines, int readers,
                          const char* timeout) {
    ChildProcess listener({bin("windfdi-test-peer"), "listen", "--expect",
                           std::to_string(turbines * blocks * 10), "--timeout", timeout},
                          env, "listen");
    ChildProcess publisher(
        {bin("windfdi-test-peer"), "publish", "--ids", ids, "--blocks", std::to_string(blocks), "--rate",
         "20", "--readers", std::to_string(readers), "--wall-stamp"},
        env, "publish");
    publisher.wait(std::chrono::seconds(60));
    listener.wait(std::chrono::seconds(60));
    EXPECT_NE(publisher.stderr_text().find("network emulation"), std::string::npos)
        << publisher.stderr_text();
    const auto lines = json_lines(listener.stdout_text());
    if (lines.empty()) {
      ADD_FAILURE() << listener.stderr_text();
      return {};
    }
    return lines.back();
  }
  int domain = private_domain(19);
  std::string dir =
      std::filesystem::temp_directory_path().string() + "/windfdi-network-" + std::to_string(getpid());
  std::string file = dir + "/network";
  std::map<std::string, std::string> env = dds_env(domain);
};

TEST_F(NetworkEmulation, AnOutageCarriesNothingAndALossyLinkStillCarriesTheStream) {
  // GIVEN the network down: a publisher that does not wait for readers sends 30 blocks
  set_network("down");
  const auto down = exchange("WT01", 30, 1, 0, "6");
  // THEN the listener received nothing and discovered nobody
  EXPECT_EQ(down.value("total", -1), 0) << down.dump();
  EXPECT_EQ(down.value("participants_discovered", -1), 0) << down.dump();
  // WHEN 20 % of every process's messages are lost (data, heartbeats, acknowledgements, discovery)
  set_network("loss 20");
  // (200 blocks, 10 s: at 20 % loss the reader's side of discovery took up to 2.7 s to match the publisher's
  // writer, which had matched the reader and started; a 5 s stream left too little after that)
  const auto lossy = exchange("WT01,WT02,WT03", 200, 3, 1, "20");
  // THEN the reliable stream still arrives from the moment the reader's side matched (discovery messages are
  // lost too, and the volatile blocks sent before that are not the reader's): at least 90 % of every
  // turbine's samples from its first one received (a keep-last 8 history may be overwritten before a repair
  // on a slow machine; the readers see that as a sequence gap)
  // (the reader matched the publisher's writer, which needs its participant discovered: the listener's count
  // of participant discoveries read 0 once in CI with the writer matched and all 3000 samples received; and
  // the count of writers matched now read 0 in stop 84's CI with 5610 samples received, the publisher gone
  // by the listener's timeout, so the witness is the count of writers it ever matched)
  EXPECT_GE(lossy.value("writers_ever_matched", 0), 1) << lossy.dump();
  for (const char* id : {"WT01", "WT02", "WT03"}) {
    const auto& first = lossy["first"];
    ASSERT_TRUE(first.contains(id)) << id << " " << lossy.dump();
    const int from = first[id].get<int>();
    EXPECT_LT(from, 2000) << id << " " << lossy.dump();
    EXPECT_GE(lossy["counts"].value(id, 0), (2000 - from) * 9 / 10) << id << " " << lossy.dump();
  }
  std::cout << "[ measured ] at 20 % loss: " << lossy.value("total", 0) << " of 6000 samples, first "
            << lossy["first"].dump() << ", gaps " << lossy["gaps"].dump() << "\n";
}

TEST_F(NetworkEmulation, AJitteryLinkDelaysAndReordersButTheReliableStreamArrivesWholeAndInOrder) {
  // GIVEN no emulated trouble: the frames' delay from write to take is the machine's own
  set_network("");
  const auto clear = exchange("WT01,WT02", 60, 2, 1, "20");
  // WHEN every message sent (data, heartbeats, acknowledgements, discovery) is held a random 0..50 ms, so
  // that messages overtake each other
  set_network("jitter 50");
  const auto jittery = exchange("WT01,WT02", 60, 2, 1, "20");
  // THEN every sample from the first one the reader took arrives, in sequence (a message overtaken by a later
  // one is delivered after it by the reliable reader, or repaired; the volatile blocks written before the
  // reader's side matched the writer are not the reader's: on a loaded machine the jittered discovery left
  // the first 11 blocks out), and the frames are late by what the link held them: more than 10 ms at the
  // median (uniform 0..50 ms is 25 ms at the median; the clear run's median is well under 10 ms)
  for (const auto* run : {&clear, &jittery}) {
    for (const char* id : {"WT01", "WT02"}) {
      ASSERT_TRUE(run->contains("first") && (*run)["first"].contains(id)) << id << " " << run->dump();
      const int from = (*run)["first"][id].get<int>();
      EXPECT_LT(from, 300) << id << " " << run->dump();
      EXPECT_EQ((*run)["counts"].value(id, 0), 600 - from) << id << " " << run->dump();
    }
    EXPECT_TRUE(!run->contains("gaps") || (*run)["gaps"].empty()) << run->dump();
    ASSERT_TRUE(run->contains("delay_ms")) << run->dump();
  }
  EXPECT_LT(clear["delay_ms"].value("p50", 1e9), 10.0) << clear.dump();
  EXPECT_GT(jittery["delay_ms"].value("p50", 0.0), 10.0) << jittery.dump();
  std::cout << "[ measured ] frame delay without / with 50 ms jitter: p50 " << clear["delay_ms"]["p50"]
            << " / " << jittery["delay_ms"]["p50"] << " ms, p99 " << clear["delay_ms"]["p99"] << " / "
            << jittery["delay_ms"]["p99"] << " ms\n";
}

}  // namespace
