// sensor_bias tests: Witczak et al.'s estimator on its printed model, the QB LMI design, and the default
// observer on the plant.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <random>

#include "bias_estimator.hpp"
#include "design_input.hpp"
#include "input_context.hpp"
#include "lti_models.hpp"
#include "observers.hpp"
#include "qb_design.hpp"
#include "turbine_sim.hpp"

using namespace windfdi;
using namespace windfdi::sensor_bias;

namespace {

const std::string kDeploy = WINDFDI_SOURCE_DEPLOY_DIR;

// ---------------------------------------------------------------- paper mode on the paper's printed model

// Runs eqs 5 + 8 on the printed model with the bias of eq 41/42 and uniform measurement noise of +-noise;
// returns the largest |bias error| after `transient` samples as a share of amplitude * |C x| per output.
template <int N, int M, int R>
Eigen::Matrix<double, M, 1> paper_run(const DiscreteModel& m, const Eigen::MatrixXd& K, double amplitude,
                                      const Eigen::Matrix<double, N, 1>& x0,
                                      const std::function<Eigen::Matrix<double, R, 1>(int)>& input,
                                      double noise, int samples = 20000, int transient = 1000) {
  PaperEstimator<N, M, R> est;
  est.A = m.A;
  est.B = m.B;
  est.C = m.C;
  est.K = K;
  // Initial estimate: the (biased) first measurement for the measured states, zero for the others.
  est.reset(m.C.transpose() * (m.C * x0 * (1.0 + amplitude)));
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-noise, noise);
  Eigen::Matrix<double, N, 1> x = x0;
  Eigen::Matrix<double, M, 1> worst = Eigen::Matrix<double, M, 1>::Zero();
  for (int k = 0; k < samples; ++k) {
    const Eigen::Matrix<double, M, 1> cx = m.C * x;
    const Eigen::Matrix<double, M, 1> f =
        amplitude * (cx * std::sin(k / 500.0) + cx * std::sin(k / 1000.0) + cx);
    Eigen::Matrix<double, M, 1> y = cx + f;
    for (int j = 0; j < M; ++j) y(j) += u(rng);
    const auto uk = input(k);
    const auto fhat = est.step(y, uk);
    if (k >= transient)
      for (int j = 0; j < M; ++j)
        worst(j) = std::max(worst(j), std::fabs(fhat(j) - f(j)) / (amplitude * std::fabs(cx(j))));
    x = m.A * x + m.B * uk;
  }
  return worst;
}

Eigen::Vector3d dt_steady() {
  // Printed eq 35-36 hold omega_g = 100 omega_r and theta = 0 in steady state; omega_g 162 rad/s needs
  // T_g = row 2 balance / B(2,2) (about -7.6 kN m, docs/papers.md, Witczak et al.).
  const DiscreteModel m = paper_drive_train();
  const Eigen::Vector3d x(1.62, 162.0, 0.0);
  return x;
}

double dt_torque() {
  const DiscreteModel m = paper_drive_train();
  const Eigen::Vector3d x = dt_steady();
  return -((m.A.row(1) * x)(0) - x(1)) / m.B(1, 1);
}

TEST(PaperMode, PrintedModelsMeetThePapersBiasErrors) {
  // GIVEN the printed drive train (eqs 35-37) and pitch (eqs 38-40) models and gains (eqs 43-44), the paper's
  // time-varying biases (eqs 41-42), the first (biased) measurement as initial estimate - the drive train's
  // transient decays with rho(A) = 0.999585 (24 s), so errors count after 300 s there, 10 s for pitch - and
  // uniform measurement noise of +-1e-3 (rad/s, deg: the paper does not state its noise; this is the level at
  // which its figures are reachable)
  const double tg = dt_torque();
  const auto dt = paper_run<3, 2, 2>(
      paper_drive_train(), paper_K_drive_train(), 0.02, dt_steady(),
      [&](int) { return Eigen::Vector2d(0.0, tg); }, 1e-3, 60000, 30000);
  const DiscreteModel p = paper_pitch();
  const auto pr = paper_run<2, 1, 1>(
      p, paper_K_pitch(), 0.05, Eigen::Vector2d(10.0, 0.0),
      [](int k) { return Eigen::Matrix<double, 1, 1>(10.0 + 3.0 * std::sin(k / 700.0)); }, 1e-3);
  std::printf("paper mode, printed models: max bias error rotor %.3f %%, generator %.4f %%, pitch %.3f %%\n",
              100 * dt(0), 100 * dt(1), 100 * pr(0));
  // THEN after the transient the errors are within the paper's: < 4 % rotor, ~0.15 % generator, < 3.3 % pitch
  EXPECT_LT(dt(0), 0.04);
  EXPECT_LT(dt(1), 0.0015);
  EXPECT_LT(pr(0), 0.033);
}

TEST(PaperMode, TheGainDoesNotMatterAndBenchmarkNoiseGoesStraightThrough) {
  // GIVEN the printed pitch model with K = K_p and with K = 0 (docs/papers.md, Witczak et al.: y cancels in
  // eq 8)
  const DiscreteModel p = paper_pitch();
  auto in = [](int k) { return Eigen::Matrix<double, 1, 1>(10.0 + 3.0 * std::sin(k / 700.0)); };
  const auto with_k = paper_run<2, 1, 1>(p, paper_K_pitch(), 0.05, Eigen::Vector2d(10.0, 0.0), in, 1e-3);
  const auto no_k =
      paper_run<2, 1, 1>(p, Eigen::MatrixXd::Zero(2, 1), 0.05, Eigen::Vector2d(10.0, 0.0), in, 1e-3);
  // THEN after the transient both give the same bias errors (within 1e-6 of the share)
  EXPECT_NEAR(with_k(0), no_k(0), 1e-6);
  // AND with the benchmark's 0.2 deg pitch noise (uniform +-0.35 deg, same variance) eq 5 passes the noise
  // into the bias estimate unfiltered: the error exceeds 20 % of the bias amplitude
  const auto noisy = paper_run<2, 1, 1>(p, paper_K_pitch(), 0.05, Eigen::Vector2d(10.0, 0.0), in, 0.35);
  std::printf("paper mode, pitch with benchmark noise: max error %.1f %% of the bias amplitude\n",
              100 * noisy(0));
  EXPECT_GT(noisy(0), 0.2);
}

// ---------------------------------------------------------------- LMI design

TEST(QbDesign, PitchReproducesThePrintedGain) {
  // GIVEN the printed pitch model (eqs 38-40), W1 = I, Qw = I, alpha = 0.07
  // (deploy/sensor_bias/paper_pitch.yaml)
  const DesignInput in = load_design_input_file(kDeploy + "/sensor_bias/paper_pitch.yaml");
  const QbSolution s = qb_solve(in.problem, in.alpha);
  ASSERT_TRUE(s.feasible) << s.message;
  const Eigen::MatrixXd Kp = paper_K_pitch();
  std::printf("pitch, alpha 0.07: K = [%.4f, %.4f] (printed [0.5839, -3.8104]), %.4f s\n", s.K(0), s.K(1),
              s.seconds);
  // THEN K is within 15 % of the printed K_p (eq 44) ...
  EXPECT_NEAR(s.K(0), Kp(0), 0.15 * std::fabs(Kp(0)));
  EXPECT_NEAR(s.K(1), Kp(1), 0.15 * std::fabs(Kp(1)));
  // ... and independently of CSDP: the LMI of eq 19 at the returned P, R, U has only negative eigenvalues
  const Eigen::MatrixXd M = qb_lmi(in.problem, in.alpha, s.P, s.R, s.P * s.K);
  EXPECT_LT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(M).eigenvalues().maxCoeff(), 0.0);
  // AND the printed K_p itself is certified at alpha 0.07 (an LMI in P, R with U = P K_p)
  const QbSolution c = qb_certify(in.problem, in.alpha, Kp);
  EXPECT_TRUE(c.feasible) << c.message;
}

TEST(QbDesign, DriveTrainAlphaOfThePaperIsInfeasible) {
  // GIVEN the printed drive train (eqs 35-37) with the paper's alpha_dt = 0.01
  const DesignInput in = load_design_input_file(kDeploy + "/sensor_bias/paper_drive_train.yaml");
  const QbSolution s = qb_solve(in.problem, 0.01);
  // THEN CSDP finds no strictly feasible point ...
  EXPECT_FALSE(s.feasible);
  EXPECT_NE(s.message.find("infeasible"), std::string::npos) << s.message;
  // ... which the eigenvalues confirm independently: eq 12's companion matrix [[A-KC, KCA], [I, 0]] has every
  // eigenvalue of A for any K (here the printed K_dt), so V+ <= (1-alpha) V needs rho(A)^2 < 1 - alpha
  const Eigen::MatrixXd A = in.problem.A, C = in.problem.C, K = paper_K_drive_train();
  Eigen::MatrixXd Mc = Eigen::MatrixXd::Zero(6, 6);
  Mc.topLeftCorner(3, 3) = A - K * C;
  Mc.topRightCorner(3, 3) = K * C * A;
  Mc.bottomLeftCorner(3, 3).setIdentity();
  const double rho_m = Mc.eigenvalues().cwiseAbs().maxCoeff(), rho_a = A.eigenvalues().cwiseAbs().maxCoeff();
  std::printf("drive train: rho(A) = %.6f, rho(companion with K_dt) = %.6f, alpha bound %.3g\n", rho_a, rho_m,
              1 - rho_a * rho_a);
  EXPECT_NEAR(rho_a, 0.999585, 2e-6);
  EXPECT_GE(rho_m, rho_a - 1e-9);
  EXPECT_GT(0.01, 1.0 - rho_a * rho_a);
  // AND the printed K_dt cannot be certified at 0.01 either
  EXPECT_FALSE(qb_certify(in.problem, 0.01, K).feasible);
}

TEST(QbDesign, IllPosedInputGetsAMessageNotAGain) {
  QbProblem q;
  q.A = Eigen::MatrixXd::Identity(2, 2);
  q.C = Eigen::MatrixXd::Identity(1, 2);
  q.W1 = Eigen::MatrixXd::Identity(2, 2);
  q.W2 = Eigen::MatrixXd::Zero(1, 2);
  q.Qw = -Eigen::MatrixXd::Identity(2, 2);  // not positive definite
  QbSolution s = qb_solve(q, 0.1);
  EXPECT_FALSE(s.feasible);
  EXPECT_NE(s.message.find("positive definite"), std::string::npos);
  q.Qw = Eigen::MatrixXd::Identity(2, 2);
  q.C = Eigen::MatrixXd::Zero(1, 2);  // nothing measured: an unstable-free but unobservable integrator pair
  q.A = 1.01 * Eigen::MatrixXd::Identity(2, 2);
  s = qb_design(q);
  EXPECT_FALSE(s.feasible);
  EXPECT_FALSE(s.message.empty());
  EXPECT_THROW(
      load_design_input(YamlSection(YAML::Load("A: [[1, 2]]\nB: [[1]]\nC: [[1, 0]]\nW1: [[1]]"), "x.yaml")),
      ConfigError);
}

