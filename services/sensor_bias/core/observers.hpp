// Fixed-size estimators of Witczak et al.: the paper's bias estimator (eqs 5 + 8) and the bias-augmented
// observer.
#pragma once

#include <Eigen/Dense>

namespace windfdi::sensor_bias {

/// Witczak et al. eqs 5 and 8 on x+ = A x + B u, y = C x + f:
///   f_k = y_k - C A x_{k-1} - C B u_{k-1}              (eq 5)
///   x_{k+1} = A x_k + B u_k + K (y_k - C x_k - f_k)     (eq 8)
/// Errata 001: y cancels in eq 8, so x is an open-loop simulation and f is "measurement minus prediction".
template <int N, int M, int R>
class PaperEstimator {
 public:
  using X = Eigen::Matrix<double, N, 1>;
  using Y = Eigen::Matrix<double, M, 1>;
  using U = Eigen::Matrix<double, R, 1>;
  Eigen::Matrix<double, N, N> A;
  Eigen::Matrix<double, N, R> B;
  Eigen::Matrix<double, M, N> C;
  Eigen::Matrix<double, N, M> K;

  void reset(const X& x0) {
    x_ = x0;
    x_prev_ = x0;
    u_prev_.setZero();
    have_prev_ = false;
    f_.setZero();
  }
  /// One sample: returns the bias estimate f_k (zero until a previous sample exists).
  const Y& step(const Y& y, const U& u) {
    if (have_prev_) {
      f_ = y - C * (A * x_prev_ + B * u_prev_);  // eq 5
    } else {
      f_ = y - C * x_;  // first sample: no prediction yet
    }
    const X next = A * x_ + B * u + K * (y - C * x_ - f_);  // eq 8
    x_prev_ = x_;
    u_prev_ = u;
    x_ = next;
    have_prev_ = true;
    return f_;
  }
  const X& state() const { return x_; }  ///< x_{k+1} after step k
  const Y& bias() const { return f_; }

 private:
  X x_ = X::Zero(), x_prev_ = X::Zero();
  U u_prev_ = U::Zero();
  Y f_ = Y::Zero();
  bool have_prev_ = false;
};

/// The default: x+ = A x + B u + K (y - C x) on the state augmented with the sensor biases (gain from the
/// QB LMI of the augmented system). `state()` before step() is the prediction x_{k|k-1}.
/// Per sample it evaluates x+ = (A - K C) x + B u + K y with A - K C formed once in prepare() (call it after
/// setting A, B, C, K): one N x N, one N x R and one N x M product, no temporaries on the heap.
template <int N, int M, int R>
class AugmentedObserver {
 public:
  using X = Eigen::Matrix<double, N, 1>;
  using Y = Eigen::Matrix<double, M, 1>;
  using U = Eigen::Matrix<double, R, 1>;
  Eigen::Matrix<double, N, N> A;
  Eigen::Matrix<double, N, R> B;
  Eigen::Matrix<double, M, N> C;
  Eigen::Matrix<double, N, M> K;

  /// Forms A - K C and (B K) side by side; must follow any change of A, B, C or K.
  void prepare() {
    F_ = A - K * C;
    G_.template leftCols<R>() = B;
    G_.template rightCols<M>() = K;
    prepared_ = true;
  }
  void reset(const X& x0) { x_ = x0; }
  /// One sample; x+ = (A - K C) x + [B K] [u; y].
  void step(const Y& y, const U& u) {
    if (!prepared_) prepare();
    Eigen::Matrix<double, R + M, 1> v;
    v.template head<R>() = u;
    v.template tail<M>() = y;
    x_ = F_ * x_ + G_ * v;
  }
  /// One sample with output `skip` missing (its innovation counts as zero: the model predicts it). Equivalent
  /// to step() with y(skip) replaced by the prediction C x.
  void step_without(Y y, const U& u, int skip) {
    y(skip) = C.row(skip).dot(x_);
    step(y, u);
  }
  const X& state() const { return x_; }
  X& state() { return x_; }

 private:
  X x_ = X::Zero();
  Eigen::Matrix<double, N, N> F_ = Eigen::Matrix<double, N, N>::Zero();
  Eigen::Matrix<double, N, R + M> G_ = Eigen::Matrix<double, N, R + M>::Zero();
  bool prepared_ = false;
};

}  // namespace windfdi::sensor_bias
