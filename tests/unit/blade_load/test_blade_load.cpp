// blade_load tests: Stotsky 2014's Appendix example, harmonic least squares on synthetic and plant signals,
// the t-tests, persistence, adaptation, and fault detection on the plant.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <random>
#include <utility>

#include "blade_load_monitor.hpp"
#include "suspect_inputs.hpp"
#include "turbine_sim.hpp"

using namespace windfdi;
using namespace windfdi::blade_load;

namespace {

const std::string kTable = std::string(WINDFDI_SOURCE_DEPLOY_DIR) + "/turbine/benchmark_4.8MW_load_table.csv";

MonitorConfig config(YAML::Node n = YAML::Node(YAML::NodeType::Map)) {
  return load_monitor_config(YamlSection(n, "(test)"), TurbineParams{});
}

TEST(Appendix, InformationMatrixAndSchurComplementAsPrinted) {
  // GIVEN regressor A1 with omega 0.0228 and N 83 (Appendix, numerical example)
  const Matrix G = paper_information_matrix(0.0228, 83, 4);
  const double printed[4][4] = {{34.4747, 16.2691, -1.9465, -4.8693},
                                {16.2691, 46.5787, 19.8127, -10.6043},
                                {-1.9465, 19.8127, 37.9209, 22.3866},
                                {-4.8693, -10.6043, 22.3866, 42.5117}};
  // THEN G is the printed matrix to its 4 decimals (tolerance 1e-4)
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) EXPECT_NEAR(G(i, j), printed[i][j], 1e-4) << i << "," << j;
  // AND eq A2 and the closed form of g11 (A3) agree with the sums (1e-9)
  EXPECT_NEAR(
      cosine_sum(0.0228, 83),
      [] {
        double s = 0;
        for (int k = 1; k <= 83; ++k) s += std::cos(0.0228 * k);
        return s;
      }(),
      1e-9);
  EXPECT_NEAR(G(0, 0), 83 / 2.0 + std::sin(83 * 0.0228) * std::cos(84 * 0.0228) / (2 * std::sin(0.0228)),
              1e-9);
  // WHEN partitioned, G is not SDD, A and the Schur complement are SDD and positive definite, and the
  // Schur complement is the printed one (tolerance 1e-3: the paper prints 4 decimals of G)
  const Partition p = partition(G);
  EXPECT_FALSE(p.g_sdd);
  EXPECT_TRUE(p.a_sdd);
  EXPECT_TRUE(p.s_sdd);
  EXPECT_TRUE(p.a_pd);
  EXPECT_TRUE(p.s_pd);
  EXPECT_NEAR(p.S(0, 0), 26.7629, 1e-3);
  EXPECT_NEAR(p.S(0, 1), 26.5384, 1e-3);
  EXPECT_NEAR(p.S(1, 0), 26.5384, 1e-3);
  EXPECT_NEAR(p.S(1, 1), 40.0503, 1e-3);
}

// Four harmonics plus white noise (the setting of Figure 2), normalised units.
double run_synthetic(RegressorMode mode, double phase1, uint64_t seed) {
  HarmonicConfig c;
  c.mode = mode;
  c.mean_time = 0.0;
  const double omega = 1.3, dt = 0.01;  // rad/s: about 483 samples per revolution
  HarmonicEstimator est(c);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.1);
  const double A[4] = {1.0, 0.5, 0.3, 0.2}, ph[4] = {phase1, 1.0, -0.5, 2.0};
  double se = 0.0;
  int n = 0;
  for (int k = 1; k <= 20000; ++k) {
    const double psi = omega * dt * k;  // the paper's omega k; azimuth mode sees it as the measured azimuth
    double y = noise(rng);
    for (int h = 0; h < 4; ++h)
      y += A[h] * std::cos((h + 1) * psi + (mode == RegressorMode::kPaper ? 0.0 : ph[h]));
    est.update(y, std::fmod(psi, 2 * M_PI), omega);
    if (k % 100 == 0 && est.solve().valid) {
      se += (est.amplitude() - A[0]) * (est.amplitude() - A[0]);
      ++n;
    }
  }
  EXPECT_GT(n, 150);
  return std::sqrt(se / std::max(n, 1));
}

TEST(SuspectInputs, APitchReadingOffItsActuatorsResponseIsSuspectWithinHalfASecond) {
  // GIVEN a blade whose reference swings 4 deg at 0.5 Hz (a fast IPC-like demand, 12.6 deg/s at its
  // steepest: the rate limit clips it) and whose reading is the healthy actuator's angle, exactly, until 20
  // s, then 1 deg high (a biased sensor); the other blades idle at their reference
  SuspectInputConfig c;
  c.pitch_mismatch = 0.0;  // the old |reading - reference| test off: this tests the response alone
  SuspectInputs suspects(c, 0.01);
  PitchActuator blade{5.0, 0.0};
  double first_suspect = -1.0, max_healthy = 0.0;
  for (int k = 0; k < 3000; ++k) {
    FrameSample s;
    s.t = 0.01 * k;
    s.valid_mask = kValidPitch1 | (kValidPitch1 << 1) | (kValidPitch1 << 2);
    const double ref = 5.0 + 4.0 * std::sin(M_PI * s.t);
    s.pitch = {blade.angle + (s.t >= 20.0 ? 1.0 : 0.0), 5.0, 5.0};
    s.pitch_ref = {ref, 5.0, 5.0};
    const bool suspect = suspects.update(s);
    if (s.t < 20.0) max_healthy = std::max(max_healthy, std::fabs(suspects.pitch_response_departure(0)));
    if (suspect && first_suspect < 0.0) first_suspect = s.t;
    for (int i = 0; i < 5; ++i)  // the plant's 500 Hz
      blade.step(ref, 0.002, c.pitch_omega_n, c.pitch_zeta, c.pitch_rate_limit, c.pitch_min, c.pitch_max);
  }
  // THEN the healthy reading departs from the response by integration error only, rate limit included
  EXPECT_LT(max_healthy, 1e-3);
  // AND the 1 deg offset is suspect once its 0.5 s low-pass passes 0.5 deg: ln 2 x 0.5 s = 0.35 s
  EXPECT_NEAR(first_suspect, 20.35, 0.02);
  EXPECT_NEAR(suspects.pitch_response_departure(0), 1.0, 0.01);
}

TEST(MonitorConfig, TheIdlingSpeedAndTheMomentRangeAreTheTurbinesOwn) {
  // GIVEN the shipped configuration and each shipped turbine
  const std::string deploy = WINDFDI_SOURCE_DEPLOY_DIR;
  const YamlSection shipped = YamlSection::load_file(deploy + "/config/blade_load.yaml");
  const TurbineParams bench{}, two = load_turbine_params_file(deploy + "/turbine/example_2MW.yaml");
  // THEN the rotor speed below which nothing is monitored is a share of the rated rotor speed (the 0.5 rad/s
  // tuned on the benchmark rotor would be most of the region 2 of a rotor rated at 7.5 rpm) ...
  EXPECT_NEAR(load_monitor_config(shipped, bench).min_rotor_speed, 0.5, 0.001);
  EXPECT_NEAR(load_monitor_config(shipped, two).min_rotor_speed, 0.659, 0.001);
  // ... the healthy pitch actuator the readings are judged against is the turbine file's ...
  TurbineParams slow = bench;
  slow.pitch_omega_n = 6.0, slow.pitch_rate_limit = 5.0;
  EXPECT_EQ(load_monitor_config(shipped, slow).suspect_inputs.pitch_omega_n, 6.0);
  EXPECT_EQ(load_monitor_config(shipped, slow).suspect_inputs.pitch_rate_limit, 5.0);
  EXPECT_EQ(load_monitor_config(shipped, bench).suspect_inputs.pitch_response_mismatch,
            SuspectInputConfig{}.pitch_response_mismatch);
  // ... and a blade moment is out of range beyond the rotor's own root moment at a thrust coefficient of 1 in
  // 25 m/s: the 5e7 N m of the benchmark rotor, a third of it on the 2 MW one
  EXPECT_NEAR(load_monitor_config(shipped, bench).validity.max_moment, 5.08e7, 0.01e7);
  EXPECT_NEAR(load_monitor_config(shipped, two).validity.max_moment, 1.71e7, 0.01e7);
  // AND the absolute keys still give them in rad/s and N m
  const MonitorConfig absolute =
      load_monitor_config(YamlSection(YAML::Load("min_rotor_speed: 0.4\nmax_moment: 3.0e7"), "x.yaml"), two);
  EXPECT_DOUBLE_EQ(absolute.min_rotor_speed, 0.4);
  EXPECT_DOUBLE_EQ(absolute.validity.max_moment, 3.0e7);
}

TEST(LoadTable, TheTurbinesOwnTableIsTheShippedOne) {
  // GIVEN the load table built from each shipped turbine's file at start (load_table_file "", the default)
  const std::string deploy = WINDFDI_SOURCE_DEPLOY_DIR;
  for (const std::string name : {"benchmark_4.8MW", "example_2MW"}) {
    const LoadTable built =
        LoadTable::from_turbine(load_turbine_params_file(deploy + "/turbine/" + name + ".yaml"));
    const LoadTable shipped = LoadTable::load_csv(deploy + "/turbine/" + name + "_load_table.csv");
    // THEN it is the table windfdi-blade-load-table wrote for it, to the CSV's ten digits, between the nodes
    // too
    ASSERT_EQ(built.n_lambda(), shipped.n_lambda());
    ASSERT_EQ(built.n_pitch(), shipped.n_pitch());
    double worst = 0.0;
    for (double lambda = 0.1; lambda < 20.0; lambda += 0.37)
      for (double pitch = -4.9; pitch < 45.0; pitch += 0.83)
        worst = std::max(worst, std::fabs(built.k(lambda, pitch) - shipped.k(lambda, pitch)) /
                                    std::max(1.0, std::fabs(shipped.k(lambda, pitch))));
    EXPECT_LT(worst, 1e-8) << name;
  }
}

TEST(HarmonicEstimator, FourHarmonicsWithNoiseWithinTwoPercent) {
  // GIVEN A = 1, 0.5, 0.3, 0.2 and noise 0.1 at constant speed, window one revolution
  // THEN the paper's cosine regressor (phase 0, as it assumes) and the default cos+sin regressor (any phase)
  // both recover A_1 within 2 % rms
  EXPECT_LT(run_synthetic(RegressorMode::kPaper, 0.0, 1), 0.02);
  for (double phase : {0.0, 0.7, 2.5})
    EXPECT_LT(run_synthetic(RegressorMode::kAzimuth, phase, 2), 0.02) << phase;
}

TEST(HarmonicEstimator, PaperRegressorIsBlindToAnUnknownPhase) {
  // GIVEN the same signal with the first harmonic 90 deg out of the assumed phase: cosine-only sees ~0
  HarmonicConfig c;
  c.mode = RegressorMode::kPaper;
  c.mean_time = 0.0;
  HarmonicEstimator est(c);
  for (int k = 1; k <= 2000; ++k) est.update(std::sin(1.3 * 0.01 * k), 0.0, 1.3);
  ASSERT_TRUE(est.solve().valid);
  EXPECT_LT(est.amplitude(), 0.05);  // the true amplitude is 1
}

TEST(HarmonicEstimator, RefusesWindowsShorterThanARevolutionAndUsesThePartitionWhenNotSdd) {
  // GIVEN cos+sin with a fixed window of a third of a revolution
  HarmonicConfig c;
  c.window_samples = 160;
  c.mean_time = 0.0;
  HarmonicEstimator short_win(c);
  for (int k = 1; k <= 1000; ++k)
    short_win.update(std::cos(1.3 * 0.01 * k), std::fmod(1.3 * 0.01 * k, 2 * M_PI), 1.3);
  // THEN it is refused (not positive definite or ill-conditioned), never published
  EXPECT_FALSE(short_win.solve().valid);
  EXPECT_EQ(short_win.info().path, SolvePath::kPartitioned);
  // GIVEN the paper's regressor on the Appendix window (omega 0.0228 rad/sample, N 83): not SDD
  HarmonicConfig p;
  p.mode = RegressorMode::kPaper;
  p.window_samples = 83;
  p.mean_time = 0.0;
  p.dt = 1.0;
  p.min_rcond = 1e-6;
  HarmonicEstimator paper(p);
  for (int k = 1; k <= 83; ++k)
    paper.update(2.0 * std::cos(0.0228 * k) + 0.5 * std::cos(2 * 0.0228 * k), 0.0, 0.0228);
  // THEN the partitioned path proves it positive definite and solves exactly (1e-6)
  ASSERT_TRUE(paper.solve().valid) << paper.info().reason;
  EXPECT_EQ(paper.info().path, SolvePath::kPartitioned);
  EXPECT_NEAR(paper.amplitude(), 2.0, 1e-6);
  // AND a full revolution with cos+sin is SDD, solved by a few Gauss-Seidel sweeps
  HarmonicConfig d;
  d.mean_time = 0.0;
  HarmonicEstimator rev(d);
  for (int k = 1; k <= 3000; ++k)
    rev.update(std::cos(1.3 * 0.01 * k - 0.4), std::fmod(1.3 * 0.01 * k, 2 * M_PI), 1.3);
  ASSERT_TRUE(rev.solve().valid);
  EXPECT_EQ(rev.info().path, SolvePath::kSdd);
  EXPECT_NEAR(rev.amplitude(), 1.0, 1e-3);
}

