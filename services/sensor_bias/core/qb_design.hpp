// Quadratic-boundedness gain design (Witczak et al. Theorem 1, eq 19, and the observer form of Alessandri et
// al. 2006) solved with CSDP for a fixed alpha, with a search over alpha in (0, 1); K = P^-1 U (eq 30).
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

namespace windfdi::sensor_bias {

/// Which estimator the LMI certifies.
enum class QbStructure {
  kPaper,     ///< eqs 5 + 8: e+ = (A - KC) e + KCA e- + W1 w + KCW1 w- (eq 12), LMI eq 19 with P, R, U
  kObserver,  ///< x+ = A x + B u + K (y - C x): e+ = (A - KC) e + (W1 - K W2) w, LMI with P, U (Alessandri
              ///< 2006)
};
/// What the solver maximises at a fixed alpha.
enum class QbObjective {
  kMargin,  ///< the largest t with LMI + t I <= 0 (a centred feasibility solve)
  kTrace,  ///< tr(P) (+ tr(R)): the smallest invariant set (the paper's Figs 1-2 measure), with LMI <= -t_min
           ///< I
  kFeasibility,  ///< a point with LMI <= -t_max/2 I and no objective (the interior-point solver's choice)
};

/// x+ = A x + B u + W1 w, y = C x + f + W2 w, w' Qw w <= 1 (eqs 1-3).
struct QbProblem {
  Eigen::MatrixXd A, B, C, W1, W2, Qw;
  QbStructure structure = QbStructure::kObserver;
  QbObjective objective = QbObjective::kTrace;
  Eigen::VectorXd state_scale;  ///< the solver works on x / scale (conditioning); empty: ones
};

struct QbSolution {
  bool feasible = false;
  std::string message;  ///< why not, when not feasible; solver notes otherwise
  double alpha = 0.0;
  Eigen::MatrixXd P, R, U, K;  ///< R is empty for the observer structure
  double margin = 0.0;         ///< t of the margin solve (> 0: strictly feasible), in scaled coordinates
  double trace = 0.0;          ///< tr(P) (+ tr(R) for the paper structure) in state_scale units
  double lmi_max_eigenvalue =
      0.0;  ///< independent check: largest eigenvalue of the LMI in original coordinates
  double closed_loop_radius = 0.0;  ///< spectral radius of the error dynamics with K
  Eigen::VectorXd state_bound;  ///< sqrt(diag(P^-1)): the largest |e_i| on the invariant set {e' P e <= 1}
  Eigen::VectorXd
      bias_bound;  ///< bound on each output's bias-estimation error (paper: eq 11; observer: bias states)
  int csdp_status = -1;
  int solves = 0;  ///< SDPs solved (alpha search)
  double seconds = 0.0;
};

/// Checks dimensions, finiteness and Qw > 0; returns "" when well posed, else what is wrong.
std::string check_problem(const QbProblem& q);

/// The LMI matrix of the structure at (alpha, P, R, U), original coordinates (eq 19 or the observer form).
Eigen::MatrixXd qb_lmi(const QbProblem& q, double alpha, const Eigen::MatrixXd& P, const Eigen::MatrixXd& R,
                       const Eigen::MatrixXd& U);

/// For the paper structure every eigenvalue of A is an eigenvalue of the error dynamics (eq 12) whatever K
/// (docs/papers.md, Witczak et al.), so QB needs alpha < 1 - rho(A)^2. Returns that bound (1 for the observer
/// structure).
double qb_alpha_upper_bound(const QbProblem& q);

/// Solves the LMI for a fixed alpha (CSDP, stdout suppressed).
QbSolution qb_solve(const QbProblem& q, double alpha);

/// Certifies a given gain: solves the LMI for P (and R) with U = P K fixed (e.g. the paper's printed K_p,
/// K_dt).
QbSolution qb_certify(const QbProblem& q, double alpha, const Eigen::MatrixXd& K);

struct AlphaSearch {
  double min = 1e-6;  ///< search bounds within (0, 1)
  double max = 0.999;
  int grid = 24;    ///< log-spaced grid points
  int refine = 12;  ///< golden-section steps around the best grid point
  /// Only alphas whose largest bias bound is within this factor of the grid's smallest take part (0: all).
  /// The trace can peak twice over alpha, and its far peak can be a fast observer whose bias bound, the
  /// quantity the service relies on, is twenty times the near peak's.
  double bias_bound_ratio = 2.0;
};
/// Searches alpha (log grid, then golden section) for the largest objective (trace or margin) among the
/// alphas `bias_bound_ratio` admits.
QbSolution qb_design(const QbProblem& q, const AlphaSearch& s = {});

}  // namespace windfdi::sensor_bias
