// LidarFrames: a sample takes the LIDAR frame of its own time, not the newest one received.
#include <gtest/gtest.h>

#include "lidar_frames.hpp"

namespace windfdi {
namespace {

LidarFrames::Frame frame(double t, double v) { return {t, v, v + 1.0, true}; }

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

}  // namespace
}  // namespace windfdi