TEST(HarmonicEstimator, RecursiveInformationMatrixMatchesADirectSum) {
  // GIVEN 200000 add/drop updates with re-forming every 2000 samples, and a varying speed
  HarmonicConfig c;
  HarmonicEstimator est(c);
  double psi = 0.0;
  for (int k = 0; k < 200000; ++k) {
    const double w = 1.2 + 0.4 * std::sin(k * 1e-4);
    psi = std::fmod(psi + w * 0.01, 2 * M_PI);
    est.update(5e6 + 1e6 * std::cos(psi), psi, w);
  }
  // THEN G equals the direct sum over the window's regressors (relative 1e-9): rebuild it from the azimuths
  const Matrix G = est.information_matrix();
  EXPECT_NEAR(G(0, 0) + G(1, 1), est.size(), 1e-6 * est.size());  // cos^2 + sin^2 = 1 per sample
  EXPECT_TRUE(est.solve().valid);
}

TEST(Statistics, StudentTCriticalValues) {
  // Tables: t(0.975, 10) = 2.2281, t(0.995, 30) = 2.7500; normal limit for alpha 1e-6: 4.8916 (1e-3)
  EXPECT_NEAR(student_t_critical(0.05, 10), 2.2281, 1e-3);
  EXPECT_NEAR(student_t_critical(0.01, 30), 2.7500, 1e-3);
  EXPECT_NEAR(student_t_critical(1e-6, 1e6), 4.8916, 1e-3);
  EXPECT_NEAR(student_t_cdf(0.0, 5), 0.5, 1e-12);
}

struct PlantRun {
  double rms_error = 0.0;  // sensor amplitude vs truth, relative rms
  double rms_abs_over_mean = 0.0;
  double rms_abs = 0.0;  // N m
  std::vector<FaultEvent> events;
  int adaptations = 0;
  uint64_t gated_revolutions = 0, lull_revolutions = 0, suspect_samples = 0;
  double max_ratio[kChannels] = {};
};

/// Samples a starved service loses: `length` s of them every `every` s (0: none), from 60 s on.
struct SampleLosses {
  double every = 0.0, length = 0.0;
};

PlantRun run_plant(double wind, double ti, double shear, double shear_var, int seconds,
                   const std::vector<plant::FaultSpec>& faults, uint64_t seed, const MonitorConfig& c,
                   LoadTable table, bool drop_lidar_after = false, SampleLosses losses = {},
                   const TurbineParams& turbine = TurbineParams{}, const std::string& turbine_id = "WT01") {
  plant::TurbineScenario t;
  t.id = turbine_id;  // part of the plant's random streams
  t.wind.mean = wind;
  t.wind.turbulence_intensity = ti;
  t.wind.shear_exponent = shear;
  t.wind.shear_variation = shear_var;
  plant::TurbineSim sim(turbine, t, faults, seed, 100.0);
  BladeLoadMonitor m(c, std::move(table));
  PlantRun r;
  BladeLoadOutput o;
  double se = 0, sa = 0, st = 0;
  int n = 0;
  bool lost = false;
  for (int k = 0; k < seconds * 100; ++k) {
    FrameSample s = sim.step();
    if (drop_lidar_after && s.t > 200.0) s.lidar_v_upper = s.lidar_v_lower = kNaN;
    if (losses.every > 0.0 && s.t > 60.0 && std::fmod(s.t, losses.every) < losses.length) {
      lost = true;
      continue;
    }
    m.update(s, lost, r.events);
    lost = false;
    if (m.estimate_due(o) && s.t > 60.0)
      for (int b = 0; b < 3; ++b)
        if (o.valid[b] && std::isfinite(sim.truth().a1[b])) {
          const double tr = sim.truth().a1[b];
          se += std::pow(o.a1_sensor[b] / tr - 1.0, 2);
          sa += std::pow(o.a1_sensor[b] - tr, 2);
          st += tr;
          ++n;
        }
  }
  r.rms_error = std::sqrt(se / std::max(n, 1));
  r.rms_abs = std::sqrt(sa / std::max(n, 1));
  r.rms_abs_over_mean = r.rms_abs / (st / std::max(n, 1));
  r.adaptations = m.adaptations();
  r.gated_revolutions = m.gated_revolutions();
  r.lull_revolutions = m.lull_revolutions();
  r.suspect_samples = m.suspect_samples();
  for (int ch = 0; ch < kChannels; ++ch) r.max_ratio[ch] = m.max_ratio(ch);
  return r;
}

TEST(PlantAmplitude, SteadyWindWithinFivePercentOfTruth) {
  // GIVEN the plant in steady wind (no turbulence) with shear 0.2, tower shadow and sensor noise, IPC on
  for (double wind : {8.0, 12.0, 16.0, 20.0}) {
    const auto r = run_plant(wind, 0.0, 0.2, 0.0, 200, {}, 3, config(), LoadTable::load_csv(kTable));
    // THEN the strain-gauge amplitude is within 5 % rms of the plant's truth. Above rated the IPC drives the
    // true first harmonic towards zero, where a relative error means nothing: the error is taken relative
    // to the mean true amplitude there.
    std::printf("[measured] steady %g m/s: rms amplitude error %.4f relative, %.0f N m\n", wind, r.rms_error,
                r.rms_abs);
    if (wind < 18.0) {
      EXPECT_LT(r.rms_error, 0.05) << wind;
    }
    // At 20 m/s the true amplitude is about 1e3 N m (0.03 % of the 4e6 N m mean load): the estimate must sit
    // at the noise floor, 2e4 N m / sqrt(samples per revolution) ~ 1.5e3 N m.
    else
      EXPECT_LT(r.rms_abs, 5e3) << wind;
  }
}

plant::FaultSpec fault(const std::string& target, const std::string& type, double start) {
  auto f = plant::FaultSpec::make("WT01", target, type, start);
  return f;
}

const FaultEvent* first_raised(const std::vector<FaultEvent>& ev, const std::string& component,
                               double after) {
  for (const auto& e : ev)
    if (e.raised && e.component == component && e.t >= after) return &e;
  return nullptr;
}

TEST(PlantDetection, AbruptTenPercentGainDetectedWithinFiveSeconds) {
  // GIVEN the sensor_abrupt scenario's turbulence and shear (TI 0.08, shear 0.25), a 10 % gain on blade 2 at
  // 400 s (after the 100 s learning), at 8, 12, 16 and 20 m/s, two seeds
  for (uint64_t seed : {21u, 31u})
    for (double wind : {8.0, 12.0, 16.0, 20.0}) {
      auto f = fault("blade_moment_2", "gain", 400.0);
      f.gain = 1.1;
      const auto r = run_plant(wind, 0.08, 0.25, 0.0, 430, {f}, seed, config(), LoadTable::load_csv(kTable));
      const FaultEvent* e = first_raised(r.events, "blade_moment_sensor_2", 400.0);
      ASSERT_NE(e, nullptr) << wind;
      std::printf("[measured] abrupt %g m/s seed %llu: %s after %.1f s (%s, |t| %.1f vs %.1f)\n", wind,
                  static_cast<unsigned long long>(seed), e->fault.c_str(), e->t - 400.0, e->detail.c_str(),
                  std::fabs(e->statistic), e->threshold);
      // THEN sensor_abrupt on blade 2 within 5 s, and nothing raised before the fault or on another blade
      EXPECT_EQ(e->fault, "sensor_abrupt") << wind;
      EXPECT_LE(e->t - 400.0, 5.0) << wind;
      for (const auto& x : r.events)
        EXPECT_TRUE(x.component == "blade_moment_sensor_2" && x.t >= 400.0)
            << wind << " " << x.component << " " << x.t;
    }
}

// "component fault raised@t (detail); ..." of every event, for messages.
std::string event_sequence(const std::vector<FaultEvent>& events) {
  std::string seq;
  for (const auto& e : events)
    seq += e.component + " " + e.fault + (e.raised ? " raised@" : " cleared@") +
           std::to_string(static_cast<int>(e.t)) + " (" + e.detail + "); ";
  return seq;
}

TEST(PlantDetection, APersistentGainStaysAbruptForMinutes) {
  // GIVEN a 10 % gain on blade 2 from 250 s that stays, 16 m/s, TI 0.08, shear 0.25, for 450 s after it
  for (uint64_t seed : {7u, 21u, 31u}) {
    auto f = fault("blade_moment_2", "gain", 250.0);
    f.gain = 1.1;
    const auto r = run_plant(16.0, 0.08, 0.25, 0.0, 700, {f}, seed, config(), LoadTable::load_csv(kTable));
    // THEN one event: sensor_abrupt raised on blade 2, never cleared nor re-classified as intermittent while
    // turbulence moves the statistic around its critical value
    const std::string seq = event_sequence(r.events);
    std::printf("[measured] persistent gain seed %llu: %s\n", static_cast<unsigned long long>(seed),
                seq.c_str());
    ASSERT_EQ(r.events.size(), 1u) << seed << ": " << seq;
    EXPECT_EQ(r.events[0].fault, "sensor_abrupt") << seed;
    EXPECT_EQ(r.events[0].component, "blade_moment_sensor_2") << seed;
  }
}

TEST(PlantDetection, APersistentGainStaysAbruptThroughShortHolesOfLostSamples) {
  // GIVEN the persistent gain above, and 0.2 s of samples lost every 7 s (a loaded host): each hole restarts
  // the windows, which refill for a revolution with no test able to judge
  for (uint64_t seed : {7u, 21u}) {
    auto f = fault("blade_moment_2", "gain", 250.0);
    f.gain = 1.1;
    const auto r = run_plant(16.0, 0.08, 0.25, 0.0, 500, {f}, seed, config(), LoadTable::load_csv(kTable),
                             false, SampleLosses{7.0, 0.2});
    // THEN still one event, sensor_abrupt on blade 2: a refill is no quiet spell, so no "return" and no
    // sensor_intermittent a revolution later (it was, 50 s after the step)
    const std::string seq = event_sequence(r.events);
    ASSERT_EQ(r.events.size(), 1u) << seed << ": " << seq;
    EXPECT_EQ(r.events[0].fault, "sensor_abrupt") << seed;
    EXPECT_EQ(r.events[0].component, "blade_moment_sensor_2") << seed;
  }
}

TEST(PlantDetection, DriftOfOnePercentPerMinuteDetectedBeforeFivePercentAndHeld) {
  // GIVEN the sensor_drift scenario's wind and 900 N m/s (1 % of the mean load per minute) on blade 1 at 300
  // s, three turbulence seeds, 400 s of drift
  for (uint64_t seed : {22u, 7u, 31u}) {
    auto f = fault("blade_moment_1", "drift", 300.0);
    f.rate = 900.0;
    const auto r = run_plant(16.0, 0.08, 0.25, 0.0, 700, {f}, seed, config(), LoadTable::load_csv(kTable));
    const std::string seq = event_sequence(r.events);
    std::printf("[measured] drift seed %llu: %s\n", static_cast<unsigned long long>(seed), seq.c_str());
    // THEN one event: sensor_drift raised on blade 1 before 5 % (300 s), and held while the drift grows (the
    // drift's own effect on the other blades must not read as noise that hides it again)
    ASSERT_EQ(r.events.size(), 1u) << seed << ": " << seq;
    EXPECT_TRUE(r.events[0].raised) << seed;
    EXPECT_EQ(r.events[0].fault, "sensor_drift") << seed;
    EXPECT_EQ(r.events[0].component, "blade_moment_sensor_1") << seed;
    EXPECT_GT(r.events[0].t, 300.0) << seed;
    EXPECT_LE(r.events[0].t - 300.0, 300.0) << seed;
  }
}

TEST(PlantDetection, ASuiteSizedDriftThatEndsIsFoundOnTheMeanLoadAndNamedOnce) {
  // GIVEN the example 2 MW turbine and drifts the multi-fault suite draws on it (1 % of its mean load per
  // minute for 120 s, then the gauge is repaired) on blade 3 at 7.5, 9 and 12 m/s in 15 % turbulence, four
  // seeds each. A constant added to a gauge moves its mean load, not its first harmonic: judged at the first
  // harmonic's 1e-8 and on the LIDAR-normalised mean alone, 3 of 5 such drifts of suite seed 64 ended
  // unreported, and 4 of these 12 (measured before the change).
  const std::string deploy = WINDFDI_SOURCE_DEPLOY_DIR;
  const TurbineParams two = load_turbine_params_file(deploy + "/turbine/example_2MW.yaml");
  const MonitorConfig c = load_monitor_config(YamlSection(YAML::Node(YAML::NodeType::Map), "(test)"), two);
  int found = 0;
  for (double wind : {7.5, 9.0, 12.0})
    for (uint64_t seed : {4u, 9u, 13u, 21u}) {
      auto f = fault("blade_moment_3", "drift", 300.0);
      f.rate = -300.0;
      f.end = 420.0;
      const auto r =
          run_plant(wind, 0.15, 0.25, 0.03, 700, {f}, seed, c,
                    LoadTable::load_csv(deploy + "/turbine/example_2MW_load_table.csv"), false, {}, two);
      const std::string seq = event_sequence(r.events);
      std::printf("[measured] 2 MW suite drift %g m/s seed %llu: %s\n", wind,
                  static_cast<unsigned long long>(seed), seq.c_str());
      // THEN sensor_drift on blade 3 while it drifts, never renamed (intermittent) when the gauge is
      // repaired, and nothing else raised
      int raised = 0;
      for (const auto& e : r.events)
        if (e.raised) {
          ++raised;
          EXPECT_EQ(e.component, "blade_moment_sensor_3") << seq;
          EXPECT_EQ(e.fault, "sensor_drift") << seq;
          EXPECT_GT(e.t, 300.0) << seq;
          EXPECT_LT(e.t, 425.0) << seq;
        }
      EXPECT_LE(raised, 1) << seq;
      found += raised;
    }
  std::printf("[measured] 2 MW suite-sized drifts found: %d of 12\n", found);
  EXPECT_GE(found, 11);
}

