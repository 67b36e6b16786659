// Sliding-window harmonic least squares (Stotsky 2014 eqs 3-8) with the SDD / partitioned (Appendix) solves.
#include "harmonic_ls.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace windfdi::blade_load {

namespace {
constexpr double kTwoPi = 2.0 * M_PI;
constexpr int kMaxSweeps = 60;
}  // namespace

bool is_sdd(const Matrix& G) {
  for (int i = 0; i < G.rows(); ++i) {
    double off = 0.0;
    for (int j = 0; j < G.cols(); ++j)
      if (j != i) off += std::fabs(G(i, j));
    if (!(G(i, i) > off)) return false;
  }
  return true;
}

Partition partition(const Matrix& G) {
  Partition p;
  const int n = static_cast<int>(G.rows()), k = n / 2;
  p.A = G.topLeftCorner(k, k);
  p.B = G.topRightCorner(k, n - k);
  p.C = G.bottomRightCorner(n - k, n - k);
  p.g_sdd = is_sdd(G);
  p.a_sdd = is_sdd(p.A);
  Eigen::LLT<Matrix> a(p.A);
  p.a_pd = a.info() == Eigen::Success;
  if (!p.a_pd) return p;
  // Appendix: G > 0 iff A > 0 and C - B^T A^-1 B > 0 (Horn & Johnson 7.7.6).
  p.S = p.C - p.B.transpose() * a.solve(p.B);
  p.s_sdd = is_sdd(p.S);
  p.s_pd = Eigen::LLT<Matrix>(p.S).info() == Eigen::Success;
  return p;
}

double cosine_sum(double h_omega, int N) {
  // Eq A2.
  return std::cos(0.5 * (N + 1) * h_omega) * std::sin(0.5 * N * h_omega) / std::sin(0.5 * h_omega);
}

Matrix paper_information_matrix(double omega, int N, int d) {
  Matrix G = Matrix::Zero(d, d);
  for (int k = 1; k <= N; ++k)
    for (int i = 0; i < d; ++i)
      for (int j = 0; j < d; ++j) G(i, j) += std::cos((i + 1) * omega * k) * std::cos((j + 1) * omega * k);
  return G;
}

HarmonicEstimator::HarmonicEstimator(const HarmonicConfig& c) : c_(c) {
  if (c.harmonics < 1 || c.harmonics > kMaxHarmonics) throw std::invalid_argument("harmonics must be 1..8");
  if (c.window_samples > c.capacity) c_.capacity = c.window_samples;
  p_ = c.mode == RegressorMode::kAzimuth ? 2 * c.harmonics : c.harmonics;
  phi_buf_.resize(static_cast<std::size_t>(c_.capacity) * p_);
  y_buf_.resize(c_.capacity);
  raw_buf_.resize(c_.capacity);
  dpsi_buf_.resize(c_.capacity);
  reset();
}

void HarmonicEstimator::reset() {
  G_ = Matrix::Zero(p_, p_);
  b_ = Vector::Zero(p_);
  theta_ = Vector::Zero(p_);
  head_ = n_ = 0;
  sum_y_raw_ = sum_dpsi_ = 0.0;
  have_mean_ = have_azimuth_ = false;
  k_ = 0;
  since_reform_ = 0;
  amplitude_ = 0.0;
  info_ = SolveInfo{};
}

void HarmonicEstimator::regressor(double angle, double* phi) const {
  if (c_.mode == RegressorMode::kPaper) {
    // Eq 4: cosines only.
    for (int h = 1; h <= c_.harmonics; ++h) phi[h - 1] = std::cos(h * angle);
    return;
  }
  // cos(h psi), sin(h psi) by the angle-addition recurrence from one sincos.
  const double c1 = std::cos(angle), s1 = std::sin(angle);
  double c = c1, s = s1;
  for (int h = 0; h < c_.harmonics; ++h) {
    phi[2 * h] = c;
    phi[2 * h + 1] = s;
    const double cn = c * c1 - s * s1;
    s = s * c1 + c * s1;
    c = cn;
  }
}

