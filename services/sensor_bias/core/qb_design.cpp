// Quadratic-boundedness gain design with CSDP (Witczak et al. Theorem 1, eq 19; observer form of Alessandri
// et al. 2006).
#include "qb_design.hpp"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <mutex>

extern "C" {
#include <csdp/declarations.h>
}

namespace windfdi::sensor_bias {

namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

bool finite(const MatrixXd& m) { return m.allFinite(); }

// Decision variables: P (upper triangle), R (upper triangle, paper only), U (n x m), in that order.
struct Layout {
  int n = 0, m = 0, s = 0, nP = 0, nR = 0, nU = 0;
  bool paper = false;
  const MatrixXd* K = nullptr;  // fixed gain (certification): U = P K is not a decision variable
  int count() const { return nP + nR + nU; }
  int lmi_size() const { return paper ? 3 * n + 2 * s : 2 * n + s; }
};

Layout layout(const QbProblem& q) {
  Layout l;
  l.n = static_cast<int>(q.A.rows());
  l.m = static_cast<int>(q.C.rows());
  l.s = static_cast<int>(q.W1.cols());
  l.paper = q.structure == QbStructure::kPaper;
  l.nP = l.n * (l.n + 1) / 2;
  l.nR = l.paper ? l.nP : 0;
  l.nU = l.n * l.m;
  return l;
}

Layout layout(const QbProblem& q, const MatrixXd* K) {
  Layout l = layout(q);
  if (K) {
    l.K = K;
    l.nU = 0;
  }
  return l;
}

void unpack(const Layout& l, const double* y, MatrixXd& P, MatrixXd& R, MatrixXd& U) {
  P = MatrixXd::Zero(l.n, l.n);
  R = MatrixXd::Zero(l.n, l.n);
  U = MatrixXd::Zero(l.n, l.m);
  int k = 0;
  for (int i = 0; i < l.n; ++i)
    for (int j = i; j < l.n; ++j, ++k) P(i, j) = P(j, i) = y[k];
  if (l.paper)
    for (int i = 0; i < l.n; ++i)
      for (int j = i; j < l.n; ++j, ++k) R(i, j) = R(j, i) = y[k];
  if (l.K) {
    U = P * *l.K;
    return;
  }
  for (int i = 0; i < l.n; ++i)
    for (int j = 0; j < l.m; ++j, ++k) U(i, j) = y[k];
}

// Scaled problem: x = S xs, so A_s = S^-1 A S, C_s = C S, W1_s = S^-1 W1.
QbProblem scaled(const QbProblem& q, VectorXd& scale) {
  scale = q.state_scale.size() == q.A.rows() ? q.state_scale : VectorXd::Ones(q.A.rows());
  QbProblem s = q;
  const auto S = scale.asDiagonal();
  const auto Si = scale.cwiseInverse().asDiagonal();
  s.A = Si * q.A * S;
  s.C = q.C * S;
  s.W1 = Si * q.W1;
  s.state_scale.resize(0);
  return s;
}

// Suppresses CSDP's printing on stdout for the duration of a solve (easy_sdp has no print-level argument).
class QuietStdout {
 public:
  QuietStdout() {
    std::fflush(stdout);
    saved_ = dup(1);
    FILE* null = std::fopen("/dev/null", "w");
    if (null) {
      dup2(fileno(null), 1);
      std::fclose(null);
    }
  }
  ~QuietStdout() {
    std::fflush(stdout);
    if (saved_ >= 0) {
      dup2(saved_, 1);
      close(saved_);
    }
  }