TEST(QbDesign, IntegratedRandomWalkBiasModel) {
  // GIVEN the shipped drive-train design (bias_model: integrated_random_walk)
  const DesignInput in = load_design_input_file(kDeploy + "/sensor_bias/design_drive_train_observer.yaml");
  // THEN it has 7 states: the 3 physical ones, the 2 biases at indices 3 and 4 (as in the random-walk form)
  // and their rates, with b+ = b + T r, r+ = r (exactly), and the rates invisible to every output
  ASSERT_EQ(in.problem.A.rows(), 7);
  EXPECT_EQ(in.states[3], "bias_omega_r");
  EXPECT_EQ(in.states[6], "rate_bias_omega_g");
  for (int j = 0; j < 2; ++j) {
    EXPECT_EQ(in.problem.A(3 + j, 5 + j), 0.01);
    EXPECT_EQ(in.problem.A(5 + j, 5 + j), 1.0);
    EXPECT_EQ(in.problem.A.col(3 + j), Eigen::VectorXd::Unit(7, 3 + j));
    EXPECT_EQ(in.problem.C.col(5 + j).norm(), 0.0);
  }
  // AND the solved gain reports the bias-state bound (not the rate's) for each biased output: the gain file's
  // bias_bound equals its state_bound of states 3 and 4
  const GainFile g = load_gain_file(kDeploy + "/sensor_bias/gains_drive_train_observer.yaml");
  ASSERT_EQ(g.bias_bound.size(), 3);
  EXPECT_DOUBLE_EQ(g.bias_bound(0), g.state_bound(3));
  EXPECT_DOUBLE_EQ(g.bias_bound(1), g.state_bound(4));
  // AND a rate bound without the rate model, or the rate model without the biases, is a ConfigError
  const char* base = "name: x\nmodel:\n  turbine_file: %s\n  subsystem: pitch\n  input_bound: [0.05]\n%s";
  const std::string turbine = kDeploy + "/turbine/benchmark_4.8MW.yaml";
  char a[600], b[600];
  std::snprintf(a, sizeof a, base, turbine.c_str(),
                "  augment_biases: true\n  bias_acceleration_bound: [1.0e-3]\n");
  std::snprintf(b, sizeof b, base, turbine.c_str(), "  bias_model: integrated_random_walk\n");
  EXPECT_THROW(load_design_input(YamlSection(YAML::Load(a), "a.yaml")), ConfigError);
  EXPECT_THROW(load_design_input(YamlSection(YAML::Load(b), "b.yaml")), ConfigError);
}

TEST(QbDesign, AnotherTurbinesGainIsDesignedForItFromItsFileAlone) {
  // GIVEN the shipped observer gains (the benchmark turbine's) and the example 2 MW turbine, whose gains were
  // designed by hand from design_drive_train_observer_2MW.yaml (the shipped design's torque bounds and
  // aerodynamic damping scaled to its rated torques)
  const std::string gains = kDeploy + "/sensor_bias/gains_drive_train_observer.yaml",
                    design = kDeploy + "/sensor_bias/design_drive_train_observer.yaml",
                    two_mw = kDeploy + "/turbine/example_2MW.yaml";
  const GainFile bench = load_gain_file(gains),
                 by_hand = load_gain_file(kDeploy + "/sensor_bias/gains_drive_train_observer_2MW.yaml");
  const TurbineParams two = load_turbine_params_file(two_mw);
  // THEN each shipped gain fits its own turbine and not the other (nor the medium-speed one) ...
  EXPECT_TRUE(gain_fits_turbine(bench, TurbineParams{}));
  EXPECT_TRUE(gain_fits_turbine(by_hand, two));
  EXPECT_FALSE(gain_fits_turbine(bench, two));
  EXPECT_FALSE(
      gain_fits_turbine(bench, load_turbine_params_file(kDeploy + "/turbine/example_3MW_medium_speed.yaml")));
  EXPECT_TRUE(gain_fits_turbine(load_gain_file(kDeploy + "/sensor_bias/gains_pitch_observer.yaml"), two));
  // ... the design made for the 2 MW turbine by rule is the hand-made one within 2 % ...
  const DesignInput rule = design_for_turbine(design, two_mw);
  const DesignInput hand =
      load_design_input_file(kDeploy + "/sensor_bias/design_drive_train_observer_2MW.yaml");
  EXPECT_NEAR(rule.aero_damping / hand.aero_damping, 1.0, 0.02);
  EXPECT_NEAR(rule.problem.W1.norm() / hand.problem.W1.norm(), 1.0, 0.02);
  // ... and a gain that does not fit is designed at start: it fits, is certified, and bounds the biases as
  // the hand-made gain does (within 5 %)
  std::string note;
  const GainFile designed = gain_for_turbine(bench, "drive_train_gains", design, two_mw, two, true, note);
  EXPECT_NE(note.find("designed from design_drive_train_observer.yaml"), std::string::npos) << note;
  EXPECT_TRUE(gain_fits_turbine(designed, two));
  EXPECT_LT(designed.lmi_max_eigenvalue, 0.0);
  EXPECT_LT(designed.closed_loop_radius, 1.0);
  ASSERT_EQ(designed.bias_bound.size(), by_hand.bias_bound.size());
  for (Eigen::Index i = 0; i < designed.bias_bound.size(); ++i)
    EXPECT_NEAR(designed.bias_bound(i) / by_hand.bias_bound(i), 1.0, 0.05) << i;
  std::printf("[ measured ] %s\n", note.c_str());
  // AND a gain that fits is kept as it is, and without design_for_turbine a misfit is a ConfigError naming
  // the key
  note.clear();
  EXPECT_EQ(gain_for_turbine(by_hand, "drive_train_gains", design, two_mw, two, true, note).K, by_hand.K);
  EXPECT_TRUE(note.empty());
  try {
    gain_for_turbine(bench, "drive_train_gains", design, two_mw, two, false, note);
    ADD_FAILURE() << "a gain of another turbine was taken";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("drive_train_gains"), std::string::npos) << e.what();
  }
}

TEST(QbDesign, ShippedGainsAreCertifiedAndReproducible) {
  for (const char* name : {"drive_train_observer", "pitch_observer", "pitch_paper"}) {
    // GIVEN the shipped design input and its gain file
    const DesignInput in = load_design_input_file(kDeploy + "/sensor_bias/design_" + name + ".yaml");
    const GainFile g = load_gain_file(kDeploy + "/sensor_bias/gains_" + name + ".yaml");
    // THEN the shipped P, K satisfy the LMI at the shipped alpha (Eigen, independently of CSDP; R from the
    // file)
    const Eigen::MatrixXd R = g.R.size() ? g.R : Eigen::MatrixXd::Zero(g.A.rows(), g.A.rows());
    const Eigen::MatrixXd M = qb_lmi(in.problem, g.alpha, g.P, R, g.P * g.K);
    const double top =
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(0.5 * (M + M.transpose())).eigenvalues().maxCoeff();
    EXPECT_LT(top, 0.0) << name;
    EXPECT_LT(g.closed_loop_radius, 1.0) << name;
    EXPECT_LT((g.A - in.problem.A).norm(), 1e-9 * (1 + in.problem.A.norm())) << name;
  }
}

TEST(QbDesign, ASlowerActuatorsPitchObserverIsDesignedAtTheTracesNearPeakNotItsFarOne) {
  // GIVEN the shipped pitch-observer design made for turbines whose healthy actuator is slower than the
  // benchmark's 11.11 rad/s (a 6 MW rotor's larger blades)
  const std::string design = kDeploy + "/sensor_bias/design_pitch_observer.yaml";
  for (const double omega_n : {6.0, 8.0, 9.0}) {
    const std::string turbine = ::testing::TempDir() + "slow_actuator_" + std::to_string(omega_n) + ".yaml";
    {
      std::ofstream f(turbine);
      f << "pitch_omega_n: " << omega_n << "\npitch_zeta: 0.65\n";
    }
    DesignInput in = design_for_turbine(design, turbine);
    // WHEN alpha is searched as shipped
    const QbSolution sol = qb_design(in.problem, in.search);
    ASSERT_TRUE(sol.feasible) << sol.message;
    // THEN the observer is a slow one like the benchmark's (alpha 0.09, radius 0.91), whose bias bound is a
    // few degrees
    EXPECT_LT(sol.alpha, 0.2) << omega_n;
    EXPECT_GT(sol.closed_loop_radius, 0.8) << omega_n;
    EXPECT_LT(sol.bias_bound.maxCoeff(), 3.5) << omega_n;
    // AND by the trace alone it was the far peak at the search's end: a fast observer whose bias bound is
    // tens of degrees (a 6 MW turbine's pitch biases were missed and its bias estimates jumped by 8 deg)
    in.search.bias_bound_ratio = 0.0;
    const QbSolution by_trace = qb_design(in.problem, in.search);
    EXPECT_GT(by_trace.alpha, 0.4) << omega_n;
    EXPECT_GT(by_trace.bias_bound.maxCoeff(), 10.0) << omega_n;
    std::printf(
        "[ measured ] omega_n %.0f: alpha %.3f, bias bound %.2f deg (trace alone: alpha %.3f, %.1f deg)\n",
        omega_n, sol.alpha, sol.bias_bound.maxCoeff(), by_trace.alpha, by_trace.bias_bound.maxCoeff());
    std::remove(turbine.c_str());
  }
  // AND the benchmark's actuator still gets the shipped gain's alpha
  const DesignInput bench = load_design_input_file(design);
  EXPECT_NEAR(qb_design(bench.problem, bench.search).alpha,
              load_gain_file(kDeploy + "/sensor_bias/gains_pitch_observer.yaml").alpha, 1e-6);
}

// ---------------------------------------------------------------- observability of the augmented pairs

