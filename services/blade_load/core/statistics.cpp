// Student-t distribution and healthy statistics for the blade-load tests (Stotsky 2014, outlier and drift
// t-tests).
#include "statistics.hpp"

#include <algorithm>
#include <cmath>

namespace windfdi::blade_load {

namespace {
// Continued fraction of the incomplete beta function (modified Lentz).
double beta_cf(double a, double b, double x) {
  const double tiny = 1e-300;
  double c = 1.0, d = 1.0 - (a + b) * x / (a + 1.0);
  d = std::fabs(d) < tiny ? tiny : d;
  d = 1.0 / d;
  double h = d;
  for (int m = 1; m <= 300; ++m) {
    const double m2 = 2.0 * m;
    double aa = m * (b - m) * x / ((a + m2 - 1.0) * (a + m2));
    d = 1.0 + aa * d;
    d = std::fabs(d) < tiny ? tiny : d;
    c = 1.0 + aa / c;
    c = std::fabs(c) < tiny ? tiny : c;
    d = 1.0 / d;
    h *= d * c;
    aa = -(a + m) * (a + b + m) * x / ((a + m2) * (a + m2 + 1.0));
    d = 1.0 + aa * d;
    d = std::fabs(d) < tiny ? tiny : d;
    c = 1.0 + aa / c;
    c = std::fabs(c) < tiny ? tiny : c;
    d = 1.0 / d;
    const double del = d * c;
    h *= del;
    if (std::fabs(del - 1.0) < 1e-15) break;
  }
  return h;
}

double incomplete_beta(double a, double b, double x) {
  if (x <= 0.0) return 0.0;
  if (x >= 1.0) return 1.0;
  const double lbt =
      std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x);
  if (x < (a + 1.0) / (a + b + 2.0)) return std::exp(lbt) * beta_cf(a, b, x) / a;
  return 1.0 - std::exp(lbt) * beta_cf(b, a, 1.0 - x) / b;
}
}  // namespace

double student_t_cdf(double t, double nu) {
  const double tail = 0.5 * incomplete_beta(0.5 * nu, 0.5, nu / (nu + t * t));
  return t >= 0 ? 1.0 - tail : tail;
}

double student_t_critical(double alpha, double nu) {
  // Bisection on the upper tail: P(T > q) = alpha / 2.
  double lo = 0.0, hi = 1e4;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    const double upper = 0.5 * incomplete_beta(0.5 * nu, 0.5, nu / (nu + mid * mid));
    (upper > 0.5 * alpha ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double HealthyStats::sd() const { return std::sqrt(std::max(var, 1e-300)); }

double HealthyStats::n_eff(double m) const { return std::max(1.0, m * (1.0 - rho) / (1.0 + rho)); }

double HealthyStats::outlier_sd() const { return sd() * std::sqrt(1.0 + 1.0 / std::max(n, 1)); }

double HealthyStats::outlier_t(double x) const { return (x - mean) / outlier_sd(); }

double HealthyStats::drift_sd(int m) const { return sd() * std::sqrt(1.0 / n_eff(m) + 1.0 / n_eff(n)); }

double HealthyStats::drift_t(double window_mean, int m) const { return (window_mean - mean) / drift_sd(m); }

HealthyStats HealthyLearner::freeze() const {
  HealthyStats s;
  const int n = size();
  if (n < 3) return s;
  auto median = [](std::vector<double> v) {
    const std::size_t m = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + m, v.end());
    const double hi = v[m];
    if (v.size() % 2) return hi;
    return 0.5 * (hi + *std::max_element(v.begin(), v.begin() + m));
  };
  const double med = median(values_);
  std::vector<double> dev(values_.size());
  for (std::size_t i = 0; i < dev.size(); ++i) dev[i] = std::fabs(values_[i] - med);
  double sd = 1.4826 * median(dev);
  if (!(sd > 0)) {  // more than half the values equal: fall back to the classical estimate
    double var = 0.0;
    for (double v : values_) var += (v - med) * (v - med);
    sd = std::sqrt(var / (n - 1));
  }
  double var = 0.0, cov = 0.0;
  const double lim = 3.0 * sd;
  for (int i = 0; i < n; ++i) {
    const double d = std::clamp(values_[i] - med, -lim, lim);
    var += d * d;
    if (i > 0) cov += d * std::clamp(values_[i - 1] - med, -lim, lim);
  }
  s.n = n;
  s.mean = med;
  s.var = sd * sd;
  s.rho = var > 0 ? std::clamp(cov / var, 0.0, 0.95) : 0.0;
  s.learned = true;
  return s;
}

}  // namespace windfdi::blade_load