void HarmonicEstimator::update(double y, double azimuth, double rotor_speed) {
  double angle, dpsi;
  if (c_.mode == RegressorMode::kAzimuth) {
    dpsi = have_azimuth_ ? std::remainder(azimuth - last_azimuth_, kTwoPi) : rotor_speed * c_.dt;
    dpsi = std::max(0.0, dpsi);
    last_azimuth_ = azimuth;
    have_azimuth_ = true;
    angle = azimuth;
  } else {
    // Eq 3: phase = w_k k with w_k the discretised speed (rad/sample) and k the step number.
    ++k_;
    dpsi = rotor_speed * c_.dt;
    angle = dpsi * static_cast<double>(k_);
  }
  last_angle_ = angle;
  // Mean removal by a first-order low-pass (section "Processing of ... sensor signal").
  double yd = y;
  if (c_.mean_time > 0.0) {
    const double a = c_.dt / (c_.mean_time + c_.dt);
    mean_ = have_mean_ ? mean_ + a * (y - mean_) : y;
    have_mean_ = true;
    yd = y - mean_;
  }
  if (n_ == c_.capacity) {
    // The rotor is too slow for the window to cover its revolutions: drop anyway (solve() refuses).
    const int old = (head_ - n_ + c_.capacity) % c_.capacity;
    const double* po = &phi_buf_[static_cast<std::size_t>(old) * p_];
    for (int i = 0; i < p_; ++i) {
      for (int j = i; j < p_; ++j) G_(i, j) -= po[i] * po[j];
      b_(i) -= po[i] * y_buf_[old];
    }
    sum_y_raw_ -= raw_buf_[old];
    sum_dpsi_ -= dpsi_buf_[old];
    --n_;
  }
  double* phi = &phi_buf_[static_cast<std::size_t>(head_) * p_];
  regressor(angle, phi);
  y_buf_[head_] = yd;
  raw_buf_[head_] = y;
  dpsi_buf_[head_] = dpsi;
  head_ = (head_ + 1) % c_.capacity;
  ++n_;
  // Recursive update of the information matrix (upper triangle) and of sum phi y (eq 7): add the newest ...
  for (int i = 0; i < p_; ++i) {
    for (int j = i; j < p_; ++j) G_(i, j) += phi[i] * phi[j];
    b_(i) += phi[i] * yd;
  }
  sum_y_raw_ += y;
  sum_dpsi_ += dpsi;
  // ... and drop the oldest while the window stays long enough.
  const double span = kTwoPi * c_.revolutions;
  while (n_ > 1) {
    const int old = (head_ - n_ + c_.capacity) % c_.capacity;
    const bool drop = c_.window_samples > 0 ? n_ > c_.window_samples : sum_dpsi_ - dpsi_buf_[old] >= span;
    if (!drop) break;
    const double* po = &phi_buf_[static_cast<std::size_t>(old) * p_];
    for (int i = 0; i < p_; ++i) {
      for (int j = i; j < p_; ++j) G_(i, j) -= po[i] * po[j];
      b_(i) -= po[i] * y_buf_[old];
    }
    sum_y_raw_ -= raw_buf_[old];
    sum_dpsi_ -= dpsi_buf_[old];
    --n_;
  }
  if (++since_reform_ >= c_.reform_every) reform();
}

void HarmonicEstimator::reform() {
  // Add/drop accumulates rounding error: re-form G and b from the window.
  since_reform_ = 0;
  G_.setZero();
  b_.setZero();
  sum_y_raw_ = sum_dpsi_ = 0.0;
  for (int m = 0; m < n_; ++m) {
    const int idx = (head_ - n_ + m + c_.capacity) % c_.capacity;
    const double* po = &phi_buf_[static_cast<std::size_t>(idx) * p_];
    for (int i = 0; i < p_; ++i) {
      for (int j = i; j < p_; ++j) G_(i, j) += po[i] * po[j];
      b_(i) += po[i] * y_buf_[idx];
    }
    sum_y_raw_ += raw_buf_[idx];
    sum_dpsi_ += dpsi_buf_[idx];
  }
}

bool HarmonicEstimator::window_full() const {
  if (n_ < p_) return false;
  if (c_.window_samples > 0) return n_ == c_.window_samples;
  // Errata 000: the window must cover the revolutions (shorter is singular with cosine and sine).
  return n_ < c_.capacity && sum_dpsi_ >= kTwoPi * c_.revolutions * (1.0 - 1e-9);
}