TEST(Observability, AugmentedDriveTrainAndPitch) {
  TurbineParams p;
  Eigen::MatrixXd A, B, C;
  drive_train_continuous(p, 0.0, A, B, C);
  const DiscreteModel dt = augment_with_output_biases(discretise_zoh(A, B, C, 0.01));
  pitch_continuous(p.pitch_omega_n, p.pitch_zeta, A, B, C);
  const DiscreteModel pt = augment_with_output_biases(discretise_zoh(A, B, C, 0.01));
  // The shipped design: the same pair plus the power witness (a third output that sees omega_g, no bias).
  const DesignInput shipped =
      load_design_input_file(kDeploy + "/sensor_bias/design_drive_train_observer.yaml");
  const Observability od = observability(dt.A, dt.C), op = observability(pt.A, pt.C);
  Eigen::MatrixXd Cw(3, 5);
  Cw << dt.C, Eigen::RowVectorXd::Unit(5, 1);
  const Observability ow = observability(dt.A, Cw), os = observability(shipped.problem.A, shipped.problem.C);
  auto print = [](const char* what, const Observability& o) {
    std::printf("PBH sigma_min, %s:", what);
    for (int i = 0; i < o.n; ++i) std::printf(" %.2e", o.pbh_sigma_min(i));
    std::printf("\n");
  };
  print("drive train + 2 biases (speed sensors only)", od);
  print("drive train + 2 biases + power witness", ow);
  print("shipped design (aero damping folded in)", os);
  print("pitch + bias", op);
  // THEN the pitch bias is observable against the reference-driven model (smallest PBH singular value > 1e-3)
  EXPECT_EQ(op.rank, 3);
  EXPECT_GT(op.pbh_sigma_min.minCoeff(), 1e-3);
  // AND with the two speed sensors alone the common mode (both speeds and both biases moving together) is
  // only barely observable: at the bias modes (eigenvalue 1) the PBH matrix is nearly singular (< 1e-3)
  EXPECT_LT(od.pbh_sigma_min.minCoeff(), 1e-3);
  // AND the power witness makes every mode observable by orders of magnitude more (> 1e-3), for the shipped
  // design's pair too (the witness row is what the gain file's C holds)
  EXPECT_EQ(ow.rank, 5);
  EXPECT_GT(ow.pbh_sigma_min.minCoeff(), 1e-3);
  ASSERT_EQ(shipped.problem.C.rows(), 3);
  EXPECT_GT(os.pbh_sigma_min.minCoeff(), 1e-3);
}

// ---------------------------------------------------------------- on the plant

BiasConfig config(Mode mode) {
  const YamlSection y = YamlSection::load_file(kDeploy + "/config/sensor_bias.yaml");
  YAML::Node n = YAML::Clone(y.node());
  n["mode"] = mode == Mode::kPaper ? "paper" : "observer";
  return load_bias_config(YamlSection(n, y.file()), kDeploy + "/sensor_bias");
}

struct PlantRun {
  std::vector<FaultEvent> events;
  std::array<double, kChannels> rms_error{},
      max_error{};                                // of the bias estimate vs the injected bias, after settle
  std::array<double, kChannels> mean_estimate{};  // over the last 60 s
  uint64_t rejected = 0;
  double witness_share = 0.0;  // share of drive-train samples with the power witness in use
  double witness_noise =
      0.0;  // rad/s, rms of the power witness P / (eta_g T_g) minus the true generator speed
  std::array<std::vector<double>, kChannels> error,
      injected;  // per sample after settle: estimate - injected, injected
};

// Noise floor of tracking `b` (one bias series, per sample at T = 0.01 s) from b + n, n white with std
// `sigma`: the smallest rms error of a steady-state Kalman filter on a bias model with the plant known
// exactly, over a log grid of its process noise (i.e. of its bandwidth). rates: integrated random walk (b,
// r), else random walk. No causal linear estimator of that model structure does better on this signal at this
// noise.
double tracking_floor(const std::vector<double>& b, double sigma, bool rates, uint64_t seed = 3) {
  const double T = 0.01, R = sigma * sigma;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> nd(0.0, sigma);
  std::vector<double> z(b.size());
  for (std::size_t k = 0; k < b.size(); ++k) z[k] = b[k] + nd(rng);
  double best = 1e300;
  for (double lq = -20.0; lq <= 0.0; lq += 0.25) {
    const double q = std::pow(10.0, lq) * R;
    // Steady-state gain by iterating the Riccati recursion (F = [[1, T], [0, 1]], H = [1, 0], Q = diag(0,
    // q)).
    Eigen::Matrix2d F, P = Eigen::Matrix2d::Identity() * R, Q = Eigen::Matrix2d::Zero();
    F << 1, rates ? T : 0.0, 0, rates ? 1.0 : 0.0;
    if (rates)
      Q(1, 1) = q;
    else
      Q(0, 0) = q;
    Eigen::Vector2d K;
    for (int it = 0; it < 200000; ++it) {
      const Eigen::Matrix2d Pp = F * P * F.transpose() + Q;
      K = Pp.col(0) / (Pp(0, 0) + R);
      const Eigen::Matrix2d Pn = Pp - K * Pp.row(0);
      if ((Pn - P).cwiseAbs().maxCoeff() <= 1e-12 * Pn.cwiseAbs().maxCoeff()) {
        P = Pn;
        break;
      }
      P = Pn;
    }
    Eigen::Vector2d x(z[0], 0.0);
    double se = 0.0;
    const std::size_t skip = std::min<std::size_t>(b.size() / 4, 3000);
    for (std::size_t k = 0; k < b.size(); ++k) {
      x = F * x;
      x += K * (z[k] - x(0));
      if (k >= skip) se += (x(0) - b[k]) * (x(0) - b[k]);
    }
    best = std::min(best, std::sqrt(se / static_cast<double>(b.size() - skip)));
  }
  return best;
}

// Splits an error series into its slow part (centred 2 s moving average: lag, model error) and the rest
// (noise).
std::pair<double, double> slow_fast_rms(const std::vector<double>& e, int half = 100) {
  const int n = static_cast<int>(e.size());
  if (n <= 2 * half) return {0.0, 0.0};
  double slow = 0.0, fast = 0.0, sum = 0.0;
  for (int k = 0; k < 2 * half + 1; ++k) sum += e[static_cast<std::size_t>(k)];
  int m = 0;
  for (int k = half; k < n - half - 1; ++k, ++m) {
    const double mean = sum / (2 * half + 1);
    slow += mean * mean;
    fast += (e[static_cast<std::size_t>(k)] - mean) * (e[static_cast<std::size_t>(k)] - mean);
    sum += e[static_cast<std::size_t>(k + half + 1)] - e[static_cast<std::size_t>(k - half)];
  }
  return {std::sqrt(slow / m), std::sqrt(fast / m)};
}

PlantRun run_plant(double wind, double seconds, const std::vector<plant::FaultSpec>& faults,
                   Mode mode = Mode::kObserver, uint64_t seed = 7, double ti = 0.1, double settle = 60.0,
                   double type_lag_ratio_max = -1.0, const std::function<void(BiasConfig&)>& adjust = {}) {
  TurbineParams p;
  plant::TurbineScenario t;
  t.id = "WT01";
  t.wind.mean = wind;
  t.wind.turbulence_intensity = ti;
  plant::TurbineSim sim(p, t, faults, seed, 100.0);
  BiasConfig c = config(mode);
  if (type_lag_ratio_max >= 0.0) c.type_lag_ratio_max = type_lag_ratio_max;
  if (adjust) adjust(c);
  BiasEstimator est(c, load_gain_file(c.drive_train_gain_file), load_gain_file(c.pitch_gain_file), p);
  PlantRun r;
  int n = 0, nlast = 0, nw = 0;
  std::array<double, kChannels> filt{};
  const double a = 1.0 - std::exp(-0.01 / c.filter_time);
  const int total = static_cast<int>(seconds * 100);
  for (int k = 0; k < total; ++k) {
    FrameSample s = sim.step();
    s.aero_torque = kNaN;  // the DDS path: aerodynamic torque from the model
    s.aero_power = kNaN;
    const auto& tr = sim.truth();
    est.update(s, false, r.events);
    if (std::isfinite(est.output().witness_speed)) {
      const double e = est.output().witness_speed - sim.truth().generator_speed;
      r.witness_noise += e * e;
      ++nw;
    }
    // The injected bias (the fault definition on the true value), so sensor noise is not counted as error.
    const std::array<double, kChannels> truth = {tr.rotor_speed, tr.generator_speed, tr.pitch[0], tr.pitch[1],
                                                 tr.pitch[2]};
    static const char* kTargets[] = {"rotor_speed", "generator_speed", "pitch_1", "pitch_2", "pitch_3"};
    if (s.t >= settle) {
      for (int j = 0; j < kChannels; ++j) {
        const std::size_t i = static_cast<std::size_t>(j);
        double b = 0.0;
        for (const auto& f : faults)
          if (f.target == kTargets[j] && s.t >= f.start) {
            const double kk = std::floor((s.t - f.start) / 0.01 + 1e-6);
            b += f.type == "bias" ? f.value
                 : f.type == "drift"
                     ? f.rate * (s.t - f.start)
                     : f.amplitude * truth[i] * (std::sin(kk / 500.0) + std::sin(kk / 1000.0) + 1.0);
          }
        const double e = est.output().bias[i] - b;
        r.rms_error[i] += e * e;
        r.error[i].push_back(e);
        r.injected[i].push_back(b);
        // The peak of the detector's view: the estimate after the detector's low-pass (filter_time)
        filt[i] += a * (e - filt[i]);
        r.max_error[i] = std::max(r.max_error[i], std::fabs(filt[i]));
      }
      ++n;
    }
    if (s.t >= seconds - 60.0) {
      for (int j = 0; j < kChannels; ++j)
        r.mean_estimate[static_cast<std::size_t>(j)] += est.output().bias[static_cast<std::size_t>(j)];
      ++nlast;
    }
  }
  for (auto& v : r.rms_error) v = std::sqrt(v / std::max(n, 1));
  for (auto& v : r.mean_estimate) v /= std::max(nlast, 1);
  r.witness_noise = std::sqrt(r.witness_noise / std::max(nw, 1));
  r.rejected = est.rejected();
  r.witness_share = static_cast<double>(est.witness_used()) /
                    static_cast<double>(std::max<uint64_t>(est.fed_drive_train(), 1));
  return r;
}

plant::FaultSpec bias(const std::string& target, double value, double start) {
  auto f = plant::FaultSpec::make("WT01", target, "bias", start).with_value(value);
  return f;
}

struct StepCase {
  const char* target;
  const char* component;
  double value;
  double wind;
  int channel;
};

// A rotor-speed fault is reported when its type is known, at most type_decision_time_rotor_speed (20 s) after
// the threshold is crossed: the rotor's inertia keeps its speed too steady to tell a gain from an offset
// sooner. The other channels: 5 s.
double report_deadline(const std::string& component, double onset) {
  return onset + (component == "rotor_speed_sensor" ? 62.0 : 5.0);
}

/// The first report raised among `events`; none: nullptr.
const FaultEvent* first_raised(const std::vector<FaultEvent>& events) {
  for (const auto& e : events)
    if (e.raised) return &e;
  return nullptr;
}

