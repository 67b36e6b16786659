// One turbine's stream of standard normal numbers, shared by its wind and its sensors (one seed per turbine).
#pragma once

#include <cstdint>
#include <random>

namespace windfdi::plant {

class RandomSource {
 public:
  explicit RandomSource(uint64_t seed) : rng_(seed) {}
  /// A standard normal number.
  double normal() { return normal_(rng_); }

 private:
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
};

}  // namespace windfdi::plant
