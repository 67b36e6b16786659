// Sliding-window least squares with a harmonic regressor (Stotsky 2014, eqs 3-8 and Appendix).
#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <vector>

namespace windfdi::blade_load {

/// Regressor of eq 4. kPaper: cos(h w_k k), h = 1..d, at the discretised speed w_k (rad/sample) and step
/// number k, phase assumed 0 (the paper's method, kept to reproduce it). kAzimuth (default): cosine AND
/// sine of h times the blade's measured azimuth (docs/papers.md, Stotsky 2014: the phase is unknown in
/// practice).
enum class RegressorMode { kAzimuth, kPaper };

constexpr int kMaxHarmonics = 8;
constexpr int kMaxParams = 2 * kMaxHarmonics;
using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, kMaxParams, kMaxParams>;
using Vector = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kMaxParams, 1>;

struct HarmonicConfig {
  int harmonics = 4;  ///< d, harmonics in the regressor (1..8)
  RegressorMode mode = RegressorMode::kAzimuth;
  double revolutions = 1.0;  ///< window length in revolutions (0.5..8); errata: one tracks best
  int window_samples = 0;    ///< > 0: a fixed window of N samples (checked to cover `revolutions`)
  int capacity = 2600;       ///< samples, longest window held (one revolution at 0.25 rad/s, 100 Hz)
  double mean_time = 10.0;   ///< s, low-pass time constant of the mean removal (0: none)
  double dt = 0.01;          ///< s, sample period
  int reform_every = 2000;   ///< samples between re-forming G and b from the buffer (rounding)
  double min_rcond = 1e-3;   ///< refuse an amplitude when the reciprocal condition is below this
};

/// How a solve went.
enum class SolvePath { kNone, kSdd, kPartitioned };
struct SolveInfo {
  bool valid = false;  ///< an amplitude may be published
  SolvePath path = SolvePath::kNone;
  const char* reason = "";  ///< why not valid ("window", "not positive definite", "ill-conditioned")
  double rcond = 0.0;       ///< reciprocal condition (a Gershgorin lower bound on the SDD path)
  int sweeps = 0;           ///< Gauss-Seidel sweeps on the SDD path
};

/// The Appendix's partitioning G = [A B; B^T C] (A: the first half of the parameters).
struct Partition {
  Matrix A, B, C, S;  ///< S = C - B^T A^-1 B, the Schur complement
  bool g_sdd = false, a_sdd = false, s_sdd = false;
  bool a_pd = false, s_pd = false;  ///< G is positive definite iff both (Horn & Johnson theorem 7.7.6)
};

/// Strict diagonal dominance by rows.
bool is_sdd(const Matrix& G);
/// Partitions G and checks A and the Schur complement for positive definiteness (Appendix).
Partition partition(const Matrix& G);
/// The information matrix sum_{k=1..N} phi_k phi_k^T of regressor A1 (cosines of h w k, h = 1..d).
Matrix paper_information_matrix(double omega, int N, int d);
/// Eq A2: sum_{k=1..N} cos(h w k) in closed form.
double cosine_sum(double h_omega, int N);

/// One signal's first-harmonic amplitude over a sliding window (eq 7), G and b updated recursively (add the
/// newest sample, drop the oldest) and re-formed from the buffer every `reform_every` samples.
class HarmonicEstimator {
 public:
  explicit HarmonicEstimator(const HarmonicConfig& c);

  /// Adds one sample: `y` the signal, `azimuth` the blade's measured azimuth (rad), `rotor_speed` (rad/s).
  void update(double y, double azimuth, double rotor_speed);
  /// Solves eq 7 for the current window (SDD: Gauss-Seidel warm-started; else the Appendix partition).
  const SolveInfo& solve();
  void reset();

  /// |A_1| (eq 6) of the last solve, corrected for the mean-removal filter's gain at the rotor frequency.
  double amplitude() const { return amplitude_; }
  /// The first harmonic now, eq 8 (with the sine term in azimuth mode).
  double first_harmonic() const;
  /// Mean of the raw signal over the window (N m): the blade's mean load over the last revolution.
  double window_mean() const { return n_ > 0 ? sum_y_raw_ / n_ : 0.0; }
  /// Azimuth covered by the window (rad).
  double coverage() const { return sum_dpsi_; }
  int size() const { return n_; }
  int params() const { return p_; }
  /// The information matrix of the window (symmetric copy; the kernel keeps its upper triangle).
  Matrix information_matrix() const { return G_.selfadjointView<Eigen::Upper>(); }
  const Vector& theta() const { return theta_; }
  const SolveInfo& info() const { return info_; }
  const HarmonicConfig& config() const { return c_; }

 private:
  void regressor(double angle, double* phi) const;
  void reform();
  bool window_full() const;

  HarmonicConfig c_;
  int p_;
  // Ring buffer: regressor (p values), detrended signal, raw signal, azimuth increment per sample.
  std::vector<double> phi_buf_, y_buf_, raw_buf_, dpsi_buf_;
  int head_ = 0, n_ = 0;
  Matrix G_;
  Vector b_, theta_;
  double sum_y_raw_ = 0.0, sum_dpsi_ = 0.0;
  double mean_ = 0.0;
  bool have_mean_ = false;
  double last_azimuth_ = 0.0;
  bool have_azimuth_ = false;
  uint64_t k_ = 0;  // step number (paper mode), and samples since the last re-form
  int since_reform_ = 0;
  double last_angle_ = 0.0;
  double amplitude_ = 0.0;
  SolveInfo info_;
};

}  // namespace windfdi::blade_load
