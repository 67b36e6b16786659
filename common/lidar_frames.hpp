// The LIDAR frames of one turbine, held for merging into its frame samples at their own time.
#pragma once

#include <cstddef>
#include <deque>

#include "frame_sample.hpp"

namespace windfdi {

// A turbine's LIDAR frames, each merged into the frame samples from its own time on (as the recording
// holds it), while fresh. The two topics are taken one after the other, and a service behind on frames
// holds LIDAR frames newer than the samples it works through: merging the newest paired a later wind
// preview with earlier blade moments, so a starved service diagnosed other inputs than its replay.
class LidarFrames {
 public:
  static constexpr double kStale = 1.0;  ///< s of sample time without a LIDAR frame before it counts as lost
  struct Frame {
    double t = -1e300, v_upper = kNaN, v_lower = kNaN;
    bool valid = false;
  };
  void add(const Frame& f) {
    if (!frames_.empty() && f.t < frames_.back().t) frames_.clear();  // a restarted plant's clock
    if (frames_.size() == kMaxFrames) frames_.pop_front();
    frames_.push_back(f);
  }
  /// The newest frame at or before `t` within kStale of it, or nullptr. Samples come in time order,
  /// so frames older than that one are not needed again.
  const Frame* at(double t) {
    while (frames_.size() >= 2 && frames_[1].t <= t) frames_.pop_front();
    if (frames_.empty() || frames_.front().t > t || t - frames_.front().t >= kStale) return nullptr;
    return &frames_.front();
  }

 private:
  static constexpr std::size_t kMaxFrames = 4096;  // minutes of frames at the plant's rate
  std::deque<Frame> frames_;
};

}  // namespace windfdi
