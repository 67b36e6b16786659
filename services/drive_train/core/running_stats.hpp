// Small accumulators the drive-train monitors share.
#pragma once

#include <cstdint>

namespace windfdi::drive_train {

/// Mean of the values added since the last reset.
struct RunningMean {
  double sum = 0.0;
  uint64_t n = 0;
  void add(double x) {
    sum += x;
    ++n;
  }
  void reset() { sum = 0.0, n = 0; }
  double mean() const { return n > 0 ? sum / static_cast<double>(n) : 0.0; }
};

}  // namespace windfdi::drive_train
