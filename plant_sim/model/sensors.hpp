// The turbine's sensors: a true value plus Gaussian noise, changed by the scenario's sensor faults (bias,
// the paper's state-dependent bias, gain, drift, stuck, intermittent, invalid).
#pragma once

#include <string>
#include <vector>

#include "frame_sample.hpp"
#include "random_source.hpp"
#include "scenario.hpp"

namespace windfdi::plant {

class Sensors {
 public:
  Sensors(const std::vector<FaultSpec>& faults, double dt);

  /// The measurement of `channel` (a recording column, e.g. "pitch_2") at time t (s); `inject` false while
  /// the plant settles. The noise is drawn even when its std is 0, so every channel uses the same numbers of
  /// the turbine's stream whatever the noise levels.
  double measure(const std::string& channel, double true_value, double noise_std, double t, bool inject,
                 RandomSource& random);

 private:
  std::vector<FaultSpec> faults_;
  double dt_;
  // Per fault, the value latched at the start of a stuck fault.
  std::vector<double> stuck_value_;
  std::vector<bool> stuck_latched_;
};

}  // namespace windfdi::plant
