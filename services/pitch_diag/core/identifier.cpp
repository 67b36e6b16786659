// Wu & Li: MIFG (eqs 16-19), RLS with forgetting, auxiliary-model forms, path bank, eq 20 gate.
#include "identifier.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace windfdi::pitch_diag {

namespace {
constexpr int kPeCheckEvery = 10;  // samples between the eq 20 tests (10 Hz at 100 Hz): a 4x4 Cholesky each

// One sample's squared residuals into a bank's forgetting sums V (per model) and W (their weight); while
// `bounded`, the evidence for the healthy model (0) against any model is capped at evidence_max sigma^2.
void remember(Eigen::ArrayXd& V, double& W, const Eigen::ArrayXd& squared, double lambda, double evidence_max,
              bool bounded) {
  V = lambda * V + squared;
  W = lambda * W + 1.0;
  if (evidence_max > 0.0 && bounded) V = V.min(V(0) + evidence_max * std::max(V.minCoeff() / W, 1e-12));
}

// (V(model) - V(best)) / sigma^2, sigma^2 = V(best) / W: the log-likelihood ratio of `best` against `model`.
double log_likelihood_ratio(const Eigen::ArrayXd& V, double W, Eigen::Index model, Eigen::Index best) {
  const double vb = V(best);
  return (V(model) - vb) / std::max(vb / W, 1e-12);
}
}  // namespace

const char* method_name(Method m) {
  switch (m) {
    case Method::kPaperMifg:
      return "paper_mifg";
    case Method::kPaperRls:
      return "paper_rls";
    case Method::kAmMifg:
      return "am_mifg";
    case Method::kAmRls:
      return "am_rls";
    case Method::kOeRls:
      return "oe_rls";
    case Method::kBank:
      return "bank";
  }
  return "?";
}

bool parse_method(const std::string& name, Method& out) {
  for (Method m : {Method::kPaperMifg, Method::kPaperRls, Method::kAmMifg, Method::kAmRls, Method::kOeRls,
                   Method::kBank})
    if (name == method_name(m)) {
      out = m;
      return true;
    }
  return false;
}

Identifier::Identifier(const IdentifierConfig& config) : cfg_(config) {
  theta0_ = theta_from_continuous(cfg_.omega_n0, cfg_.zeta0, cfg_.T);
  c_hp_ = cfg_.highpass_hz > 0.0 ? std::exp(-2.0 * M_PI * cfg_.highpass_hz * cfg_.T) : 0.0;
  lambda_pe_ = 1.0 - cfg_.T / std::max(cfg_.pe_window, cfg_.T);
  settle_samples_ = std::max(3, static_cast<int>(std::lround(cfg_.restart_settle / cfg_.T)));
  if (cfg_.highpass_hz > 0.0 && cfg_.level_window > 0.0)
    level_samples_ = settle_samples_ + static_cast<int>(std::lround(cfg_.level_window / cfg_.T));
  pe_scale_ = 1.0 / (cfg_.pe_omega * cfg_.T);
  Phi_.assign(std::max(1, cfg_.p), Eigen::Vector4d::Zero());
  Y_.assign(std::max(1, cfg_.p), 0.0);
  if (cfg_.method == Method::kBank) {
    // Healthy model first, then bank_steps models along each path h + alpha (f - h) (eqs 11-13).
    const auto& sig = cfg_.signatures;
    const int n = std::max(1, cfg_.bank_steps);
    const int paths = static_cast<int>(sig.size()) - 1;
    const int models = 1 + paths * n;
    ba1_.resize(models);
    ba2_.resize(models);
    bb1_.resize(models);
    bb2_.resize(models);
    bpath_.assign(models, -1);
    balpha_.assign(models, 0.0);
    for (int k = 0; k < paths; ++k) bends_.push_back((k + 1) * n);
    for (int m = 0; m < models; ++m) {
      double wn = sig[0].omega_n, z = sig[0].zeta, alpha = 0.0;
      if (m > 0) {
        const int k = (m - 1) / n;
        alpha = static_cast<double>((m - 1) % n + 1) / n;
        bpath_[m] = k;
        balpha_[m] = alpha;
        wn = (1.0 - alpha) * sig[0].omega_n + alpha * sig[k + 1].omega_n;
        z = (1.0 - alpha) * sig[0].zeta + alpha * sig[k + 1].zeta;
      }
      const Theta th = theta_from_continuous(wn, z, cfg_.T);
      ba1_(m) = th(0);
      ba2_(m) = th(1);
      bb1_(m) = th(2);
      bb2_(m) = th(3);
    }
  }
  reset();
}

