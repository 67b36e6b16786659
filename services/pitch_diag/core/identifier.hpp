// Per-blade identification kernel of Wu & Li: MIFG (eqs 16-19), RLS with forgetting, their
// auxiliary-model (output-error) forms and a likelihood bank along the Table 1 fault paths; eq 20 gate.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "pitch_model.hpp"

namespace windfdi::pitch_diag {

/// Identification method. Paper modes regress on the measured output (equation error, eqs 9-10); the
/// auxiliary-model modes regress on the model's own simulated output driven by the reference (output error),
/// which stays unbiased with pitch noise (docs/papers.md, Wu & Li).
enum class Method {
  kPaperMifg,  ///< eqs 16-19 on phi = [-y(t-1), -y(t-2), u(t-1), u(t-2)]
  kPaperRls,   ///< recursive least squares with forgetting on the same regressor
  kAmMifg,     ///< eqs 16-19 with y(t-i) in phi replaced by the auxiliary model output x(t-i)
  kAmRls,      ///< RLS with forgetting on the auxiliary-model regressor (pseudo-linear: needs 1/A SPR)
  kOeRls,      ///< output-error recursive prediction error in eta = (omega_n, zeta), unit DC gain:
               ///< Gauss-Newton RLS on the AM regressor filtered by 1/A(q), mapped by d theta / d eta
  kBank,       ///< residual variance of models along the Table 1 fault paths (grid in alpha, refined)
};

/// Canonical method names used in the configuration: paper_mifg, paper_rls, am_mifg, am_rls, oe_rls, bank.
const char* method_name(Method m);
/// Parses a method name; returns false for an unknown one.
bool parse_method(const std::string& name, Method& out);

struct IdentifierConfig {
  Method method = Method::kBank;  ///< see Method; bank measured best (README.md)
  double T = 0.01;                ///< s, sampling period (100 Hz)
  double lambda = 0.97;           ///< MIFG forgetting factor of eq 17 (paper: 0.97), (0, 1)
  int p = 8;                      ///< MIFG innovation length of eqs 18-19 (paper: 8), 1..64
  double r0 = 1.0;                ///< MIFG r(0) of eq 17, > 0
  double rls_lambda = 0.998;      ///< RLS forgetting factor (memory T / (1 - lambda) = 5 s), (0, 1)
  double p0 = 1e-3;             ///< initial covariance: RLS p0 I (theta), oe_rls p0 diag(omega_n0^2, zeta0^2)
  double highpass_hz = 0.02;    ///< Hz, level removal on u and y alike (first-order high-pass); 0: raw
  double restart_settle = 1.0;  ///< s after a (re)start in which filters settle and nothing is identified
  double level_window = 5.0;    ///< s after the first sample over which the pitch's level relative to the
                                ///< reference is fitted before anything is identified (0: the first sample's
                                ///< tracking error is taken as level, and decays through the high-pass)
  double omega_n0 = 11.11;      ///< rad/s, initial model (the healthy actuator)
  double zeta0 = 0.6;           ///< initial damping ratio
  double pe_window = 2.0;       ///< s, window of the eq 20 test: the estimator memory (bank: 2 s)
  double pe_omega = 3.0;        ///< rad/s, scale of the difference basis of the eq 20 regressor
  double pe_threshold = 0.02;   ///< deg^2, alpha of eq 20: smallest eigenvalue required; 0: always excited
  double bank_lambda = 0.995;   ///< bank residual forgetting factor (memory 2 s)
  int bank_steps = 10;          ///< bank models per fault path (alpha = 1/n .. 1)
  bool bank_pe_gate = true;     ///< bank: eq 20 gates the residuals (false: every settled sample counts and
                                ///< only evidence_min decides; the estimate then drifts while unexcited)
  double evidence_min = 25.0;  ///< bank: log-likelihood ratio (V_healthy - V_best) / sigma^2 a fault decision
                               ///< needs (25: 5 sigma against the healthy actuator); 0 disables
  double information_min =
      0.0002;  ///< bank: deg^2, windowed mean square difference between the healthy
               ///< model's output and the nearest fault signature's (both driven by the
               ///< reference) above which the bank learns even when eq 20 fails: a slow
               ///< swing tells the models apart though it excites no 4-parameter fit. 0: off
  double information_ref = 0.03;  ///< bank: deg^2; while eq 20 fails, the residual memory is bank_lambda's
                                  ///< times information_ref / that difference (the same information, not the
                                  ///< same seconds, is remembered). 0: memory in seconds only
  double evidence_max = 10.0;     ///< bank: while the memory is stretched (above), the most evidence for the
                               ///< healthy actuator against any model that is kept, in sigma^2 (a fault must
                               ///< undo it before its own evidence counts). 0: unbounded
  bool information_evidence = true;  ///< bank: a fault decision may also rest on residuals remembered in
                                     ///< information whether or not eq 20 holds (decisive_by_information; the
                                     ///< best model is the 2 s bank's): a slow swing with a little fast
                                     ///< content passes eq 20 now and then, and its 2 s memory forgot the lag
                                     ///< of high air content as fast as it came. false: as before stop 48
  double decide_alpha = 0.25;  ///< bank: best models from this alpha are fault decisions (the classifier's
                               ///< alpha_detect; set by the loader)
  std::vector<Signature> signatures = table1_signatures();  ///< bank paths ([0] healthy)
};

/// One blade: valid samples in, theta out. No clock: one call per sample of period T.
class Identifier {
 public:
  explicit Identifier(const IdentifierConfig& config);