const SolveInfo& HarmonicEstimator::solve() {
  info_ = SolveInfo{};
  if (!window_full()) {
    info_.reason = "window";
    return info_;
  }
  for (int i = 0; i < p_; ++i)
    for (int j = 0; j < i; ++j) G_(i, j) = G_(j, i);
  // SDD: G is positive definite (Gershgorin) with lambda_min >= min_i (g_ii - r_i) and lambda_max <=
  // max_i (g_ii + r_i); Gauss-Seidel converges, warm-started from the last window's theta (a few sweeps).
  double lo = 1e300, hi = 0.0;
  bool sdd = true;
  for (int i = 0; i < p_; ++i) {
    double r = 0.0;
    for (int j = 0; j < p_; ++j)
      if (j != i) r += std::fabs(G_(i, j));
    sdd = sdd && G_(i, i) > r;
    lo = std::min(lo, G_(i, i) - r);
    hi = std::max(hi, G_(i, i) + r);
  }
  if (sdd && lo / hi >= c_.min_rcond) {
    info_.path = SolvePath::kSdd;
    info_.rcond = lo / hi;
    int sweep = 0;
    for (; sweep < kMaxSweeps; ++sweep) {
      double change = 0.0, size = 0.0;
      for (int i = 0; i < p_; ++i) {
        double s = b_(i);
        for (int j = 0; j < p_; ++j)
          if (j != i) s -= G_(i, j) * theta_(j);
        const double v = s / G_(i, i);
        change = std::max(change, std::fabs(v - theta_(i)));
        size = std::max(size, std::fabs(v));
        theta_(i) = v;
      }
      if (change <= 1e-12 * size || size == 0.0) break;
    }
    info_.sweeps = sweep + 1;
  } else {
    // Not SDD (short window, paper regressor): the Appendix's partitioning decides positive definiteness,
    // and its block factorisation solves.
    info_.path = SolvePath::kPartitioned;
    const int k = p_ / 2;
    const auto A = G_.topLeftCorner(k, k);
    const auto B = G_.topRightCorner(k, p_ - k);
    Eigen::LLT<Matrix> la(A);
    if (la.info() != Eigen::Success) {
      info_.reason = "not positive definite";
      return info_;
    }
    const Matrix S = G_.bottomRightCorner(p_ - k, p_ - k) - B.transpose() * la.solve(B);
    Eigen::LLT<Matrix> ls(S);
    if (ls.info() != Eigen::Success) {
      info_.reason = "not positive definite";
      return info_;
    }
    const Eigen::SelfAdjointEigenSolver<Matrix> es(G_, Eigen::EigenvaluesOnly);
    info_.rcond = es.eigenvalues()(0) / es.eigenvalues()(p_ - 1);
    if (!(info_.rcond >= c_.min_rcond)) {
      info_.reason = "ill-conditioned";
      return info_;
    }
    const Vector b1 = b_.head(k), b2 = b_.tail(p_ - k);
    const Vector t2 = ls.solve(b2 - B.transpose() * la.solve(b1));
    const Vector t1 = la.solve(b1 - B * t2);
    theta_.head(k) = t1;
    theta_.tail(p_ - k) = t2;
  }
  info_.valid = std::isfinite(theta_(0));
  if (!info_.valid) {
    info_.reason = "not finite";
    theta_.setZero();
    return info_;
  }
  // Eq 6: |A_1|; in azimuth mode the amplitude of the cosine-sine pair.
  double a = c_.mode == RegressorMode::kAzimuth ? std::hypot(theta_(0), theta_(1)) : std::fabs(theta_(0));
  if (c_.mean_time > 0.0 && n_ > 0) {
    // y - lowpass(y) passes the rotor frequency with gain w tau / sqrt(1 + (w tau)^2): undo it.
    const double wt = sum_dpsi_ / (n_ * c_.dt) * c_.mean_time;
    if (wt > 1e-6) a *= std::sqrt(1.0 + wt * wt) / wt;
  }
  amplitude_ = a;
  return info_;
}

double HarmonicEstimator::first_harmonic() const {
  // Eq 8.
  if (c_.mode == RegressorMode::kAzimuth)
    return theta_(0) * std::cos(last_angle_) + theta_(1) * std::sin(last_angle_);
  return theta_(0) * std::cos(last_angle_);
}

}  // namespace windfdi::blade_load