void Identifier::reset() {
  forget();
  started_ = false;  // level removal starts again from the next sample
}

void Identifier::forget() {
  theta_ = theta0_;
  theta_sim_ = theta0_;
  eta_ = Eigen::Vector2d(cfg_.omega_n0, cfg_.zeta0);
  P2_ = Eigen::Vector2d(cfg_.p0 * cfg_.omega_n0 * cfg_.omega_n0, cfg_.p0 * cfg_.zeta0 * cfg_.zeta0)
            .asDiagonal();
  oe_refresh();
  P_ = cfg_.p0 * Eigen::Matrix4d::Identity();
  r_ = cfg_.r0;
  R_pe_.setZero();
  excited_ = cfg_.pe_threshold <= 0.0;
  pe_count_ = 0;
  info_weight_ = 1.0;  // (info_mean_ and info_excited_: restart() below)
  if (cfg_.method == Method::kBank) {
    bV_ = Eigen::ArrayXd::Zero(ba1_.size());
    bVi_ = Eigen::ArrayXd::Zero(ba1_.size());
    bx1_ = Eigen::ArrayXd::Zero(ba1_.size());
    bx2_ = Eigen::ArrayXd::Zero(ba1_.size());
  }
  bW_ = 0.0;
  bWi_ = 0.0;
  restart();
}

void Identifier::start_level_fit(double u) {
  level_refit_ = false;
  level_seen_ = 0;
  lu1_ = lu2_ = lx1_ = lx2_ = u;
  ln_ = lr_ = ld_ = ldd_ = lrd_ = 0.0;
}

void Identifier::level_fit_step(double u, double y, bool judged) {
  // The high-pass starts at the first sample with u_f = y_f = 0: it takes that sample's tracking error as a
  // level difference, and each residual then carries it as an offset decaying with the filter (8 s at 0.02
  // Hz). At a swinging reference a healthy blade starts up to a degree off it (the plant: 0.8 deg at 12 m/s),
  // and the bank read that slow offset as a slow actuator (a leak raised on a healthy blade 51-56 s after a
  // start). The true level difference is a constant pitch offset o; the rest of y - u is the actuator's lag.
  // So the healthy model runs on the raw reference, and its residual r = y - x is fitted over the window as
  // o + b dx/dt: b takes up what another actuator's lag adds (a leak lags 0.4 s more), o is the level.
  if (level_refit_) start_level_fit(u);  // lost samples broke the model's history: the window starts again
  const Theta& th = theta0_;
  const double x = -th(0) * lx1_ - th(1) * lx2_ + th(2) * lu1_ + th(3) * lu2_;
  const double d = (x - lx1_) / cfg_.T;
  lx2_ = lx1_;
  lx1_ = x;
  lu2_ = lu1_;
  lu1_ = u;
  // The model starts at rest at the reference; its own transient is over within restart_settle.
  if (judged && ++level_seen_ > settle_samples_) {
    const double r = y - x;
    ln_ += 1.0;
    lr_ += r;
    ld_ += d;
    ldd_ += d * d;
    lrd_ += r * d;
  }
  if (level_seen_ < level_samples_) return;
  level_pending_ = false;
  if (ln_ < 10.0) return;  // nothing judged in the window: the first sample's level stands
  const double mean_r = lr_ / ln_, mean_d = ld_ / ln_;
  const double var_d = ldd_ / ln_ - mean_d * mean_d;
  // A reference that stands still (var_d ~ 0) has no lag to fit: the mean residual is the level.
  const double b = var_d > 1e-6 ? (lrd_ / ln_ - mean_r * mean_d) / var_d : 0.0;
  const double offset = mean_r - b * mean_d;
  // y_f as if the filters had started with the level difference `offset` instead of the first sample's y - u:
  // the start's error, decayed by the filter since, leaves y_f (LTI: it adds as level_decay_ times it).
  yf_ += (level_start_gap_ - offset) * level_decay_;
  restart();  // the models start afresh on the corrected levels
}

