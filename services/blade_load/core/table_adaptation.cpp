// Load-table adaptation in uniform wind over segments of one operating point (Stotsky 2014, last section).
#include "table_adaptation.hpp"

#include <algorithm>
#include <cmath>

#include "frame_sample.hpp"

namespace windfdi::blade_load {

void TableAdaptation::add_sample(double shear, double lambda, double pitch) {
  shear_sum_ += shear;
  lambda_sum_ += lambda;
  pitch_sum_ += pitch;
  ++op_n_;
}

void TableAdaptation::restart() {
  op_n_ = 0;
  shear_sum_ = lambda_sum_ = pitch_sum_ = 0.0;
}

void TableAdaptation::revolution(bool healthy, const std::array<double, 3>& mean_sensor,
                                 const std::array<double, 3>& mean_model, LoadTable& table) {
  const double shear = op_n_ > 0 ? shear_sum_ / op_n_ : kNaN;
  const double lambda = op_n_ > 0 ? lambda_sum_ / op_n_ : kNaN;
  const double pitch = op_n_ > 0 ? pitch_sum_ / op_n_ : kNaN;
  restart();
  if (!(c_.enabled && healthy && std::isfinite(shear) && std::fabs(shear) < c_.uniform_shear)) {
    n_ = 0;
    return;
  }
  const double ms = (mean_sensor[0] + mean_sensor[1] + mean_sensor[2]) / 3.0;
  const double mm = (mean_model[0] + mean_model[1] + mean_model[2]) / 3.0;
  if (!(ms > 0 && mm > 0)) {
    n_ = 0;
    return;
  }
  // A segment holds one operating point: when it moves, start a new segment at this revolution.
  if (n_ > 0 && (std::max(lmax_, lambda) - std::min(lmin_, lambda) > c_.max_lambda_spread ||
                 std::max(pmax_, pitch) - std::min(pmin_, pitch) > c_.max_pitch_spread))
    n_ = 0;
  if (n_ == 0) {
    sensor_ = model_ = lsum_ = psum_ = 0.0;
    lmin_ = lmax_ = lambda;
    pmin_ = pmax_ = pitch;
  }
  lmin_ = std::min(lmin_, lambda);
  lmax_ = std::max(lmax_, lambda);
  pmin_ = std::min(pmin_, pitch);
  pmax_ = std::max(pmax_, pitch);
  sensor_ += ms;
  model_ += mm;
  lsum_ += lambda;
  psum_ += pitch;
  if (++n_ < c_.revolutions) return;
  // Uniform wind over a long segment: the model's mean load should equal the sensors' (Stotsky 2014, last
  // section).
  const double l = lsum_ / n_, p = psum_ / n_;
  const double target = table.factor(l, p) * sensor_ / model_;
  table.adapt(l, p, target, c_.gain, c_.sigma_lambda, c_.sigma_pitch, c_.bound);
  ++adaptations_;
  n_ = 0;
}

}  // namespace windfdi::blade_load