TEST(PlantDetection, ADriftsReflectionOnTheOtherBladesIsNoSecondDrift) {
  // GIVEN the example 2 MW turbine at 12 m/s, 8 % turbulence, shear 0.26, blade 1's gauge drifting by
  // -325 N m/s for 130 s (multi-fault suite seed 72, judged: the cross-blade residuals of blades 2 and 3 move
  // by minus half of blade 1's, and 42 s after blade 1's drift was raised blade 3's passed the mean-load
  // level and the isolation test on noise: a second drift, on a healthy gauge)
  const std::string deploy = WINDFDI_SOURCE_DEPLOY_DIR;
  const TurbineParams two = load_turbine_params_file(deploy + "/turbine/example_2MW.yaml");
  const MonitorConfig c = load_monitor_config(YamlSection(YAML::Node(YAML::NodeType::Map), "(test)"), two);
  int found = 0, others = 0;
  for (uint64_t seed = 1; seed <= 12; ++seed) {
    auto f = fault("blade_moment_1", "drift", 300.0);
    f.rate = -325.5;
    f.end = 430.0;
    const auto r =
        run_plant(12.1, 0.08, 0.257, 0.03, 600, {f}, seed, c,
                  LoadTable::load_csv(deploy + "/turbine/example_2MW_load_table.csv"), false, {}, two);
    const std::string seq = event_sequence(r.events);
    std::printf("[measured] 2 MW drift and its reflection, seed %llu: %s\n",
                static_cast<unsigned long long>(seed), seq.c_str());
    for (const auto& e : r.events)
      if (e.raised) (e.component == "blade_moment_sensor_1" ? found : others) += 1;
  }
  // THEN blade 1's drift is found, and no other blade is reported
  std::printf("[measured] drifts found %d of 12, reports on the healthy blades %d\n", found, others);
  EXPECT_GE(found, 10);
  EXPECT_EQ(others, 0);
}

TEST(PlantDetection, AFastDriftFirstSeenByTheOutlierTestIsStillADrift) {
  // GIVEN drifts of 1.45 % of the mean load per minute at 8 and 12 m/s in 7.6 % turbulence, shear 0.29, ten
  // seeds: the outlier test often confirms them before the moving-window test (multi-fault suite seed 13,
  // where one revolution two back decided the shape and named 3 of 20 such drifts sensor_abrupt here)
  int drifts = 0, abrupt = 0;
  for (uint64_t seed = 1; seed <= 10; ++seed)
    for (double wind : {8.0, 12.0}) {
      auto f = fault("blade_moment_2", "drift", 300.0);
      f.rate = (seed % 2 ? -1.0 : 1.0) * 1300.0;
      const auto r =
          run_plant(wind, 0.076, 0.29, 0.03, 500, {f}, seed, config(), LoadTable::load_csv(kTable));
      const FaultEvent* e = first_raised(r.events, "blade_moment_sensor_2", 300.0);
      std::printf("[measured] fast drift %g m/s seed %llu: %s\n", wind, static_cast<unsigned long long>(seed),
                  event_sequence(r.events).c_str());
      ASSERT_NE(e, nullptr) << wind << " " << seed;
      (e->fault == "sensor_drift" ? drifts : abrupt) +=
          e->fault == "sensor_drift" || e->fault == "sensor_abrupt";
    }
  // THEN every one is raised, and at most one of 20 is named sensor_abrupt (the mean of four revolutions
  // before the detection, signed along it, lies beyond a quarter of the critical value on a ramp, at 0 +- 0.5
  // on a step)
  std::printf("[measured] fast drifts: %d sensor_drift, %d sensor_abrupt of 20\n", drifts, abrupt);
  EXPECT_GE(drifts, 19);
  EXPECT_LE(abrupt, 1);
}

TEST(PlantDetection, ARampConfirmedAFewRevolutionsAfterItsOnsetIsADrift) {
  // GIVEN the benchmark turbine as suite scenario 145_07 runs its WT04 (6.2 m/s, TI 0.126, shear 0.187, seed
  // 145007) with blade 2's gauge drifting 914 N m/s from 300 s: at 6.2 m/s a revolution takes 7 s, and the
  // outlier test confirms the ramp about 5 revolutions after its onset, so the revolutions 2-5 back that tell
  // a ramp from a step lie half before it
  auto run = [](int ramp_revolutions) {
    YAML::Node n(YAML::NodeType::Map);
    n["ramp_revolutions"] = ramp_revolutions;
    auto f = fault("blade_moment_2", "drift", 300.0);
    f.rate = 914.4;
    const auto r = run_plant(6.2, 0.126, 0.187, 0.03, 420, {f}, 145007, config(n),
                             LoadTable::from_turbine({}), false, {}, TurbineParams{}, "WT04");
    const FaultEvent* e = first_raised(r.events, "blade_moment_sensor_2", 300.0);
    std::printf("[measured] ramp_revolutions %d: %s\n", ramp_revolutions, event_sequence(r.events).c_str());
    return e ? e->fault : std::string("none");
  };
  // WHEN only the mean of those four revolutions names the shape
  // THEN the drift reads as a step
  ASSERT_EQ(run(0), "sensor_abrupt") << "the mean no longer misreads this ramp: this test no longer tests";
  // WHEN the two revolutions before the newest, both above a quarter of the critical value, name it too
  // THEN it is a drift (a step confirmed within ~1.1 revolutions leaves at most one of them raised; the step
  // side: APersistentGainStaysAbruptForMinutes, ADriftThatGrewThroughAHoldIsADriftAndAStepAStep)
  EXPECT_EQ(run(2), "sensor_drift");
}

TEST(PlantDetection, ADriftThatGrewThroughAHoldIsADriftAndAStepAStep) {
  // GIVEN blade_load holding its judgement from 290 s to 400 s (+ context_hold) while sensor_bias reports
  // blade 2's pitch sensor, and in that hold either a drift of 1.45 % of the mean load per minute or a 10 %
  // gain on blade 1 from 300 s, at 12 and 16 m/s, two seeds (suite seeds 35-37: 5 of 5 drifts that grew
  // through a pitch or speed fault's hold were named sensor_abrupt: the revolutions before the detection,
  // which tell a ramp from a step, were held)
  for (const char* type : {"drift", "gain"})
    for (double wind : {12.0, 16.0})
      for (uint64_t seed : {3u, 8u}) {
        auto f = fault("blade_moment_1", type, 300.0);
        f.rate = 1300.0;
        f.gain = 1.1;
        plant::TurbineScenario t;
        t.id = "WT01";
        t.wind.mean = wind;
        t.wind.turbulence_intensity = 0.08;
        t.wind.shear_exponent = 0.2;
        plant::TurbineSim sim(TurbineParams{}, t, {f}, seed, 100.0);
        BladeLoadMonitor m(config(), LoadTable::load_csv(kTable));
        std::vector<FaultEvent> events;
        for (int k = 0; k < 520 * 100; ++k) {
          const FrameSample s = sim.step();
          if (k == 290 * 100 || k == 400 * 100) {
            InputContext context;
            context.pitch_sensor_suspect[1] = k == 290 * 100;
            m.set_context(context, s.t);
          }
          m.update(s, false, events);
        }
        // THEN blade 1 is raised once the hold is over, with the fault's own class first
        const FaultEvent* e = first_raised(events, "blade_moment_sensor_1", 300.0);
        std::printf("[measured] %s through a hold, %g m/s seed %llu: %s\n", type, wind,
                    static_cast<unsigned long long>(seed), event_sequence(events).c_str());
        ASSERT_NE(e, nullptr) << type << " " << wind << " " << seed;
        EXPECT_GE(e->t, 400.0) << type << " " << wind << " " << seed;
        EXPECT_EQ(e->fault, std::string(type) == "drift" ? "sensor_drift" : "sensor_abrupt")
            << wind << " " << seed << ": " << e->detail;
      }
}

TEST(PlantDetection, IntermittentFaultClassifiedAsIntermittent) {
  // GIVEN the sensor_intermittent scenario's fault (gain 1.3, 30 % of a 20 s period: on 6 s, off 14 s) on
  // blade 3 at 400 s
  auto f = fault("blade_moment_3", "intermittent", 400.0);
  f.gain = 1.3;
  f.period = 20.0;
  f.duty = 0.3;
  const auto r = run_plant(16.0, 0.08, 0.25, 0.0, 520, {f}, 23, config(), LoadTable::load_csv(kTable));
  const FaultEvent* first = first_raised(r.events, "blade_moment_sensor_3", 400.0);
  ASSERT_NE(first, nullptr);
  // THEN the first episode is raised within 5 s (as abrupt: it cannot yet be told from one)
  EXPECT_EQ(first->fault, "sensor_abrupt");
  EXPECT_LE(first->t - 400.0, 5.0);
  // AND when the evidence returns to healthy and reappears, sensor_abrupt is cleared and sensor_intermittent
  // raised at the same instant, within the second episode (20-26 s after the onset, + confirmation)
  const FaultEvent* inter = nullptr;
  int cleared_abrupt = 0, raised3 = 0;
  for (const auto& e : r.events) {
    if (e.component != "blade_moment_sensor_3") continue;
    raised3 += e.raised;
    if (!e.raised && e.fault == "sensor_abrupt") ++cleared_abrupt;
    if (e.raised && e.fault == "sensor_intermittent" && !inter) inter = &e;
  }
  ASSERT_NE(inter, nullptr);
  std::printf("[measured] intermittent: first %s after %.1f s, sensor_intermittent after %.1f s\n",
              first->fault.c_str(), first->t - 400.0, inter->t - 400.0);
  EXPECT_EQ(cleared_abrupt, 1);
  EXPECT_GE(inter->t - 400.0, 20.0);
  EXPECT_LE(inter->t - 400.0, 26.0 + 5.0);
  // AND the five further episodes produce no event storm: exactly two raises in 120 s
  EXPECT_EQ(raised3, 2);
  // AND nothing on the healthy blades
  for (const auto& e : r.events) EXPECT_EQ(e.component, "blade_moment_sensor_3") << e.fault << " " << e.t;
}

TEST(PlantDetection, ASpeedSensorFaultHidesNoBladeFaultWhileTheOtherSpeedSensorIsGood) {
  // GIVEN a gain of 1.1 on one speed sensor from 300 s that sensor_bias has placed (the context says so from
  // 302 s; the controller keeps running on the measured generator speed), and the intermittent fault of the
  // scenario above on blade 3 from 400 s
  struct Case {
    const char* speed;
    bool generator_suspect, rotor_suspect, judged;
  };
  const Case cases[] = {{"generator_speed", true, false, true},
                        {"rotor_speed", false, true, true},
                        {"rotor_speed", true, true, false}};
  auto f = fault("blade_moment_3", "intermittent", 400.0);
  f.gain = 1.3;
  f.period = 20.0;
  f.duty = 0.3;
  for (const auto& c : cases) {
    auto gain = fault(c.speed, "gain", 300.0);
    gain.gain = 1.1;
    plant::TurbineScenario t;
    t.id = "WT01";
    t.wind.mean = 16.0;
    t.wind.turbulence_intensity = 0.08;
    t.wind.shear_exponent = 0.25;
    plant::TurbineSim sim(TurbineParams{}, t, {gain, f}, 23, 100.0);
    BladeLoadMonitor m(config(), LoadTable::load_csv(kTable));
    std::vector<FaultEvent> events;
    bool told = false;
    for (int k = 0; k < 480 * 100; ++k) {
      const FrameSample s = sim.step();
      if (!told && s.t >= 302.0) {
        InputContext context;
        context.generator_speed_suspect = c.generator_suspect;
        context.rotor_speed_suspect = c.rotor_suspect;
        m.set_context(context, s.t);
        told = true;
      }
      m.update(s, false, events);
    }
    const FaultEvent* first = first_raised(events, "blade_moment_sensor_3", 400.0);
    if (!c.judged) {
      // THEN with both speed sensors suspect, lambda is unknown and nothing is judged
      EXPECT_EQ(first, nullptr) << c.speed;
    } else {
      // THEN with one speed sensor placed, the load model still holds (lambda from the rotor speed, or from
      // the generator speed over N for a faulty rotor speed): the blade fault is raised within 5 s (the
      // whole speed fault was held before)
      ASSERT_NE(first, nullptr) << c.speed;
      EXPECT_LE(first->t - 400.0, 5.0) << c.speed;
    }
    // AND nothing is raised on the healthy blades
    for (const auto& e : events)
      EXPECT_EQ(e.component, "blade_moment_sensor_3") << c.speed << ": " << e.fault << " " << e.t;
  }
}

TEST(PlantDetection, AnActuatorReportAwaitingMaintenanceHidesNoGaugeFault) {
  // GIVEN high air content in blade 2's actuator from 200 s, which pitch_diag reports from 203 s on (suite
  // set 224, scenario 09: the report stayed raised after the actuator recovered, and a gain of 0.723 on blade
  // 1's gauge 370 s later went unseen), either ending at 300 s or staying; and that gain on blade 1 from 400
  // s, at 16 and 21 m/s
  YAML::Node held_throughout;
  held_throughout["actuator_report_holds"] = true;
  for (bool actuator_recovers : {true, false})
    for (double wind : {16.0, 21.0}) {
      auto air = fault("pitch_actuator_2", "high_air_content", 200.0);
      if (actuator_recovers) air.end = 300.0;
      auto gain = fault("blade_moment_1", "gain", 400.0);
      gain.gain = 0.723;
      auto run = [&](const MonitorConfig& cfg) {
        plant::TurbineScenario t;
        t.id = "WT01";
        t.wind.mean = wind;
        t.wind.turbulence_intensity = 0.12;
        t.wind.shear_exponent = 0.15;
        plant::TurbineSim sim(TurbineParams{}, t, {air, gain}, 9, 100.0);
        BladeLoadMonitor m(cfg, LoadTable::load_csv(kTable));
        std::vector<FaultEvent> events;
        for (int k = 0; k < 480 * 100; ++k) {
          const FrameSample s = sim.step();
          if (k == 203 * 100) {
            InputContext context;
            context.pitch_actuator_suspect[1] = true;
            m.set_context(context, s.t);
          }
          m.update(s, false, events);
        }
        return events;
      };
      const auto held = run(config(held_throughout));
      const auto judged = run(config());
      const FaultEvent* first = first_raised(judged, "blade_moment_sensor_1", 400.0);
      std::printf("[measured] %s actuator, %g m/s: held throughout: %s; through the transient only: %s\n",
                  actuator_recovers ? "recovered" : "faulty", wind, event_sequence(held).c_str(),
                  event_sequence(judged).c_str());
      // THEN held for the whole report (as before stop 63: actuator_report_holds) the gain is not seen
      EXPECT_EQ(first_raised(held, "blade_moment_sensor_1", 400.0), nullptr) << wind;
      // AND held through the report's transient only (as shipped), it is raised as a step within 5 s; the
      // reading is true, and while the actuator is faulty its departure from a healthy actuator's response
      // holds the tests where it matters
      ASSERT_NE(first, nullptr) << wind << (actuator_recovers ? " recovered" : " faulty");
      EXPECT_EQ(first->fault, "sensor_abrupt") << first->detail;
      EXPECT_LE(first->t - 400.0, 5.0) << wind;
      // AND the slow actuator raises nothing on its own blade's or the third blade's gauge
      for (const auto& e : judged) EXPECT_EQ(e.component, "blade_moment_sensor_1") << e.fault << " " << e.t;
    }
}