 private:
  int saved_ = -1;
};

std::mutex& csdp_mutex() {
  static std::mutex m;  // CSDP and the stdout redirection are process-global
  return m;
}

// Solves min a'y s.t. -(F0 + sum y_i F_i) - c I >= 0 (CSDP's dual form: Z = sum y_i A_i - C with A_i = -F_i,
// C = F0 + c I). `with_t`: one more variable t with A_t = -I (the margin). Returns the CSDP status.
int csdp_lmi(const std::vector<MatrixXd>& F, const MatrixXd& F0, double c, bool with_t, const VectorXd& a,
             VectorXd& y) {
  const int N = static_cast<int>(F0.rows());
  const int k = static_cast<int>(F.size()) + (with_t ? 1 : 0);
  struct blockmatrix C;
  C.nblocks = 1;
  C.blocks = static_cast<struct blockrec*>(std::malloc(2 * sizeof(struct blockrec)));
  C.blocks[1].blockcategory = MATRIX;
  C.blocks[1].blocksize = N;
  C.blocks[1].data.mat = static_cast<double*>(std::malloc(static_cast<std::size_t>(N * N) * sizeof(double)));
  for (int i = 1; i <= N; ++i)
    for (int j = 1; j <= N; ++j) C.blocks[1].data.mat[ijtok(i, j, N)] = F0(i - 1, j - 1) + (i == j ? c : 0.0);
  double* av = static_cast<double*>(std::malloc(static_cast<std::size_t>(k + 1) * sizeof(double)));
  for (int i = 1; i <= k; ++i) av[i] = a(i - 1);
  auto* constraints = static_cast<struct constraintmatrix*>(
      std::malloc(static_cast<std::size_t>(k + 1) * sizeof(struct constraintmatrix)));
  for (int i = 1; i <= k; ++i) {
    std::vector<std::pair<std::pair<int, int>, double>> entries;
    if (with_t && i == k) {
      for (int d = 1; d <= N; ++d) entries.push_back({{d, d}, -1.0});
    } else {
      const MatrixXd& Fi = F[static_cast<std::size_t>(i - 1)];
      for (int r = 0; r < N; ++r)
        for (int cc = r; cc < N; ++cc)
          if (Fi(r, cc) != 0.0) entries.push_back({{r + 1, cc + 1}, -Fi(r, cc)});
    }
    auto* b = static_cast<struct sparseblock*>(std::malloc(sizeof(struct sparseblock)));
    b->blocknum = 1;
    b->blocksize = N;
    b->constraintnum = i;
    b->next = nullptr;
    b->nextbyblock = nullptr;
    b->issparse = 1;
    const int ne = static_cast<int>(entries.size());
    b->numentries = ne;
    b->entries = static_cast<double*>(std::malloc(static_cast<std::size_t>(ne + 1) * sizeof(double)));
    b->iindices = static_cast<int*>(std::malloc(static_cast<std::size_t>(ne + 1) * sizeof(int)));
    b->jindices = static_cast<int*>(std::malloc(static_cast<std::size_t>(ne + 1) * sizeof(int)));
    for (int e = 0; e < ne; ++e) {
      b->iindices[e + 1] = entries[static_cast<std::size_t>(e)].first.first;
      b->jindices[e + 1] = entries[static_cast<std::size_t>(e)].first.second;
      b->entries[e + 1] = entries[static_cast<std::size_t>(e)].second;
    }
    constraints[i].blocks = b;
  }
  struct blockmatrix X, Z;
  double* yy = nullptr;
  double pobj = 0, dobj = 0;
  int ret;
  {
    std::lock_guard<std::mutex> lock(csdp_mutex());
    QuietStdout quiet;
    initsoln(N, k, C, av, constraints, &X, &yy, &Z);
    ret = easy_sdp(N, k, C, av, constraints, 0.0, &X, &yy, &Z, &pobj, &dobj);
  }
  y.resize(k);
  for (int i = 1; i <= k; ++i) y(i - 1) = yy[i];
  free_prob(N, k, C, av, constraints, X, yy, Z);
  return ret;
}

const char* csdp_status_text(int s) {
  switch (s) {
    case 0:
      return "solved";
    case 1:
      return "primal infeasible (the LMI's objective is unbounded)";
    case 2:
      return "dual infeasible (the LMI has no solution)";
    case 3:
      return "solved to reduced accuracy";
    case 4:
      return "maximum iterations reached";
    case 5:
      return "stuck at the edge of primal feasibility";
    case 6:
      return "stuck at the edge of dual feasibility";
    case 7:
      return "lack of progress";
    case 8:
      return "X, Z or O singular";
    default:
      return "numerical failure (NaN or Inf)";
  }
}

double spectral_radius(const MatrixXd& M) { return M.eigenvalues().cwiseAbs().maxCoeff(); }

}  // namespace