  /// One valid sample: reference u(t) and measured pitch y(t) (deg). `judged` false: a sample made up across
  /// a short hole of lost samples (PitchDiagnoser's bridge): the filters, lags and models move on through it,
  /// but nothing is learned or judged from it (no estimate, evidence or excitation).
  void update(double u, double y, bool judged = true);
  /// The history is broken (lost or rejected samples): restart the regressor history from the next sample
  /// (the level-removal filters continue across the break), keep theta.
  void restart();
  /// Back to the initial model as well.
  void reset();
  /// Back to the initial model and no evidence, the level-removal filters continuing (a hold: what was
  /// learned before or around a suspect input says nothing about the actuator after it).
  void forget();

  /// The pitch rate limit the actuator works under (deg/s; the arbiter's derate). The bank's models saturate
  /// at it as the valve does, so a healthy derated actuator still fits the healthy model. Infinite: none.
  void set_rate_limit(double deg_per_s) { rate_step_ = deg_per_s * cfg_.T; }

  /// Current estimate (for the bank: the refined best model, computed on demand).
  Theta theta() const;
  ContinuousModel model() const { return continuous_from_theta(theta(), cfg_.T); }
  /// Eq 20 held over the last window (the estimate is being updated), or for the bank its information test;
  /// false: held.
  bool excited() const { return excited_ || info_excited_; }
  /// Bank: the share (0..1) of information_ref the last window carried (1 when information_ref is 0): the
  /// residual memory is bank_lambda's divided by it.
  double information_weight() const { return info_weight_; }
  /// Bank: the windowed mean square output difference between the healthy model and the nearest signature
  /// (deg^2; 0 unless information_min or information_ref is set).
  double information() const { return info_mean_; }
  /// A decision may be taken on the current estimate: eq 20 held (paper and RLS modes; the bank when
  /// bank_pe_gate), settled, and for a bank fault decision (best alpha >= decide_alpha) evidence() >=
  /// evidence_min.
  bool decisive() const;
  /// Bank: not decisive() but a fault decision on the residuals remembered in information
  /// (information_evidence, while the window carried less than information_ref).
  bool decisive_by_information() const;
  /// Bank: (V_healthy - V_best) / sigma^2, sigma^2 = V_best / W the best model's mean square residual: the
  /// log-likelihood ratio of the best model against the healthy actuator. Other methods: 0.
  double evidence() const;
  /// Bank: evidence() on the residuals remembered in information (information_evidence), for the 2 s bank's
  /// best model; 0 when off.
  double information_evidence() const;
  /// Bank: (V_signature - V_best) / sigma^2, the evidence against the signature (alpha 1) of fault path
  /// `path` (0-based, signatures[path + 1]) in favour of the best model. Other methods: infinite.
  double evidence_against_signature(int path) const;
  /// Smallest eigenvalue of the eq 20 matrix (deg^2); computed on demand.
  double excitation() const;
  const IdentifierConfig& config() const { return cfg_; }
  /// Samples identified since construction.
  uint64_t updates() const { return updates_; }

 private:
  void identify(double uf, double yf);
  void bank_step(double yf, bool settled);
  /// Bank: (V_model - V_best) / sigma^2, sigma^2 = V_best / W; 0 before any residual.
  double evidence_against(Eigen::Index model) const;
  // Bank: settled, updated and (with bank_pe_gate) excited: a decision may be taken at all.
  bool bank_ready() const;
  // Bank: the 2 s memory's best model is a fault decision (a fault path at decide_alpha or more).
  bool best_is_fault() const;