TEST(LidarLoss, FallsBackToSensorOnlyAndReportsTheLidar) {
  // GIVEN the LIDAR speeds vanish at 200 s
  const auto r = run_plant(12.0, 0.05, 0.2, 0.0, 230, {}, 5, config(), LoadTable::load_csv(kTable), true);
  // THEN lidar sensor_invalid is raised within 1.5 s (invalid_time 1 s + the frozen-turbulence delay's slack)
  const FaultEvent* e = first_raised(r.events, "lidar", 200.0);
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->fault, "sensor_invalid");
  // The delayed LIDAR history still covers D / V (100 m / 12 m/s, about 8.3 s) after the loss, then
  // invalid_time (1 s) and the allowed LIDAR age (1 s).
  EXPECT_LE(e->t - 200.0, 100.0 / 12.0 + 1.0 + 1.0 + 0.5);
}

// The monitor on the plant at 12 m/s (10 % turbulence) for `seconds`; `alter` changes sample k in place or
// drops it (false); the sample after a dropped one, and the one at `gap_at` s, are flagged as following a
// gap.
std::vector<FaultEvent> run_at_12(double seconds, double gap_at,
                                  const std::function<bool(int, FrameSample&)>& alter) {
  plant::TurbineScenario t;
  t.id = "WT01";
  t.wind.mean = 12.0;
  t.wind.turbulence_intensity = 0.1;
  plant::TurbineSim sim(TurbineParams{}, t, {}, 5, 100.0);
  BladeLoadMonitor m(config(), LoadTable::load_csv(kTable));
  std::vector<FaultEvent> events;
  bool dropped = false;
  for (int k = 0; k < static_cast<int>(seconds * 100); ++k) {
    FrameSample s = sim.step();
    if (!alter(k, s)) {
      dropped = true;
      continue;
    }
    m.update(s, std::exchange(dropped, false) || k == static_cast<int>(gap_at * 100), events);
  }
  return events;
}

TEST(LidarLoss, ARestartedPlantAClockStepOrLostSamplesAreNoLidarLoss) {
  // GIVEN a monitor that followed the plant for 300 s, WHEN the plant restarts (its sample time from 0
  // again, flagged as a gap, as the services do when the sequence restarts), its clock steps 5 minutes
  // forward, or 10 s of samples are lost (a frozen service or plant): the reliability campaign's restarted
  // or frozen plant, and a frozen blade_load, raised "no delayed LIDAR speeds" on every turbine
  const auto restart = [](int k, FrameSample& s) {
    if (k >= 300 * 100) s.t -= 300.0;
    return true;
  };
  const auto clock_step = [](int k, FrameSample& s) {
    if (k >= 300 * 100) s.t += 300.0;
    return true;
  };
  const auto lost = [](int k, FrameSample&) { return k < 300 * 100 || k >= 310 * 100; };
  // THEN nothing is raised
  for (const auto& [what, events] : {std::pair{"restart", run_at_12(600.0, 300.0, restart)},
                                     std::pair{"clock step", run_at_12(600.0, 300.0, clock_step)},
                                     std::pair{"lost samples", run_at_12(600.0, 310.0, lost)}})
    EXPECT_TRUE(events.empty()) << what << ": " << events.front().component << " " << events.front().fault
                                << " at " << events.front().t;
  // AND a LIDAR that stays silent after lost samples is still reported, once its D / V has passed
  const auto events = run_at_12(360.0, 310.0, [](int k, FrameSample& s) {
    if (k >= 300 * 100) s.lidar_v_upper = s.lidar_v_lower = kNaN;
    return k < 300 * 100 || k >= 310 * 100;
  });
  const FaultEvent* e = first_raised(events, "lidar", 310.0);
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->fault, "sensor_invalid");
  EXPECT_LE(e->t - 310.0, 100.0 / 12.0 + 1.0 + 1.0 + 1.0);
}

TEST(LidarLoss, LidarFramesLostOnTheWayAreNoLidarLoss) {
  // GIVEN the 24-hour soak's pattern: 2.8 s of LIDAR frames lost on the way five times in 25 s (a loaded
  // reader dropped them from its history), the samples whole
  const auto in_hole = [](double t) {
    for (int i = 0; i < 5; ++i)
      if (t >= 300.0 + 5.0 * i && t < 302.8 + 5.0 * i) return true;
    return false;
  };
  const auto holes = [&](bool told) {
    return [&, told](int, FrameSample& s) {
      if (in_hole(s.t)) {
        s.lidar_v_upper = s.lidar_v_lower = kNaN;
        s.valid_mask &= ~kValidLidar;
      }
      // The service's merge says so at the first sample after each hole (LidarFrames::take_lost).
      s.lidar_lost_on_the_way = told && !in_hole(s.t) && in_hole(s.t - 0.01);
      return true;
    };
  };
  const auto untold = run_at_12(360.0, -1.0, holes(false));
  const auto told = run_at_12(360.0, -1.0, holes(true));
  std::printf("[measured] holes not told: %s; told: %s\n", event_sequence(untold).c_str(),
              event_sequence(told).c_str());
  // THEN a monitor not told of the loss takes the holes for a lost LIDAR (what the soak reported)
  ASSERT_NE(first_raised(untold, "lidar", 300.0), nullptr);
  // AND told, it raises nothing
  EXPECT_TRUE(told.empty()) << told.front().component << " " << told.front().fault << " at "
                            << told.front().t;
  // AND neither do the soak's holes in the samples themselves, 32 to 288 samples five times in 24 s (the
  // service is told by the sequence gap)
  const int lost[5] = {32, 288, 64, 160, 96};
  const auto events = run_at_12(360.0, -1.0, [&](int k, FrameSample&) {
    const int i = (k - 300 * 100) / 480, into = (k - 300 * 100) % 480;
    return !(k >= 300 * 100 && i < 5 && into < lost[i]);
  });
  EXPECT_TRUE(events.empty()) << events.front().component << " " << events.front().fault << " at "
                              << events.front().t;
}

TEST(Persistence, StateRoundTripsAtomically) {
  // GIVEN a state with a learned correction and statistics
  const auto dir = std::filesystem::temp_directory_path() / "windfdi_bl_test";
  std::filesystem::remove_all(dir);
  const std::string path = (dir / "WT01" / "state.yaml").string();
  MonitorState s;
  s.n_lambda = 2;
  s.n_pitch = 3;
  s.table_factors = {1.0, 1.01, 0.99, 1.1, 0.9, 1.0 + 1e-12};
  s.healthy[1][kMeanChannel] = HealthyStats{120, 0.00123, 4.5e-6, 0.2, true};
  // WHEN saved and loaded
  save_state(s, path);
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));  // renamed into place
  MonitorState l;
  ASSERT_TRUE(load_state(path, l));
  // THEN everything is back, bit for bit
  EXPECT_EQ(l.table_factors, s.table_factors);
  EXPECT_EQ(l.healthy[1][kMeanChannel].n, 120);
  EXPECT_DOUBLE_EQ(l.healthy[1][kMeanChannel].mean, 0.00123);
  EXPECT_DOUBLE_EQ(l.healthy[1][kMeanChannel].var, 4.5e-6);
  EXPECT_TRUE(l.healthy[1][kMeanChannel].learned);
  EXPECT_FALSE(l.healthy[0][kModelChannel].learned);
  MonitorState none;
  EXPECT_FALSE(load_state((dir / "absent.yaml").string(), none));
  std::filesystem::remove_all(dir);
}

TEST(Adaptation, UniformWindPullsAWrongTableBackWithinItsBound) {
  // GIVEN a shipped table 8 % too low everywhere, and uniform wind (shear 0) with little turbulence
  LoadTable base = LoadTable::load_csv(kTable);
  MonitorConfig c = config();
  c.learning.learn_time = 60.0;
  c.learning.min_learn_revolutions = 10;
  c.adaptation.revolutions = 10;
  c.adaptation.gain = 0.3;
  LoadTable low = base;
  for (auto& f : low.factors()) f = 0.92;  // the correction starts at the wrong value; the bound is around 1
  const auto r = run_plant(10.0, 0.02, 0.0, 0.0, 900, {}, 9, c, low);
  // THEN it adapted, and no sensor fault was raised on the way
  EXPECT_GT(r.adaptations, 3);
  for (const auto& e : r.events)
    EXPECT_NE(e.component.rfind("blade_moment_sensor", 0), 0u) << e.fault << " " << e.t;
  // GIVEN the same in sheared wind (0.2): no adaptation at all
  const auto sheared = run_plant(10.0, 0.02, 0.2, 0.0, 400, {}, 9, c, low);
  EXPECT_EQ(sheared.adaptations, 0);
}

TEST(Adaptation, SurfaceMovesLocallyAndStaysBounded) {
  // GIVEN a flat table and repeated updates toward +50 % at (7, 2 deg) with bound 15 %
  LoadTable t(0.0, 0.25, 81, -5.0, 0.5, 101, std::vector<double>(81 * 101, 100.0));
  for (int i = 0; i < 200; ++i) t.adapt(7.0, 2.0, 1.5, 0.2, 0.5, 1.5, 0.15);
  // THEN the surface rose at that point to its bound, and not far away (lambda 12, pitch 20)
  EXPECT_NEAR(t.k(7.0, 2.0), 115.0, 1e-9);
  EXPECT_NEAR(t.k(12.0, 20.0), 100.0, 1e-9);
}

TEST(Config, UnknownKeyNamesFileAndKey) {
  YAML::Node n(YAML::NodeType::Map);
  n["signifcance"] = 0.01;
  try {
    config(n);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "signifcance");
  }
}

TEST(Config, OutOfRangeValueNamesTheKey) {
  // GIVEN a significance above its range (0..0.1), a negative confirmation, and a clear_time shorter than the
  // intermittent window (a fault would clear before a recurrence could make it intermittent)
  for (const auto& [key, value] : std::vector<std::pair<std::string, double>>{
           {"significance", 0.5}, {"confirm_revolutions", -1.0}, {"clear_time", 30.0}, {"learn_time", 1.0}}) {
    YAML::Node n(YAML::NodeType::Map);
    n[key] = value;
    try {
      config(n);
      FAIL() << key;
    } catch (const ConfigError& e) {
      EXPECT_EQ(e.key(), key);
    }
  }
  // AND min_a1_share is gone (it was never used): an unknown key now
  YAML::Node n(YAML::NodeType::Map);
  n["min_a1_share"] = 0.02;
  EXPECT_THROW(config(n), ConfigError);
}

TEST(EpisodeClassifier, AbruptThenReturnThenRecurrenceIsIntermittentWithoutStorm) {
  EpisodeConfig c;
  c.return_time = 3.0;
  c.intermittent_window = 60.0;
  c.clear_time = 60.0;
  EpisodeClassifier k(c);
  std::vector<Transition> tr;
  // t = 0: evidence but not yet confirmed -> nothing
  k.update(0.0, true, false, "sensor_abrupt", tr);
  EXPECT_TRUE(tr.empty());
  // t = 4: confirmed -> sensor_abrupt raised
  k.update(4.0, true, true, "sensor_abrupt", tr);
  ASSERT_EQ(tr.size(), 1u);
  EXPECT_EQ(tr[0].fault, "sensor_abrupt");
  EXPECT_TRUE(tr[0].raised);
  tr.clear();
  // t = 10..12.9: quiet for less than return_time, then evidence again: the same episode, no event
  k.update(10.0, false, false, "sensor_abrupt", tr);
  k.update(12.9, false, false, "sensor_abrupt", tr);
  EXPECT_FALSE(k.returned());
  k.update(13.0, true, true, "sensor_abrupt", tr);
  EXPECT_TRUE(tr.empty());
  // t = 14..17: quiet for return_time -> returned (no event)
  k.update(14.0, false, false, "sensor_abrupt", tr);
  k.update(17.0, false, false, "sensor_abrupt", tr);
  EXPECT_TRUE(k.returned());
  EXPECT_TRUE(tr.empty());
  // t = 30: evidence back, not confirmed yet -> nothing
  k.update(30.0, true, false, "sensor_abrupt", tr);
  EXPECT_TRUE(tr.empty());
  // t = 34: confirmed within the window -> sensor_abrupt cleared, sensor_intermittent raised
  k.update(34.0, true, true, "sensor_abrupt", tr);
  ASSERT_EQ(tr.size(), 2u);
  EXPECT_EQ(tr[0].fault, "sensor_abrupt");
  EXPECT_FALSE(tr[0].raised);
  EXPECT_EQ(tr[1].fault, "sensor_intermittent");
  EXPECT_TRUE(tr[1].raised);
  tr.clear();
  // t = 40..80: more episodes (return, recurrence) -> no events
  for (double t = 40.0; t < 80.0; t += 10.0) {
    k.update(t, false, false, "sensor_abrupt", tr);
    k.update(t + 4.0, false, false, "sensor_abrupt", tr);
    k.update(t + 5.0, true, true, "sensor_abrupt", tr);
  }
  EXPECT_TRUE(tr.empty());
  EXPECT_EQ(k.raised(), "sensor_intermittent");
  // t = 76..135.9: quiet, less than clear_time -> still raised; t = 136: clear_time -> cleared
  k.update(76.0, false, false, "sensor_abrupt", tr);
  k.update(135.9, false, false, "sensor_abrupt", tr);
  EXPECT_TRUE(tr.empty());
  k.update(136.0, false, false, "sensor_abrupt", tr);
  ASSERT_EQ(tr.size(), 1u);
  EXPECT_EQ(tr[0].fault, "sensor_intermittent");
  EXPECT_FALSE(tr[0].raised);
  EXPECT_EQ(k.raised(), "");
}

