// The residual channels of each blade from its gauge and LIDAR-model estimates (Stotsky 2014's delta_A and
// the cross-blade witnesses).
#include "residual_channels.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "frame_sample.hpp"

namespace windfdi::blade_load {

namespace {
double avg_others(const std::array<double, 3>& v, int b) { return 0.5 * (v[(b + 1) % 3] + v[(b + 2) % 3]); }
}  // namespace

const char* channel_name(int c) {
  static const char* n[] = {"lidar_model", "cross_blade_model_residual", "cross_blade_mean_ratio",
                            "cross_blade_amplitude", "cross_blade_mean"};
  return n[c];
}

BladeChannels unavailable_channels() {
  BladeChannels x;
  for (auto& r : x) r.fill(kNaN);
  return x;
}

double window_load(const BladeEstimates& e) {
  std::array<double, 3> m{};
  int n = 0;
  for (int b = 0; b < 3; ++b)
    if (e.sensor_valid[b] && std::isfinite(e.mean_sensor[b])) m[n++] = std::fabs(e.mean_sensor[b]);
  if (n < 2) return kNaN;
  if (n == 2) return 0.5 * (m[0] + m[1]);
  return std::max(std::min(m[0], m[1]), std::min(std::max(m[0], m[1]), m[2]));
}

BladeChannels residual_channels(const BladeEstimates& e) {
  BladeChannels x = unavailable_channels();
  const bool all_sensors = e.sensor_valid[0] && e.sensor_valid[1] && e.sensor_valid[2];
  const bool all_models = e.model_valid[0] && e.model_valid[1] && e.model_valid[2];
  const double mean_all = std::fabs(e.mean_sensor[0] + e.mean_sensor[1] + e.mean_sensor[2]) / 3.0;
  std::array<double, 3> d{}, r{};
  for (int b = 0; b < 3; ++b) {
    if (e.sensor_valid[b] && e.model_valid[b] && std::fabs(e.mean_model[b]) > 1e3) {
      // The paper's residual delta_A = A_model - A_sensor, relative to the mean load: with IPC and turbulence
      // the true first harmonic passes near zero, where a ratio to it would explode.
      x[b][kModelChannel] = (e.a_model[b] - e.a_sensor[b]) / std::fabs(e.mean_model[b]);
      d[b] = (e.a_sensor[b] - e.a_model[b]) / std::fabs(e.mean_model[b]);
      r[b] = e.mean_sensor[b] / e.mean_model[b];
    }
  }
  if (!all_sensors || mean_all <= 1e3) return x;
  for (int b = 0; b < 3; ++b) {
    // Second witness: the other two blades see the same shear 120 deg apart, so a LIDAR-model error common to
    // all blades cancels in the difference; the model still explains each blade's own pitch.
    if (all_models && std::isfinite(x[0][kModelChannel]) && std::isfinite(x[1][kModelChannel]) &&
        std::isfinite(x[2][kModelChannel])) {
      x[b][kWitnessChannel] = d[b] - avg_others(d, b);
      // Mean load (docs/papers.md, Stotsky 2014: an offset leaves the first harmonic unchanged),
      // model-normalised.
      x[b][kMeanChannel] = r[b] - avg_others(r, b);
    }
    x[b][kRawWitnessChannel] = (e.a_sensor[b] - avg_others(e.a_sensor, b)) / mean_all;
    x[b][kRawMeanChannel] = (e.mean_sensor[b] - avg_others(e.mean_sensor, b)) / mean_all;
  }
  return x;
}

double residual_size(const BladeEstimates& e, int b, int c) {
  double size = 0.0;
  if (c == kModelChannel || c == kWitnessChannel) size = e.a_sensor[b] - e.a_model[b];
  if (c == kRawWitnessChannel) size = e.a_sensor[b] - avg_others(e.a_sensor, b);
  if (c == kMeanChannel)
    size = e.mean_sensor[b] - e.mean_model[b] * avg_others({e.mean_sensor[0] / e.mean_model[0],
                                                            e.mean_sensor[1] / e.mean_model[1],
                                                            e.mean_sensor[2] / e.mean_model[2]},
                                                           b);
  if (c == kRawMeanChannel) size = e.mean_sensor[b] - avg_others(e.mean_sensor, b);
  return size;
}

double residual_share(const BladeEstimates& e, int b, int c) {
  if (c < 0) return 0.0;
  const double reference = std::fabs(avg_others(mean_load_channel(c) ? e.mean_sensor : e.a_sensor, b));
  return reference > 0.0 ? residual_size(e, b, c) / reference : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace windfdi::blade_load