  IdentifierConfig cfg_;
  Theta theta0_;
  double c_hp_;       // high-pass pole exp(-2 pi f_c T)
  double lambda_pe_;  // eq 20 window as exponential forgetting
  int settle_samples_;
  // Filters and regressor history (after level removal).
  bool started_ = false;
  double rate_step_ = std::numeric_limits<double>::infinity();  // deg per sample the bank's models may move
  bool reseat_ = true;  // the next sample restarts the regressor history (level filters continue)
  double u_raw1_ = 0.0, y_raw1_ = 0.0, uf_ = 0.0, yf_ = 0.0;
  double u1_ = 0.0, u2_ = 0.0, u3_ = 0.0, u4_ = 0.0;  // u_f(t-1..t-4)
  double y1_ = 0.0, y2_ = 0.0;                        // y_f(t-1), y_f(t-2)
  double x1_ = 0.0, x2_ = 0.0;                        // auxiliary model output x(t-1), x(t-2)
  Eigen::Vector4d psi1_, psi2_;                       // output-error gradient psi(t-1), psi(t-2)
  Eigen::Vector2d eta_;                               // oe_rls: (omega_n, zeta)
  Eigen::Matrix2d P2_;                                // oe_rls covariance
  Eigen::Matrix<double, 4, 2> J_;                     // d theta / d eta at eta_ (refreshed at 10 Hz)
  int oe_count_ = 0;
  void oe_refresh();
  int since_restart_ = 0;
  // The level fit of the first level_window (see start_level_fit()): the healthy model run on the raw
  // reference, and sums of its residual r against its rate d.
  void start_level_fit(double u);
  void level_fit_step(double u, double y, bool judged);
  int level_samples_ = 0;         // level_window in samples; 0: no fit
  bool level_pending_ = false;    // the fit is still running: nothing is identified
  bool level_refit_ = false;      // a restart during the fit: it starts again at the next sample
  int level_seen_ = 0;            // samples since the fit (re)started
  double level_decay_ = 1.0;      // c_hp^n, n samples since the first: what is left of a level error then
  double level_start_gap_ = 0.0;  // y - u at the first sample: the level difference the filters started with
  double lu1_ = 0.0, lu2_ = 0.0, lx1_ = 0.0, lx2_ = 0.0;  // raw u(t-1), u(t-2); healthy model x(t-1), x(t-2)
  double ln_ = 0.0, lr_ = 0.0, ld_ = 0.0, ldd_ = 0.0, lrd_ = 0.0;  // sums of 1, r, d, d^2, r d
  // Estimators.
  Theta theta_;
  Theta theta_sim_;                   // last stable estimate: drives the auxiliary model
  Eigen::Matrix4d P_;                 // RLS covariance
  double r_;                          // MIFG eq 17
  std::vector<Eigen::Vector4d> Phi_;  // eq 18 as a ring of the last p regressors
  std::vector<double> Y_;             // eq 19 likewise
  int ring_head_ = 0, ring_fill_ = 0;
  // Eq 20 in a difference basis of the input: R = mean of psi psi^T over the window.
  Eigen::Matrix4d R_pe_ = Eigen::Matrix4d::Zero();
  double pe_scale_;  // 1 / (pe_omega T)
  int pe_count_ = 0;
  bool excited_ = false;
  uint64_t updates_ = 0;
  // Bank: structure of arrays (vectorised over the models).
  Eigen::ArrayXd ba1_, ba2_, bb1_, bb2_, bx1_, bx2_, bV_;
  Eigen::ArrayXd bx_next_, bsquared_;  // bank_step's work arrays, kept to allocate nothing per sample
  double bW_ = 0.0;                    // sum of the forgetting weights of bV_ (its sample count)
  Eigen::ArrayXd bVi_;                 // bV_ remembered in information always (information_evidence)
  double bWi_ = 0.0;                   // its weights' sum
  double info_mean_ = 0.0;      // windowed mean square healthy-to-nearest-signature output difference (deg^2)
  bool info_excited_ = false;   // info_mean_ >= information_min (bank)
  double info_weight_ = 1.0;    // see information_weight()
  std::vector<int> bends_;      // index of each path's signature model (alpha = 1)
  std::vector<int> bpath_;      // path index of each model (-1 healthy)
  std::vector<double> balpha_;  // alpha of each model
};

}  // namespace windfdi::pitch_diag