// The moving-window test on synthetic residuals: healthy noise learned, then a quiet spell where blade 1's
// mean-load residual rises to a plateau of 12 revolutions whose 10-revolution mean is just above the drift
// critical value for 3 revolutions (a slow excursion that touches it and falls back), then a ramp (a drift).
// Three blades whose gauges and LIDAR model agree (the residual tests take their channels as given).
BladeEstimates three_equal_blades() {
  BladeEstimates e;
  for (int b = 0; b < 3; ++b) {
    e.sensor_valid[b] = e.model_valid[b] = true;
    e.a_sensor[b] = e.a_model[b] = 1e5;
    e.mean_sensor[b] = e.mean_model[b] = 1e6;
  }
  return e;
}

// Healthy residuals of the synthetic tests: white, of one sd on every blade and channel.
struct WhiteResiduals {
  explicit WhiteResiduals(unsigned seed) : rng(seed) {}
  BladeChannels draw(double sd) {
    BladeChannels x;
    for (auto& blade : x)
      for (double& v : blade) v = sd * unit(rng);
    return x;
  }
  std::mt19937 rng;
  std::normal_distribution<double> unit{0.0, 1.0};
};

// The residual tests of one rotor fed synthetic channels, a revolution at a time.
struct SyntheticRotor {
  SyntheticRotor(const DetectionConfig& d, unsigned seed)
      : tests(d, LearningConfig{}, EpisodeConfig{}), noise(seed) {}
  /// One revolution of channel values `x` at t, then its ticks at 10 Hz; the events they gave. `held`: the
  /// outlier test is held through the revolution (a lull), the drift test sees it.
  std::vector<FaultEvent> turn(double t, double revolution_time, const BladeChannels& x, bool held = false) {
    std::vector<FaultEvent> all, events;
    tests.revolution(t, revolution_time, x, true);
    for (int i = 0; i < static_cast<int>(revolution_time * 10.0); ++i) {
      events.clear();
      if (held)
        tests.hold();
      else
        tests.tick(t + 0.1 * i, revolution_time, x, estimates, true, events);
      all.insert(all.end(), events.begin(), events.end());
    }
    return all;
  }
  ResidualTests tests;
  BladeEstimates estimates = three_equal_blades();
  WhiteResiduals noise;
};

// One gauge off (blade 1): its own cross residual on channel c moves by `shift`, the other blades' by half of
// it the other way.
void shift_blade_1(BladeChannels& x, int c, double shift) {
  x[0][c] += shift;
  x[1][c] -= 0.5 * shift;
  x[2][c] -= 0.5 * shift;
}

struct DriftRun {
  double excursion_raised_at = -1.0;  // s, first sensor_drift during the plateau (-1: none)
  double ramp_raised_at = -1.0;       // s, first sensor_drift during the ramp
};

DriftRun run_drift_tests(int drift_confirm_revolutions) {
  DetectionConfig d;
  d.drift_confirm_revolutions = drift_confirm_revolutions;
  // One critical value: the plateau is placed against it (the looser mean-load level would see it whole).
  d.mean_drift_significance = d.drift_significance;
  SyntheticRotor rotor(d, 7);
  const double revolution_time = 4.0, learn_sd = 0.01;
  DriftRun run;
  double plateau = 0.0;  // set once learned
  const int learn_revolutions = 60, quiet = 30, plateau_revolutions = 12, ramp_start = 150;
  for (int k = 0; k < 260; ++k) {
    const double t = k * revolution_time;
    // After learning, a tenth of the learned noise: the window means follow the shape, not the noise.
    const double sd = k < learn_revolutions ? learn_sd : 0.1 * learn_sd;
    BladeChannels x = rotor.noise.draw(sd);
    const int into_plateau = k - (learn_revolutions + quiet);
    double shift = 0.0;
    if (into_plateau >= 0 && into_plateau < plateau_revolutions) shift = plateau;
    if (k >= ramp_start) shift = 0.02 * plateau * (k - ramp_start);
    shift_blade_1(x, kMeanChannel, shift);
    for (const auto& ev : rotor.turn(t, revolution_time, x))
      if (ev.raised && ev.fault == "sensor_drift" && ev.component == "blade_moment_sensor_1") {
        double& at = k < ramp_start ? run.excursion_raised_at : run.ramp_raised_at;
        if (at < 0) at = t;
      }
    if (k == learn_revolutions) {
      // 1.05 x the critical value of a 10-revolution mean (statistics.hpp) above the learned mean.
      const HealthyChannels& healthy = rotor.tests.healthy();
      EXPECT_TRUE(healthy.learned(kMeanChannel));
      double ne = 1e9;
      for (int b = 0; b < 3; ++b)
        ne = std::min(ne, healthy.at(b, kMeanChannel).n_eff(healthy.at(b, kMeanChannel).n));
      const double critical = student_t_critical(d.drift_significance, ne - 1.0);
      const HealthyStats& h = healthy.at(0, kMeanChannel);
      plateau = h.mean + 1.05 * critical * h.drift_sd(d.drift_window);
    }
  }
  return run;
}

TEST(ResidualTests, AnExcursionThatTouchesTheDriftCriticalValueAndFallsBackRaisesNothing) {
  // At once (drift_confirm_revolutions 1, before): the plateau's three revolutions above the critical value
  // raise a drift; with 4 consecutive revolutions, nothing, and the ramp is still raised, within 4
  // revolutions (16 s) of when the single revolution raised it.
  const DriftRun at_once = run_drift_tests(1);
  EXPECT_GE(at_once.excursion_raised_at, 0.0);
  const DriftRun confirmed = run_drift_tests(4);
  EXPECT_LT(confirmed.excursion_raised_at, 0.0);
  ASSERT_GE(confirmed.ramp_raised_at, 0.0);
  EXPECT_LE(confirmed.ramp_raised_at, (at_once.ramp_raised_at < 0 ? 1e9 : at_once.ramp_raised_at) + 16.0);
}

// The drift test on synthetic mean-load residuals learned with a narrow spread (0.15 % of the load): blade
// 1's gauge mean, against the other gauges and against its LIDAR model alike, stands `plateau` above healthy
// for 15 revolutions (the other blades half of it the other way), then from revolution 160 ramps by 0.05 % a
// revolution. Returns when sensor_drift was raised on blade 1 in each part (-1: never) and the ramp's shift
// then.
struct ShareRun {
  double plateau_raised_at = -1.0, ramp_raised_at = -1.0, ramp_shift_at_raise = 0.0;
};

ShareRun run_drift_share_tests(bool needs_share, double plateau) {
  DetectionConfig d;
  d.drift_raise_needs_share = needs_share;
  SyntheticRotor rotor(d, 5);
  const double revolution_time = 4.0, sd = 0.0015;
  ShareRun run;
  const int plateau_start = 100, plateau_end = 115, ramp_start = 160;
  for (int k = 0; k < 220; ++k) {
    const double t = k * revolution_time;
    BladeChannels x = rotor.noise.draw(sd);
    double shift = k >= plateau_start && k < plateau_end ? plateau : 0.0;
    if (k >= ramp_start) shift = 0.0005 * (k - ramp_start);
    for (const int c : {kMeanChannel, kRawMeanChannel}) shift_blade_1(x, c, shift);
    for (const auto& ev : rotor.turn(t, revolution_time, x))
      if (ev.raised && ev.fault == "sensor_drift" && ev.component == "blade_moment_sensor_1") {
        if (k < ramp_start && run.plateau_raised_at < 0) run.plateau_raised_at = t;
        if (k >= ramp_start && run.ramp_raised_at < 0)
          run.ramp_raised_at = t, run.ramp_shift_at_raise = shift;
      }
  }
  return run;
}

TEST(ResidualTests, AMeanLoadExcursionBelowTheDriftShareIsNoDriftHoweverLargeItsT) {
  // A plateau of 0.8 % is 11-12 t of a 10-revolution mean (critical 7.2) and below the one-revolution
  // outlier test's critical value: the strict level's t alone raised it as a drift (as a healthy 8 m/s
  // minute of suite set 185 at 0.6-0.8 %, peak 0.94 %); with the share it is nothing.
  const ShareRun t_alone = run_drift_share_tests(false, 0.008);
  EXPECT_GE(t_alone.plateau_raised_at, 0.0);
  const ShareRun with_share = run_drift_share_tests(true, 0.008);
  EXPECT_LT(with_share.plateau_raised_at, 0.0);
  // The ramp is raised once past the share (on t alone at 0.9 %; the window mean lags it by half a window)
  ASSERT_GE(with_share.ramp_raised_at, 0.0);
  std::printf(
      "[measured] ramp raised at %.0f s (shift %.2f %%) with the share, %.0f s (%.2f %%) on t alone\n",
      with_share.ramp_raised_at, 100.0 * with_share.ramp_shift_at_raise, t_alone.ramp_raised_at,
      100.0 * t_alone.ramp_shift_at_raise);
  EXPECT_GE(with_share.ramp_shift_at_raise, 0.01);
  EXPECT_LE(with_share.ramp_shift_at_raise, 0.015);
}

// The drift test on synthetic mean-load residuals (learned spread of a revolution 0.6 % of the load, of a
// 10-revolution mean 0.19 %) through a healthy stretch of 15 revolutions as judged suite set 237's (6 MW
// rotor, 8 m/s, shear 0.30): blade 1's ratio to its LIDAR model +1.5 % (the others -0.75 %), and the gauges'
// own cross-blade means +1.0, -1.7 and +0.4 %, which put blade 2 apart, not blade 1. Then from revolution 160
// a real drift of blade 1 ramps by 0.05 % a revolution on both channels. Returns when sensor_drift was raised
// on blade 1 in each part (-1: never).
ShareRun run_wind_on_another_blade(bool witness_isolates, bool count_as_one = true) {
  DetectionConfig d;
  d.mean_witness_isolates = witness_isolates;
  d.mean_channels_count_as_one = count_as_one;
  SyntheticRotor rotor(d, 5);
  const double revolution_time = 8.0, learn_sd = 0.0045;
  ShareRun run;
  const int learn_revolutions = 40, stretch_start = 100, stretch_end = 115, ramp_start = 160;
  for (int k = 0; k < 220; ++k) {
    const double t = k * revolution_time;
    // After learning, less noise: the window means follow the shape, as the 10-revolution means did there.
    BladeChannels x = rotor.noise.draw(k < learn_revolutions ? learn_sd : 0.3 * learn_sd);
    if (k >= stretch_start && k < stretch_end) {
      shift_blade_1(x, kMeanChannel, 0.015);
      x[0][kRawMeanChannel] += 0.010;
      x[1][kRawMeanChannel] -= 0.017;
      x[2][kRawMeanChannel] += 0.004;
    }
    const double ramp = k >= ramp_start ? 0.0005 * (k - ramp_start) : 0.0;
    for (const int c : {kMeanChannel, kRawMeanChannel}) shift_blade_1(x, c, ramp);
    for (const auto& ev : rotor.turn(t, revolution_time, x))
      if (ev.raised && ev.fault == "sensor_drift" && ev.component == "blade_moment_sensor_1") {
        if (k < ramp_start && run.plateau_raised_at < 0) run.plateau_raised_at = t;
        if (k >= ramp_start && run.ramp_raised_at < 0) run.ramp_raised_at = t, run.ramp_shift_at_raise = ramp;
      }
  }
  return run;
}

TEST(ResidualTests, AMeanShiftTheGaugesPutOnAnotherBladeIsNoDrift) {
  // Shared in sign and size, the gauges' means raised blade 1's drift; singling blade 1 out is needed now.
  const ShareRun shared = run_wind_on_another_blade(false);
  EXPECT_GE(shared.plateau_raised_at, 0.0);
  const ShareRun isolated = run_wind_on_another_blade(true);
  EXPECT_LT(isolated.plateau_raised_at, 0.0);
  // The real drift is raised as soon either way.
  ASSERT_GE(isolated.ramp_raised_at, 0.0);
  EXPECT_EQ(isolated.ramp_raised_at, shared.ramp_raised_at);
  // Its two mean-load channels take turns as the larger t; counted per channel, each turn restarted the
  // four revolutions (with this seed, 3 revolutions later).
  const ShareRun per_channel = run_wind_on_another_blade(true, false);
  ASSERT_GE(per_channel.ramp_raised_at, 0.0);
  EXPECT_GT(per_channel.ramp_raised_at, isolated.ramp_raised_at);
  std::printf("[measured] ramp raised at %.0f s (shift %.2f %%); counted per channel %.0f s (%.2f %%)\n",
              isolated.ramp_raised_at, 100.0 * isolated.ramp_shift_at_raise, per_channel.ramp_raised_at,
              100.0 * per_channel.ramp_shift_at_raise);
}