void Identifier::restart() {
  // The level-removal filters keep their state: the next sample continues them as if the lost stretch had
  // been one step, so u_f and y_f keep the same levels. Restarting them at the new sample instead put the
  // tracking error and that sample's pitch noise into y_f as a step that the 0.02 Hz high-pass takes 8 s to
  // forget: an offset common to every residual, which biased the bank for seconds after each gap.
  reseat_ = true;
  since_restart_ = 0;
  level_refit_ = level_pending_;
  // Held until eq 20 holds again on data after the restart: the old excitation says nothing about now.
  excited_ = cfg_.pe_threshold <= 0.0;  // without the eq 20 gate every sample counts as exciting
  info_excited_ = false;
  info_mean_ = 0.0;
  R_pe_.setZero();
  pe_count_ = 0;
  ring_head_ = 0;
  ring_fill_ = 0;
  psi1_.setZero();
  psi2_.setZero();
}

void Identifier::update(double u, double y, bool judged) {
  level_decay_ *= c_hp_;  // a level error of the first sample's y_f, filtered since (1 at that sample)
  if (!started_) {
    // Level removal starts from the current operating point: u_f = y_f = 0 and the models at rest.
    started_ = true;
    u_raw1_ = u;
    y_raw1_ = y;
    uf_ = yf_ = 0.0;
    level_decay_ = 1.0;
    level_start_gap_ = y - u;
    level_pending_ = level_samples_ > 0;
    if (level_pending_) start_level_fit(u);
  }
  double uf = u, yf = y;
  if (c_hp_ > 0.0) {
    // The same first-order high-pass on u and y: the model between them is unchanged (LTI filters commute),
    // while the 2-20 deg operating level and any constant pitch-sensor offset are removed.
    uf = c_hp_ * (uf_ + u - u_raw1_);
    yf = c_hp_ * (yf_ + y - y_raw1_);
  }
  u_raw1_ = u;
  y_raw1_ = y;
  uf_ = uf;
  yf_ = yf;
  if (level_pending_) {
    level_fit_step(u, y, judged);
    yf = yf_;
  }
  if (reseat_) {
    // After a (re)start the history is this sample: regressor lags, the auxiliary model and every bank model
    // at rest at the current reference. The actuator's own state differs (tracking lag, rate, noise); that
    // transient decays with its dynamics within restart_settle, in which nothing is identified.
    reseat_ = false;
    u1_ = u2_ = u3_ = u4_ = uf;
    y1_ = y2_ = yf;
    x1_ = x2_ = uf;
    if (cfg_.method == Method::kBank) {
      bx1_.setConstant(uf);
      bx2_.setConstant(uf);
    }
  }

  if (judged && since_restart_ >= 4 && cfg_.pe_threshold > 0.0) {
    // Eq 20 on psi = M phi_u, a non-singular difference basis of the input lags u(t-1..t-4): the same PE
    // condition, but well conditioned at 100 Hz where the raw lags are nearly equal.
    const double s = pe_scale_;
    Eigen::Vector4d psi(u1_, (u1_ - u2_) * s, (u1_ - 2.0 * u2_ + u3_) * s * s,
                        (u1_ - 3.0 * u2_ + 3.0 * u3_ - u4_) * s * s * s);
    R_pe_ *= lambda_pe_;
    R_pe_.selfadjointView<Eigen::Lower>().rankUpdate(psi, 1.0 - lambda_pe_);
    if (++pe_count_ >= kPeCheckEvery) {
      pe_count_ = 0;
      // lambda_min(R) >= alpha  <=>  R - alpha I is positive definite.
      Eigen::Matrix4d A = R_pe_;
      A.diagonal().array() -= cfg_.pe_threshold;
      Eigen::LLT<Eigen::Matrix4d, Eigen::Lower> llt(A);
      excited_ = llt.info() == Eigen::Success;
    }
  }

  const bool settled = judged && since_restart_ >= settle_samples_ && !level_pending_;
  const bool learn = excited_ && settled;
  if (cfg_.method == Method::kBank) {
    bank_step(yf, settled);
  } else {
    const bool oe = cfg_.method == Method::kOeRls;
    const bool am = oe || cfg_.method == Method::kAmMifg || cfg_.method == Method::kAmRls;
    // Eq 10 regressor with the errata's b2 u(t-2) term; the AM forms use the model output x for y.
    const Eigen::Vector4d phi(am ? -x1_ : -y1_, am ? -x2_ : -y2_, u1_, u2_);
    if (oe) {
      // Recursive prediction error for the output-error model (Ljung): prediction x(t) = phi_a^T theta(eta),
      // gradient -de/dtheta = phi_a / A(q), i.e. psi(t) = phi_a(t) - a1 psi(t-1) - a2 psi(t-2). The 1/A
      // filter is what the pseudo-linear AM form lacks (it needs 1/A(q) SPR, false for poles this close to z
      // = 1); two physical parameters instead of four keep it well conditioned at 0.2 deg noise.
      const Eigen::Vector4d psi = phi - theta_sim_(0) * psi1_ - theta_sim_(1) * psi2_;
      psi2_ = psi1_;
      psi1_ = psi;
      const double e = yf - phi.dot(theta_sim_);
      if (learn) {
        const Eigen::Vector2d g = J_.transpose() * psi;
        const Eigen::Vector2d Pg = P2_ * g;
        const Eigen::Vector2d K = Pg / (cfg_.rls_lambda + g.dot(Pg));
        eta_ += K * e;
        P2_ = (P2_ - K * Pg.transpose()) / cfg_.rls_lambda;
        // Physical bounds: a wild step in a transient must not leave the model family.
        eta_(0) = std::clamp(eta_(0), 0.3, 60.0);
        eta_(1) = std::clamp(eta_(1), 0.05, 3.0);
        ++updates_;
        if (++oe_count_ >= kPeCheckEvery) {
          oe_count_ = 0;
          oe_refresh();
        }
      }
    } else if (learn) {
      if (cfg_.method == Method::kPaperMifg || cfg_.method == Method::kAmMifg) {
        // Eqs 18-19: the last p regressors and outputs; eq 17: r(t) = lambda r(t-1) + |phi(t)|^2.
        const int p = static_cast<int>(Phi_.size());
        Phi_[ring_head_] = phi;
        Y_[ring_head_] = yf;
        ring_head_ = (ring_head_ + 1) % p;
        ring_fill_ = std::min(ring_fill_ + 1, p);
        r_ = cfg_.lambda * r_ + phi.squaredNorm();
        // Eq 16: theta(t) = theta(t-1) + Phi(t) / r(t) [Y(t) - Phi^T(t) theta(t-1)].
        Eigen::Vector4d g = Eigen::Vector4d::Zero();
        for (int i = 0; i < ring_fill_; ++i) g += Phi_[i] * (Y_[i] - Phi_[i].dot(theta_));
        theta_ += g / r_;
      } else {
        // RLS with forgetting: K = P phi / (lambda + phi^T P phi), P = (P - K phi^T P) / lambda.
        const Eigen::Vector4d Pphi = P_ * phi;
        const double denom = cfg_.rls_lambda + phi.dot(Pphi);
        const Eigen::Vector4d K = Pphi / denom;
        theta_ += K * (yf - phi.dot(theta_));
        P_ = (P_ - K * Pphi.transpose()) / cfg_.rls_lambda;
      }
      ++updates_;
      if (is_stable(theta_)) theta_sim_ = theta_;
    }
    if (am) {
      // Auxiliary model x(t) = phi_a^T(t) theta(t), driven by the reference only (never by the noisy y);
      // an unstable estimate would make it diverge, so it runs on the last stable one.
      const double x = phi.dot(theta_sim_);
      x2_ = x1_;
      x1_ = x;
    }
  }
  u4_ = u3_;
  u3_ = u2_;
  u2_ = u1_;
  u1_ = uf;
  y2_ = y1_;
  y1_ = yf;
  ++since_restart_;
}