TEST(ObserverMode, StepBiasOfTwoPercentFlaggedInTimeAsAnOffsetWithItsSize) {
  const StepCase cases[] = {{"rotor_speed", "rotor_speed_sensor", 0.034, 14.0, 0},
                            {"rotor_speed", "rotor_speed_sensor", -0.034, 8.0, 0},
                            {"generator_speed", "generator_speed_sensor", 3.24, 14.0, 1},
                            {"generator_speed", "generator_speed_sensor", -3.24, 20.0, 1},
                            {"pitch_2", "pitch_sensor_2", 1.0, 16.0, 3},
                            {"pitch_1", "pitch_sensor_1", -1.0, 20.0, 2}};
  for (const auto& c : cases) {
    // GIVEN turbulent wind (TI 0.1) and a step bias of 2 % of rated speed (pitch: 1 deg) from t = 150 s
    const PlantRun r = run_plant(c.wind, 300.0, {bias(c.target, c.value, 150.0)}, Mode::kObserver, 24);
    const FaultEvent* first = first_raised(r.events);
    ASSERT_NE(first, nullptr) << c.target << " at " << c.wind << " m/s: nothing raised";
    std::printf(
        "%s %+g at %g m/s: %s raised at %.2f s (delay %.2f s), size %+.4g, mean estimate (last 60 s) %+.4g\n",
        c.target, c.value, c.wind, first->component.c_str(), first->t, first->t - 150.0, first->size,
        r.mean_estimate[static_cast<std::size_t>(c.channel)]);
    // THEN the first event is sensor_bias on the biased sensor, within 5 s (rotor speed: 62 s), sized within
    // 30 %
    EXPECT_EQ(first->component, c.component);
    EXPECT_EQ(first->fault, "sensor_bias") << first->detail;
    EXPECT_GE(first->t, 150.0);
    EXPECT_LE(first->t, report_deadline(c.component, 150.0));
    EXPECT_NEAR(r.mean_estimate[static_cast<std::size_t>(c.channel)], c.value, 0.3 * std::fabs(c.value));
    // AND no other sensor is flagged
    for (const auto& e : r.events) EXPECT_EQ(e.component, c.component) << c.target;
  }
}

// The observer on the plant (TI 0.1) losing the samples `lost(k)` says (k: sample index). Returns the events
// and the estimates after the last sample.
struct HoleRun {
  std::vector<FaultEvent> events;
  BiasOutput last;
};
HoleRun run_with_holes(double wind, double seconds, const std::vector<plant::FaultSpec>& faults,
                       uint64_t seed, const std::function<bool(int)>& lost,
                       double max_bridged_gap = BiasConfig{}.max_bridged_gap) {
  TurbineParams p;
  plant::TurbineScenario t;
  t.id = "WT01";
  t.wind.mean = wind;
  t.wind.turbulence_intensity = 0.1;
  plant::TurbineSim sim(p, t, faults, seed, 100.0);
  BiasConfig c = config(Mode::kObserver);
  c.max_bridged_gap = max_bridged_gap;
  BiasEstimator est(c, load_gain_file(c.drive_train_gain_file), load_gain_file(c.pitch_gain_file), p);
  HoleRun r;
  bool gap = false;
  for (int k = 0; k < static_cast<int>(seconds * 100); ++k) {
    FrameSample s = sim.step();
    if (lost(k)) {
      gap = true;
      continue;
    }
    s.aero_torque = kNaN;
    s.aero_power = kNaN;
    est.update(s, gap, r.events);
    gap = false;
  }
  r.last = est.output();
  return r;
}

// The events of the observer losing 20 samples every 5 s, as a loaded host loses them.
std::vector<FaultEvent> run_with_losses(double wind, double seconds,
                                        const std::vector<plant::FaultSpec>& faults, uint64_t seed,
                                        double max_bridged_gap) {
  return run_with_holes(
             wind, seconds, faults, seed, [](int k) { return k % 500 >= 480; }, max_bridged_gap)
      .events;
}

TEST(ObserverMode, AFaultIsFoundThroughShortHolesOfLostSamples) {
  // GIVEN a 1 deg bias on pitch sensor 2 from 150 s at 16 m/s, 20 samples lost every 5 s
  const auto events = run_with_losses(16.0, 200.0, {bias("pitch_2", 1.0, 150.0)}, 24, 0.5);
  // THEN it is raised within 5 s, and nothing else
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.front().component, "pitch_sensor_2");
  EXPECT_EQ(events.front().fault, "sensor_bias");
  EXPECT_LE(events.front().t, 155.0);
  for (const auto& e : events) EXPECT_EQ(e.component, "pitch_sensor_2") << e.fault << " at " << e.t;
  // ... where re-settling (20 s) on every hole never raised it
  EXPECT_TRUE(run_with_losses(16.0, 200.0, {bias("pitch_2", 1.0, 150.0)}, 24, 0.0).empty());
  // AND half an hour of a healthy turbine with the same losses raises nothing, at 8 and 14 m/s
  for (double wind : {8.0, 14.0}) {
    const auto healthy = run_with_losses(wind, 1800.0, {}, 108, 0.5);
    EXPECT_TRUE(healthy.empty()) << wind << " m/s: " << healthy.front().component << " "
                                 << healthy.front().fault << " at " << healthy.front().t;
  }
}

TEST(ObserverMode, SecondsOfLostSamplesMoveNoPitchBias) {
  // GIVEN a 1 deg bias on pitch sensor 2 from 5 s, and from 200 s the 24-hour soak's burst of holes (stop 78,
  // a host starved for seconds: 50, 140, 250, 260 and 30 samples lost between blocks of 20 received, 710 in
  // 8.3 s), at 14 to 18 m/s (the soak's winds; the blades pitch through the holes)
  int k0 = 20000;
  std::vector<std::pair<int, int>> holes;
  for (int lost : {50, 140, 250, 260, 30}) {
    holes.emplace_back(k0, lost);
    k0 += lost + 20;
  }
  for (double wind : {14.0, 15.0, 16.0, 17.0, 18.0})
    for (uint64_t seed : {11, 12}) {
      const HoleRun r = run_with_holes(wind, 300.0, {bias("pitch_2", 1.0, 5.0)}, seed, [&holes](int k) {
        return std::any_of(holes.begin(), holes.end(),
                           [k](const auto& h) { return k >= h.first && k < h.first + h.second; });
      });
      // THEN the bias is raised once and never cleared, and nothing else is raised
      ASSERT_FALSE(r.events.empty()) << wind << " m/s, seed " << seed;
      EXPECT_EQ(r.events.front().component, "pitch_sensor_2");
      for (const auto& e : r.events)
        EXPECT_TRUE(e.raised && e.component == "pitch_sensor_2")
            << wind << " m/s, seed " << seed << ": " << e.component << " " << e.fault
            << (e.raised ? " raised" : " cleared") << " at " << e.t << " s";
      // AND 90 s after the holes every blade's estimate is where it was: 1 deg on blade 2, none on 1 and 3
      // (before the fix: +-2.8 to 4.1 deg, held there for good by the outrun actuator's hold)
      EXPECT_NEAR(r.last.bias[3], 1.0, 0.25) << wind << " m/s, seed " << seed;
      EXPECT_NEAR(r.last.bias[2], 0.0, 0.25) << wind << " m/s, seed " << seed;
      EXPECT_NEAR(r.last.bias[4], 0.0, 0.25) << wind << " m/s, seed " << seed;
    }
}

TEST(ObserverMode, AnAbruptLeakIsNoPitchSensorBias) {
  // GIVEN an abrupt hydraulic leak on blade 3's actuator from 150 s (a slow actuator, static gain 1), at six
  // winds from 13.7 to 18 m/s, six seeds each
  const auto flagged_runs = [](double lag_ratio_max) {
    int flagged = 0;
    for (uint64_t seed = 0; seed < 6; ++seed)
      for (double wind : {13.7, 14.2, 15.0, 16.0, 17.0, 18.0}) {
        const PlantRun r = run_plant(
            wind, 300.0, {plant::FaultSpec::make("WT01", "pitch_actuator_3", "hydraulic_leakage", 150.0)},
            Mode::kObserver, 31 + static_cast<uint64_t>(wind * 10.0) + seed, 0.1, 60.0, lag_ratio_max);
        flagged += !r.events.empty();
        for (const auto& e : r.events)
          std::printf("type_lag_ratio_max %g, %g m/s seed %d: %s %s raised at %.2f s: %s\n", lag_ratio_max,
                      wind, static_cast<int>(seed), e.component.c_str(), e.fault.c_str(), e.t,
                      e.detail.c_str());
      }
    return flagged;
  };
  const double shipped = config(Mode::kObserver).type_lag_ratio_max;
  const int flagged = flagged_runs(shipped), flagged_without_lag = flagged_runs(0.0);
  std::printf("abrupt leaks flagged as a pitch-sensor fault: %d of 36 runs (%d without the lag's test)\n",
              flagged, flagged_without_lag);
  // THEN no run flags a pitch sensor. Before, the observer's healthy actuator model read the lag as a 0.7-2.6
  // deg bias within 1 s (every run); then, with the static offset's lag removed, 7 of these 36 runs still
  // raised a bias or gain within 1.3-3.5 s: the slow actuator answers the IPC's 1P swing with less amplitude
  // (0.87) while its mean stays right, a gain of 0.68-0.95 on a moving reference that the misfit of both the
  // offset and the gain model (type_misfit_max) tells from a sensor's. The one left without the lag's test
  // (18 m/s, seed 2) fits a gain of 0.91 as well as a sensor's would, with a lag of 0.41 s where a sensor's
  // fault leaves the actuator's 0.11 s
  EXPECT_GT(shipped, 0.0);
  EXPECT_EQ(flagged, 0);
  EXPECT_GE(flagged_without_lag, 1);
}

TEST(ObserverMode, AStuckPitchSensorIsFlaggedThoughItsTrackingErrorIsLarge) {
  // GIVEN blade 1's pitch reading stuck at 5 deg from 150 s at 15 m/s (the benchmark's fault 1): the
  // reference stands near 10 deg, so |reference - pitch| passes max_tracking_error (5 deg) that holds a
  // rate-limited blade
  auto stuck = plant::FaultSpec::make("WT01", "pitch_1", "stuck", 150.0).with_value(5.0);
  const PlantRun r = run_plant(15.0, 300.0, {stuck}, Mode::kObserver, 41);
  // THEN it is flagged on pitch_sensor_1 within 5 s (a repeated reading is not held by that gate)
  const FaultEvent* first = first_raised(r.events);
  ASSERT_NE(first, nullptr);
  EXPECT_EQ(first->component, "pitch_sensor_1");
  EXPECT_GE(first->t, 150.0);
  EXPECT_LE(first->t, 155.0);
  // AND it is named a stuck reading, with the value it is stuck at
  EXPECT_EQ(first->fault, "sensor_stuck");
  EXPECT_NE(first->detail.find("stuck at 5 deg"), std::string::npos) << first->detail;
}

