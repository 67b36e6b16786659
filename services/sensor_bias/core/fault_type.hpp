// Tells a sensor's gain fault from its offset fault by how its error moves with the measured quantity.
#pragma once

#include <Eigen/Dense>

namespace windfdi::sensor_bias {

/// A faulty reading y of a quantity q (known from an independent witness w) has the error e = y - w:
///   offset (the benchmark's bias):   e = a + c z
///   gain   (the benchmark's gain):   e = k x + c z
/// with x the witness (k = gain - 1) or the reading itself (k = 1 - 1 / gain; for a noisy witness: e and x
/// must not share the witness's noise, which alone would fit a negative k), and z a nuisance regressor (the
/// pitch reference rate, for the actuator's lag; 0 for the speeds). At a constant x the two are the same
/// fault; the quantity's own variation separates them. The evidence is the drop of the residual sum of
/// squares from the offset model to the gain model over the noise variance of the full model [1, x, z] (a
/// likelihood ratio for white noise: > 0 says gain, < 0 offset). Samples are averaged in blocks of
/// `block_samples` first, so that a disturbance faster than the block (a speed witness's drive-train torsion)
/// does not count as evidence.
class GainOrOffsetTest {
 public:
  enum class Verdict { kUndecided, kOffset, kGain };

  GainOrOffsetTest() = default;
  /// `regressor_is_reading`: x is the faulty reading (else the witness).
  /// `small_sample`: the evidence is the chi-square value of the F statistic's tail probability (else the
  /// ratio itself, as before stop 71).
  GainOrOffsetTest(int block_samples, bool regressor_is_reading, bool small_sample = true)
      : block_samples_(block_samples < 1 ? 1 : block_samples),
        regressor_is_reading_(regressor_is_reading),
        small_sample_(small_sample) {}

  /// Forgets everything: the next sample starts the record (call at the fault's onset).
  void restart();
  void add(double error, double value, double nuisance = 0.0);

  /// Blocks recorded since the restart.
  int blocks() const { return blocks_; }
  /// The likelihood ratio above; 0 until there are more blocks than regressors.
  double evidence() const;
  /// kGain or kOffset once |evidence| reaches `min_evidence`.
  Verdict verdict(double min_evidence) const;
  /// The decision when no more time is left: kGain when the evidence reaches `gain_margin`, else kOffset (the
  /// simpler model, which a tie leaves standing).
  Verdict verdict_now(double gain_margin) const;
  /// How much better the full model [1, x, z] fits than the better of the two (the same likelihood ratio):
  /// small for a sensor's offset or gain; large when the error is neither, e.g. a slow actuator whose answer
  /// to the quantity's swing is smaller while its mean is right (an intercept cancelling a slope).
  double misfit() const;
  double gain() const;    ///< the gain model's sensor gain
  double offset() const;  ///< a of the offset model
  struct Nuisance {
    /// c: for the pitch, whose nuisance is the reference rate, minus the actuator's lag in s
    double coefficient;
    /// the model's residual variance per block through the inverse normal matrix: large where the nuisance
    /// hardly moved (a pitch reference standing at fine pitch); infinite with too few blocks
    double standard_error;
  };
  /// The nuisance's coefficient in the gain model (`gain_model`) or the offset model, from one fit.
  Nuisance nuisance(bool gain_model) const;

 private:
  // Least squares over the regressors in `use` ([1, x, z]); returns the residual sum of squares.
  double fit(const Eigen::Vector3d& use, Eigen::Vector3d* coefficients) const;
  // The normal equations' matrix of that fit (identity rows for the regressors not used).
  Eigen::Matrix3d normal_matrix(const Eigen::Vector3d& use) const;
  // The noise variance per block from the full model's residual sum of squares (the likelihood units).
  double noise_variance(double full_rss) const;

  int block_samples_ = 1;
  bool regressor_is_reading_ = false;
  bool small_sample_ = true;
  int in_block_ = 0;
  Eigen::Vector3d block_sum_ = Eigen::Vector3d::Zero();  // e, x, z of the block being filled
  Eigen::Matrix3d uu_ = Eigen::Matrix3d::Zero();         // sums of u u^T, u = [1, x, z]
  Eigen::Vector3d ue_ = Eigen::Vector3d::Zero();         // sums of u e
  double ee_ = 0.0;
  int blocks_ = 0;
};

}  // namespace windfdi::sensor_bias
