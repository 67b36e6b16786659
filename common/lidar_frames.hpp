// The LIDAR frames of one turbine, held for merging into its frame samples at their own time.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <utility>

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
    uint64_t sequence = 0;    ///< the plant's LIDAR frame count: a skipped number is a frame lost on the way
    bool after_loss = false;  ///< set by add: frames before this one were lost on the way
  };
  void add(Frame f) {
    if (!frames_.empty() && f.t < frames_.back().t) {  // a restarted plant's clock
      frames_.clear();
      served_without_ = -1e300;
    }
    f.after_loss = have_sequence_ && f.sequence > last_sequence_ + 1;
    have_sequence_ = true;
    last_sequence_ = f.sequence;
    // A frame that comes after a sample of a later time went without a LIDAR value (a repair held up on a
    // loaded link): the samples in between lost it on the way.
    if (f.t <= served_without_) lost_ = true;
    if (frames_.size() == kMaxFrames) frames_.pop_front();
    frames_.push_back(f);
  }
  /// The newest frame at or before `t` within kStale of it, or nullptr. Samples come in time order,
  /// so frames older than that one are not needed again.
  const Frame* at(double t) {
    while (!frames_.empty() && frames_.front().t <= t) {
      if (frames_.front().after_loss) lost_ = true;  // the samples have reached the end of a hole
      frames_.front().after_loss = false;
      if (frames_.size() < 2 || frames_[1].t > t) break;
      frames_.pop_front();
    }
    if (frames_.empty() || frames_.front().t > t || t - frames_.front().t >= kStale) {
      served_without_ = std::max(served_without_, t);
      return nullptr;
    }
    return &frames_.front();
  }
  /// Whether LIDAR frames were lost on the way since the last call: the samples reached a frame after a
  /// skipped sequence number, or a frame came after a later sample went without one. The gap a lost frame
  /// leaves in the LIDAR history is the network's, not the LIDAR's (a loaded farm raised "no delayed LIDAR
  /// speeds" on every turbine when its reader dropped frames); a LIDAR that falls silent skips no number.
  bool take_lost() { return std::exchange(lost_, false); }

 private:
  static constexpr std::size_t kMaxFrames = 4096;  // minutes of frames at the plant's rate
  std::deque<Frame> frames_;
  bool have_sequence_ = false;
  uint64_t last_sequence_ = 0;
  double served_without_ = -1e300;  // the latest sample time given no frame
  bool lost_ = false;
};

}  // namespace windfdi