std::string check_problem(const QbProblem& q) {
  const auto n = q.A.rows();
  if (n == 0 || q.A.cols() != n) return "A must be square and non-empty";
  if (q.C.cols() != n || q.C.rows() == 0) return "C must have as many columns as A";
  if (q.W1.rows() != n || q.W1.cols() == 0) return "W1 must have as many rows as A and at least one column";
  if (q.W2.rows() != q.C.rows() || q.W2.cols() != q.W1.cols())
    return "W2 must be (rows of C) x (columns of W1)";
  if (q.Qw.rows() != q.W1.cols() || q.Qw.cols() != q.W1.cols())
    return "Qw must be square with as many rows as W1 has columns";
  if (q.B.size() > 0 && q.B.rows() != n) return "B must have as many rows as A";
  if (!finite(q.A) || !finite(q.C) || !finite(q.W1) || !finite(q.W2) || !finite(q.Qw) || !finite(q.B))
    return "a matrix holds NaN or Inf";
  if ((q.Qw - q.Qw.transpose()).norm() > 1e-9 * (1.0 + q.Qw.norm())) return "Qw must be symmetric";
  Eigen::SelfAdjointEigenSolver<MatrixXd> es(q.Qw);
  if (es.eigenvalues().minCoeff() <= 0.0) return "Qw must be positive definite (eq 3)";
  if (q.state_scale.size() != 0 &&
      (q.state_scale.size() != n || (q.state_scale.array() <= 0.0).any() || !q.state_scale.allFinite()))
    return "state_scale must hold one positive number per state";
  return "";
}

MatrixXd qb_lmi(const QbProblem& q, double alpha, const MatrixXd& P, const MatrixXd& R, const MatrixXd& U) {
  const Eigen::Index n = q.A.rows(), s = q.W1.cols();
  const MatrixXd PAUC = P * q.A - U * q.C;
  if (q.structure == QbStructure::kObserver) {
    // [[-(1-a)P, 0, (PA-UC)'], [0, -a Qw, (PW1-UW2)'], [PA-UC, PW1-UW2, -P]] < 0.
    MatrixXd M = MatrixXd::Zero(2 * n + s, 2 * n + s);
    M.block(0, 0, n, n) = -(1.0 - alpha) * P;
    M.block(n, n, s, s) = -alpha * q.Qw;
    M.block(n + s, 0, n, n) = PAUC;
    M.block(n + s, n, n, s) = P * q.W1 - U * q.W2;
    M.block(n + s, n + s, n, n) = -P;
    M.block(0, n + s, n, n) = PAUC.transpose();
    M.block(n, n + s, s, n) = (P * q.W1 - U * q.W2).transpose();
    return M;
  }
  // Eq 19, blocks [e_k, e_k-1, w_k, w_k-1, Schur].
  MatrixXd M = MatrixXd::Zero(3 * n + 2 * s, 3 * n + 2 * s);
  const Eigen::Index o5 = 2 * n + 2 * s;
  M.block(0, 0, n, n) = R - P + alpha * P;
  M.block(n, n, n, n) = -R + alpha * R;
  M.block(2 * n, 2 * n, s, s) = -alpha * q.Qw;
  M.block(2 * n + s, 2 * n + s, s, s) = -alpha * q.Qw;
  const MatrixXd row[4] = {PAUC, U * q.C * q.A, P * q.W1, U * q.C * q.W1};
  const Eigen::Index off[4] = {0, n, 2 * n, 2 * n + s};
  for (int b = 0; b < 4; ++b) {
    M.block(o5, off[b], n, row[b].cols()) = row[b];
    M.block(off[b], o5, row[b].cols(), n) = row[b].transpose();
  }
  M.block(o5, o5, n, n) = -P;
  return M;
}

