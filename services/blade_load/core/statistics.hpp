// Student-t quantiles and the healthy distribution of a monitored residual (Stotsky 2014, "Monitoring ...
// outlier detection"): the point t-test for outliers and the moving-window mean test for drift.
#pragma once

#include <deque>
#include <vector>

namespace windfdi::blade_load {

/// P(T <= t) for Student's t with nu degrees of freedom (regularised incomplete beta).
double student_t_cdf(double t, double nu);
/// Two-sided critical value: P(|T| > q) = alpha.
double student_t_critical(double alpha, double nu);

/// The healthy distribution of one residual, learned from one value per revolution (non-overlapping windows),
/// with its lag-1 autocorrelation so the drift test uses an effective sample size.
struct HealthyStats {
  int n = 0;  ///< values learned
  double mean = 0.0;
  double var = 0.0;
  double rho = 0.0;  ///< lag-1 autocorrelation of the per-revolution values, clipped to [0, 0.95]
  bool learned = false;

  double sd() const;
  /// Effective sample size of m consecutive values: m (1 - rho) / (1 + rho).
  double n_eff(double m) const;
  /// The paper's two-sample t-test of one value against the healthy mean: (x - mean) / outlier_sd().
  double outlier_t(double x) const;
  double outlier_sd() const;  ///< sd sqrt(1 + 1/n)
  /// Moving-window mean test: (mean_w - mean) / drift_sd(m).
  double drift_t(double window_mean, int m) const;
  double drift_sd(int m) const;  ///< sd sqrt(1/n_eff(m) + 1/n_eff(n))
};

/// Learns HealthyStats from a series, then freezes (or adapts slowly, only when the caller says it is
/// healthy).
class HealthyLearner {
 public:
  void add(double x) { values_.push_back(x); }
  /// Freezes the statistics from the values seen (needs at least 3): robust, the median and 1.4826 * MAD (the
  /// residuals are heavy-tailed in turbulence), the lag-1 autocorrelation from the values clipped at 3 sd.
  HealthyStats freeze() const;
  int size() const { return static_cast<int>(values_.size()); }
  void clear() { values_.clear(); }

 private:
  std::vector<double> values_;
};

}  // namespace windfdi::blade_load