void Identifier::oe_refresh() {
  // theta(eta) by the exact ZOH map and its Jacobian by central differences (at 10 Hz, not per sample).
  theta_ = theta_from_continuous(eta_(0), eta_(1), cfg_.T);
  theta_sim_ = theta_;
  const double hw = 1e-4 * eta_(0), hz = 1e-4 * eta_(1);
  J_.col(0) = (theta_from_continuous(eta_(0) + hw, eta_(1), cfg_.T) -
               theta_from_continuous(eta_(0) - hw, eta_(1), cfg_.T)) /
              (2.0 * hw);
  J_.col(1) = (theta_from_continuous(eta_(0), eta_(1) + hz, cfg_.T) -
               theta_from_continuous(eta_(0), eta_(1) - hz, cfg_.T)) /
              (2.0 * hz);
}

void Identifier::bank_step(double yf, bool settled) {
  // Every model of the bank simulated from the reference; residual variance with forgetting. Without the eq
  // 20 gate a sample that does not move the pitch adds the same residual to every model, so it changes no
  // decision; it only lets the old evidence fade, which evidence() sees.
  // The next outputs in a member array (swapped in below): a fresh array here, and for the rate limit and the
  // squared residuals, were three heap allocations per sample and blade.
  Eigen::ArrayXd& x = bx_next_;
  x = -ba1_ * bx1_ - ba2_ * bx2_ + bb1_ * u1_ + bb2_ * u2_;
  // The valve saturates at the commanded rate (the plant: the angle moves at the limit). Without it a healthy
  // blade derated to 5 deg/s in turbulence read as hydraulic_leakage and stopped the turbine (multi-fault
  // suite), and a raised fault on a derated blade never saw the healthy model fit again to clear.
  // The limit is on the raw pitch; the bank runs on the level-removed signals, whose step is
  // c (y(t) - y(t-1)) + (c - 1) y_f(t-1) (the 0.02 Hz high-pass: 0.6 deg/s at 5 deg off the level).
  if (std::isfinite(rate_step_)) {
    const double c = c_hp_ > 0.0 ? c_hp_ : 1.0;
    x = x.max(bx1_ + (c - 1.0) * bx1_ - c * rate_step_).min(bx1_ + (c - 1.0) * bx1_ + c * rate_step_);
  }
  // What the reference lets the bank tell apart: the healthy model's output against the nearest fault
  // signature's, both driven by the same reference (noise-free). A slow swing of several degrees separates
  // them by its rate times the difference of their lags (a leak 0.42 s, high air content 0.05 s) although its
  // third differences are too small for eq 20's four-parameter test.
  if (cfg_.information_min > 0.0 || cfg_.information_ref > 0.0) {
    double nearest = std::numeric_limits<double>::infinity();
    for (int e : bends_) nearest = std::min(nearest, (x(0) - x(e)) * (x(0) - x(e)));
    if (!std::isfinite(nearest)) nearest = 0.0;
    info_mean_ = lambda_pe_ * info_mean_ + (1.0 - lambda_pe_) * nearest;
    info_excited_ = settled && cfg_.information_min > 0.0 && info_mean_ >= cfg_.information_min;
    // Under eq 20 (turbulence) the memory stays bank_lambda's: stretched there, it changed the plant's ramp
    // naming, and with the bound below a derated healthy blade read as slow 25 times in 80 minutes (5
    // without).
    info_weight_ =
        excited_ || cfg_.information_ref <= 0.0 ? 1.0 : std::min(1.0, info_mean_ / cfg_.information_ref);
  }
  const bool learn = settled && (excited_ || info_excited_ || !cfg_.bank_pe_gate);
  if (learn) {
    // Forgetting in information, not seconds: a slow-swing window carrying a fifth of information_ref forgets
    // a fifth as fast (bank_lambda's 2 s forgot the evidence for high air content as fast as it came).
    const double lambda = 1.0 - (1.0 - cfg_.bank_lambda) * info_weight_;
    Eigen::ArrayXd& squared = bsquared_;
    squared = (yf - x).square();
    // A memory stretched by a poor window keeps more evidence for the healthy actuator than turbulence's 2 s
    // would; a fault then has to undo it before its own evidence counts. Bounded while the window is poor.
    remember(bV_, bW_, squared, lambda, cfg_.evidence_max, info_weight_ < 1.0);
    if (cfg_.information_evidence && cfg_.information_ref > 0.0) {
      // The same residuals on the information clock whether or not eq 20 holds (a turbulent window carries
      // information_ref or more: there the two memories are the same), bounded alike.
      const double w = std::min(1.0, info_mean_ / cfg_.information_ref);
      remember(bVi_, bWi_, squared, 1.0 - (1.0 - cfg_.bank_lambda) * w, cfg_.evidence_max, w < 1.0);
    }
    ++updates_;
  }
  bx2_.swap(bx1_);
  bx1_.swap(bx_next_);
}

