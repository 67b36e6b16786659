// LidarFrames: a sample takes the LIDAR frame of its own time, and frames lost on the way are told apart.
#include <gtest/gtest.h>

#include "lidar_frames.hpp"

namespace windfdi {
namespace {

LidarFrames::Frame frame(double t, double v, uint64_t sequence = 0) {
  return {t, v, v + 1.0, true, sequence};
}

TEST(LidarFrames, ASampleTakesTheNewestFrameAtOrBeforeItsOwnTime) {
  // GIVEN frames at 10 Hz for 2 s, all received before the samples (a service behind on frames)
  LidarFrames lidar;
  for (int k = 0; k <= 20; ++k) lidar.add(frame(0.1 * k, 10.0 + k));
  // THEN each sample is given the frame of its own time: the newest at or before it
  ASSERT_NE(lidar.at(0.0), nullptr);
  EXPECT_DOUBLE_EQ(lidar.at(0.0)->v_upper, 10.0);
  EXPECT_DOUBLE_EQ(lidar.at(0.05)->v_upper, 10.0);
  EXPECT_DOUBLE_EQ(lidar.at(0.1)->v_upper, 11.0);
  EXPECT_DOUBLE_EQ(lidar.at(0.99)->v_upper, 19.0);
  EXPECT_DOUBLE_EQ(lidar.at(2.5)->v_upper, 30.0);
  EXPECT_DOUBLE_EQ(lidar.at(2.5)->v_lower, 31.0);
}

TEST(LidarFrames, NoFrameBeforeASampleOrOneOlderThanASecondGivesNone) {
  LidarFrames lidar;
  EXPECT_EQ(lidar.at(0.0), nullptr);
  lidar.add(frame(5.0, 1.0));
  EXPECT_EQ(lidar.at(4.9), nullptr);  // only a later frame: none of this sample's time
  EXPECT_NE(lidar.at(5.5), nullptr);
  EXPECT_EQ(lidar.at(6.0), nullptr);  // stale: kStale without a frame
}

TEST(LidarFrames, ARestartedPlantsClockStartsTheFramesAgain) {
  // GIVEN frames up to t = 100 s, then a restarted plant's frames from t = 0
  LidarFrames lidar;
  for (int k = 0; k <= 10; ++k) lidar.add(frame(90.0 + k, 1.0));
  lidar.add(frame(0.0, 2.0));
  // THEN the new clock's samples take the new frames
  ASSERT_NE(lidar.at(0.01), nullptr);
  EXPECT_DOUBLE_EQ(lidar.at(0.01)->v_upper, 2.0);
}

TEST(LidarFrames, FramesSkippedOnTheWayAreALossOnceTheSamplesReachThem) {
  // GIVEN frames at 5 Hz numbered 0..9, then 20.. (10 frames, 2 s, dropped by a full reader history)
  LidarFrames lidar;
  for (uint64_t k = 0; k < 10; ++k) lidar.add(frame(0.2 * static_cast<double>(k), 1.0, k));
  for (uint64_t k = 20; k < 25; ++k) lidar.add(frame(0.2 * static_cast<double>(k), 2.0, k));
  // THEN the samples before the hole's end see no loss, however far ahead the frames are
  for (double t = 0.0; t < 3.99; t += 0.01) {
    lidar.at(t);
    ASSERT_FALSE(lidar.take_lost()) << t;
  }
  // AND the sample that reaches the first frame after it sees one, once
  ASSERT_NE(lidar.at(4.0), nullptr);
  EXPECT_TRUE(lidar.take_lost());
  EXPECT_FALSE(lidar.take_lost());
  lidar.at(4.5);
  EXPECT_FALSE(lidar.take_lost());
}

TEST(LidarFrames, AFrameThatComesAfterALaterSampleWentWithoutItIsALoss) {
  // GIVEN frames up to 1 s, and samples served up to 2.5 s (stale from 2.0 s on)
  LidarFrames lidar;
  for (uint64_t k = 0; k <= 5; ++k) lidar.add(frame(0.2 * static_cast<double>(k), 1.0, k));
  for (double t = 0.0; t < 2.5; t += 0.01) lidar.at(t);
  EXPECT_EQ(lidar.at(2.5), nullptr);
  EXPECT_FALSE(lidar.take_lost());
  // WHEN the next frames come late (a repair held up), in sequence
  lidar.add(frame(1.2, 1.0, 6));
  lidar.add(frame(2.6, 1.0, 7));
  // THEN that is a loss on the way
  EXPECT_TRUE(lidar.take_lost());
  EXPECT_FALSE(lidar.take_lost());
}

TEST(LidarFrames, ALidarThatFallsSilentAndFramesAheadOfTheSamplesAreNoLoss) {
  // GIVEN frames ahead of the samples (a block of samples comes after the LIDAR frames of its time), then
  // 5 s of silence and the next frame in sequence
  LidarFrames lidar;
  uint64_t n = 0;
  for (int k = 0; k < 10; ++k) lidar.add(frame(0.2 * k, 1.0, n++));
  for (double t = 0.0; t < 7.0; t += 0.01) lidar.at(t);
  lidar.add(frame(7.0, 1.0, n++));
  ASSERT_NE(lidar.at(7.0), nullptr);
  // THEN no loss on the way: a silent LIDAR is the LIDAR's own loss, which the service reports
  EXPECT_FALSE(lidar.take_lost());
  // AND a restarted plant (sequence and clock from 0) is none either
  lidar.add(frame(0.0, 1.0, 0));
  lidar.add(frame(0.2, 1.0, 1));
  ASSERT_NE(lidar.at(0.1), nullptr);
  EXPECT_FALSE(lidar.take_lost());
}

}  // namespace
}  // namespace windfdi