// Blade 1's mean-load channels (healthy noise 0.0015) shifted by burst(k) on revolution k, the outlier test
// held through the revolutions lull(k) names; the classes raised on blade 1, in order.
std::vector<std::string> run_bursts(const DetectionConfig& d, unsigned seed, double revolution_time,
                                    const std::function<double(int)>& burst,
                                    const std::function<bool(int)>& lull) {
  SyntheticRotor rotor(d, seed);
  std::vector<std::string> raised;
  for (int k = 0; k < 130; ++k) {
    BladeChannels x = rotor.noise.draw(0.0015);
    if (const double shift = burst(k); shift != 0.0)
      for (const int c : {kMeanChannel, kRawMeanChannel}) shift_blade_1(x, c, shift);
    for (const auto& ev : rotor.turn(k * revolution_time, revolution_time, x, lull(k)))
      if (ev.raised && ev.component == "blade_moment_sensor_1") raised.push_back(ev.fault);
  }
  return raised;
}

// An intermittent gauge on synthetic mean-load residuals (learned spread 0.15 % of the load): blade 1 reads
// 15 % high for one revolution in every five (4 s revolutions, 20 s period, as the suite's 30 % duty), the
// first burst in a lull, which holds the outlier test but not the drift test. Returns the classes raised on
// blade 1, in order.
std::vector<std::string> run_intermittent_in_a_lull(bool drift_median, bool step_after_quiet, unsigned seed) {
  DetectionConfig d;
  d.drift_median_share = drift_median ? 0.5 : 0.0;
  d.step_after_quiet = step_after_quiet;
  const int first_burst = 100;
  return run_bursts(
      d, seed, 4.0, [&](int k) { return k >= first_burst && (k - first_burst) % 5 == 0 ? 0.15 : 0.0; },
      [&](int k) { return k == first_burst; });
}

TEST(ResidualTests, AnIntermittentGaugesBurstInALullIsNoDriftAndItsNextBurstIsAbrupt) {
  for (unsigned seed = 1; seed <= 10; ++seed) {
    // Before: the drift test raised the first burst from its window mean (1.5 %, 30 t) four revolutions after
    // it had ended, while the outlier test was held; and without that, the span before the second burst held
    // the first one, which read as a ramp: sensor_drift either way (judged suite set 191, medium-speed rotor)
    const auto before = run_intermittent_in_a_lull(false, false, seed);
    ASSERT_FALSE(before.empty()) << seed;
    EXPECT_EQ(before.front(), "sensor_drift") << seed;
    const auto median_only = run_intermittent_in_a_lull(true, false, seed);
    ASSERT_FALSE(median_only.empty()) << seed;
    EXPECT_EQ(median_only.front(), "sensor_drift") << seed;
    // Now: a drift must move the window's median, which a burst does not, and an outlier after two
    // revolutions below the onset level is a step: the second burst is sensor_abrupt, renamed
    // sensor_intermittent when it comes back, and nothing is named a drift
    const auto now = run_intermittent_in_a_lull(true, true, seed);
    ASSERT_GE(now.size(), 2u) << seed;
    EXPECT_EQ(now[0], "sensor_abrupt") << seed;
    EXPECT_EQ(now[1], "sensor_intermittent") << seed;
    EXPECT_EQ(std::count(now.begin(), now.end(), "sensor_drift"), 0) << seed;
  }
}

// An intermittent gauge on a slow rotor (judged in stop 61 on the 6 and 1.5 MW examples: 6 s bursts 14 s
// apart, revolutions of 4.5-5.6 s): a burst covers two revolutions, the second partly, and one quiet
// revolution lies between bursts. The first burst falls in a lull (held). Returns the classes raised on
// blade 1, in order.
std::vector<std::string> run_intermittent_one_quiet_revolution(double quiet_step_strength, unsigned seed) {
  DetectionConfig d;
  d.quiet_step_strength = quiet_step_strength;
  const int first_burst = 100;
  const auto phase = [&](int k) { return k >= first_burst ? (k - first_burst) % 3 : -1; };
  return run_bursts(
      d, seed, 5.6, [&](int k) { return phase(k) == 0   ? 0.15
                                        : phase(k) == 1 ? 0.08
                                                        : 0.0; },
      [&](int k) { return k == first_burst || k == first_burst + 1; });
}

TEST(ResidualTests, AnIntermittentGaugeWithOneQuietRevolutionBetweenBurstsIsNoDrift) {
  for (unsigned seed = 1; seed <= 10; ++seed) {
    // Stop 60's rule asked for two quiet revolutions before the newest: the second burst was named a drift
    // (its span held the first burst, which read as a ramp)
    const auto two_quiet = run_intermittent_one_quiet_revolution(0.0, seed);
    ASSERT_FALSE(two_quiet.empty()) << seed;
    EXPECT_EQ(two_quiet.front(), "sensor_drift") << seed;
    // Now one quiet revolution after a burst of twice the critical value or more is an episode that ended:
    // sensor_abrupt, renamed sensor_intermittent when it comes back, never a drift
    const auto now = run_intermittent_one_quiet_revolution(2.0, seed);
    ASSERT_GE(now.size(), 2u) << seed;
    EXPECT_EQ(now[0], "sensor_abrupt") << seed;
    EXPECT_EQ(now[1], "sensor_intermittent") << seed;
    EXPECT_EQ(std::count(now.begin(), now.end(), "sensor_drift"), 0) << seed;
  }
}

// The outlier test on synthetic residuals: healthy noise learned, then blade 1's LIDAR residual steps by 15
// learned deviations, its cross-blade model residual the other way. With `gauge_fault` its gauge reads high
// (its amplitude against the other gauges' moves too); without it the LIDAR model is off on that blade alone
// (the gauges agree). Returns the first class raised on blade 1 ("" none).
std::string run_witness_tests(Witness witness, bool gauge_fault) {
  DetectionConfig d;
  d.witness = witness;
  SyntheticRotor rotor(d, 11);
  const double revolution_time = 4.0, sd = 0.01, step = 15.0 * sd;
  const int learn_revolutions = 60, step_at = 90;
  for (int k = 0; k < 120; ++k) {
    const double t = k * revolution_time;
    BladeChannels x = rotor.noise.draw(sd);
    if (k >= step_at) {
      x[0][kModelChannel] -= step;
      shift_blade_1(x, kWitnessChannel, step);
      if (gauge_fault) shift_blade_1(x, kRawWitnessChannel, step);
    }
    for (const auto& ev : rotor.turn(t, revolution_time, x))
      if (ev.raised && ev.component == "blade_moment_sensor_1") return ev.fault;
    if (k == learn_revolutions) {
      EXPECT_TRUE(rotor.tests.healthy().learned(kModelChannel));
    }
  }
  return "";
}

TEST(ResidualTests, ALidarModelErrorOnOneBladeNeedsTheGaugesToAgreeBeforeItIsAFault) {
  // A failed gauge is raised with either witness.
  EXPECT_EQ(run_witness_tests(Witness::kConfirm, true), "sensor_abrupt");
  EXPECT_EQ(run_witness_tests(Witness::kSensors, true), "sensor_abrupt");
  // The LIDAR model off on one blade: confirm (the model residuals alone) raised it, as it did in the healthy
  // suite hours; sensors (the gauges' own cross-blade amplitude must agree) raises nothing.
  EXPECT_EQ(run_witness_tests(Witness::kConfirm, false), "sensor_abrupt");
  EXPECT_EQ(run_witness_tests(Witness::kSensors, false), "");
}

TEST(EpisodeClassifier, NoTestAbleToJudgeIsNoQuietSpell) {
  EpisodeClassifier k;
  std::vector<Transition> tr;
  k.update(0.0, true, true, "sensor_abrupt", tr);
  ASSERT_EQ(tr.size(), 1u);
  tr.clear();
  // GIVEN 6 s in which no test could judge (windows refilling after lost samples), then evidence again
  for (double t = 1.0; t <= 7.0; t += 0.5) k.update(t, false, false, "sensor_abrupt", tr, false);
  EXPECT_FALSE(k.returned());
  k.update(7.5, true, true, "sensor_abrupt", tr);
  // THEN the episode went on: no return, no intermittent
  EXPECT_TRUE(tr.empty());
  // ... while the same 6 s judged quiet is a return, and the evidence back a recurrence
  EpisodeClassifier q;
  q.update(0.0, true, true, "sensor_abrupt", tr);
  tr.clear();
  for (double t = 1.0; t <= 7.0; t += 0.5) q.update(t, false, false, "sensor_abrupt", tr);
  EXPECT_TRUE(q.returned());
  q.update(7.5, true, true, "sensor_abrupt", tr);
  ASSERT_EQ(tr.size(), 2u);
  EXPECT_EQ(tr[1].fault, "sensor_intermittent");
}

TEST(EpisodeClassifier, RecurrenceAfterTheWindowKeepsTheClass) {
  EpisodeConfig c;
  c.return_time = 3.0;
  c.intermittent_window = 20.0;
  c.clear_time = 100.0;
  EpisodeClassifier k(c);
  std::vector<Transition> tr;
  k.update(0.0, true, true, "sensor_drift", tr);  // raised drift
  k.update(1.0, false, false, "sensor_drift", tr);
  k.update(4.0, false, false, "sensor_drift", tr);  // returned at 1
  ASSERT_TRUE(k.returned());
  k.update(30.0, true, true, "sensor_abrupt", tr);  // 29 s after the return > window: same fault, no event
  EXPECT_EQ(tr.size(), 1u);
  EXPECT_EQ(k.raised(), "sensor_drift");
}

// A growing drift whose evidence dipped for one revolution (3.6 s at rated speed, over return_time) came back
// as a ramp in its own direction: it is the drift going on. An intermittent gauge steps back instead, and an
// abrupt fault's recurrence stays intermittent whatever its shape (fault set 385: two drifts renamed).
TEST(EpisodeClassifier, ADriftConfirmedAgainAsItsOwnRampResumesUnderItsName) {
  EpisodeConfig c;  // return_time 3 s, intermittent_window 120 s
  const auto raised_drift_returned = [&](EpisodeClassifier& k, std::vector<Transition>& tr) {
    k.update(0.0, true, true, "sensor_drift", tr);
    for (double t = 1.0; t <= 4.6; t += 0.2) k.update(t, false, false, "sensor_drift", tr);
    ASSERT_TRUE(k.returned());
    tr.clear();
  };
  std::vector<Transition> tr;
  // GIVEN a raised drift that returned, confirmed again as a ramp in its raised direction
  EpisodeClassifier ramp(c);
  raised_drift_returned(ramp, tr);
  ramp.update(8.0, true, true, "sensor_drift", tr, true, true);
  // THEN no event: the episode is on again under its own name, and it still needs a return to clear
  EXPECT_TRUE(tr.empty());
  EXPECT_EQ(ramp.raised(), "sensor_drift");
  EXPECT_FALSE(ramp.returned());
  // GIVEN the same evidence back as a step (or against the raised direction: continues false)
  for (const auto& [cls, continues] :
       {std::pair<std::string, bool>{"sensor_abrupt", true}, {"sensor_drift", false}}) {
    EpisodeClassifier k(c);
    raised_drift_returned(k, tr);
    k.update(8.0, true, true, cls, tr, true, continues);
    // THEN it is an intermittent gauge
    ASSERT_EQ(tr.size(), 2u) << cls << " " << continues;
    EXPECT_EQ(tr[1].fault, "sensor_intermittent");
    tr.clear();
  }
  // GIVEN an abrupt fault's recurrence read as a ramp: still intermittent (only a drift resumes)
  EpisodeClassifier abrupt(c);
  abrupt.update(0.0, true, true, "sensor_abrupt", tr);
  for (double t = 1.0; t <= 4.6; t += 0.2) abrupt.update(t, false, false, "sensor_abrupt", tr);
  tr.clear();
  abrupt.update(8.0, true, true, "sensor_drift", tr, true, true);
  ASSERT_EQ(tr.size(), 2u);
  EXPECT_EQ(tr[1].fault, "sensor_intermittent");
  // AND with drift_resumes false the drift is renamed, as before
  c.drift_resumes = false;
  EpisodeClassifier old(c);
  raised_drift_returned(old, tr);
  old.update(8.0, true, true, "sensor_drift", tr, true, true);
  ASSERT_EQ(tr.size(), 2u);
  EXPECT_EQ(tr[1].fault, "sensor_intermittent");
}

// An hour of healthy operation per wind speed and two seeds, turbulence 10-12 % and shear varying (std 0.05).
// 14 m/s is near rated: the collective pitch keeps reaching its lower limit and the IPC switching off sweeps
// a blade's pitch through -1 deg, where the plant's k_M is singular (the steep-surface gate).
TEST(PlantHealthy, AHealthyHourRaisesNothing) {
  for (uint64_t seed : {100u, 200u})
    for (double wind : {8.0, 12.0, 14.0, 16.0, 20.0}) {
      const auto r = run_plant(wind, wind < 10 ? 0.12 : 0.1, 0.2, 0.05, 3600, {},
                               seed + static_cast<uint64_t>(wind), config(), LoadTable::load_csv(kTable));
      int raised = 0;
      for (const auto& e : r.events)
        if (e.raised && e.component.rfind("blade_moment_sensor", 0) == 0) {
          ++raised;
          std::printf("[measured]   raised at %.1f s: %s %s (%s)\n", e.t, e.component.c_str(),
                      e.fault.c_str(), e.detail.c_str());
        }
      std::printf(
          "[measured] healthy hour %g m/s seed %llu: %d raised; gated revolutions %llu; max |t|/crit "
          "model %.2f mean %.2f\n",
          wind, static_cast<unsigned long long>(seed), raised,
          static_cast<unsigned long long>(r.gated_revolutions), r.max_ratio[kModelChannel],
          r.max_ratio[kMeanChannel]);
      EXPECT_EQ(raised, 0) << wind << " " << seed;
      // ... and the tests ran: both residuals' statistics were computed
      EXPECT_GT(r.max_ratio[kModelChannel], 0.05) << wind << " " << seed;
      EXPECT_GT(r.max_ratio[kMeanChannel], 0.05) << wind << " " << seed;
    }
}