TEST(ObserverMode, AStuckSpeedSensorIsSensorStuckAndABiasStaysSensorBias) {
  // GIVEN the rotor speed reading stuck at 1.4 rad/s (the benchmark's fault 4) or the generator speed at
  // 150 rad/s, from 150 s at 14 m/s; and the same sensors with a 2 % offset
  struct Case {
    plant::FaultSpec fault;
    const char* component;
    const char* fault_class;
    const char* detail;
  };
  const Case cases[] = {
      {plant::FaultSpec::make("WT01", "rotor_speed", "stuck", 150.0).with_value(1.4), "rotor_speed_sensor",
       "sensor_stuck", "stuck at 1.4 rad/s"},
      {plant::FaultSpec::make("WT01", "generator_speed", "stuck", 150.0).with_value(150.0),
       "generator_speed_sensor", "sensor_stuck", "stuck at 150 rad/s"},
      {bias("rotor_speed", 0.034, 150.0), "rotor_speed_sensor", "sensor_bias", "bias"},
      {bias("generator_speed", 3.24, 150.0), "generator_speed_sensor", "sensor_bias", "bias"}};
  for (const auto& c : cases) {
    const PlantRun r = run_plant(14.0, 260.0, {c.fault}, Mode::kObserver, 52);
    const FaultEvent* first = first_raised(r.events);
    ASSERT_NE(first, nullptr) << c.component << " " << c.fault_class;
    // THEN the first report names the sensor and the kind of its fault, within 5 s (a rotor-speed offset: 62
    // s)
    EXPECT_EQ(first->component, c.component);
    EXPECT_EQ(first->fault, c.fault_class) << first->detail;
    EXPECT_NE(first->detail.find(c.detail), std::string::npos) << first->detail;
    EXPECT_LE(first->t, c.fault.type == "stuck" ? 155.0 : report_deadline(c.component, 150.0));
  }
}

TEST(ObserverMode, AStuckSpeedSensorStaysRaisedWhileItsTwinSticksToo) {
  // GIVEN the generator speed reading stuck at 88 rad/s (10 above the truth) from 150 to 264 s at 6.5 m/s,
  // turbulence 0.16, and the rotor speed's stuck at 0.98 rad/s (its own 16 % above) from 243 s (as on suite
  // seed 69: the second stuck sensor takes the model-free differential that confirms the first one away,
  // and the first was cleared at 249 s, still stuck at 88 rad/s, 16 rad/s from its estimate)
  auto generator = plant::FaultSpec::make("WT01", "generator_speed", "stuck", 150.0).with_value(87.9);
  generator.end = 264.0;
  auto rotor = plant::FaultSpec::make("WT01", "rotor_speed", "stuck", 243.0).with_value(0.979);
  const PlantRun r = run_plant(6.5, 330.0, {generator, rotor}, Mode::kObserver, 69, 0.16);
  const FaultEvent *raised = nullptr, *cleared = nullptr;
  for (const auto& e : r.events)
    if (e.component == "generator_speed_sensor") (e.raised ? raised : cleared) = &e;
  // THEN the generator speed is reported stuck within 5 s and cleared only after its reading moves again
  ASSERT_NE(raised, nullptr);
  EXPECT_EQ(raised->fault, "sensor_stuck");
  EXPECT_LE(raised->t, 155.0);
  if (cleared) {
    EXPECT_GE(cleared->t, 264.0) << cleared->detail;
  }
}

TEST(ObserverMode, ARaisedGainWhoseReadingThenSticksIsReportedStuck) {
  // GIVEN the generator speed with a gain of 1.062 from 150 to 337 s at 10 m/s, and its reading stuck at
  // 144.9 rad/s from 338 s, before the gain's report could clear (fault suite set 427, scenario 03: the
  // gain's report stood through the stuck reading and the stuck sensor was never named)
  auto gain = plant::FaultSpec::make("WT01", "generator_speed", "gain", 150.0);
  gain.gain = 1.062;
  gain.end = 337.0;
  auto stuck = plant::FaultSpec::make("WT01", "generator_speed", "stuck", 338.0).with_value(144.9);
  stuck.end = 500.0;
  const auto run = [&](bool stuck_after_raise) {
    return run_plant(10.0, 480.0, {gain, stuck}, Mode::kObserver, 427, 0.1, 60.0, -1.0,
                     [&](BiasConfig& c) { c.stuck_after_raise = stuck_after_raise; })
        .events;
  };
  const auto find = [](const std::vector<FaultEvent>& events, const char* fault, bool raised) {
    for (const auto& e : events)
      if (e.component == "generator_speed_sensor" && e.fault == fault && e.raised == raised) return &e;
    return static_cast<const FaultEvent*>(nullptr);
  };
  const auto events = run(true);
  for (const auto& e : events)
    std::printf("[measured] %.2f s %s %s %s: %s\n", e.t, e.component.c_str(), e.fault.c_str(),
                e.raised ? "raised" : "cleared", e.detail.c_str());
  // THEN the gain is raised first, and once the reading sticks the gain is cleared and sensor_stuck raised
  // within 5 s, with the value it is stuck at
  const FaultEvent* g = find(events, "sensor_gain", true);
  ASSERT_NE(g, nullptr);
  EXPECT_LT(g->t, 337.0);
  const FaultEvent* g_cleared = find(events, "sensor_gain", false);
  const FaultEvent* s = find(events, "sensor_stuck", true);
  ASSERT_NE(s, nullptr);
  ASSERT_NE(g_cleared, nullptr);
  EXPECT_GE(s->t, 338.0);
  EXPECT_LE(s->t, 343.0);
  EXPECT_LE(g_cleared->t, s->t);
  EXPECT_NE(s->detail.find("stuck at 144.9"), std::string::npos) << s->detail;
  // AND without the switch the gain's report stands and the stuck reading is never named
  EXPECT_EQ(find(run(false), "sensor_stuck", true), nullptr) << "this test no longer tests";
}

TEST(ObserverMode, AGainFaultIsSensorGainWithItsGain) {
  // GIVEN the benchmark's gain faults (generator speed 0.9, pitch 1.2, rotor speed 1.1) and gains of other
  // size and sign, from 150 s, at winds where the quantity moves (the pitch above rated); among them pitch
  // gains at 20-22 m/s whose error passes 5 deg (a pitch of 20-25 deg), which the rate-limit hold took for a
  // feathering ramp and held, with the estimate running the wrong way (the suite missed 5 of 68 gains on the
  // example 2 MW turbine and named 4 of 65 late on the benchmark one)
  struct Case {
    const char* target;
    const char* component;
    double gain, wind;
  };
  const Case cases[] = {{"generator_speed", "generator_speed_sensor", 0.9, 15.0},
                        {"generator_speed", "generator_speed_sensor", 1.07, 10.0},
                        {"pitch_2", "pitch_sensor_2", 1.2, 15.0},
                        {"pitch_3", "pitch_sensor_3", 1.15, 20.0},
                        {"pitch_1", "pitch_sensor_1", 1.25, 20.7},
                        {"pitch_2", "pitch_sensor_2", 0.78, 22.0},
                        {"rotor_speed", "rotor_speed_sensor", 1.1, 15.0}};
  for (const auto& c : cases) {
    auto f = plant::FaultSpec::make("WT01", c.target, "gain", 150.0);
    f.gain = c.gain;
    const PlantRun r = run_plant(c.wind, 240.0, {f}, Mode::kObserver, 61);
    const FaultEvent* first = first_raised(r.events);
    ASSERT_NE(first, nullptr) << c.target << " x" << c.gain << ": nothing raised";
    std::printf("%s gain %g at %g m/s: %s %s at %.2f s: %s\n", c.target, c.gain, c.wind,
                first->component.c_str(), first->fault.c_str(), first->t, first->detail.c_str());
    // THEN the first report is sensor_gain on that sensor, in time, with the gain within 0.01
    EXPECT_EQ(first->component, c.component);
    EXPECT_EQ(first->fault, "sensor_gain") << first->detail;
    EXPECT_GE(first->t, 150.0);
    EXPECT_LE(first->t, report_deadline(c.component, 150.0));
    double gain = 0.0;
    ASSERT_EQ(std::sscanf(first->detail.c_str(), "gain %lf", &gain), 1) << first->detail;
    EXPECT_NEAR(gain, c.gain, 0.01) << first->detail;
  }
}

TEST(ObserverMode, BelowRatedAGeneratorSpeedGainWaitsForTheSpeedToMove) {
  // GIVEN generator-speed gains of 5-8 % and offsets of 2-3 % of rated speed at 6.5-7.5 m/s with little
  // turbulence (TI 0.07), where the power is far below rated and the speed follows the wind slowly (the
  // suite's seed 14 named 4 of 5 such gains `sensor_bias` after the 5 s wait that holds above rated)
  struct Case {
    const char* type;
    double size, wind;
    uint64_t seed;
  };
  const Case cases[] = {{"gain", 1.078, 6.5, 71}, {"gain", 0.93, 7.5, 72}, {"gain", 1.055, 7.0, 73},
                        {"gain", 0.945, 7.0, 74}, {"bias", 4.3, 6.5, 75},  {"bias", -3.5, 7.5, 76}};
  for (const auto& c : cases) {
    auto f = std::string(c.type) == "gain" ? plant::FaultSpec::make("WT01", "generator_speed", "gain", 150.0)
                                           : bias("generator_speed", c.size, 150.0);
    if (std::string(c.type) == "gain") f.gain = c.size;
    const PlantRun r = run_plant(c.wind, 240.0, {f}, Mode::kObserver, c.seed, 0.07);
    const FaultEvent* first = first_raised(r.events);
    ASSERT_NE(first, nullptr) << c.type << " " << c.size << ": nothing raised";
    std::printf("generator_speed %s %g at %g m/s: %s at %.2f s: %s\n", c.type, c.size, c.wind,
                first->fault.c_str(), first->t, first->detail.c_str());
    // THEN each is named for what it is, on the generator-speed sensor, within the below-rated wait (20 s)
    EXPECT_EQ(first->component, "generator_speed_sensor");
    EXPECT_EQ(first->fault, std::string("sensor_") + c.type) << first->detail;
    EXPECT_GE(first->t, 150.0);
    EXPECT_LE(first->t, 150.0 + 22.0);
  }
}

TEST(ObserverMode, AHealthyHourRaisesNothing) {
  // GIVEN one healthy hour of turbulent wind (TI 0.1) at each of 8, 12, 14, 16 and 20 m/s, its own seed each
  for (double wind : {8.0, 12.0, 14.0, 16.0, 20.0}) {
    const PlantRun r = run_plant(wind, 3600.0, {}, Mode::kObserver, 100 + static_cast<uint64_t>(wind));
    std::printf(
        "healthy hour at %g m/s: %zu events; rms bias error rotor %.4f, generator %.3f rad/s, pitch %.3f "
        "deg; "
        "peak |estimate| rotor %.4f, generator %.3f rad/s; witness on %.1f %% of samples\n",
        wind, r.events.size(), r.rms_error[0], r.rms_error[1], r.rms_error[2], r.max_error[0], r.max_error[1],
        100.0 * r.witness_share);
    // THEN nothing is raised in the hour ...
    EXPECT_TRUE(r.events.empty()) << wind << " m/s: first "
                                  << (r.events.empty() ? "" : r.events[0].component);
    // ... the power witness was in use for (nearly) the whole hour, so the hour tested the observer with it
    // ...
    EXPECT_GT(r.witness_share, 0.95) << wind;
    // ... and no bias estimate came closer than 1.5x to its threshold (rms at most a fifth of it)
    EXPECT_LT(r.max_error[0], 0.017 / 1.5) << wind;
    EXPECT_LT(r.max_error[1], 1.62 / 1.5) << wind;
    EXPECT_LT(r.rms_error[0], 0.017 / 5) << wind;
    EXPECT_LT(r.rms_error[1], 1.62 / 5) << wind;
  }
}