namespace {
QbSolution qb_solve_impl(const QbProblem& q, double alpha, const MatrixXd* Kfix);
}

double qb_alpha_upper_bound(const QbProblem& q) {
  if (q.structure != QbStructure::kPaper) return 1.0;
  const double rho = spectral_radius(q.A);
  return std::max(0.0, 1.0 - rho * rho);
}

QbSolution qb_solve(const QbProblem& q, double alpha) { return qb_solve_impl(q, alpha, nullptr); }

QbSolution qb_certify(const QbProblem& q, double alpha, const MatrixXd& K) {
  if (K.rows() != q.A.rows() || K.cols() != q.C.rows()) {
    QbSolution s;
    s.message = "K must be (states) x (outputs)";
    return s;
  }
  return qb_solve_impl(q, alpha, &K);
}

namespace {
QbSolution qb_solve_impl(const QbProblem& q, double alpha, const MatrixXd* Kfix) {
  const auto t0 = std::chrono::steady_clock::now();
  QbSolution sol;
  sol.alpha = alpha;
  sol.message = check_problem(q);
  if (!sol.message.empty()) return sol;
  if (!(alpha > 0.0 && alpha < 1.0)) {
    sol.message = "alpha must lie in (0, 1)";
    return sol;
  }
  VectorXd scale;
  const QbProblem qs = scaled(q, scale);
  // With a fixed K the scaled gain is S^-1 K.
  MatrixXd Ks;
  if (Kfix) Ks = scale.cwiseInverse().asDiagonal() * *Kfix;
  const Layout l = layout(qs, Kfix ? &Ks : nullptr);
  // F0 and the F_i by evaluating the (affine) LMI at zero and at each unit vector of the decision variables.
  std::vector<double> y0(static_cast<std::size_t>(l.count()), 0.0);
  MatrixXd P, R, U;
  unpack(l, y0.data(), P, R, U);
  const MatrixXd F0 = qb_lmi(qs, alpha, P, R, U);
  std::vector<MatrixXd> F;
  for (int i = 0; i < l.count(); ++i) {
    y0[static_cast<std::size_t>(i)] = 1.0;
    unpack(l, y0.data(), P, R, U);
    F.push_back(qb_lmi(qs, alpha, P, R, U) - F0);
    y0[static_cast<std::size_t>(i)] = 0.0;
    if (F.back().cwiseAbs().maxCoeff() == 0.0) {
      sol.message = "ill-posed: decision variable " + std::to_string(i) +
                    " does not enter the LMI (C has a zero column?)";
      return sol;
    }
  }
  // 1) Margin: max t s.t. LMI + t I <= 0.
  VectorXd a = VectorXd::Zero(l.count() + 1), y;
  a(l.count()) = -1.0;
  int status = csdp_lmi(F, F0, 0.0, true, a, y);
  ++sol.solves;
  sol.csdp_status = status;
  sol.margin = status == 0 || status == 3 ? y(l.count()) : -1.0;
  const double scale_ref = std::max(1.0, F0.cwiseAbs().maxCoeff());
  if ((status != 0 && status != 3) || !(sol.margin > 1e-9 * scale_ref)) {
    sol.message = "infeasible at alpha " + std::to_string(alpha) +
                  ": largest margin t = " + std::to_string(sol.margin) +
                  " (CSDP: " + csdp_status_text(status) + ")";
    if (alpha >= qb_alpha_upper_bound(q))
      sol.message += "; eq 12 keeps every eigenvalue of A, so alpha must be < 1 - rho(A)^2 = " +
                     std::to_string(qb_alpha_upper_bound(q));
    return sol;
  }
  VectorXd ybest = y.head(l.count());
  // 2') Feasibility: any point of {LMI <= -t*/2 I} (zero objective: the interior-point solver stops inside).
  if (q.objective == QbObjective::kFeasibility) {
    VectorXd yf;
    status = csdp_lmi(F, F0, 0.5 * sol.margin, false, VectorXd::Zero(l.count()), yf);
    ++sol.solves;
    if (status == 0 || status == 3) ybest = yf;
  }
  // 2) Trace: max tr(P) (+ tr(R)) s.t. LMI <= -t_min I, t_min a small share of the margin (strictness).
  if (q.objective == QbObjective::kTrace) {
    VectorXd at = VectorXd::Zero(l.count());
    // tr(P) in original coordinates: P = S^-1 Ps S^-1, so tr(P) = sum Ps_ii / s_i^2.
    // tr of the scaled P (and R): every state counts in its own unit of state_scale.
    int k = 0;
    for (int i = 0; i < l.n; ++i)
      for (int j = i; j < l.n; ++j, ++k)
        if (i == j) at(k) = -1.0;
    if (l.paper)
      for (int i = 0; i < l.n; ++i)
        for (int j = i; j < l.n; ++j, ++k)
          if (i == j) at(k) = -1.0;
    VectorXd yt;
    status = csdp_lmi(F, F0, 1e-2 * sol.margin, false, at, yt);
    ++sol.solves;
    sol.csdp_status = status;
    if (status == 0 || status == 3)
      ybest = yt;
    else if (status == 1)
      sol.message = "trace unbounded (W1 does not excite every state?); kept the margin solution";
    else
      sol.message = std::string("trace solve: ") + csdp_status_text(status) + "; kept the margin solution";
  }
  unpack(l, ybest.data(), P, R, U);
  // Back to original coordinates: P = S^-1 Ps S^-1, U = S^-1 Us, K = P^-1 U (eq 30).
  const auto Si = scale.cwiseInverse().asDiagonal();
  sol.P = Si * P * Si;
  sol.U = Si * U;
  if (l.paper) sol.R = Si * R * Si;
  sol.K = Kfix ? *Kfix : MatrixXd(sol.P.ldlt().solve(sol.U));
  // Independent check with Eigen on the original matrices.
  const MatrixXd M = qb_lmi(q, alpha, sol.P, l.paper ? sol.R : MatrixXd::Zero(l.n, l.n), sol.U);
  sol.lmi_max_eigenvalue =
      Eigen::SelfAdjointEigenSolver<MatrixXd>(0.5 * (M + M.transpose())).eigenvalues().maxCoeff();
  const MatrixXd Acl = q.A - sol.K * q.C;
  if (l.paper) {
    MatrixXd Mc = MatrixXd::Zero(2 * l.n, 2 * l.n);
    Mc.topLeftCorner(l.n, l.n) = Acl;
    Mc.topRightCorner(l.n, l.n) = sol.K * q.C * q.A;
    Mc.bottomLeftCorner(l.n, l.n).setIdentity();
    sol.closed_loop_radius = spectral_radius(Mc);
  } else {
    sol.closed_loop_radius = spectral_radius(Acl);
  }
  const MatrixXd Pinv = sol.P.inverse();
  sol.state_bound = Pinv.diagonal().cwiseMax(0.0).cwiseSqrt();
  sol.trace = P.trace() + (l.paper ? R.trace() : 0.0);  // scaled coordinates (the objective)
  const Eigen::LLT<MatrixXd> Lq(q.Qw);
  const MatrixXd Qi_half =
      Lq.matrixL().solve(MatrixXd::Identity(l.s, l.s)).transpose();  // Qw^-1/2 up to rotation
  sol.bias_bound.resize(l.m);
  for (int j = 0; j < l.m; ++j) {
    if (l.paper) {
      // Eq 11: e_s = -CA e_k-1 - W2 w_k - C W1 w_k-1, e_k-1 in {e' R e <= 1}.
      const VectorXd c = (q.C * q.A).row(j).transpose();
      sol.bias_bound(j) = std::sqrt(c.dot(sol.R.ldlt().solve(c))) + (q.W2.row(j) * Qi_half).norm() +
                          ((q.C * q.W1).row(j) * Qi_half).norm();
    } else {
      // An output's bias state is a state that only that output sees (unit column of C, unit column of A:
      // nothing else drives it; a bias rate state, when there is one, enters through its own column); an
      // output without one (an unbiased witness) gets the bound of its output error C e.
      VectorXd c = q.C.row(j).transpose();
      for (int i = l.n - 1; i >= 0; --i)
        if (q.C.col(i).isApprox(VectorXd::Unit(l.m, j)) && q.A.col(i).isApprox(VectorXd::Unit(l.n, i))) {
          c = VectorXd::Unit(l.n, i);
          break;
        }
      sol.bias_bound(j) = std::sqrt(c.dot(Pinv * c));
    }
  }
  sol.feasible = sol.lmi_max_eigenvalue < 0.0 && sol.K.allFinite();
  if (!sol.feasible)
    sol.message = "CSDP returned a point whose LMI has eigenvalue " + std::to_string(sol.lmi_max_eigenvalue) +
                  " >= 0 (numerically infeasible)";
  sol.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return sol;
}

}  // namespace