TEST(PlantHealthy, LostSamplesRaiseNothing) {
  // GIVEN a healthy turbine whose service loses samples as a starved one does (frames overwritten in the
  // reader's 8-frame history): 2 s of every 3, 0.4 s of every 1.3, 3 s of every 17, 1 s of every 30
  for (double wind : {8.0, 14.0, 20.0})
    for (SampleLosses losses :
         {SampleLosses{3.0, 2.0}, SampleLosses{1.3, 0.4}, SampleLosses{17.0, 3.0}, SampleLosses{30.0, 1.0}}) {
      const auto r = run_plant(wind, 0.1, 0.2, 0.05, 900, {}, 7 + static_cast<uint64_t>(wind), config(),
                               LoadTable::load_csv(kTable), false, losses);
      // THEN nothing is raised (3 s of every 17 raised a cross-blade mean step at 14 and a drift at 20 m/s
      // while the LIDAR model's windows ran across the hole the loss left in the delayed LIDAR values)
      for (const auto& e : r.events)
        std::printf("[measured]   %g m/s losses %g/%g: %s at %.1f s: %s %s (%s)\n", wind, losses.length,
                    losses.every, e.raised ? "raised" : "cleared", e.t, e.component.c_str(), e.fault.c_str(),
                    e.detail.c_str());
      EXPECT_TRUE(r.events.empty()) << wind << " " << losses.length << "/" << losses.every;
      // ... and the tests ran between losses far enough apart for whole windows (at 2 of every 3 s or 0.4 of
      // every 1.3 no window fills: nothing is diagnosed, and the service's health counts the gaps)
      if (losses.every < 10.0) continue;
      EXPECT_GT(r.max_ratio[kModelChannel], 0.05) << wind << " " << losses.length << "/" << losses.every;
      EXPECT_GT(r.max_ratio[kMeanChannel], 0.05) << wind << " " << losses.length << "/" << losses.every;
    }
}

TEST(PlantHealthy, ALullAtTheEndOfLearningIsNoDrift) {
  // GIVEN the example 2 MW turbine as healthy suite scenario 102_01 runs its WT02 (12 m/s, TI 0.146, shear
  // 0.197, seed 102001): in the last ten revolutions of the 200 s of learning the wind drops, the revolutions
  // lengthen from 3.0 to 4.5 s and three of them read +3.3 to +5.9 % on blade 3's mean-load channels
  const std::string deploy = WINDFDI_SOURCE_DEPLOY_DIR;
  const TurbineParams two = load_turbine_params_file(deploy + "/turbine/example_2MW.yaml");
  const MonitorConfig c = load_monitor_config(YamlSection(YAML::Node(YAML::NodeType::Map), "(test)"), two);
  const auto r =
      run_plant(12.0, 0.146, 0.197, 0.03, 400, {}, 102001, c,
                LoadTable::load_csv(deploy + "/turbine/example_2MW_load_table.csv"), false, {}, two, "WT02");
  for (const auto& e : r.events)
    std::printf("[measured] at %.1f s: %s %s %s (%s)\n", e.t, e.component.c_str(), e.fault.c_str(),
                e.raised ? "raised" : "cleared", e.detail.c_str());
  ASSERT_GT(r.lull_revolutions, 0u) << "no lull: this test no longer tests";
  // THEN nothing is raised: the drift test judges only revolutions after the freeze. Before, the first
  // windows held the lull (+1.4 % on blade 3, -1.3 % on blade 1) and sensor_drift was raised on both blades
  // at 225.8 s, the 4th revolution after the freeze.
  EXPECT_TRUE(r.events.empty());
}

// A fault of the example medium-speed turbine's WT02, from `start` to `end` s.
plant::FaultSpec wt02_fault(const std::string& target, const std::string& type, double start, double end) {
  auto f = plant::FaultSpec::make("WT02", target, type, start);
  f.end = end;
  return f;
}

// The example medium-speed turbine's WT02 as a fault suite scenario runs it (shear variation 0.03), with
// boolean keys of the defaults set.
PlantRun run_medium_wt02(double wind, double ti, double shear, int seconds,
                         const std::vector<plant::FaultSpec>& faults, uint64_t seed,
                         const std::map<std::string, bool>& keys,
                         const std::map<std::string, double>& numbers = {}) {
  const std::string deploy = WINDFDI_SOURCE_DEPLOY_DIR;
  const TurbineParams medium = load_turbine_params_file(deploy + "/turbine/example_3MW_medium_speed.yaml");
  auto yaml = YAML::Node(YAML::NodeType::Map);
  for (const auto& [key, value] : keys) yaml[key] = value;
  for (const auto& [key, value] : numbers) yaml[key] = value;
  const MonitorConfig c = load_monitor_config(YamlSection(yaml, "(test)"), medium);
  return run_plant(wind, ti, shear, 0.03, seconds, faults, seed, c, LoadTable::from_turbine(medium), false,
                   {}, medium, "WT02");
}

TEST(PlantFaults, WithAGaugeRaisedAnotherBladesPitchSensorBiasIsNoFaultOfTheThirdGauge) {
  // GIVEN the example medium-speed turbine as fault suite scenario 116_06 runs its WT02 (16.7 m/s, TI 0.105,
  // shear 0.174, seed 116006): blade 3's gauge reads 1.233 times its load from 300 s, and from 363 s pitch
  // sensor 2 reads 2.61 deg high, so the controller turns blade 2 to 2.61 deg less pitch and its load rises
  auto gain = wt02_fault("blade_moment_3", "gain", 300.0, 475.0);
  gain.gain = 1.233;
  auto bias = wt02_fault("pitch_2", "bias", 363.0, 468.0);
  bias.value = 2.61;
  bias.has_value = true;
  // (each rule alone removes the third gauge's report: blade 2's own LIDAR residual is beyond the onset
  // level; the mean-load witness is off here, this tests the second-fault witness, and so are the pitch
  // reading's test against its actuator's response, which holds the model from the bias's onset on, and the
  // gauges' witness of the mean-load ratio, and the fast path's clean witnesses; the noise followers follow
  // every pair, as before stop 62, whose pairs with the raised blade 3 then no longer stood far above blade
  // 2's change)
  for (const bool witness : {false, true}) {
    const auto r = run_medium_wt02(16.7, 0.105, 0.174, 420, {gain, bias}, 116006,
                                   {{"second_fault_model_witness", witness},
                                    {"mean_model_witness", false},
                                    {"fast_needs_clean_witnesses", false},
                                    {"noise_holds_raised", false}},
                                   {{"pitch_response_mismatch", 0.0}, {"mean_gauge_witness_share", 0.0}});
    bool blade3 = false, other = false;
    for (const auto& e : r.events) {
      std::printf("[measured] witness %d, at %.1f s: %s %s %s (%s)\n", witness, e.t, e.component.c_str(),
                  e.fault.c_str(), e.raised ? "raised" : "cleared", e.detail.c_str());
      if (!e.raised) continue;
      (e.component == "blade_moment_sensor_3" ? blade3 : other) = true;
    }
    // THEN blade 3's gauge is raised either way
    EXPECT_TRUE(blade3) << witness;
    // and with the LIDAR witness nothing else: without it (as before) the two changed blades put blade 1
    // below both and its gauge was raised (suite: sensor_drift on blade 1 at 364.8 s, t -72), before
    // sensor_bias named the pitch sensor
    if (witness)
      EXPECT_FALSE(other);
    else
      EXPECT_TRUE(other) << "the second fault no longer reads as the third gauge: this test no longer tests";
  }
  // AND with every rule as shipped, blade 3's gauge alone is raised
  const auto shipped = run_medium_wt02(16.7, 0.105, 0.174, 420, {gain, bias}, 116006, {});
  ASSERT_FALSE(shipped.events.empty());
  for (const auto& e : shipped.events)
    EXPECT_EQ(e.component, "blade_moment_sensor_3") << e.fault << " at " << e.t << " (" << e.detail << ")";
}

TEST(PlantFaults, APitchSensorsBiasIsASuspectInputNotItsBladesGaugeFailing) {
  // GIVEN the example medium-speed turbine at 16.7 m/s (TI 0.105, shear 0.174) whose pitch sensor 2 reads
  // 2.61 deg high from 363 s: the actuator follows its reference, so the blade and its load are as before and
  // only the load model, which takes the pitch reading, is wrong
  auto bias = wt02_fault("pitch_2", "bias", 363.0, 468.0);
  bias.value = 2.61;
  bias.has_value = true;
  bool gauge[2] = {false, false};
  uint64_t held[2] = {0, 0};
  for (const bool response : {false, true}) {
    const auto r = run_medium_wt02(16.7, 0.105, 0.174, 420, {bias}, 116006, {{"mean_model_witness", false}},
                                   {{"pitch_response_mismatch", response ? 0.5 : 0.0}});
    for (const auto& e : r.events) {
      std::printf("[measured] response test %d, at %.1f s: %s %s %s (%s)\n", response, e.t,
                  e.component.c_str(), e.fault.c_str(), e.raised ? "raised" : "cleared", e.detail.c_str());
      gauge[response] = gauge[response] || (e.raised && e.t >= 363.0);
    }
    held[response] = r.suspect_samples;
  }
  // THEN without the response test the model's error reads as blade 2's gauge failing (as in the suite,
  // 1-2 s after the onset, before sensor_bias names the pitch sensor) ...
  EXPECT_TRUE(gauge[0]) << "the bias no longer misleads the model: this test no longer tests";
  // ... and with it the model is held from the onset on (57 s of the bias at 100 Hz) and nothing is raised
  EXPECT_FALSE(gauge[1]);
  EXPECT_GE(held[1], held[0] + 5000u);
}

TEST(PlantFaults, ADriftThatEndedIsClearedOnceTheGaugeIsQuietInItsDirection) {
  // GIVEN the example medium-speed turbine as fault suite scenario 120_06 runs its WT02 (19.4 m/s, TI 0.144,
  // shear 0.158, seed 120006): blade 2's gauge drifts by 342.9 N m/s from 713 to 854 s, then reads 1.158
  // times its load from 1196 to 1314 s. In the suite's closed loop (the arbiter's IPC on the LIDAR model
  // after the raise) the drift stayed raised until 1519 s, over the gain, which went unreported: the healthy
  // gauge's runs past half the critical value, either way (-0.79 at 962 s, +0.55 at 1086 s), each restarted
  // the 120 s quiet time the clear needs.
  auto drift = wt02_fault("blade_moment_2", "drift", 713.0, 854.0);
  drift.rate = 342.9;
  auto gain = wt02_fault("blade_moment_2", "gain", 1196.0, 1314.0);
  gain.gain = 1.158;
  double after_end[2] = {NAN, NAN};  // s from the drift's end to its clear
  for (const bool hold_in_direction : {false, true}) {
    const auto r = run_medium_wt02(19.4, 0.144, 0.158, 1330, {drift, gain}, 120006,
                                   {{"hold_in_raised_direction", hold_in_direction}});
    std::printf("[measured] hold in the raised direction %d: %s\n", hold_in_direction,
                event_sequence(r.events).c_str());
    bool gain_raised = false;
    for (const auto& e : r.events) {
      if (e.component != "blade_moment_sensor_2") continue;
      if (!e.raised && e.fault == "sensor_drift" && std::isnan(after_end[hold_in_direction]))
        after_end[hold_in_direction] = e.t - 854.0;
      if (e.raised && e.t >= 1196.0) gain_raised = true;
    }
    EXPECT_TRUE(gain_raised) << hold_in_direction;
  }
  // THEN the drift clears within clear_time and a minute of its end (measured 161.5 s) ...
  const double clear_time = EpisodeConfig{}.clear_time;
  EXPECT_LT(after_end[1], clear_time + 60.0);
  // ... where a run past the onset level either way held it (measured 229.4 s here, 665 s in the suite)
  EXPECT_GT(after_end[0], clear_time + 60.0)
      << "the drift clears as soon either way: this test no longer tests";
  // (Seeds 121006-129006 of the same turbine clear the drift at the same time either way.)
}

TEST(LullHold, HoldsWindowsWellBelowTheUsualLoadAndFollowsALastingDrop) {
  LullHold lull(LullConfig{0.6, 600.0});
  // Nothing is held before a usual load is known, and NaN teaches nothing
  EXPECT_FALSE(lull.holds(1.0));
  lull.follow(kNaN, 6.0);
  EXPECT_LT(lull.usual_load(), 0.0);
  lull.follow(2.0e6, 6.0);
  EXPECT_DOUBLE_EQ(lull.usual_load(), 2.0e6);
  // Below 0.6 of the usual load (1.2 MN m) a window is a lull; NaN is none
  EXPECT_TRUE(lull.holds(1.1e6));
  EXPECT_FALSE(lull.holds(1.3e6));
  EXPECT_FALSE(lull.holds(kNaN));
  // A lasting drop to 0.8 MN m: 100 revolutions of 6 s (one memory) leave 0.8 + 1.2 x 0.99^100 = 1.239 MN m,
  // and the drop is no lull any more
  for (int k = 0; k < 100; ++k) lull.follow(0.8e6, 6.0);
  EXPECT_NEAR(lull.usual_load(), 0.8e6 + 1.2e6 * std::pow(0.99, 100), 1.0);
  EXPECT_FALSE(lull.holds(0.8e6));
  // A share of 0 holds nothing
  LullHold off(LullConfig{0.0, 600.0});
  off.follow(2.0e6, 6.0);
  EXPECT_FALSE(off.holds(1.0));
}