TEST(ObserverMode, ASafeStopOfAHealthyTurbineRaisesNothing) {
  // GIVEN a healthy turbine at 17 m/s that the arbiter safe-stops at 200 s (blades to feather at the 10 deg/s
  // rate limit, torque ramped to zero), as in the demo where this raised 28-31 deg "biases" on healthy blades
  // and a rotor-speed bias
  for (uint64_t seed : {7u, 8u}) {
    TurbineParams p;
    plant::TurbineScenario t;
    t.id = "WT01";
    t.wind.mean = 17.0;
    t.wind.turbulence_intensity = 0.1;
    plant::TurbineSim sim(p, t, {}, seed, 100.0);
    const BiasConfig c = config(Mode::kObserver);
    BiasEstimator est(c, load_gain_file(c.drive_train_gain_file), load_gain_file(c.pitch_gain_file), p);
    std::vector<FaultEvent> events;
    plant::ControlInput stop;
    stop.mode = plant::OperatingMode::kSafeStop;
    for (int k = 0; k < 400 * 100; ++k) {
      FrameSample s = sim.step(k >= 200 * 100 ? stop : plant::ControlInput{});
      s.aero_torque = s.aero_power = kNaN;
      est.update(s, false, events);
    }
    // THEN nothing is raised, and the feathering ramp was recognised (pitch bias held on rate-limited
    // samples)
    std::string first = events.empty() ? "" : events[0].component + " " + events[0].detail;
    EXPECT_TRUE(events.empty()) << seed << ": " << first;
    EXPECT_GT(est.tracking_holds(), 100u) << seed;
  }
}

TEST(ObserverMode, TheExample2MWTurbineHoldsItsSpeedBiasesThroughTheArbitersSafeStop) {
  // GIVEN the example 2 MW turbine (its own file and its own drive-train gains, the README's "Your own
  // turbine"), healthy at 15 and 17 m/s, safe-stopped at 200 s by the arbiter (its configuration reaches the
  // service as the context's turbine_stopped), where the multi-fault suite raised a +3 to +5.6 rad/s
  // generator-speed "bias" 20 s into each of six stops
  const TurbineParams p = load_turbine_params_file(kDeploy + "/turbine/example_2MW.yaml");
  const YamlSection y = YamlSection::load_file(kDeploy + "/config/sensor_bias.yaml");
  YAML::Node n = YAML::Clone(y.node());
  n["drive_train_gains"] = "../sensor_bias/gains_drive_train_observer_2MW.yaml";
  const BiasConfig c = load_bias_config(YamlSection(n, y.file()), kDeploy + "/sensor_bias", p);
  for (double wind : {15.0, 17.0})
    for (uint64_t seed : {3u, 4u}) {
      plant::TurbineScenario t;
      t.id = "WT01";
      t.wind.mean = wind;
      t.wind.turbulence_intensity = 0.14;
      plant::TurbineSim sim(p, t, {}, seed, 100.0);
      BiasEstimator est(c, load_gain_file(c.drive_train_gain_file), load_gain_file(c.pitch_gain_file), p);
      std::vector<FaultEvent> events;
      plant::ControlInput stop;
      stop.mode = plant::OperatingMode::kSafeStop;
      InputContext stopped;
      stopped.turbine_stopped = true;
      stopped.transitions = 1;
      double peak_before = 0.0;
      for (int k = 0; k < 400 * 100; ++k) {
        const bool stopping = k >= 200 * 100;
        if (k == 200 * 100) est.set_context(stopped, 200.0);
        FrameSample s = sim.step(stopping ? stop : plant::ControlInput{});
        s.aero_torque = s.aero_power = kNaN;
        est.update(s, false, events);
        if (!stopping && k > 60 * 100) peak_before = std::max(peak_before, std::fabs(est.output().bias[1]));
      }
      // THEN nothing is raised before or after the stop: the 2 MW gains hold the healthy turbine's generator
      // speed bias below the 1.8 rad/s threshold (1 % of its rated speed), and the stop does not move it
      const std::string first = events.empty() ? "" : events[0].component + " " + events[0].detail;
      std::printf(
          "[measured] 2 MW safe stop %g m/s seed %llu: peak generator-speed bias before %.2f rad/s, "
          "%zu events\n",
          wind, static_cast<unsigned long long>(seed), peak_before, events.size());
      EXPECT_TRUE(events.empty()) << wind << " " << seed << ": " << first;
      EXPECT_LT(peak_before, 0.5 * c.threshold[1]) << wind << " " << seed;
    }
}

TEST(PaperModeOnPlant, HealthyTurbulentTurbineGivesPaperModeFalseBiasesTheObserverDoesNot) {
  // GIVEN a healthy turbine in turbulent wind (TI 0.15) for 10 minutes, the paper's estimator (eqs 5 + 8: the
  // measurement minus an open-loop simulation of the Table I model) and the default observer on the same data
  const PlantRun paper = run_plant(14.0, 600.0, {}, Mode::kPaper, 5, 0.15);
  const PlantRun obs = run_plant(14.0, 600.0, {}, Mode::kObserver, 5, 0.15);
  std::printf(
      "healthy, TI 0.15: rms bias error rotor paper %.4f vs observer %.4f rad/s; generator %.3f vs %.3f "
      "rad/s; "
      "events paper %zu, observer %zu\n",
      paper.rms_error[0], obs.rms_error[0], paper.rms_error[1], obs.rms_error[1], paper.events.size(),
      obs.events.size());
  // THEN the paper mode's drive-train "bias" (there is none) has an rms above the rotor-speed threshold and
  // it raises sensor_bias events: the open-loop simulation does not follow the turbulence ...
  EXPECT_GT(paper.rms_error[0], 0.017);
  EXPECT_FALSE(paper.events.empty());
  // ... while the observer's errors are below a fifth of the thresholds and it raises nothing
  EXPECT_LT(obs.rms_error[0], 0.2 * 0.017);
  EXPECT_LT(obs.rms_error[1], 0.2 * 1.62);
  EXPECT_TRUE(obs.events.empty());
}

TEST(ObserverMode, AGeneratorTorqueSensorOffsetFlagsNeitherSpeedSensor) {
  // GIVEN a 3 % offset on the generator-torque sensor from 150 s at 16 m/s: the power witness P / (eta_g T_g)
  // then reads the generator speed 3 % low (4.9 rad/s), but both speed sensors still agree (b_r - b_g / N =
  // 0)
  plant::FaultSpec f = bias("gen_torque", 900.0, 150.0);
  const PlantRun r = run_plant(16.0, 300.0, {f}, Mode::kObserver, 31);
  std::printf("gen_torque +900 N m at 16 m/s: mean estimate rotor %+.4f, generator %+.3f rad/s, %zu events\n",
              r.mean_estimate[0], r.mean_estimate[1], r.events.size());
  // THEN the observer moves the common mode (both bias estimates, alike) ...
  EXPECT_GT(r.mean_estimate[1], 1.62);
  EXPECT_NEAR(r.mean_estimate[0] * 95.0, r.mean_estimate[1], 0.3 * std::fabs(r.mean_estimate[1]));
  // ... and the differential check keeps either speed sensor from being flagged
  EXPECT_TRUE(r.events.empty()) << (r.events.empty() ? "" : r.events[0].component);
}

TEST(ObserverMode, TimeVaryingBiasOfThePaperOnThePlant) {
  for (const char* target : {"rotor_speed", "generator_speed", "pitch_1"}) {
    auto f = plant::FaultSpec::make("WT01", target, "bias_paper", 60.0);
    f.amplitude = std::string(target) == "pitch_1" ? 0.05 : 0.02;
    // GIVEN eqs 41-42 injected from 60 s on the plant at 16 m/s, TI 0.1
    const PlantRun r = run_plant(16.0, 900.0, {f}, Mode::kObserver, 9, 0.1, 90.0);
    const int ch = std::string(target) == "rotor_speed"       ? 0
                   : std::string(target) == "generator_speed" ? 1
                                                              : 2;
    const double scale = std::string(target) == "rotor_speed"       ? 0.02 * 1.71
                         : std::string(target) == "generator_speed" ? 0.02 * 162.0
                                                                    : 0.05 * 14.0;
    const auto sf = slow_fast_rms(r.error[static_cast<std::size_t>(ch)]);
    std::printf(
        "bias_paper on %s: rms bias error %.4g = %.2f %% of amplitude*signal (slow 2 s-mean part %.2f %%, "
        "the rest %.2f %%)\n",
        target, r.rms_error[static_cast<std::size_t>(ch)],
        100.0 * r.rms_error[static_cast<std::size_t>(ch)] / scale, 100.0 * sf.first / scale,
        100.0 * sf.second / scale);
    const auto si = slow_fast_rms(r.injected[static_cast<std::size_t>(ch)]);
    std::printf("  injected bias: slow part rms %.2f %%, fast part (the signal's own fluctuation) %.2f %%\n",
                100.0 * si.first / scale, 100.0 * si.second / scale);
    // The noise a bias estimate of this channel cannot avoid, per sample: rotor, the rotor-speed sensor (the
    // differential b_r - b_g / N sees it; the generator sensor's share, 0.05 / 95, is negligible); generator,
    // the power witness (the only bias-free view of the common mode) with the generator sensor; pitch, the
    // pitch sensor.
    const double sigma = ch == 0 ? 0.025 : ch == 1 ? std::hypot(r.witness_noise, 0.05) : 0.2;
    const auto& inj = r.injected[static_cast<std::size_t>(ch)];
    const double floor_rw = tracking_floor(inj, sigma, false) / scale,
                 floor_rate = tracking_floor(inj, sigma, true) / scale;
    std::printf(
        "  noise floor (sigma %.3g per sample): best random-walk estimator %.2f %%, best rate-state "
        "estimator %.2f %%\n",
        sigma, 100.0 * floor_rw, 100.0 * floor_rate);
    if (ch == 0)
      std::printf(
          "  in this run: generator-bias estimate error rms %.4g rad/s (= %.2f %% of the rotor scale after / "
          "N)\n",
          r.rms_error[1], 100.0 * r.rms_error[1] / 95.0 / scale);
    const double err = r.rms_error[static_cast<std::size_t>(ch)] / scale;
    // THEN the error (rate-state drive train: rotor 9.1 %, generator 2.8 %; random-walk pitch 8.0 % measured)
    // is within 1.5x of the noise floor of the best estimator of its bias model (known plant, only sensor
    // noise) ...
    EXPECT_LT(err, ch == 0 ? 0.11 : ch == 1 ? 0.04 : 0.10) << target;
    EXPECT_LT(err, 1.5 * (ch < 2 ? floor_rate : floor_rw)) << target;
    // ... and the paper's figures (< 4 %, 0.15 %, < 3.3 %) lie below that floor on the plant's sensor noise
    EXPECT_GT(floor_rate, ch == 0 ? 0.04 : ch == 1 ? 0.0015 : 0.033) << target;
    // AND the biased sensor is flagged (the bias reaches 3 x 2 %)
    bool flagged = false;
    for (const auto& e : r.events)
      if (e.raised && e.component == channel_components()[static_cast<std::size_t>(ch)]) flagged = true;
    EXPECT_TRUE(flagged) << target;
  }
}