QbSolution qb_design(const QbProblem& q, const AlphaSearch& s) {
  const auto t0 = std::chrono::steady_clock::now();
  QbSolution none;
  none.message = check_problem(q);
  if (!none.message.empty()) return none;
  const double hi = std::min(s.max, qb_alpha_upper_bound(q) * 0.999);
  const double lo = std::min(s.min, hi * 0.5);
  if (!(hi > 0.0) || s.grid < 2) {
    none.message =
        "no alpha in (0, 1) can work: the bound 1 - rho(A)^2 is " + std::to_string(qb_alpha_upper_bound(q));
    return none;
  }
  int solves = 0;
  std::vector<double> grid;
  std::vector<QbSolution> on_grid;
  for (int i = 0; i < s.grid; ++i) {
    grid.push_back(std::exp(std::log(lo) + (std::log(hi) - std::log(lo)) * i / (s.grid - 1)));
    on_grid.push_back(qb_solve(q, grid.back()));
    solves += on_grid.back().solves;
  }
  const auto largest_bias_bound = [](const QbSolution& x) {
    return x.bias_bound.size() ? x.bias_bound.maxCoeff() : 0.0;
  };
  double smallest_bias_bound = 1e300;
  for (const QbSolution& x : on_grid)
    if (x.feasible && x.bias_bound.size())
      smallest_bias_bound = std::min(smallest_bias_bound, largest_bias_bound(x));
  const auto admitted = [&](const QbSolution& x) {
    return s.bias_bound_ratio <= 0.0 || !x.bias_bound.size() ||
           largest_bias_bound(x) <= s.bias_bound_ratio * smallest_bias_bound;
  };
  auto value = [&](const QbSolution& x) {
    return !x.feasible || !admitted(x) ? -1e300 : (q.objective == QbObjective::kTrace ? x.trace : x.margin);
  };
  QbSolution best;
  best.message =
      "infeasible for every alpha tried in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  int best_i = -1;
  for (int i = 0; i < s.grid; ++i) {
    const QbSolution& x = on_grid[static_cast<std::size_t>(i)];
    if (x.feasible && admitted(x) && (best_i < 0 || value(x) > value(best))) {
      best = x;
      best_i = i;
    }
  }
  if (best_i >= 0) {
    // Golden section on log(alpha) between the neighbours of the best grid point.
    double a = std::log(grid[static_cast<std::size_t>(std::max(0, best_i - 1))]);
    double b = std::log(grid[static_cast<std::size_t>(std::min(s.grid - 1, best_i + 1))]);
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    for (int it = 0; it < s.refine; ++it) {
      const double c = b - g * (b - a), d = a + g * (b - a);
      QbSolution xc = qb_solve(q, std::exp(c)), xd = qb_solve(q, std::exp(d));
      solves += xc.solves + xd.solves;
      for (auto* x : {&xc, &xd})
        if (value(*x) > value(best)) best = *x;
      if (value(xc) >= value(xd))
        b = d;
      else
        a = c;
    }
  }
  best.solves = solves;
  best.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return best;
}

}  // namespace windfdi::sensor_bias