Theta Identifier::theta() const {
  if (cfg_.method != Method::kBank) return theta_;
  if (updates_ == 0) return theta0_;
  // The best model, refined by a parabola through its neighbours on the same path (the healthy model is the
  // alpha = 0 neighbour of every path).
  Eigen::Index best;
  bV_.minCoeff(&best);
  const int n = std::max(1, cfg_.bank_steps);
  const auto& sig = cfg_.signatures;
  int path = bpath_[best];
  int lo = -1, hi = -1;
  if (path < 0) {
    // Healthy: refine toward the path whose first model fits best.
    int bp = 0;
    for (int k = 1; k < static_cast<int>(sig.size()) - 1; ++k)
      if (bV_(1 + k * n) < bV_(1 + bp * n)) bp = k;
    path = bp;
    hi = 1 + bp * n;
  } else {
    const int j = (static_cast<int>(best) - 1) % n;  // 0-based step on the path
    lo = j == 0 ? 0 : static_cast<int>(best) - 1;
    hi = j == n - 1 ? -1 : static_cast<int>(best) + 1;
  }
  const double h = 1.0 / n;
  double alpha = balpha_[best];
  if (hi >= 0) {
    const double vm = lo >= 0 ? bV_(lo) : bV_(hi);  // mirror at alpha = 0: a parabola symmetric about 0
    const double v0 = bV_(best), vp = bV_(hi);
    const double curv = vp - 2.0 * v0 + vm;
    if (curv > 0.0) alpha += std::clamp(0.5 * h * (vm - vp) / curv, -h, h);
  }
  alpha = std::clamp(alpha, 0.0, 1.0);
  const double wn = (1.0 - alpha) * sig[0].omega_n + alpha * sig[path + 1].omega_n;
  const double z = (1.0 - alpha) * sig[0].zeta + alpha * sig[path + 1].zeta;
  return theta_from_continuous(wn, z, cfg_.T);
}