TEST(ObserverMode, ARampBiasIsFollowedWithoutLag) {
  // GIVEN a generator-speed sensor drifting at 0.3 rad/s per s from 60 s at 14 m/s (36 rad/s after 120 s)
  auto f = plant::FaultSpec::make("WT01", "generator_speed", "drift", 60.0);
  f.rate = 0.3;
  const PlantRun r = run_plant(14.0, 180.0, {f}, Mode::kObserver, 12, 0.1, 60.0);
  // WHEN the error is averaged over the ramp after 20 s (the common mode wanders +-0.05 rad/s over a minute
  // with the power witness's noise; the average over 100 s shows the lag)
  const auto& e = r.error[1];
  double mean = 0.0;
  for (std::size_t k = 2000; k < e.size(); ++k) mean += e[k] / static_cast<double>(e.size() - 2000);
  std::printf("drift 0.3 rad/s/s on the generator speed: mean error %+.4f rad/s (bias reached %.1f rad/s)\n",
              mean, r.injected[1].back());
  // THEN it stays below a third of what a random-walk bias model lags (rate x its ~0.7 s time constant, 0.2
  // rad/s; measured with the previous random-walk gains: -0.22 rad/s): the rate state follows the ramp
  EXPECT_LT(std::fabs(mean), 0.07);
}

TEST(BiasEstimator, BadSamplesAreCountedAndNeverFed) {
  TurbineParams p;
  const BiasConfig c = config(Mode::kObserver);
  BiasEstimator est(c, load_gain_file(c.drive_train_gain_file), load_gain_file(c.pitch_gain_file), p);
  std::vector<FaultEvent> ev;
  FrameSample s;
  s.t = 0;
  s.rotor_speed = 1.6;
  s.generator_speed = 152.0;
  s.gen_torque = 2e4;
  s.wind_hub = 10.0;
  s.pitch = {1, 1, 1};
  s.pitch_ref = {1, 1, 1};
  EXPECT_TRUE(est.update(s, false, ev));
  EXPECT_EQ(est.fed_drive_train(), 1u);
  s.generator_speed = kNaN;
  EXPECT_FALSE(est.update(s, false, ev));
  s.generator_speed = 152.0;
  s.rotor_speed = -1.0;
  EXPECT_FALSE(est.update(s, false, ev));
  s.rotor_speed = 1.6;
  s.wind_hub = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(est.update(s, false, ev));
  EXPECT_EQ(est.rejected(), 3u);
  EXPECT_EQ(est.fed_drive_train(), 1u);
  EXPECT_TRUE(std::isfinite(est.output().bias[0]));
}

TEST(BiasEstimator, SpeedThresholdsAndTheWitnessLevelAreTheTurbinesOwn) {
  // GIVEN the benchmark turbine and a 2 MW turbine (rated generator speed 188 rad/s, gear ratio 80)
  TurbineParams small;
  small.rated_power = 2.0e6;
  small.rated_generator_speed = 188.0;
  small.gear_ratio = 80.0;
  const YamlSection none(YAML::Load("{}"), "x.yaml");
  const BiasConfig big = load_bias_config(none, kDeploy + "/sensor_bias", TurbineParams{});
  const BiasConfig two = load_bias_config(none, kDeploy + "/sensor_bias", small);
  // THEN the speed thresholds are 1 % of each turbine's rated speeds and the witness level 10 % of its rated
  // torque, unless given in absolute units
  EXPECT_NEAR(big.threshold[1], 1.62, 1e-9);
  EXPECT_NEAR(big.threshold[0], 1.62 / 95.0, 1e-9);
  EXPECT_NEAR(two.threshold[1], 1.88, 1e-9);
  EXPECT_NEAR(two.threshold[0], 1.88 / 80.0, 1e-9);
  EXPECT_NEAR(two.witness_torque_min, 0.1 * 2.0e6 / (0.98 * 188.0), 1e-6);
  EXPECT_NEAR(load_bias_config(YamlSection(YAML::Load("threshold_rotor_speed: 0.03"), "x.yaml"),
                               kDeploy + "/sensor_bias", small)
                  .threshold[0],
              0.03, 1e-12);
  // AND the plausible ranges are multiples of the rated values: the benchmark turbine's 5 rad/s, 400 rad/s
  // and 1e6 N m there, proportionally more on a faster rotor or a larger generator
  EXPECT_NEAR(big.rotor_speed_max, 5.0, 0.01);
  EXPECT_NEAR(big.generator_speed_max, 400.0, 0.5);
  EXPECT_NEAR(big.torque_max, 1.0e6, 0.01e6);
  EXPECT_NEAR(two.rotor_speed_max, 2.93 * 188.0 / 80.0, 1e-9);
}

TEST(BiasEstimator, ConfigRejectsUnknownKeysBadRangesAndWrongGains) {
  EXPECT_THROW(load_bias_config(YamlSection(YAML::Load("treshold_pitch: 1"), "x.yaml"), kDeploy),
               ConfigError);
  EXPECT_THROW(load_bias_config(YamlSection(YAML::Load("clear_ratio: 2"), "x.yaml"), kDeploy), ConfigError);
  // An observer-mode estimator refuses paper gain files (wrong structure and state count).
  TurbineParams p;
  BiasConfig c = config(Mode::kObserver);
  EXPECT_THROW(BiasEstimator(c, load_gain_file(kDeploy + "/sensor_bias/gains_drive_train_paper.yaml"),
                             load_gain_file(c.pitch_gain_file), p),
               ConfigError);
}

TEST(BiasDetector, RaisesAfterRaiseTimeAndClearsWithHysteresis) {
  // GIVEN a pitch-only feed (drive train inputs missing) whose measured pitch steps by 2 deg against its
  // reference
  TurbineParams p;
  BiasConfig c = config(Mode::kObserver);
  c.settle_time = 1.0;
  BiasEstimator est(c, load_gain_file(c.drive_train_gain_file), load_gain_file(c.pitch_gain_file), p);
  std::vector<FaultEvent> ev;
  FrameSample s;
  double t_raise = -1, t_clear = -1;
  for (int k = 0; k < 6000; ++k) {
    s.t = k * 0.01;
    const double offset = (s.t >= 10.0 && s.t < 30.0) ? 2.0 : 0.0;
    s.pitch = {5.0, 5.0 + offset, 5.0};
    s.pitch_ref = {5.0, 5.0, 5.0};
    ev.clear();
    est.update(s, false, ev);
    for (const auto& e : ev) {
      EXPECT_EQ(e.component, "pitch_sensor_2");
      (e.raised ? t_raise : t_clear) = s.t;
    }
  }
  // THEN it is raised at least raise_time after the step (and within 3 s), and cleared at least clear_time
  // after the bias went (and within clear_time + 3 s)
  EXPECT_GE(t_raise, 10.0 + c.raise_time);
  EXPECT_LE(t_raise, 13.0);
  EXPECT_GE(t_clear, 30.0 + c.clear_time);
  EXPECT_LE(t_clear, 30.0 + c.clear_time + 3.0);
}

}  // namespace

TEST(ObserverMode, ARaisedPitchBiasStaysRaisedThroughEveryBladeDerated) {
  // GIVEN a 1 deg bias on pitch sensor 2 from 30 s, raised; then from 150 s for 60 s the arbiter derates
  // every blade (5 deg/s) and asks for degraded mode, as it does while pitch_diag is lost (the reliability
  // campaign: a frozen pitch_diag cleared this bias 6 s into the derate, though the bias was still +1.03 deg)
  // (Before the outrun blade stopped feeding the offset fit and the hold after a reconfiguration: 8 of these
  // 36 runs cleared the bias within 6 s of the derate, one raised a false sensor_gain on blade 1.)
  for (const double wind : {13.0, 14.0, 15.0, 16.0, 17.0, 18.0}) {
    for (uint64_t seed = 1; seed <= 6; ++seed) {
      TurbineParams p;
      plant::TurbineScenario t;
      t.id = "WT01";
      t.wind.mean = wind;
      t.wind.turbulence_intensity = 0.1;
      plant::TurbineSim sim(p, t, {bias("pitch_2", 1.0, 30.0)}, seed, 100.0);
      const BiasConfig c = config(Mode::kObserver);
      BiasEstimator est(c, load_gain_file(c.drive_train_gain_file), load_gain_file(c.pitch_gain_file), p);
      InputContextTracker context("sensor_bias");
      std::vector<FaultEvent> events;
      plant::ControlInput derated;
      derated.mode = plant::OperatingMode::kDegraded;
      derated.pitch_rate_limit = {5.0, 5.0, 5.0};
      for (int k = 0; k < 300 * 100; ++k) {
        const bool derating = k >= 150 * 100 && k < 210 * 100;
        if (k == 150 * 100) context.on_reconfiguration(false, {5.0, 5.0, 5.0});
        if (k == 210 * 100) context.on_reconfiguration();
        FrameSample s = sim.step(derating ? derated : plant::ControlInput{});
        s.aero_torque = s.aero_power = kNaN;
        est.set_context(context.context(), s.t);
        est.update(s, false, events);
      }
      // THEN pitch sensor 2's bias is raised once and never cleared, and nothing else is raised
      std::string all;
      for (const auto& e : events)
        all +=
            e.component + " " + e.fault + (e.raised ? " raised " : " cleared ") + std::to_string(e.t) + "; ";
      EXPECT_EQ(events.size(), 1u) << wind << " m/s seed " << seed << ": " << all;
      if (events.empty()) continue;
      EXPECT_EQ(events[0].component, "pitch_sensor_2");
      EXPECT_TRUE(events[0].raised);
    }
  }
}

/// The shipped configuration with `key` set to `value`, and gains designed for `turbine_file` at start as the
/// service does: an estimator for that turbine.
template <typename T>
BiasEstimator estimator_for(const std::string& turbine_file, const TurbineParams& p, const char* key,
                            T value) {
  const YamlSection y = YamlSection::load_file(kDeploy + "/config/sensor_bias.yaml");
  YAML::Node n = YAML::Clone(y.node());
  n[key] = value;
  const BiasConfig c = load_bias_config(YamlSection(n, y.file()), kDeploy + "/sensor_bias", p);
  std::string note;
  const GainFile drive_train = gain_for_turbine(load_gain_file(c.drive_train_gain_file), "drive_train_gains",
                                                c.drive_train_design, turbine_file, p, true, note);
  const GainFile pitch = gain_for_turbine(load_gain_file(c.pitch_gain_file), "pitch_gains", c.pitch_design,
                                          turbine_file, p, true, note);
  return BiasEstimator(c, drive_train, pitch, p);
}