TEST(WindowLoad, TheMedianOfTheValidGaugesWhichOneFailedGaugeCannotMove) {
  BladeEstimates e;
  e.sensor_valid = {true, true, true};
  e.mean_sensor = {2.0e6, 2.2e6, 0.2e6};  // gauge 3 failed low
  EXPECT_DOUBLE_EQ(window_load(e), 2.0e6);
  e.mean_sensor = {2.0e6, 2.2e6, 9.0e6};  // high
  EXPECT_DOUBLE_EQ(window_load(e), 2.2e6);
  e.sensor_valid = {true, true, false};
  EXPECT_DOUBLE_EQ(window_load(e), 2.1e6);
  e.sensor_valid = {true, false, false};
  EXPECT_TRUE(std::isnan(window_load(e)));
}

TEST(PlantHealthy, ALullDoesNotMakeTheMeanLoadRatioAnOutlier) {
  // GIVEN the healthy suite turbine WT01 of scenario 55_01 (seed 55001): 8 m/s, 15.9 % turbulence, shear
  // 0.208. Near 1290 s the wind falls from 7.5 to 3-4 m/s for half a minute; the blades' mean loads fall from
  // about 2.2 to 0.5 MN m, and the LIDAR model's error of each blade's mean, a load, becomes a four times
  // larger share of it: the cross-blade mean ratio of blade 3 stood at 6.6 % (t 7.64 against a critical 7.58)
  // (mean_model_witness_ratio 0: the mean-load witness off; the gauges' witness of the ratio is off too, it
  // removes this step as well: the gauges did not share the ratio's 6.6 %)
  auto run = [](double lull_load_share, double mean_model_witness_ratio = 0.0) {
    YAML::Node n(YAML::NodeType::Map);
    n["lull_load_share"] = lull_load_share;
    n["mean_gauge_witness_share"] = 0.0;
    n["mean_model_witness"] = mean_model_witness_ratio > 0.0;
    if (mean_model_witness_ratio > 0.0) n["mean_model_witness_ratio"] = mean_model_witness_ratio;
    return run_plant(8.0, 0.159, 0.208, 0.03, 1400, {}, 55001, config(n), LoadTable::load_csv(kTable));
  };
  // THEN nothing is raised: the windows below 0.6 of the usual mean blade load are held
  const auto r = run(0.6);
  EXPECT_TRUE(r.events.empty()) << r.events.front().t << " " << r.events.front().detail;
  EXPECT_GT(r.lull_revolutions, 0u);
  // ... where without the hold (and without the mean-load witness, which at the onset level held it too:
  // another blade's LIDAR residual is beyond 0.5 of its critical value in the lull) a blade moment step was
  // raised
  const auto without = run(0.0);
  EXPECT_TRUE(run(0.0, 0.5).events.empty());
  EXPECT_EQ(without.lull_revolutions, 0u);
  ASSERT_FALSE(without.events.empty()) << "the lull no longer makes a false step: this test no longer tests";
  std::printf("[measured] %llu lull revolutions; without the hold: %s %s at %.1f s (%s)\n",
              static_cast<unsigned long long>(r.lull_revolutions), without.events.front().component.c_str(),
              without.events.front().fault.c_str(), without.events.front().t,
              without.events.front().detail.c_str());
  EXPECT_EQ(without.events.front().fault, "sensor_abrupt");
  EXPECT_NE(without.events.front().detail.find("cross_blade_mean_ratio"), std::string::npos);
}

TEST(PlantHealthy, AMeanRatioTheLidarModelMissesOnAnotherBladeIsNoGaugeFault) {
  // GIVEN the benchmark turbine as healthy suite scenario 134_01 runs its WT03 (16 m/s, TI 0.144, shear
  // 0.188, seed 134001): 20 s after learning, an eddy the two beams did not see puts blade 2's and blade 3's
  // LIDAR residuals at -18 and +13 t (the onset is 3.4) and their mean-load ratios at +3.9 and -4.0 %; the
  // gauges agree with each other (blade 2 +0.7 % against the others)
  auto run = [](bool mean_model_witness) {
    YAML::Node n(YAML::NodeType::Map);
    n["mean_model_witness"] = mean_model_witness;
    n["fast_needs_clean_witnesses"] = false;  // which would hold it too (its own test below)
    return run_plant(16.0, 0.144, 0.188, 0.03, 400, {}, 134001, config(n), LoadTable::from_turbine({}), false,
                     {}, TurbineParams{}, "WT03");
  };
  // WHEN the mean-load ratio is tested whatever the other blades' LIDAR residuals
  const auto without = run(false);
  // THEN blade 2's gauge was raised
  ASSERT_FALSE(without.events.empty()) << "the eddy no longer raises: this test no longer tests";
  std::printf("[measured] without the witness: %s %s at %.1f s (%s)\n",
              without.events.front().component.c_str(), without.events.front().fault.c_str(),
              without.events.front().t, without.events.front().detail.c_str());
  EXPECT_NE(without.events.front().detail.find("cross_blade_mean_ratio"), std::string::npos);
  // WHEN another blade's LIDAR residual beyond 0.8 of its critical value says the model misses the wind there
  // (the default)
  const auto r = run(true);
  // THEN nothing is raised
  EXPECT_TRUE(r.events.empty()) << r.events.front().t << " " << r.events.front().component << " "
                                << r.events.front().detail;
}

TEST(PlantHealthy, AMeanRatioTheGaugesDoNotShareIsNoGaugeFault) {
  // GIVEN the example medium-speed turbine as healthy suite scenario 185_00 runs its WT02 (12 m/s, TI 0.133,
  // shear 0.29, seed 185000): 85 s after learning, blade 1's mean-load ratio to its LIDAR model stays above
  // half its critical value for 5 s while the gauges' own cross-blade mean stays below it (the model, not the
  // gauge, is off on that blade)
  auto run = [](double share) {
    return run_medium_wt02(12.0, 0.133, 0.29, 320, {}, 185000, {}, {{"mean_gauge_witness_share", share}});
  };
  // WHEN the ratio is tested alone
  const auto without = run(0.0);
  // THEN it touches its critical value and blade 1's gauge is raised
  ASSERT_FALSE(without.events.empty()) << "the ratio no longer raises: this test no longer tests";
  std::printf("[measured] without the gauges' witness: %s %s at %.1f s (%s)\n",
              without.events.front().component.c_str(), without.events.front().fault.c_str(),
              without.events.front().t, without.events.front().detail.c_str());
  EXPECT_NE(without.events.front().detail.find("cross_blade_mean_ratio"), std::string::npos);
  // WHEN the gauges' cross-blade mean must share at least half the excursion (the default)
  const auto r = run(0.5);
  // THEN nothing is raised
  EXPECT_TRUE(r.events.empty()) << r.events.front().t << " " << r.events.front().component << " "
                                << r.events.front().detail;
}

TEST(PlantHealthy, AGustTheBeamsMissedForARevolutionTakesNoFastPath) {
  // GIVEN two healthy rotors of judged suite sets, each with a gust the two beams did not see that puts one
  // blade's mean-load ratio at 1.4-1.6 times its critical value for about a revolution: the benchmark turbine
  // at 20 m/s (set 207, scenario 11, WT04: the gauges' own cross-blade means put blade 3 with blade 1) and
  // the 6 MW example at 12 m/s (set 201, scenario 04, WT02: another blade's LIDAR residual at 0.78 of its
  // critical value)
  const std::string deploy = WINDFDI_SOURCE_DEPLOY_DIR;
  const TurbineParams six = load_turbine_params_file(deploy + "/turbine/example_6MW.yaml");
  auto run = [&](bool clean, bool six_mw) {
    YAML::Node n(YAML::NodeType::Map);
    n["fast_needs_clean_witnesses"] = clean;
    const TurbineParams& turbine = six_mw ? six : TurbineParams{};
    const MonitorConfig c = load_monitor_config(YamlSection(n, "(test)"), turbine);
    return six_mw ? run_plant(12.0, 0.118, 0.29, 0.03, 260, {}, 201004, c, LoadTable::from_turbine(six),
                              false, {}, six, "WT02")
                  : run_plant(20.0, 0.135, 0.238, 0.03, 440, {}, 207011, c, LoadTable::from_turbine({}),
                              false, {}, TurbineParams{}, "WT04");
  };
  for (bool six_mw : {false, true}) {
    // WHEN the fast path takes any run above 1.25 times the critical value for a second (before stop 62)
    const auto without = run(false, six_mw);
    // THEN a healthy gauge is raised sensor_abrupt on the mean-load ratio
    ASSERT_FALSE(without.events.empty()) << "the gust no longer raises: this test no longer tests";
    std::printf("[measured] %s, any witness: %s %s at %.1f s (%s)\n", six_mw ? "6 MW" : "benchmark",
                without.events.front().component.c_str(), without.events.front().fault.c_str(),
                without.events.front().t, without.events.front().detail.c_str());
    EXPECT_NE(without.events.front().detail.find("cross_blade_mean_ratio"), std::string::npos);
    // WHEN the fast path needs the other blades' LIDAR residuals quiet and the gauges' own means to isolate
    // the blade (the default)
    const auto r = run(true, six_mw);
    // THEN nothing is raised
    EXPECT_TRUE(r.events.empty()) << r.events.front().t << " " << r.events.front().component << " "
                                  << r.events.front().detail;
  }
}

TEST(PlantFaults, AnEarlierGaugesFaultLeavesTheNoiseLevelOfTheOtherBladesDrift) {
  // GIVEN the benchmark turbine as judged suite set 204, scenario 03, runs its WT02 (7.9 m/s, TI 0.102, shear
  // 0.242, seed 204003): blade 1's gauge reads 0.717 times its load from 300 to 455 s, and blade 3's drifts
  // by -1180 N m/s from 850 to 1023 s
  auto gain = plant::FaultSpec::make("WT02", "blade_moment_1", "gain", 300.0);
  gain.gain = 0.717;
  gain.end = 455.0;
  auto drift = plant::FaultSpec::make("WT02", "blade_moment_3", "drift", 850.0);
  drift.rate = -1179.6;
  drift.end = 1023.0;
  auto run = [&](bool noise_holds_raised) {
    YAML::Node n(YAML::NodeType::Map);
    n["noise_holds_raised"] = noise_holds_raised;
    return run_plant(7.9, 0.102, 0.242, 0.03, 1100, {gain, drift}, 204003, config(n),
                     LoadTable::from_turbine({}), false, {}, TurbineParams{}, "WT02");
  };
  auto drift_raised = [](const PlantRun& r) {
    for (const auto& e : r.events)
      if (e.raised && e.component == "blade_moment_sensor_3" && e.t >= 850.0) return e.t;
    return -1.0;
  };
  // WHEN the noise followers follow every pair of blades through blade 1's raised gain (before stop 62)
  const auto before = run(false);
  std::printf("[measured] every pair followed: %s\n", event_sequence(before.events).c_str());
  // THEN blade 3's drift is never raised: the pairs with blade 1 were still far above their healthy level
  EXPECT_LT(drift_raised(before), 0.0) << "the drift is found without the hold: this test no longer tests";
  // WHEN the pairs with a raised blade keep their level while it is raised (the default)
  const auto now = run(true);
  std::printf("[measured] pairs with a raised blade held: %s\n", event_sequence(now.events).c_str());
  // THEN blade 1's gain is raised, and blade 3's drift as a drift while it drifts
  ASSERT_FALSE(now.events.empty());
  EXPECT_EQ(now.events.front().component, "blade_moment_sensor_1");
  EXPECT_GT(drift_raised(now), 850.0);
  EXPECT_LT(drift_raised(now), 1023.0);
  for (const auto& e : now.events) {
    if (e.raised && e.component == "blade_moment_sensor_3") {
      EXPECT_EQ(e.fault, "sensor_drift") << e.t;
    }
  }
}

TEST(SteepSurfaceGate, ClosesOnlyWhereTheLoadTableIsSteepInPitch) {
  // GIVEN a table with a step in pitch at -1 deg (k_M 1 below, 0.2 above), as the plant had when its Heier Cp
  // was singular there
  std::vector<double> k;
  for (int i = 0; i < 81; ++i)
    for (int j = 0; j < 101; ++j) k.push_back(-5.0 + 0.5 * j < -1.0 ? 1.0 : 0.2);
  BladeLoadMonitor steep(config(), LoadTable(0.0, 0.25, 81, -5.0, 0.5, 101, k));
  // THEN the gate's sensitivity is far above 0.25 at the step and zero away from it
  for (double lambda : {6.5, 7.5, 9.0}) {
    EXPECT_GT(steep.model_sensitivity(lambda, -1.0), 0.5) << lambda;
    EXPECT_LT(steep.model_sensitivity(lambda, 0.0), 0.25) << lambda;
    EXPECT_LT(steep.model_sensitivity(lambda, 5.0), 0.25) << lambda;
  }
  // AND the shipped table (smooth since the plant's Cp is) never closes the gate where the blades work: fine
  // pitch with IPC (-2..2 deg) at partial load, and the full-load band at its tip-speed ratios
  BladeLoadMonitor shipped(config(), LoadTable::load_csv(kTable));
  for (double lambda : {6.5, 7.5, 8.1, 9.0})
    for (double pitch = -2.0; pitch <= 2.0; pitch += 0.1)
      EXPECT_LT(shipped.model_sensitivity(lambda, pitch), 0.25) << lambda << " " << pitch;
  for (double pitch = 2.0; pitch <= 10.0; pitch += 0.5)
    EXPECT_LT(shipped.model_sensitivity(5.5, pitch), 0.25) << pitch;
}

}  // namespace
