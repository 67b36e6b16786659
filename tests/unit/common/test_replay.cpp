// Unit tests of the replay driver: per-turbine order, sequence gaps, rejected samples, outputs.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "process.hpp"
#include "replay.hpp"
#include "replay_csv.hpp"
#include "yaml_config.hpp"

using namespace windfdi;

TEST(SequenceTracker, ReportsLostSamplesAndRestarts) {
  SequenceTracker s;
  EXPECT_EQ(s.lost_before(10), 0u);  // first sample: nothing known before it
  EXPECT_EQ(s.lost_before(11), 0u);
  EXPECT_EQ(s.lost_before(15), 3u);  // 12, 13, 14 lost
  EXPECT_EQ(s.lost_before(2), 1u);   // went backwards: a restarted source is a discontinuity
  EXPECT_EQ(s.lost_before(3), 0u);
}

TEST(BridgeableHole, EveryServiceBridgesSamplesLostOverAtMostMaxBridgedGap) {
  // 100 Hz, max_bridged_gap 0.5 s: 50 samples lost (0.50 s of them) are bridged, 51 are not
  auto hole = [](uint64_t lost) {
    return bridgeable_hole(1000, 10.0, 1001 + lost, 10.0 + 0.01 * static_cast<double>(lost + 1), 0.5);
  };
  EXPECT_TRUE(hole(1));
  EXPECT_TRUE(hole(20));
  EXPECT_TRUE(hole(50));
  EXPECT_FALSE(hole(51));
  EXPECT_FALSE(hole(0));                                        // nothing lost: nothing to bridge
  EXPECT_TRUE(bridgeable_hole(10, 1.0, 13, 4.0, 2.0));          // 1 Hz: 2 samples lost are 2 s of them
  EXPECT_FALSE(bridgeable_hole(10, 1.0, 14, 5.0, 2.0));         // 3 are not
  EXPECT_FALSE(bridgeable_hole(1000, 10.0, 1021, 9.0, 0.5));    // time went back (a restarted controller)
  EXPECT_FALSE(bridgeable_hole(1000, 10.0, 1021, 310.0, 0.5));  // 20 lost and the clock stepped 5 minutes
  EXPECT_FALSE(bridgeable_hole(1000, 10.0, 5, 10.5, 0.5));      // the sequence restarted
  EXPECT_FALSE(bridgeable_hole(1000, 10.0, 1002, 10.02, 0.0));  // max_bridged_gap 0: every hole restarts
  // The count every service uses for the samples it bridges
  EXPECT_EQ(samples_lost(1000, 1021), 20u);
  EXPECT_EQ(samples_lost(1000, 1001), 0u);
  EXPECT_EQ(samples_lost(1000, 1000), 0u);  // repeated
  EXPECT_EQ(samples_lost(1000, 990), 0u);   // out of order (a restarted controller)
}

TEST(SampleTimeTracker, AStepBackOrAJumpOfMinutesIsADiscontinuityTheSampleRateIsNot) {
  SampleTimeTracker c;
  EXPECT_EQ(c.step(100.0), 0.0);  // first sample
  EXPECT_EQ(c.step(100.01), 0.0);
  EXPECT_EQ(c.step(101.01), 0.0);            // a 1 Hz recording
  EXPECT_EQ(c.step(106.01), 0.0);            // a gap within kMaxInterval
  EXPECT_NEAR(c.step(406.01), 300.0, 1e-9);  // the controller's clock stepped 5 minutes forward (NTP)
  EXPECT_NEAR(c.step(6.0), -400.01, 1e-9);   // back: a restarted controller
  EXPECT_EQ(c.step(std::nan("")), 0.0);      // a NaN time is the core's to reject, no step
  EXPECT_EQ(c.step(6.01), 0.0);
}

TEST(Replay, DrivesEachTurbineInOrderAndWritesTheContractFiles) {
  // GIVEN a recording of two turbines where WT02 lost samples 3 and 4, and WT01 has a NaN pitch
  const std::string dir = test::temp_dir("replay");
  {
    std::ofstream f(dir + "/frames.csv");
    f << "t,turbine_id,sequence,pitch_1\n";
    for (int k = 0; k < 8; ++k) {
      f << 0.01 * k << ",WT01," << k << "," << (k == 5 ? "nan" : "2.0") << "\n";
      if (k != 3 && k != 4) f << 0.01 * k << ",WT02," << k << ",3.0\n";
    }
  }
  ReplayOptions o{dir + "/frames.csv", dir + "/est.csv", dir + "/events.jsonl"};
  std::map<std::string, int> seen;
  int gaps = 0;
  // WHEN replayed through a process function that rejects NaN pitch and emits one estimate per sample
  const auto stats = run_replay(o, {"pitch_mean"},
                                [&](const std::string& id, const FrameSample& s, bool gap, ReplaySink& sink) {
                                  ++seen[id];
                                  gaps += gap;
                                  if (!std::isfinite(s.pitch[0])) return false;
                                  sink.estimate(s.t, id, {format_number(s.pitch[0])});
                                  if (id == "WT02" && s.sequence == 7) {
                                    FaultEvent e;
                                    e.t = s.t;
                                    e.turbine_id = id;
                                    e.source = "test";
                                    e.component = "pitch_sensor_1";
                                    e.fault = "sensor_bias";
                                    sink.event(e);
                                  }
                                  return true;
                                });
  // THEN every sample was seen once, the gap was flagged once, the NaN was counted as rejected
  EXPECT_EQ(seen["WT01"], 8);
  EXPECT_EQ(seen["WT02"], 6);
  EXPECT_EQ(gaps, 1);
  EXPECT_EQ(stats.sequence_gaps, 2u);
  EXPECT_EQ(stats.rejected, 1u);
  EXPECT_EQ(stats.estimates, 13u);
  EXPECT_EQ(stats.events, 1u);
  // AND the estimates file has t first, then turbine_id, then the service's columns
  std::ifstream est(dir + "/est.csv");
  std::string header;
  std::getline(est, header);
  EXPECT_EQ(header, "t,turbine_id,pitch_mean");
}

TEST(Replay, MalformedFileIsAConfigErrorNamingTheLine) {
  const std::string dir = test::temp_dir("replay_bad");
  std::ofstream(dir + "/frames.csv") << "t,pitch_1\n0,1\n0.01,1,2\n";
  ReplayOptions o{dir + "/frames.csv", "", ""};
  try {
    run_replay(o, {}, [](const std::string&, const FrameSample&, bool, ReplaySink&) { return true; });
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.line(), 3);
  }
}