/// One turbine, WT01, in wind of `mean` m/s at turbulence `turbulence` and shear exponent `shear`.
plant::TurbineScenario one_turbine(double mean, double turbulence, double shear) {
  plant::TurbineScenario t;
  t.id = "WT01";
  t.wind.mean = mean;
  t.wind.turbulence_intensity = turbulence;
  t.wind.shear_exponent = shear;
  t.wind.shear_variation = 0.03;
  return t;
}

/// The reports `est` gives over `seconds` of `sim` (no aerodynamic torque, as on a real turbine).
std::vector<FaultEvent> run_on_plant(plant::TurbineSim& sim, BiasEstimator& est, double seconds) {
  std::vector<FaultEvent> events;
  for (int k = 0; k < static_cast<int>(seconds * 100.0); ++k) {
    FrameSample s = sim.step();
    s.aero_torque = s.aero_power = kNaN;
    est.update(s, false, events);
  }
  return events;
}

TEST(ObserverMode, AGeneratorSpeedFaultIsNamedRightThoughItsRecordBeganBeforeTheOnset) {
  // GIVEN the example 2 MW turbine at 6.3 m/s (TI 0.098), its gains designed from its file at start as the
  // service does, and generator-speed gains from 300 s, on the two plant seeds of the multi-fault suite's
  // set 173 where a gain of 0.926 was named sensor_bias 1.2 s after its onset ("evidence 488.5 against a
  // gain"): there the healthy estimate (std 0.27 rad/s) last fell below the record's restart level (0.45
  // rad/s) about a second before the onset, so the record held healthy samples; and offsets of 3-4 rad/s
  const std::string turbine_file = kDeploy + "/turbine/example_2MW.yaml";
  const TurbineParams p = load_turbine_params_file(turbine_file);
  struct Counted {
    int right = 0, runs = 0;
  };
  auto run = [&](double misfit_max) -> Counted {
    const BiasEstimator fresh = estimator_for(turbine_file, p, "type_misfit_max", misfit_max);
    Counted counted;
    for (double size : {0.926, 0.905, 0.95, 1.07, 3.2, -4.0})
      for (uint64_t seed : {173008u, 173006u}) {
        const bool gain = size > 0.0 && size < 2.0;  // else an offset (rad/s)
        const std::string expected = gain ? "sensor_gain" : "sensor_bias";
        const plant::TurbineScenario t = one_turbine(6.3, 0.098, 0.114);
        auto f = gain ? plant::FaultSpec::make("WT01", "generator_speed", "gain", 300.0)
                      : bias("generator_speed", size, 300.0);
        if (gain) f.gain = size;
        plant::TurbineSim sim(p, t, {f}, seed, 100.0);
        BiasEstimator est = fresh;
        const std::vector<FaultEvent> events = run_on_plant(sim, est, 360.0);
        const FaultEvent* first = first_raised(events);
        ++counted.runs;
        if (misfit_max <= 0.0) {
          if (first && first->fault == expected) ++counted.right;
          continue;
        }
        EXPECT_NE(first, nullptr) << size << " " << seed << ": nothing raised";
        if (!first) continue;
        std::printf("[measured] 2 MW generator-speed %s %g, seed %llu: %s at %.2f s: %s\n",
                    gain ? "gain" : "offset", size, static_cast<unsigned long long>(seed),
                    first->fault.c_str(), first->t, first->detail.c_str());
        // THEN each is named for what it is, a gain with its size, on the generator-speed sensor, within the
        // below-rated wait (20 s)
        EXPECT_EQ(first->component, "generator_speed_sensor");
        EXPECT_EQ(first->fault, expected) << size << " " << seed << ": " << first->detail;
        EXPECT_LE(first->t, 300.0 + 22.0);
        double estimated = 0.0;
        if (gain && std::sscanf(first->detail.c_str(), "gain %lf", &estimated) == 1) {
          EXPECT_NEAR(estimated, size, 0.01) << first->detail;
        }
        if (first->fault == expected) ++counted.right;
      }
    return counted;
  };
  const Counted restarted = run(config(Mode::kObserver).type_misfit_max), kept = run(0.0);
  std::printf("[measured] right first: %d of %d restarting a record that misfits, %d of %d keeping it\n",
              restarted.right, restarted.runs, kept.right, kept.runs);
  // AND keeping the record (type_misfit_max 0) names some of them wrong: the cases exercise the restart
  EXPECT_LT(kept.right, kept.runs);
}

TEST(ObserverMode, AConverterOffsetDoesNotChangeTheClassOfAGeneratorSpeedFault) {
  // GIVEN the example 1.5 MW turbine below rated (6-10 m/s, turbulence 0.06-0.14), its gains designed from
  // its file at start, and 40 seeded generator-speed faults from 200 s (gains and offsets of 3-7 %), each run
  // without and with the converter's torque 100 N m off from 100 s (the benchmark's converter fault: the
  // delivered and measured torque move, the reference does not). The converter model alone puts the power
  // witness 2-3 % off there, which named the suite's offsets of 7.31 and 4.18 rad/s (set 264, scenarios 01
  // and 07) sensor_gain
  const std::string turbine_file = kDeploy + "/turbine/example_1.5MW.yaml";
  const TurbineParams p = load_turbine_params_file(turbine_file);
  auto right_first = [&](double converter_offset, double converter_offset_time) {
    const BiasEstimator fresh =
        estimator_for(turbine_file, p, "converter_offset_time", converter_offset_time);
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int right = 0;
    for (int k = 0; k < 40; ++k) {
      const double mean = 6.0 + 4.0 * u(rng);  // (drawn in this order: the cases as measured)
      const plant::TurbineScenario t = one_turbine(mean, 0.06 + 0.08 * u(rng), 0.15);
      const bool gain = u(rng) < 0.5;
      const double share = (u(rng) < 0.5 ? -1.0 : 1.0) * (0.03 + 0.04 * u(rng));
      auto speed = gain ? plant::FaultSpec::make("WT01", "generator_speed", "gain", 200.0)
                        : bias("generator_speed", share * 0.8 * p.rated_generator_speed, 200.0);
      if (gain) speed.gain = 1.0 + share;
      std::vector<plant::FaultSpec> faults{speed};
      if (converter_offset != 0.0)
        faults.push_back(
            plant::FaultSpec::make("WT01", "converter", "torque_offset", 100.0).with_value(converter_offset));
      plant::TurbineSim sim(p, t, faults, 1000 + static_cast<uint64_t>(k), 100.0);
      BiasEstimator est = fresh;
      const std::vector<FaultEvent> events = run_on_plant(sim, est, 250.0);
      const FaultEvent* first = first_raised(events);
      EXPECT_NE(first, nullptr) << "case " << k << ": nothing raised";
      if (!first) continue;
      EXPECT_EQ(first->component, "generator_speed_sensor") << first->detail;
      EXPECT_GE(first->t, 200.0) << first->detail;
      EXPECT_LE(first->t, 200.0 + 22.0) << first->detail;  // the below-rated wait
      right += first->fault == (gain ? "sensor_gain" : "sensor_bias");
    }
    return right;
  };
  const double learn = config(Mode::kObserver).converter_offset_time;
  const int clean = right_first(0.0, 0.0), clean_learning = right_first(0.0, learn);
  const int learned = right_first(100.0, learn), model_alone = right_first(100.0, 0.0);
  std::printf(
      "[measured] 1.5 MW generator-speed faults named right first, of 40: %d clean, %d clean learning "
      "the converter's offset; beside a 100 N m converter offset %d learning it, %d with the model alone\n",
      clean, clean_learning, learned, model_alone);
  // THEN beside the converter's offset they are named as well as without it (measured: 39 and 39 of 40)
  EXPECT_GE(clean, 38);
  EXPECT_GE(learned, clean - 1);
  // AND learning costs the clean rotor nothing: the offset is held while a speed record runs (learned over
  // 10 s without the hold: 30 of 40)
  EXPECT_GE(clean_learning, clean - 1);
  // AND the converter model alone names several wrong (measured: 27 of 40): the cases exercise the offset
  EXPECT_LE(model_alone, clean - 5);
}

TEST(ObserverMode, LullsAcrossThePowerWitnessGateRaiseNothing) {
  // GIVEN the example 1.5 MW turbine in light, very turbulent wind (4.5-5.5 m/s, turbulence 0.19-0.23, as
  // IEC's normal turbulence has it there), where lulls to 2 m/s take the generator torque across the power
  // witness's gate (10 % of rated, 798 N m) for minutes: 16 healthy 20-minute runs, its gains designed from
  // its file at start. Gated on the measured sample, the witness kept the samples whose torque noise (90 N m)
  // was positive and read them up to 12 % low: healthy hours at those winds (multi_fault_suite.py generate
  // --edge, seed 304) raised 13 false generator-speed offsets of 7-13 rad/s
  const std::string turbine_file = kDeploy + "/turbine/example_1.5MW.yaml";
  const TurbineParams p = load_turbine_params_file(turbine_file);
  auto raised_runs = [&](bool gate_on_model) {
    const BiasEstimator fresh = estimator_for(turbine_file, p, "witness_gate_on_model", gate_on_model);
    std::mt19937_64 rng(304);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int raised = 0;
    for (int k = 0; k < 16; ++k) {
      const double mean = 4.5 + u(rng);
      const plant::TurbineScenario t = one_turbine(mean, 0.19 + 0.04 * u(rng), 0.2);
      plant::TurbineSim sim(p, t, {}, 3040 + static_cast<uint64_t>(k), 100.0);
      BiasEstimator est = fresh;
      const std::vector<FaultEvent> events = run_on_plant(sim, est, 1200.0);
      const FaultEvent* first = first_raised(events);
      if (first)
        std::printf("[measured] gate on the %s torque, run %d (%.1f m/s, TI %.3f): %s at %.1f s: %s\n",
                    gate_on_model ? "model" : "measured", k, t.wind.mean, t.wind.turbulence_intensity,
                    first->fault.c_str(), first->t, first->detail.c_str());
      raised += first != nullptr;
    }
    return raised;
  };
  const int on_model = raised_runs(true), on_sample = raised_runs(false);
  std::printf(
      "[measured] healthy 1.5 MW runs at 4.5-5.5 m/s raising a report, of 16: %d gated on the converter "
      "model's torque, %d on the measured sample's\n",
      on_model, on_sample);
  // THEN gated on the converter model's torque nothing is raised
  EXPECT_EQ(on_model, 0);
  // AND gated on the measured sample several runs raise a false speed fault: the runs exercise the gate
  EXPECT_GE(on_sample, 2);
}
