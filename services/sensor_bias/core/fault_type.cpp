// Tells a sensor's gain fault from its offset fault by how its error moves with the measured quantity.
#include "fault_type.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace windfdi::sensor_bias {

void GainOrOffsetTest::restart() {
  in_block_ = 0;
  block_sum_.setZero();
  uu_.setZero();
  ue_.setZero();
  ee_ = 0.0;
  blocks_ = 0;
}

void GainOrOffsetTest::add(double error, double value, double nuisance) {
  block_sum_ += Eigen::Vector3d(error, value, nuisance);
  if (++in_block_ < block_samples_) return;
  const Eigen::Vector3d m = block_sum_ / static_cast<double>(block_samples_);
  const Eigen::Vector3d u(1.0, m(1), m(2));
  uu_ += u * u.transpose();
  ue_ += u * m(0);
  ee_ += m(0) * m(0);
  ++blocks_;
  in_block_ = 0;
  block_sum_.setZero();
}

Eigen::Matrix3d GainOrOffsetTest::normal_matrix(const Eigen::Vector3d& use) const {
  // A regressor that never moved from zero (no nuisance, a pitch standing at 0 deg) gets a small ridge and so
  // a zero coefficient instead of a singular system.
  Eigen::Matrix3d a = Eigen::Matrix3d::Identity();
  for (int i = 0; i < 3; ++i) {
    if (use(i) == 0.0) continue;
    for (int j = 0; j < 3; ++j)
      if (use(j) != 0.0) a(i, j) = uu_(i, j);
    a(i, i) += 1e-9 * uu_(i, i) + 1e-12 * static_cast<double>(blocks_);
  }
  return a;
}

double GainOrOffsetTest::fit(const Eigen::Vector3d& use, Eigen::Vector3d* coefficients) const {
  const Eigen::Matrix3d a = normal_matrix(use);
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (int i = 0; i < 3; ++i)
    if (use(i) != 0.0) b(i) = ue_(i);
  const Eigen::Vector3d c = a.ldlt().solve(b);
  if (coefficients) *coefficients = c;
  return std::max(0.0, ee_ - c.dot(b));
}

double GainOrOffsetTest::noise_variance(double full_rss) const {
  // Noise-free data (a synthetic record) would divide by zero: floor the variance far below any sensor's.
  return std::max(full_rss / static_cast<double>(blocks_ - 3), 1e-12 * ee_ / blocks_ + 1e-300);
}

double GainOrOffsetTest::evidence() const {
  if (blocks_ <= 3) return 0.0;
  const double offset_rss = fit(Eigen::Vector3d(1, 0, 1), nullptr);
  const double gain_rss = fit(Eigen::Vector3d(0, 1, 1), nullptr);
  const double ratio = (offset_rss - gain_rss) / noise_variance(fit(Eigen::Vector3d(1, 1, 1), nullptr));
  if (!small_sample_) return ratio;
  // The noise variance is itself estimated from blocks - 3 degrees of freedom, so the ratio is an F(1, nu)
  // statistic, not a chi-square(1) one: four blocks of a rotor-speed record (two seconds) gave 50 "against a
  // gain" and named the benchmark's gain an offset. (nu - 1/2) ln(1 + F / nu) is the chi-square(1) value of
  // the same tail probability (within 0.3 of it from nu = 4 on; at nu = 100, F = 16 gives 14.8), so
  // type_evidence keeps its meaning at every record length.
  const double nu = static_cast<double>(blocks_ - 3);
  const double equivalent = std::max(nu - 0.5, 0.5) * std::log1p(std::fabs(ratio) / nu);
  return ratio < 0.0 ? -equivalent : equivalent;
}

double GainOrOffsetTest::misfit() const {
  if (blocks_ <= 3) return 0.0;
  const double best =
      std::min(fit(Eigen::Vector3d(1, 0, 1), nullptr), fit(Eigen::Vector3d(0, 1, 1), nullptr));
  const double full = fit(Eigen::Vector3d(1, 1, 1), nullptr);
  return (best - full) / noise_variance(full);
}

GainOrOffsetTest::Verdict GainOrOffsetTest::verdict(double min_evidence) const {
  const double e = evidence();
  // A "gain" that is further than 1 from unity (a reading of the opposite sign, or a gain model fitted on a
  // quantity standing near zero) is not a sensor's gain fault: what is left is the offset.
  if (!(std::fabs(gain() - 1.0) <= 1.0)) return blocks_ > 3 ? Verdict::kOffset : Verdict::kUndecided;
  if (e >= min_evidence) return Verdict::kGain;
  if (e <= -min_evidence) return Verdict::kOffset;
  return Verdict::kUndecided;
}

GainOrOffsetTest::Verdict GainOrOffsetTest::verdict_now(double gain_margin) const {
  return std::fabs(gain() - 1.0) <= 1.0 && evidence() >= gain_margin ? Verdict::kGain : Verdict::kOffset;
}

double GainOrOffsetTest::gain() const {
  Eigen::Vector3d c;
  fit(Eigen::Vector3d(0, 1, 1), &c);
  return regressor_is_reading_ ? 1.0 / (1.0 - c(1)) : 1.0 + c(1);
}

GainOrOffsetTest::Nuisance GainOrOffsetTest::nuisance(bool gain_model) const {
  const Eigen::Vector3d use = gain_model ? Eigen::Vector3d(0, 1, 1) : Eigen::Vector3d(1, 0, 1);
  Eigen::Vector3d c;
  const double rss = fit(use, &c);
  if (blocks_ <= 3) return {c(2), std::numeric_limits<double>::infinity()};
  const double variance = rss / static_cast<double>(blocks_ - 2);
  return {c(2), std::sqrt(variance * normal_matrix(use).inverse()(2, 2))};
}

double GainOrOffsetTest::offset() const {
  Eigen::Vector3d c;
  fit(Eigen::Vector3d(1, 0, 1), &c);
  return c(0);
}

}  // namespace windfdi::sensor_bias