bool Identifier::bank_ready() const {
  return updates_ > 0 && !(cfg_.bank_pe_gate && !excited()) && since_restart_ >= settle_samples_;
}

bool Identifier::best_is_fault() const {
  Eigen::Index best;
  bV_.minCoeff(&best);
  return bpath_[best] >= 0 && balpha_[best] >= cfg_.decide_alpha - 1e-9;
}

bool Identifier::decisive() const {
  if (updates_ == 0) return false;
  if (cfg_.method != Method::kBank) return excited_;
  if (!bank_ready()) return false;
  if (cfg_.evidence_min <= 0.0) return true;
  // A fault decision needs the data to reject the healthy actuator; "none" needs no more than eq 20.
  return !best_is_fault() || evidence() >= cfg_.evidence_min;
}

bool Identifier::decisive_by_information() const {
  if (cfg_.method != Method::kBank || !cfg_.information_evidence || cfg_.evidence_min <= 0.0) return false;
  if (!bank_ready()) return false;
  // Where the window carried information_ref or more the two memories are the same.
  if (!(cfg_.information_ref > 0.0 && info_mean_ < cfg_.information_ref)) return false;
  return best_is_fault() && information_evidence() >= cfg_.evidence_min;
}

double Identifier::information_evidence() const {
  if (cfg_.method != Method::kBank || bWi_ <= 0.0) return 0.0;
  Eigen::Index best;
  bV_.minCoeff(&best);
  return log_likelihood_ratio(bVi_, bWi_, 0, best);
}

double Identifier::evidence() const {
  if (cfg_.method != Method::kBank) return 0.0;
  // Log-likelihood ratio of the best model against the healthy one for Gaussian residuals of the best
  // model's variance: (V_healthy - V_best) / sigma^2 (0 when the healthy model is the best).
  return evidence_against(0);
}

double Identifier::evidence_against_signature(int path) const {
  if (cfg_.method != Method::kBank || path < 0 || path >= static_cast<int>(bends_.size()))
    return std::numeric_limits<double>::infinity();
  return evidence_against(bends_[path]);
}

double Identifier::evidence_against(Eigen::Index model) const {
  if (bW_ <= 0.0) return 0.0;
  Eigen::Index best;
  bV_.minCoeff(&best);
  return log_likelihood_ratio(bV_, bW_, model, best);
}

double Identifier::excitation() const {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> es(R_pe_.selfadjointView<Eigen::Lower>().toDenseMatrix(),
                                                    Eigen::EigenvaluesOnly);
  return es.eigenvalues()(0);
}

}  // namespace windfdi::pitch_diag
