// ice_detect tests: the estimator of Stotsky & Egardt 2013 against known inertia, on the two-mass plant, and
// the detector.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <tuple>

#include "allocation_counter.hpp"
#include "ice_detector.hpp"
#include "ice_service.hpp"
#include "turbine_sim.hpp"

using namespace windfdi;
using namespace windfdi::ice_detect;

namespace {

YamlSection defaults() { return YamlSection(YAML::Node(YAML::NodeType::Map), "(defaults)"); }
/// The keys in `yaml` over the defaults (a test's configuration, named x.yaml in its errors).
YamlSection config(const char* yaml) { return YamlSection(YAML::Load(yaml), "x.yaml"); }

// The estimator on the bare one-mass model: no efficiency, friction or filter. The synthetic speed swings are
// gentler than turbulence (0.5-2 rad/s of predicted speed change), so the excitation gate is the paper's
// lower one; the service's 2.0 is for noisy measured wind.
EstimatorConfig one_mass(double power_window) {
  EstimatorConfig c;
  c.min_excitation = 0.5;
  c.power_gain = 1.0;
  c.friction = 0.0;
  c.power_window = power_window;
  c.filter_time = 0.0;
  return c;
}

TEST(InertiaEstimator, NoiseFreeOneMassConvergesToTheTrueInertia) {
  // GIVEN the one-mass model J d omega/dt = P/omega - T_g (eq 2) with J = 6484 kg m^2, integrated finely,
  // and a torque balance that varies like gusts
  const double J = 6484.0, dt = 0.01;
  InertiaEstimator est(one_mass(0.0));
  double omega = 150.0;
  for (int k = 0; k < 30000; ++k) {
    const double t = k * dt;
    const double tg = 30000.0;
    const double p = omega * (tg + 3000.0 * std::sin(0.3 * t) + 1500.0 * std::sin(1.1 * t + 1.0));
    est.update(omega, p, tg);
    for (int s = 0; s < 10; ++s) omega += (p / omega - tg) / J * dt / 10.0;  // fine steps: Euler error small
  }
  // THEN the estimate is J within 0.1 %
  ASSERT_TRUE(est.excited());
  EXPECT_NEAR(est.inertia(), J, 1e-3 * J);
}

TEST(InertiaEstimator, HoldsTheEstimateWithoutTransients) {
  EstimatorConfig c;
  c.min_excitation = 0.5;  // gentle synthetic transients, as one_mass()
  c.power_window = 0.0;
  InertiaEstimator est(c);
  // GIVEN a first estimate from transients ...
  double omega = 150.0;
  for (int k = 0; k < 20000; ++k) {
    const double p = omega * ((30000.0 + 45.6 * omega) / 0.97 + 4000.0 * std::sin(0.2 * k * 0.01));
    est.update(omega, p, 30000.0);
    omega += ((p / omega) - (30000.0 + 45.6 * omega) / 0.97) / 6484.0 * 0.01;
  }
  ASSERT_TRUE(est.excited());
  const double first = est.inertia();
  // WHEN the turbine then runs perfectly steady (from where it was, with a torque balance of zero)
  const double steady_power = omega * (30000.0 + 45.6 * omega) / 0.97;
  int k = 0;
  for (; k < 20000 && est.excited(); ++k) est.update(omega, steady_power, 30000.0);
  // THEN, once the window holds no transient, the estimator says so ...
  ASSERT_FALSE(est.excited()) << "still excited after " << k << " steady samples";
  // At most a window (120 s) plus a re-initialisation period (15 s): a segment that began in the transients
  // carries its psi until the next initialisation event.
  EXPECT_LE(k, 13600);
  // ... and keeps its last estimate however long the calm lasts
  const double held = est.inertia();
  for (int j = 0; j < 30000; ++j) est.update(omega, steady_power, 30000.0);
  EXPECT_FALSE(est.excited());
  EXPECT_DOUBLE_EQ(est.inertia(), held);
  EXPECT_NEAR(held, first, 0.01 * first);
}

TEST(InertiaEstimator, AStepInCpRecalibratesAndRestartsTheRegression) {
  // GIVEN the one-mass model with gusts and a power model 1/0.975 too high, whose rotor loses 5 % of its Cp
  // at 500 s (the generator torque follows, as a speed controller would)
  const double J = 6484.0, dt = 0.01;
  InertiaEstimator est(one_mass(EstimatorConfig{}.power_window));
  double omega = 150.0;
  uint64_t estimates_at_step = 0;
  for (int k = 0; k < 90000; ++k) {
    const double t = k * dt;
    const double cp = t < 500.0 ? 1.0 : 0.95;
    const double tg = 30000.0 * cp;
    const double model_power =
        omega * (30000.0 + 3000.0 * std::sin(0.3 * t) + 1500.0 * std::sin(1.1 * t + 1.0)) / 0.975;
    est.update(omega, model_power, tg);
    if (k == 50000) estimates_at_step = est.estimates();
    // THEN within two minutes of the step it is seen once, as a 5 % loss ...
    if (k == 62000) {
      EXPECT_EQ(est.power_changes(), 1u);
      EXPECT_NEAR(est.last_power_step(), -0.05, 0.005);
    }
    for (int s = 0; s < 10; ++s) omega += (0.975 * cp * model_power / omega - tg) / J * dt / 10.0;
  }
  // ... the calibration follows the new aerodynamics (0.975 * 0.95), nothing else is seen as a step ...
  EXPECT_EQ(est.power_changes(), 1u);
  EXPECT_NEAR(est.power_scale(), 0.975 * 0.95, 0.002);
  EXPECT_GT(estimates_at_step, 0u);
  // ... and once the regression has refilled its window on the new aerodynamics, J is right again
  ASSERT_TRUE(est.excited());
  EXPECT_NEAR(est.inertia(), J, 0.01 * J);
}

// The one-mass model with gusts whose power model wanders by `wander` RMS (a first-order lag of white noise,
// 60 s time constant, as the anemometer's model error moves with the operating point) and whose rotor loses
// `cp_loss` of its Cp at `step_at` s. Returns the estimator after `seconds`; `changes_before_step`: the power
// steps it saw before the Cp step.
InertiaEstimator wandering_power_model(bool spread, double wander, double cp_loss, double step_at,
                                       double seconds, uint64_t* changes_before_step) {
  EstimatorConfig c = one_mass(EstimatorConfig{}.power_window);
  c.power_step_spread = spread;
  InertiaEstimator est(c);
  const double J = 6484.0, dt = 0.01, lag = 60.0;
  std::mt19937 rng(7);
  std::normal_distribution<double> white(0.0, 1.0);
  double omega = 150.0, error = 0.0;
  for (int k = 0; k * dt < seconds; ++k) {
    const double t = k * dt;
    if (k % 100 == 0)  // once a second: a lag of white noise whose steady RMS is `wander`
      error += -error / lag + wander * std::sqrt(2.0 / lag) * white(rng);
    const double cp = t < step_at ? 1.0 : 1.0 - cp_loss;
    const double tg = 30000.0 * cp;
    const double true_power =
        omega * (30000.0 + 3000.0 * std::sin(0.3 * t) + 1500.0 * std::sin(1.1 * t + 1.0)) * cp;
    est.update(omega, true_power / cp * (1.0 + error), tg);
    if (t < step_at) *changes_before_step = est.power_changes();
    for (int s = 0; s < 10; ++s) omega += (true_power / omega - tg) / J * dt / 10.0;
  }
  return est;
}

TEST(InertiaEstimator, APowerModelThatWandersIsNoStepButACpStepStillIs) {
  // GIVEN a power model wandering by 0.8 % RMS over a minute, for an hour without any step in the Cp
  uint64_t quiet_rule = 0, spread_rule = 0;
  wandering_power_model(false, 0.008, 0.0, 1e9, 3600.0, &quiet_rule);
  wandering_power_model(true, 0.008, 0.0, 1e9, 3600.0, &spread_rule);
  // THEN the threshold learned from the quiet seconds alone, one width for every span, took the wander for
  // steps (measured: 6 in the hour, each restarting the regression), the spread rule for none
  EXPECT_GE(quiet_rule, 3u);
  EXPECT_LE(spread_rule, 1u);
  // WHEN the rotor loses 4 % of its Cp at 2400 s
  uint64_t before_step = 0;
  const auto est = wandering_power_model(true, 0.008, 0.04, 2400.0, 2520.0, &before_step);
  // THEN within two minutes the step is seen once, and measured on the new aerodynamics as a 4 % loss
  EXPECT_EQ(est.power_changes(), before_step + 1);
  EXPECT_NEAR(est.last_power_step(), -0.04, 0.01);
}

// Runs the detector on a plant turbine; `model_power`: aerodynamic power from the model on measured wind,
// rotor speed and pitch (the DDS path) instead of the recording's true value.
struct PlantRun {
  double rms = 0, max = 0;
  double max_over = 0;  // largest relative overestimate after 300 s
  std::vector<FaultEvent> events;
  uint64_t suspect = 0;           // samples held for a suspect input
  int estimates = 0;              // inertia estimates compared after 300 s
  uint64_t rejected = 0;          // samples the detector refused
  std::size_t drop_balances = 0;  // the shedding test's balances at the end
};

/// Samples lost on the way: `count` consecutive samples every `every` s (0: none), as a loaded host loses
/// them.
struct Losses {
  double every = 0.0;
  int count = 20;
};

/// Sample times between which the run's InputContext is in force (before and after: none).
struct ContextSpan {
  double from = 0.0, until = 1e300;
};

PlantRun run_turbine(const plant::TurbineScenario& t, int seconds, bool model_power,
                     const std::vector<plant::FaultSpec>& faults, uint64_t seed, const YamlSection& config,
                     const InputContext& context, const TurbineParams& p, Losses losses = {},
                     ContextSpan span = {});

PlantRun run_plant(double wind, int seconds, bool model_power,
                   const std::vector<plant::FaultSpec>& faults = {}, double ice = 0.0, uint64_t seed = 7,
                   const YamlSection& config = defaults(), const InputContext& context = {},
                   const TurbineParams& p = TurbineParams{}, Losses losses = {}) {
  plant::TurbineScenario t;
  t.id = "WT01";
  t.wind.mean = wind;
  t.wind.turbulence_intensity = 0.12;
  t.wind.shear_variation = 0.05;
  t.ice_mass = ice;
  return run_turbine(t, seconds, model_power, faults, seed, config, context, p, losses);
}

/// One turbine of the plant as a scenario describes it (its id is part of its random streams).
PlantRun run_turbine(const plant::TurbineScenario& t, int seconds, bool model_power,
                     const std::vector<plant::FaultSpec>& faults, uint64_t seed, const YamlSection& config,
                     const InputContext& context, const TurbineParams& p, Losses losses, ContextSpan span) {
  AeroModel aero(p);
  plant::TurbineSim sim(p, t, faults, seed, 100.0);
  const DetectorConfig cfg = load_detector_config(config, p);
  IceDetector det(cfg, p);
  bool in_span = span.from <= 0.0;
  det.set_context(in_span ? context : InputContext{});
  AeroPowerInput aero_power(aero, cfg.wind_window, cfg.estimator.sample_time);
  PlantRun r;
  InertiaOutput o;
  int n = 0;
  const int lose_every = static_cast<int>(std::lround(losses.every * 100.0));
  bool gap = false;
  for (int k = 0; k < seconds * 100; ++k) {
    FrameSample s = sim.step();
    if (lose_every > 0 && k % lose_every >= lose_every - losses.count) {
      gap = true;  // lost on the way: the next sample that arrives follows a gap
      continue;
    }
    double power = sim.truth().aero_power;
    bool centre_gap = gap;
    if (model_power) {
      FrameSample centre;
      s.aero_power = kNaN;
      if (!aero_power.push(s, gap, centre, centre_gap, power)) {
        gap = false;
        continue;
      }
      s = centre;
    }
    gap = false;
    if (in_span != (s.t >= span.from && s.t < span.until)) {
      in_span = !in_span;
      det.set_context(in_span ? context : InputContext{});
    }
    det.update(s, power, centre_gap, r.events);
    if (det.estimate_due(o) && s.t > 300.0 && o.inertia > 0.0) {
      const double e = o.inertia / sim.truth().inertia - 1.0;
      r.rms += e * e;
      r.max = std::max(r.max, std::fabs(e));
      r.max_over = std::max(r.max_over, e);
      ++n;
    }
  }
  r.rms = std::sqrt(r.rms / std::max(n, 1));
  r.suspect = det.suspect_samples();
  r.estimates = n;
  r.rejected = det.rejected();
  r.drop_balances = det.drop_test().balances();
  return r;
}

/// A one-mass rotor J d(omega)/dt = P / omega - k omega^2 in gusts, stepped at 100 Hz as the drop test
/// integrates (left rectangles), its inertia falling from 1000 to `after` kg m^2 at `step_at` s; the power
/// the test sees carries white noise of `noise` (share of it), as the anemometer's does. Returns the test's
/// result at each second; the calibration learns before the step, and after it too with `learn_after` (a
/// shedding no report has confirmed).
std::vector<InertiaDropTest::Result> one_mass_drop_test(double after, double step_at, double seconds,
                                                        double noise, uint64_t seed,
                                                        std::array<double, 7>* calibration = nullptr,
                                                        bool learn_after = false) {
  DropTestConfig c;
  c.filter_time = 0.0;
  c.power_gain = 1.0;
  c.friction = 0.0;
  InertiaDropTest test(c);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  const double dt = 0.01, k = 0.02;
  double omega = 100.0, gust = 0.0;
  std::vector<InertiaDropTest::Result> results;
  for (long i = 0; i < static_cast<long>(seconds / dt); ++i) {
    const double t = static_cast<double>(i) * dt;
    gust += -gust * dt / 10.0 + 0.15 * std::sqrt(dt) * unit(rng);  // 10 s gusts of a few % of the torque
    const double aero_torque = k * 100.0 * 100.0 * (1.0 + gust);
    const double power = aero_torque * omega, gen_torque = k * omega * omega;
    test.update(omega, power * (1.0 + noise * unit(rng)), gen_torque);
    omega += dt * (aero_torque - gen_torque) / (t < step_at ? 1000.0 : after);
    if (i % 100 == 99) results.push_back(test.test(1.0, 1000.0, 0.025, 0.0, learn_after || t < step_at));
  }
  if (calibration) *calibration = test.calibration();
  return results;
}

TEST(InertiaDropTest, AStepOfTheInertiaIsMeasuredFromTheSecondsAfterIt) {
  // GIVEN a one-mass rotor whose inertia falls 10 % at 1500 s (as ice shedding lowers it), its power noisy
  const auto r = one_mass_drop_test(900.0, 1500.0, 1600.0, 0.05, 7);
  // THEN over the hour before it no fall of 2.5 % stands out 4 deviations (learned from those seconds) ...
  for (std::size_t s = 0; s < 1499; ++s) EXPECT_LT(r[s].z, 4.0) << s;
  EXPECT_TRUE(r[1300].tested);
  // ... and a minute after it the fall is measured to within 1.5 % of J0, from a window that began at the
  // step (+-15 s), far beyond the noise
  const InertiaDropTest::Result& a = r[1559];
  EXPECT_NEAR(a.drop, 0.10, 0.015);
  EXPECT_NEAR(a.since, 60.0, 15.0);
  EXPECT_GT(a.z, 8.0);
  std::printf("[measured] one-mass 10 %% step: drop %.2f %% over the last %.0f s, %.1f deviations\n",
              100.0 * a.drop, a.since, a.z);
}

TEST(InertiaDropTest, NoStepNoStandingFallAndTheReferenceRestartsAfterAShedding) {
  // GIVEN the same rotor without a step for an hour, and a test that kept only its newest 30 balances
  std::array<double, 7> calibration{};
  const auto r = one_mass_drop_test(1000.0, 1e9, 3600.0, 0.05, 8, &calibration);
  int tested = 0;
  for (const auto& x : r) {
    // THEN nothing stands out 4 learned deviations (nor 3.5: a few tests a second over an hour)
    EXPECT_LT(x.z, 3.5);
    tested += x.tested;
  }
  // ... every second is tested once the shortest window and its reference (20 + 120 s) are in
  EXPECT_NEAR(tested, 3600 - 140, 2);
  // ... and with the one-mass model exact and the noise white, each window learns the predicted variance
  // itself: a ratio near 1 (from the prior 1.5; measured 0.97-1.31, an hour of overlapping windows is few
  // independent ones for the longest), where the plant's correlated seconds give 1.0-2.2
  double mean = 0.0;
  for (double c : calibration) {
    EXPECT_NEAR(c, 1.0, 0.4);
    mean += c / static_cast<double>(calibration.size());
  }
  EXPECT_NEAR(mean, 1.0, 0.2);
  InertiaDropTest t;
  for (int i = 0; i < 200 * 100; ++i) t.update(100.0, 2e5, 2000.0);
  EXPECT_EQ(t.balances(), 199u);  // the first sample starts the filters
  t.keep_newest(30);
  EXPECT_EQ(t.balances(), 30u);
  // AND a restart drops only the second under way (99 samples were, 150 more make two balances and 49)
  for (int i = 0; i < 150; ++i) t.update(100.0, 2e5, 2000.0);
  t.restart();
  EXPECT_EQ(t.balances(), 32u);
  EXPECT_FALSE(t.test(1.0, 1000.0, 0.025, 0.0, true).tested);  // 12 reference seconds of 120
}

TEST(InertiaDropTest, AFallTooSmallToConfirmAtOnceDoesNotTeachItselfAsNoise) {
  // GIVEN the same rotor, three times noisier, whose inertia falls 3 % at 1500 s (a fall that stands out
  // 2-3.5 deviations for minutes), with the calibration learning on after it (nothing confirmed it yet)
  std::array<double, 7> before{}, after{};
  one_mass_drop_test(970.0, 1500.0, 1499.0, 0.15, 9, &before, true);
  const auto r = one_mass_drop_test(970.0, 1500.0, 2400.0, 0.15, 9, &after, true);
  // THEN within three minutes a window stands out 4 deviations for 5 tested seconds in a row (learning from
  // every second of the fall, the test never confirmed it) ...
  int in_a_row = 0;
  double confirmed_at = -1.0;
  for (std::size_t s = 1500; s < r.size() && confirmed_at < 0.0; ++s) {
    in_a_row = r[s].z >= 4.0 ? in_a_row + 1 : 0;
    if (in_a_row >= 5) confirmed_at = static_cast<double>(s) + 1.0 - 1500.0;
  }
  EXPECT_GT(confirmed_at, 0.0);
  EXPECT_LT(confirmed_at, 180.0);
  // ... and the windows' ratios stay near what the noise taught them (measured: 1.1-1.8 times after 15
  // minutes; learning from every second of the fall, 1.2-5.5 times, 5-10 times over five seeds)
  double growth = 0.0;
  for (std::size_t k = 0; k < after.size(); ++k) {
    EXPECT_LT(after[k], 2.5 * before[k]) << k;
    growth += after[k] / before[k] / static_cast<double>(after.size());
  }
  EXPECT_LT(growth, 1.6);
  std::printf("[measured] one-mass 3 %% step, learning on: confirmed %.0f s after it; ratios", confirmed_at);
  for (std::size_t k = 0; k < after.size(); ++k) std::printf(" %.2f->%.2f", before[k], after[k]);
  std::printf("\n");
}

TEST(InertiaDropTest, ForgettingDropsEveryBalanceAndKeepsWhatWasLearned) {
  // GIVEN a test that learned for 30 minutes
  std::array<double, 7> learned{};
  DropTestConfig c;
  c.filter_time = 0.0;
  InertiaDropTest t(c);
  std::mt19937_64 rng(3);
  std::normal_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < 1800 * 100; ++i) {
    t.update(100.0 + 0.5 * std::sin(i * 0.003), 2e5 * (1.0 + 0.05 * unit(rng)), 2000.0);
    if (i % 100 == 99) t.test(1.0, 1000.0, 0.025, 0.0, true);
  }
  learned = t.calibration();
  ASSERT_GT(t.balances(), 700u);
  // WHEN it forgets (a long hole in the data)
  t.forget();
  // THEN no balance is left, nothing is tested until a new reference is in, and the calibration stays
  EXPECT_EQ(t.balances(), 0u);
  for (int i = 0; i < 100 * 100; ++i) t.update(100.0, 2e5, 2000.0);
  EXPECT_FALSE(t.test(1.0, 1000.0, 0.025, 0.0, true).tested);
  for (std::size_t k = 0; k < learned.size(); ++k) EXPECT_DOUBLE_EQ(t.calibration()[k], learned[k]);
}

TEST(IceDetector, TwoMassTurbulentPlantWithTrueAeroPowerWithinOnePercent) {
  // GIVEN the two-mass plant in 12 % turbulence with benchmark sensor noise, P from the recording
  for (double wind : {8.0, 16.0}) {
    const auto r = run_plant(wind, 1200, false);
    // THEN after convergence (300 s) the reported inertia is within 1 % (rms and worst case)
    EXPECT_LT(r.rms, 0.01) << wind;
    EXPECT_LT(r.max, 0.01) << wind;
  }
}

TEST(IceDetector, ModelledPowerFromTheAnemometerWithinTwoPercentRms) {
  // GIVEN P from the aerodynamic model on the noisy anemometer (0.5 m/s), rotor speed and each pitch
  for (double wind : {12.0, 20.0}) {
    const auto r = run_plant(wind, 1500, true);
    // THEN the reported inertia is within 2 % rms (measured about 1 %) and 5 % worst case
    EXPECT_LT(r.rms, 0.02) << wind;
    EXPECT_LT(r.max, 0.05) << wind;
  }
}

TEST(IceDetector, AHealthyHourRaisesNothing) {
  for (double wind : {8.0, 12.0, 16.0, 20.0}) {
    const auto r = run_plant(wind, 3600, true, {}, 0.0, 100 + static_cast<uint64_t>(wind));
    EXPECT_TRUE(r.events.empty()) << wind << " m/s: " << r.events.size() << " events, first "
                                  << (r.events.empty() ? "" : r.events[0].fault);
    // ... and the detector ran: an inertia estimate about every second after 300 s, nothing rejected
    EXPECT_GT(r.estimates, 3000) << wind;
    EXPECT_EQ(r.rejected, 0u) << wind;
  }
}

TEST(IceDetector, AShortHoleOfLostSamplesIsBridgedNotARestart) {
  // GIVEN the accretion ramp below with 20 samples lost every 30 s (a loaded host: the CI's ice pipeline
  // test lost 20 samples at a time and saw no ice in its whole scenario)
  auto f = plant::FaultSpec::make("WT01", "rotor", "ice_accretion", 300).with_value(2500);
  f.ramp_in = 600;
  const Losses losses{30.0, 20};
  const auto bridged = run_plant(10.0, 1500, true, {f}, 0.0, 7, defaults(), {}, TurbineParams{}, losses);
  // THEN ice_accretion is raised during the ramp as without losses
  ASSERT_FALSE(bridged.events.empty());
  EXPECT_EQ(bridged.events.front().fault, "ice_accretion");
  EXPECT_GT(bridged.events.front().t, 300.0);
  EXPECT_LT(bridged.events.front().t, 1200.0);
  // ... where restarting the 120 s regression on every hole (max_bridged_gap 0) never estimates at all
  const auto restarted =
      run_plant(10.0, 1500, true, {f}, 0.0, 7, config("max_bridged_gap: 0"), {}, TurbineParams{}, losses);
  EXPECT_TRUE(restarted.events.empty()) << restarted.events.front().fault;
  EXPECT_EQ(restarted.estimates, 0);
  // AND a healthy hour with the same losses raises nothing
  const auto healthy = run_plant(12.0, 3600, true, {}, 0.0, 112, defaults(), {}, TurbineParams{}, losses);
  EXPECT_TRUE(healthy.events.empty()) << healthy.events.front().fault;
  EXPECT_GT(healthy.estimates, 3000);
}

TEST(IceDetector, AfterAHoleLongerThanAPowerStepWindowTheSheddingTestStartsAfresh) {
  // GIVEN 90 s of samples lost at 910 s (the wind and the power model's calibration move unseen: on the
  // example 2 MW turbine, windows across 260 s of suspect inputs read an inertia fall of 11-13 %)
  const auto hole =
      run_plant(10.0, 1100, true, {}, 0.0, 7, defaults(), {}, TurbineParams{}, Losses{1000.0, 9000});
  // THEN the shedding test keeps only the balances since (about 100 s), where a hole of 30 s keeps the
  // balances before it too
  EXPECT_LE(hole.drop_balances, 100u);
  EXPECT_GT(hole.drop_balances, 80u);
  const auto short_hole =
      run_plant(10.0, 1100, true, {}, 0.0, 7, defaults(), {}, TurbineParams{}, Losses{1000.0, 3000});
  EXPECT_GT(short_hole.drop_balances, 700u);
}

TEST(IceDetector, AccretionRampIsFlaggedAndSized) {
  // GIVEN 2500 kg of ice accreting over 600 s from t = 300 s (+7 % inertia) at 10 m/s
  auto f = plant::FaultSpec::make("WT01", "rotor", "ice_accretion", 300).with_value(2500);
  f.ramp_in = 600;
  const auto r = run_plant(10.0, 1500, true, {f});
  // THEN ice_accretion is raised during the ramp, and its size is the true mass at that time within 40 %
  ASSERT_FALSE(r.events.empty());
  const auto& first = r.events.front();
  EXPECT_EQ(first.fault, "ice_accretion");
  EXPECT_TRUE(first.raised);
  EXPECT_GT(first.t, 300.0);
  EXPECT_LT(first.t, 1200.0);
  const double true_mass = 2500.0 * std::min(1.0, (first.t - 300.0) / 600.0);
  EXPECT_NEAR(first.size, true_mass, 0.4 * true_mass) << first.t;
  // A 5 % inertia increase (about 1830 kg) is flagged: the warning level sits below it.
  EXPECT_LT(load_detector_config(defaults(), TurbineParams{}).warning_rise, 0.05);
}

plant::FaultSpec shedding(double fraction, double start) {
  auto f = plant::FaultSpec::make("WT01", "rotor", "ice_shedding", start);
  f.fraction = fraction;
  return f;
}

std::string describe(const PlantRun& r) {
  std::string out;
  for (const auto& e : r.events)
    out += std::to_string(static_cast<int>(e.t)) + " s " + e.fault + (e.raised ? " raised " : " cleared ") +
           e.severity + ": " + e.detail + "\n";
  return out;
}

// The first ice_shedding raised in [from, to), or nullptr.
const FaultEvent* shedding_raised(const PlantRun& r, double from, double to) {
  for (const auto& e : r.events)
    if (e.fault == "ice_shedding" && e.raised && e.t >= from && e.t < to) return &e;
  return nullptr;
}

TEST(IceDetector, SheddingOfIceThatWasThereIsFlaggedWithinAMinute) {
  // GIVEN 3000 kg of ice of which 40 % (1200 kg, -3.3 % inertia, +2.4 % Cp) falls off at 700 s
  // (tests/perf/ice_detect_plant: 8 of 9 runs within 60 s; the ninth, at 8 m/s, 96 s: the Cp comes back
  // over a minute and a half there while the rotor speeds up to its new operating point, as seed 37 here:
  // 70 s before stop 65, 94 s since, its balance peaking at 1.06 % against a step threshold of 1.10 %, up
  // from 1.05 % now that the wander is learned within 3 of its RMS)
  for (const auto& [wind, seed, limit] : {std::tuple{10.0, 35, 60.0}, {12.0, 36, 60.0}, {10.0, 37, 100.0}}) {
    // THEN ice_shedding is raised within 60 s of the drop by the Cp it gives back (the inertia's witness held
    // out of reach), and not before it ...
    const auto cp =
        run_plant(wind, 1000, true, {shedding(0.4, 700)}, 3000.0, seed, config("shed_sigmas: 100"));
    const FaultEvent* e = shedding_raised(cp, 700.0, 700.0 + limit);
    ASSERT_NE(e, nullptr) << wind << " m/s seed " << seed << "\n" << describe(cp);
    EXPECT_NE(e->detail.find("power coefficient up"), std::string::npos) << e->detail;
    EXPECT_EQ(shedding_raised(cp, 0.0, 700.0), nullptr) << describe(cp);
    // ... sized from the Cp the seconds after the step kept (as first seen, the step read 1.1-1.3 % of Cp,
    // about 550 kg), within half the ice shed: 10-16 s of balance measure it (702-1216 kg; seed 36 read 886
    // kg before stop 65, its step seen a second earlier), dated when the step was seen
    std::printf("[measured] Cp witness, %g m/s seed %d: raised %.0f s after the drop, dated %.0f s: %s\n",
                wind, seed, e->t - 700.0, e->t_detected - 700.0, e->detail.c_str());
    EXPECT_NEAR(e->size, 1200.0, 600.0) << e->detail;
    EXPECT_GE(e->t_detected, 700.0);
    EXPECT_LE(e->t_detected, e->t - 9.0) << e->detail;  // shed_power_confirm: ten seconds in a row
    // ... and with both witnesses as shipped as soon or sooner (the inertia's, in windows of at least a
    // minute on this rotor, sized at most the ice reported), once
    const auto r = run_plant(wind, 1000, true, {shedding(0.4, 700)}, 3000.0, seed);
    const FaultEvent* f = shedding_raised(r, 700.0, 1000.0);
    ASSERT_NE(f, nullptr) << describe(r);
    EXPECT_LE(f->t, e->t) << describe(r);
    EXPECT_LE(f->size, 1.1 * 3000.0) << f->detail;  // the ice reported, within its estimate's error
    EXPECT_EQ(shedding_raised(r, 0.0, 700.0), nullptr) << describe(r);
    EXPECT_EQ(shedding_raised(r, f->t + 1.0, 1000.0), nullptr) << describe(r);
  }
}

TEST(IceDetector, ASheddingRaisedFromTheCpGivenBackIsNotRaisedAgainFromTheInertia) {
  // GIVEN 2999 kg of ice of which 61 % (5 % of J0) falls off at 1500 s, as tests/perf/ice_detect_plant's runs
  for (const auto& [wind, seed] : {std::pair{10.0, 700}, {10.0, 710}, {12.0, 700}}) {
    const auto r = run_plant(wind, 1800, true, {shedding(0.61, 1500)}, 2999.0, seed);
    // THEN it is raised once, from the Cp given back: the balances from before the shedding confirmed the
    // same fall a second time 4 s after the first report's hold was over (12 of 18 such runs)
    int raised = 0;
    for (const auto& e : r.events) raised += e.fault == "ice_shedding" && e.raised && e.t >= 1500.0;
    EXPECT_EQ(raised, 1) << wind << " m/s seed " << seed << "\n" << describe(r);
    const FaultEvent* e = shedding_raised(r, 1500.0, 1800.0);
    ASSERT_NE(e, nullptr);
    EXPECT_NE(e->detail.find("power coefficient up"), std::string::npos) << e->detail;
  }
}

TEST(IceDetector, SheddingIsSeenInTheInertiaAloneToo) {
  // GIVEN the Cp witness off and 90 % of 3000 kg (-7.5 % inertia, +5.4 % Cp) falling off at 700 s. (Not seed
  // 35 at 10 m/s: there the estimate of the 3 t read below 1750 kg for 30 s just before the drop, the
  // accretion cleared, and without ice reported nothing can be shed: the Cp witness does not need that.)
  int seen = 0;
  for (const auto& [wind, seed] : {std::pair{10.0, 36}, {12.0, 36}, {10.0, 37}, {12.0, 37}}) {
    const auto r =
        run_plant(wind, 1100, true, {shedding(0.9, 700)}, 3000.0, seed, config("shed_power_step: 0"));
    // THEN the inertia's own fall raises ice_shedding within 3 minutes in three of the four (on this rotor,
    // whose ice takes Cp, in windows of at least a minute: the Cp given back blurs the shorter ones), never
    // before the drop
    EXPECT_EQ(shedding_raised(r, 0.0, 700.0), nullptr) << describe(r);
    const FaultEvent* e = shedding_raised(r, 700.0, 880.0);
    std::printf("[measured] inertia alone, %g m/s seed %d: %s\n", wind, seed,
                e ? e->detail.c_str() : "not within 3 minutes");
    if (e == nullptr) continue;
    ++seen;
    EXPECT_NE(e->detail.find("inertia fell"), std::string::npos) << e->detail;
  }
  EXPECT_GE(seen, 3);
}

/// The example 2 MW turbine (deploy/turbine/example_2MW.yaml).
TurbineParams example_2mw() {
  return load_turbine_params_file(std::string(WINDFDI_SOURCE_DEPLOY_DIR) + "/turbine/example_2MW.yaml");
}

/// A turbine of the multi-fault suite's healthy scenarios (shear 0.2 +- 0.05).
plant::TurbineScenario healthy_suite_turbine(const std::string& id, double wind, double turbulence_intensity,
                                             double shear_exponent = 0.2, double shear_variation = 0.05) {
  plant::TurbineScenario t;
  t.id = id;
  t.wind.mean = wind;
  t.wind.turbulence_intensity = turbulence_intensity;
  t.wind.shear_exponent = shear_exponent;
  t.wind.shear_variation = shear_variation;
  return t;
}

TEST(IceDetector, OnARotorWhoseIceChangesNoCpTheInertiaAloneSeesTheShedding) {
  // GIVEN the example 2 MW turbine (deploy/turbine/example_2MW.yaml: its ice changes no Cp, and its inertia
  // estimate is noisier than the benchmark rotor's, 1.2-1.3 % sd against 0.8-1.0 %) with 1000 kg of ice (+8.2
  // % inertia, severity fault) of which 70 % falls off at 1000 s, at 9 and 12 m/s, three seeds each, its
  // power from the model on the noisy anemometer
  const TurbineParams p = example_2mw();
  int seen = 0;
  for (double wind : {9.0, 12.0})
    for (uint64_t seed : {41u, 42u, 43u}) {
      const auto r = run_plant(wind, 1400, true, {shedding(0.7, 1000)}, 1000.0, seed, defaults(), {}, p);
      // THEN no shedding is raised before the drop, and it is raised within 300 s of it in at least four of
      // the six runs, dated when the fall first stood out, never before the drop. At 9 m/s
      // the anemometer's noise is the limit: a minute of balances has a standard deviation of 2.2 % of J0
      // there, and seeds 41 and 42 are not raised (the reported estimate's own fall raised them at 67-209 s
      // before stop 52, and 5-9 false sheddings in 9 hours of ice that stayed)
      EXPECT_EQ(shedding_raised(r, 0.0, 1000.0), nullptr) << wind << " " << seed << "\n" << describe(r);
      const FaultEvent* e = shedding_raised(r, 1000.0, 1300.0);
      std::printf("[measured] 2 MW shedding %g m/s seed %llu: %.0f s, %s\n", wind,
                  static_cast<unsigned long long>(seed), e ? e->t - 1000.0 : -1.0,
                  e ? e->detail.c_str() : "not within 300 s");
      if (e == nullptr) continue;
      ++seen;
      EXPECT_NE(e->detail.find("inertia fell"), std::string::npos) << e->detail;
      EXPECT_GE(e->t_detected, 1000.0) << e->detail;
      EXPECT_LE(e->t_detected, e->t - 4.0) << e->detail;  // five tested seconds in a row
    }
  EXPECT_GE(seen, 4);
}

TEST(IceDetector, WithACleanPowerSignalA5PercentSheddingIsSeenFromTheInertiaAloneWithinAMinute) {
  // GIVEN the example 2 MW turbine (its ice changes no Cp: only the inertia can see a shedding) with a power
  // signal free of the anemometer's noise (a recording's aero_power column), 8.2 % of J0 of ice (1000 kg) of
  // which 5 % of J0 falls off at 1500 s; 8, 10 and 12 m/s
  const TurbineParams p = example_2mw();
  const double kg_per_share =
      p.lumped_inertia() * p.gear_ratio * p.gear_ratio / (p.ice_radius * p.ice_radius);
  const double iced = 0.082 * kg_per_share;
  int within_a_minute = 0;
  for (double wind : {8.0, 10.0, 12.0}) {
    const auto shed = shedding(0.05 / 0.082, 1500);
    const auto r = run_plant(wind, 1800, false, {shed}, iced, 700, defaults(), {}, p);
    // THEN nothing is shed before the drop, and the drop is raised by the inertia within 60 s
    EXPECT_EQ(shedding_raised(r, 0.0, 1500.0), nullptr) << wind << "\n" << describe(r);
    const FaultEvent* e = shedding_raised(r, 1500.0, 1800.0);
    ASSERT_NE(e, nullptr) << wind << "\n" << describe(r);
    std::printf("[measured] clean-power 2 MW 5 %% shedding at %g m/s: %.0f s, %s\n", wind, e->t - 1500.0,
                e->detail.c_str());
    within_a_minute += e->t - 1500.0 <= 60.0;
  }
  EXPECT_EQ(within_a_minute, 3);
}

TEST(IceDetector, IceThatStaysIsNotShedWithANoisyOrACleanPowerSignal) {
  // GIVEN the example 2 MW turbine's steadily iced rotor (8.2 % of J0) for 50 minutes at 10 m/s, its power
  // from the noisy anemometer, and the same with a clean power signal
  const TurbineParams p = example_2mw();
  const double kg_per_share =
      p.lumped_inertia() * p.gear_ratio * p.gear_ratio / (p.ice_radius * p.ice_radius);
  const auto noisy = run_plant(10.0, 3000, true, {}, 0.082 * kg_per_share, 910, defaults(), {}, p);
  const auto clean = run_plant(10.0, 3000, false, {}, 0.082 * kg_per_share, 910, defaults(), {}, p);
  // THEN the ice is reported and neither sheds it
  for (const PlantRun* r : {&noisy, &clean}) {
    EXPECT_TRUE(std::any_of(r->events.begin(), r->events.end(), [](const FaultEvent& e) {
      return e.raised && e.fault == "ice_accretion";
    })) << describe(*r);
    EXPECT_EQ(shedding_raised(*r, 0.0, 3000.0), nullptr) << describe(*r);
  }
}

TEST(IceDetector, AFewExcitedSecondsHeldThroughACalmSpellRaiseNoIce) {
  // GIVEN the example 2 MW turbine's clean rotor at 20 m/s as the multi-fault suite's healthy scenario 40_08
  // runs it (TI 0.10, turbine WT04, seed 40008): pitch control holds its speed so well that the regression is
  // excited for a few seconds in the first 20 minutes, and their median, +8.3 %, is then held for 1400 s
  const auto r = run_turbine(healthy_suite_turbine("WT04", 20.0, 0.10), 1800, true, {}, 40008, defaults(), {},
                             example_2mw());
  // THEN no ice is raised: a level needs confirm_time of fresh estimates from a median at least half full
  // (it was raised at severity fault 10 s after those seconds)
  EXPECT_TRUE(r.events.empty()) << describe(r);
}

TEST(IceDetector, AnExcursionOfTheEstimateOnACleanRotorIsNoFirstReport) {
  // GIVEN the example 2 MW turbine's clean rotor at 8 m/s as the multi-fault suite's healthy scenario 40_09
  // runs it (TI 0.12, turbine WT01, seed 40009): the reported estimate wanders +-4 % of J0 for minutes and
  // stands 1.01-1.08 times the 4.65 % warning for about 40 s after 2840 s
  // (with the benchmark turbine's gates in rad/s and N m, under which it was recorded: with this rotor's own,
  // shares of its rated values, the estimate no longer makes this excursion)
  const TurbineParams p = example_2mw();
  const plant::TurbineScenario t = healthy_suite_turbine("WT01", 8.0, 0.12);
  const char* gates = "min_excitation: 2.0, min_generator_speed: 30, min_gen_torque: 3000";
  // THEN no ice is raised: a clean rotor's first report needs first_confirm_time (60 s) of fresh estimates
  // above the warning ...
  const auto r =
      run_turbine(t, 3000, true, {}, 40009, config((std::string("{") + gates + "}").c_str()), {}, p);
  EXPECT_TRUE(r.events.empty()) << describe(r);
  // ... where confirm_time alone (10 s, before) raised the warning at 2850 s
  const auto before = run_turbine(
      t, 3000, true, {}, 40009,
      config((std::string("{first_confirm_time: 10, first_evidence: 0, ") + gates + "}").c_str()), {}, p);
  EXPECT_FALSE(before.events.empty()) << "the excursion no longer happens: this test no longer tests";
}

TEST(IceDetector, AMinuteLongExcursionNearRatedWindIsNoFirstReportWhereIceThatStaysIs) {
  // GIVEN the example 2 MW turbine's clean rotor at 12 m/s, just above its rated wind, as the multi-fault
  // suite's healthy scenario 73_02 runs it (TI 0.099, turbine WT02, seed 73002): the speed is held at rated
  // by the pitch and the estimate jumps from +2 % to +6.5 % of J0 in 40 s near 2170 s, stays above the
  // 4.65 % warning for about 65 s and falls back within about the 120 s regression's window
  const TurbineParams p = example_2mw();
  const plant::TurbineScenario t = healthy_suite_turbine("WT02", 12.0, 0.099, 0.123, 0.03);
  const auto r = run_turbine(t, 2400, true, {}, 73002, defaults(), {}, p);
  // THEN no ice is raised: the first warning needs first_evidence, the rise above the warning level summed
  // over the fresh seconds (1.0: a minute at +1.7 % above it), each second below taking its shortfall back
  // ...
  EXPECT_TRUE(r.events.empty()) << describe(r);
  // ... where a minute above the level (first_confirm_time 60 s, without the evidence, every fresh second
  // counting fully) raised it
  const auto before =
      run_turbine(t, 2400, true, {}, 73002,
                  config("{first_confirm_time: 60, first_evidence: 0, first_excitation: 1}"), {}, p);
  ASSERT_FALSE(before.events.empty()) << "the excursion no longer happens: this test no longer tests";
  EXPECT_EQ(before.events.front().fault, "ice_accretion");
  // AND 7 % of ice that stays (850 kg from 600 s over 300 s), the same wind, is still reported within 600 s
  // of its ramp's end (the suite's measure; 613 s after its onset since first_excitation 1.5, 600 s before)
  auto ice = plant::FaultSpec::make("WT02", "rotor", "ice_accretion", 600).with_value(850);
  ice.ramp_in = 300;
  const auto iced = run_turbine(t, 1800, true, {ice}, 73002, defaults(), {}, p);
  ASSERT_FALSE(iced.events.empty()) << describe(iced);
  EXPECT_EQ(iced.events.front().fault, "ice_accretion");
  EXPECT_LT(iced.events.front().t, 600.0 + 300.0 + 600.0) << describe(iced);
}

TEST(IceDetector, AtLowTurbulenceTheFirstWarningMustStandOutOfTheCleanRotorsOwnError) {
  // GIVEN the benchmark turbine's clean rotor at 12 m/s and 6.7 % turbulence as the multi-fault suite's
  // healthy scenario 51_09 runs it (turbine WT02, seed 51009): with little excitation the estimate's error is
  // larger and skewed up, and it stood above the 4.65 % warning for over a minute near 1300 s
  const plant::TurbineScenario t = healthy_suite_turbine("WT02", 12.0, 0.067, 0.218, 0.03);
  const auto r = run_turbine(t, 1500, true, {}, 51009, defaults(), {}, TurbineParams{});
  // THEN no ice is raised: the first warning also needs warning_sigmas (3.5) standard deviations of the
  // error, learned from the estimates below J0 (ice cannot put them there) ...
  EXPECT_TRUE(r.events.empty()) << describe(r);
  // ... where the warning level alone raised it (with a minute above it as the first report's only
  // confirmation, every fresh second counting fully, as when this was written)
  const auto fixed = run_turbine(
      t, 1500, true, {}, 51009,
      config("{warning_sigmas: 0, first_confirm_time: 60, first_evidence: 0, first_excitation: 1}"), {},
      TurbineParams{});
  ASSERT_FALSE(fixed.events.empty()) << "the excursion no longer happens: this test no longer tests";
  EXPECT_EQ(fixed.events.front().fault, "ice_accretion");
}

TEST(IceDetector, AFirstWarningCountsBarelyExcitedWindowsForLittle) {
  // GIVEN the example 2 MW turbine's clean rotor at 8 m/s and 9 % turbulence as the multi-fault suite's
  // healthy scenario 51_02 runs it (turbine WT01, seed 51002): near 2330 s the estimate climbs from -2.5 % to
  // +6.3 % of J0 within two minutes and stands above the 4.65 % warning for about 130 s, from windows whose
  // excitation is 1.02-1.30 times the regression's gate (median 1.11)
  const TurbineParams p = example_2mw();
  const plant::TurbineScenario t = healthy_suite_turbine("WT01", 8.0, 0.09, 0.117, 0.03);
  const auto r = run_turbine(t, 2700, true, {}, 51002, defaults(), {}, p);
  // THEN no ice is raised: such a second counts ((e/g)^2 - 1) / (k^2 - 1) of a second toward the first
  // warning's time and evidence (first_excitation k = 1.3), and the evidence takes the lower of the median
  // and the second's own estimate (either alone holds this one back) ...
  EXPECT_TRUE(r.events.empty()) << describe(r);
  // ... where the minute above the level, every fresh second counting fully, raised the warning
  const auto before =
      run_turbine(t, 2700, true, {}, 51002, config("{first_excitation: 1, first_evidence: 0}"), {}, p);
  ASSERT_FALSE(before.events.empty()) << "the excursion no longer happens: this test no longer tests";
  EXPECT_EQ(before.events.front().fault, "ice_accretion");
  // AND 6.8 % of ice that stays (835 kg from 900 s over 300 s) on the same rotor in the same wind is still
  // reported within 600 s of the end of its ramp
  auto ice = plant::FaultSpec::make("WT01", "rotor", "ice_accretion", 900).with_value(835);
  ice.ramp_in = 300;
  const auto iced = run_turbine(t, 2100, true, {ice}, 51002, defaults(), {}, p);
  ASSERT_FALSE(iced.events.empty()) << describe(iced);
  EXPECT_EQ(iced.events.front().fault, "ice_accretion");
  EXPECT_LT(iced.events.front().t, 900.0 + 300.0 + 600.0) << describe(iced);
  std::printf("[measured] 2 MW, 8 m/s, TI 0.09: 6.8 %% ice raised %.0f s after its onset\n",
              iced.events.front().t - 900.0);
}

TEST(IceDetector, FastAccretionDoesNotOvershootIntoCritical) {
  // GIVEN 2500 kg of ice in one minute from 500 s (freezing rain; -5 % Cp with it) at 10 m/s. Before the
  // power model followed steps in Cp, the regression window across the step reported +17 % inertia
  // (9246 kg of ice: critical, the arbiter stopped the turbine).
  auto f = plant::FaultSpec::make("WT01", "rotor", "ice_accretion", 500).with_value(2500);
  f.ramp_in = 60;
  for (uint64_t seed : {7u, 8u}) {
    const auto r = run_plant(10.0, 1200, true, {f}, 0.0, seed);
    // THEN the inertia never reads more than 5 % above the truth, and no critical is raised
    EXPECT_LT(r.max_over, 0.05) << seed;
    for (const auto& e : r.events)
      EXPECT_NE(e.severity, "critical") << seed << " at " << e.t << ": " << e.detail;
  }
}

TEST(IceDetector, OnlyStrongSettledEvidenceRaisesTheStopLevel) {
  const DetectorConfig cfg = load_detector_config(defaults(), TurbineParams{});
  auto first = [](const PlantRun& r, const std::string& severity) -> const FaultEvent* {
    for (const auto& e : r.events)
      if (e.fault == "ice_accretion" && e.raised && e.severity == severity) return &e;
    return nullptr;
  };
  // GIVEN a rotor carrying 4000 kg of ice, below the critical level (critical_rise, 4500 kg) but within the
  // estimate's error of it
  const auto light = run_plant(12.0, 1500, true, {}, 4000.0, 41);
  // THEN it is reported (fault level) and never stopped
  EXPECT_NE(first(light, "fault"), nullptr) << describe(light);
  EXPECT_EQ(first(light, "critical"), nullptr) << describe(light);
  // GIVEN 7500 kg, well above it
  const auto heavy = run_plant(12.0, 1500, true, {}, 7500.0, 41);
  // THEN the fault level comes first, and the stop level after critical_confirm_time of estimates above it
  const FaultEvent* fault = first(heavy, "fault");
  const FaultEvent* critical = first(heavy, "critical");
  ASSERT_NE(fault, nullptr) << describe(heavy);
  ASSERT_NE(critical, nullptr) << describe(heavy);
  EXPECT_LT(fault->t, critical->t);
  EXPECT_GE(critical->t - critical->t_detected, cfg.critical_confirm_time - 1.0) << describe(heavy);
  // (the detail gives the level as an inertia rise, the size the kilograms: 12.3 % is 4500 kg here)
  EXPECT_GT(critical->size, 4490.0 * (1.0 + cfg.critical_margin));
  EXPECT_NE(critical->detail.find("level 14.8 %"), std::string::npos) << critical->detail;
}

TEST(IceDetector, AReportedPitchSensorHoldsTheEstimate) {
  // GIVEN a clean rotor at 11 m/s whose blade-3 pitch reading is stuck at 10.5 deg from 60 s, and another
  // service (sensor_bias) reporting pitch_sensor_3
  auto stuck = plant::FaultSpec::make("WT01", "pitch_3", "stuck", 60.0);
  stuck.value = 10.5;
  InputContext reported;
  reported.pitch_sensor_suspect[2] = true;
  const auto r = run_plant(11.0, 900, true, {stuck}, 0.0, 7, defaults(), reported);
  // THEN the estimator is held throughout (its power model would read the stuck pitch) and nothing is raised
  EXPECT_GE(r.suspect, 899u * 100u);
  EXPECT_TRUE(r.events.empty()) << describe(r);
  // (without the report it is fed: this plant run happens to raise nothing, a closed-loop one in degraded
  // mode raised ice after 180 s)
  EXPECT_EQ(run_plant(11.0, 120, true, {stuck}).suspect, 0u);
}

TEST(IceDetector, AReportedDriveTrainEfficiencyLossHoldsTheSheddingTest) {
  // GIVEN the example 2 MW rotor (its ice takes no Cp: the inertia alone sees a shedding) with 1000 kg of ice
  // (+8.2 % of J0) that stays, at 13.6 m/s and 6.9 % turbulence (the wind of suite set 222, scenario 01),
  // whose drive train loses efficiency (0.92) from 1000 to 1150 s, and drive_train reporting it from 1023 to
  // 1180 s (its measured delays: 22-23 s to raise, 30 s to clear). Four seeds
  const TurbineParams p = example_2mw();
  plant::TurbineScenario t = healthy_suite_turbine("WT03", 13.6, 0.069, 0.294, 0.03);
  t.ice_mass = 1000.0;
  auto loss = plant::FaultSpec::make("WT03", "drive_train", "efficiency", 1000.0).with_value(0.92);
  loss.end = 1150.0;
  InputContext reported;
  reported.drive_train_suspect = true;
  int false_sheddings = 0, false_sheddings_fed = 0;
  for (uint64_t seed : {222006u, 222001u, 41u, 42u}) {
    const auto held =
        run_turbine(t, 1500, true, {loss}, seed, defaults(), reported, p, {}, ContextSpan{1023.0, 1180.0});
    const auto fed = run_turbine(t, 1500, true, {loss}, seed, config("efficiency_loss_holds: false"),
                                 reported, p, {}, ContextSpan{1023.0, 1180.0});
    // (from the loss's onset: seed 42 raises a false shedding of the ice that stays at 908 s either way)
    const FaultEvent* e = shedding_raised(held, 1000.0, 1500.0);
    const FaultEvent* f = shedding_raised(fed, 1000.0, 1500.0);
    std::printf("[measured] seed %llu: held %.0f s %s; fed through the report %.0f s %s\n",
                static_cast<unsigned long long>(seed), e ? e->t_detected : 0.0,
                e ? e->detail.c_str() : "no shedding", f ? f->t_detected : 0.0,
                f ? f->detail.c_str() : "no shedding");
    false_sheddings += e != nullptr;
    false_sheddings_fed += f != nullptr;
    // THEN the inertia regression is not held (an iced rotor's Cp loss is read as efficiency_loss too) and
    // the ice that stays is reported
    EXPECT_EQ(held.suspect, 0u);
    EXPECT_NE(std::find_if(held.events.begin(), held.events.end(),
                           [](const FaultEvent& x) { return x.raised && x.fault == "ice_accretion"; }),
              held.events.end())
        << describe(held);
  }
  // AND no ice is shed where, fed through the report, the efficiency step reads as a fall of the inertia (3
  // of the 4 seeds, 68-71 s after the loss began)
  EXPECT_EQ(false_sheddings, 0);
  EXPECT_GE(false_sheddings_fed, 2);
}

TEST(IceDetector, BadSamplesAreCountedAndNeverFed) {
  TurbineParams p;
  IceDetector det(load_detector_config(defaults(), p), p);
  std::vector<FaultEvent> events;
  FrameSample s;
  s.t = 0.0;
  s.generator_speed = 150.0;
  s.gen_torque = 30000.0;
  EXPECT_TRUE(det.update(s, 4.5e6, false, events));
  s.generator_speed = kNaN;
  EXPECT_FALSE(det.update(s, 4.5e6, false, events));
  s.generator_speed = 150.0;
  EXPECT_FALSE(det.update(s, std::numeric_limits<double>::infinity(), false, events));
  s.gen_torque = 1e9;
  EXPECT_FALSE(det.update(s, 4.5e6, false, events));
  EXPECT_EQ(det.rejected(), 3u);
  EXPECT_EQ(det.estimator().estimates(), 0u);
}

TEST(AeroPowerInput, ModelPowerIsNanForMissingInputs) {
  TurbineParams p;
  AeroModel aero(p);
  FrameSample s;
  s.wind_hub = 10.0;
  s.rotor_speed = 1.3;
  s.pitch = {0.0, 0.0, 0.0};
  EXPECT_GT(model_aero_power(aero, 10.0, s), 1e6);
  s.pitch[1] = kNaN;
  EXPECT_TRUE(std::isnan(model_aero_power(aero, 10.0, s)));
  EXPECT_TRUE(std::isnan(model_aero_power(aero, kNaN, s)));
  // Out of the plausible range: no power, and the limits are the caller's
  s.pitch[1] = 0.0;
  PowerModelLimits narrow;
  narrow.rotor_speed_max = 1.0;
  EXPECT_TRUE(std::isnan(model_aero_power(aero, 10.0, s, narrow)));
  EXPECT_GT(model_aero_power(aero, 10.0, s), 1e6);
  EXPECT_TRUE(std::isnan(model_aero_power(aero, 61.0, s)));
  s.pitch[2] = 96.0;
  EXPECT_TRUE(std::isnan(model_aero_power(aero, 10.0, s)));
  s.pitch[2] = 0.0;
  s.pitch[1] = kNaN;
  // Without averaging every sample comes straight out, and a recording's column wins over the model.
  AeroPowerInput direct(aero, 0.0, 0.01);
  FrameSample out;
  bool gap = false;
  double power = 0.0;
  ASSERT_TRUE(direct.push(s, true, out, gap, power));
  EXPECT_TRUE(std::isnan(power));
  EXPECT_TRUE(gap);
  s.aero_power = 2e6;
  ASSERT_TRUE(direct.push(s, false, out, gap, power));
  EXPECT_DOUBLE_EQ(power, 2e6);
}

TEST(AeroPowerInput, AveragesTheAnemometerAroundEachSampleAndLosesNone) {
  // GIVEN a steady 10 m/s wind read by an anemometer that alternates +-1 m/s about it, and a 0.5 s window
  TurbineParams p;
  AeroModel aero(p);
  AeroPowerInput input(aero, 0.5, 0.01);
  FrameSample s;
  s.rotor_speed = 1.3;
  s.pitch = {0.0, 0.0, 0.0};
  const double steady = model_aero_power(aero, 10.0, s);
  std::vector<double> t_out;
  for (int k = 0; k < 1000; ++k) {
    s.t = k * 0.01;
    s.wind_hub = 10.0 + (k % 2 ? 1.0 : -1.0);
    FrameSample out;
    bool gap = false;
    double power = kNaN;
    if (!input.push(s, false, out, gap, power)) continue;
    t_out.push_back(out.t);
    // THEN once the window is full each sample's power is the model at the mean wind (the window holds 51
    // samples: the mean is 10 +- 1/51)
    if (out.t > 0.3) {
      EXPECT_NEAR(power, steady, 0.03 * steady) << out.t;
    }
  }
  // AND every sample leaves, in order, a quarter of a second late
  ASSERT_EQ(t_out.size(), 975u);
  for (std::size_t i = 0; i < t_out.size(); ++i) EXPECT_NEAR(t_out[i], static_cast<double>(i) * 0.01, 1e-9);
}

TEST(AeroPowerInput, ASampleAllocatesNothing) {
  // GIVEN a 0.5 s window that is full
  TurbineParams p;
  AeroModel aero(p);
  AeroPowerInput input(aero, 0.5, 0.01);
  FrameSample s, out;
  s.rotor_speed = 1.3;
  s.pitch = {0.0, 0.0, 0.0};
  bool gap = false;
  double power = kNaN;
  const auto push = [&](int k) {
    s.t = k * 0.01;
    s.wind_hub = 10.0 + (k % 2 ? 1.0 : -1.0);
    input.push(s, false, out, gap, power);
  };
  for (int k = 0; k < 100; ++k) push(k);
  // WHEN ten thousand samples more go through
  const uint64_t before = windfdi::test::allocations();
  for (int k = 100; k < 10100; ++k) push(k);
  // THEN none allocated (its deque allocated a block every other sample; issue 21)
  EXPECT_EQ(windfdi::test::allocations() - before, 0u);
  EXPECT_TRUE(std::isfinite(power));
}

TEST(IceDetector, TheIceLevelsAreTheTurbinesOwnInertiaRise) {
  // GIVEN a lighter rotor (20 000 t m^2 instead of 55 000) carrying 1000 kg of ice at 12 m/s: a 6.8 % inertia
  // rise, below the 4.8 MW rotor's 1700 kg warning in kilograms
  TurbineParams light;
  light.rotor_inertia = 20.0e6;
  const auto r = run_plant(12.0, 1200, true, {}, 1000.0, 43, defaults(), {}, light);
  // THEN the warning is raised (the level is 4.65 % of this rotor's clean inertia, 650 kg), with the
  // kilograms and the rise in its detail
  const FaultEvent* warning = nullptr;
  for (const auto& e : r.events)
    if (e.fault == "ice_accretion" && e.raised && !warning) warning = &e;
  ASSERT_NE(warning, nullptr) << describe(r);
  std::printf("light rotor, 1000 kg of ice: %s\n", warning->detail.c_str());
  EXPECT_EQ(warning->severity, "warning");
  EXPECT_NEAR(warning->threshold, 0.0465 * (20.0e6 / (95.0 * 95.0) + 390.0) * 95.0 * 95.0 / (40.0 * 40.0),
              1.0);
  EXPECT_NE(warning->detail.find("level 4.7 %"), std::string::npos) << warning->detail;
}

TEST(IceDetector, ConfigRejectsUnknownKeysAndBadRanges) {
  EXPECT_THROW(load_detector_config(config("windw: 60"), TurbineParams{}), ConfigError);
  EXPECT_THROW(load_detector_config(config("fault_rise: 0.01"), TurbineParams{}),
               ConfigError);  // below warning_rise
  EXPECT_EQ(load_detector_config(config("window: 90"), TurbineParams{}).estimator.window, 90.0);
}

TEST(IceDetector, TheFeatheredPitchIsTheTurbinesOwn) {
  // GIVEN the shipped configuration on the benchmark turbine and on the example 2 MW one
  const YamlSection shipped =
      YamlSection::load_file(std::string(WINDFDI_SOURCE_DEPLOY_DIR) + "/config/ice_detect.yaml");
  const TurbineParams bench{}, two = example_2mw();
  // THEN nothing pitched beyond what each needs for rated power 3 m/s past cut-out is fed: 32.9 and 34.7 deg
  // (a fixed 30 deg left out the 2 MW rotor's samples in its last metres per second before cut-out) ...
  EXPECT_NEAR(load_detector_config(shipped, bench).max_pitch, 32.93, 0.05);
  EXPECT_NEAR(load_detector_config(shipped, two).max_pitch, 34.68, 0.05);
  EXPECT_LT(feathering_pitch(two, 25.0), load_detector_config(shipped, two).max_pitch);
  EXPECT_GT(feathering_pitch(two, 25.0), 30.0);
  // ... and the fixed key is gone: a configuration that still sets it is told so
  EXPECT_THROW(load_detector_config(config("max_pitch: 30"), bench), ConfigError);
}

TurbineParams example_3mw_medium_speed() {
  return load_turbine_params_file(std::string(WINDFDI_SOURCE_DEPLOY_DIR) +
                                  "/turbine/example_3MW_medium_speed.yaml");
}

TEST(IceDetector, OnAMediumSpeedDriveTrainItsOwnRatedValuesSetWhereItEstimates) {
  // GIVEN the example medium-speed 3 MW turbine (its generator at 52 rad/s at rated, a third of the benchmark
  // turbine's) with the shipped configuration, which gives speed, torque and excitation levels as shares of
  // the turbine's rated values, and 2000 kg of ice (+8.6 % inertia) accreting over 400-700 s
  const YamlSection shipped =
      YamlSection::load_file(std::string(WINDFDI_SOURCE_DEPLOY_DIR) + "/config/ice_detect.yaml");
  const TurbineParams p = example_3mw_medium_speed();
  const DetectorConfig c = load_detector_config(shipped, p);
  EXPECT_NEAR(c.min_generator_speed, 9.62, 0.01);
  EXPECT_NEAR(c.min_gen_torque, 6010.0, 1.0);
  EXPECT_NEAR(c.estimator.min_excitation, 0.642, 0.001);
  // (the benchmark turbine's are the absolute values they replace)
  const DetectorConfig b = load_detector_config(shipped, TurbineParams{});
  EXPECT_NEAR(b.min_generator_speed, 30.0, 0.05);
  EXPECT_NEAR(b.min_gen_torque, 3000.0, 30.0);
  EXPECT_NEAR(b.estimator.min_excitation, 2.0, 0.01);
  auto ice = plant::FaultSpec::make("WT01", "rotor", "ice_accretion", 400).with_value(2000);
  ice.ramp_in = 300;
  const YamlSection absolute = config("min_excitation: 2.0\nmin_generator_speed: 30\nmin_gen_torque: 3000");
  for (double wind : {7.0, 9.0}) {
    // THEN the inertia is estimated and the ice raised during its accretion or about 600 s after its end (the
    // multi-fault suite's delay for a ramped accretion), nothing before. At 7 m/s this rotor's regression is
    // barely excited, and the first warning counts such seconds for little (first_excitation): 553 s after
    // the onset without, 874 s with 1.3, 901 s with 1.5 (601 s after the ramp's end: late by a second)
    const auto r = run_plant(wind, 1500, true, {ice}, 0.0, 41, shipped, {}, p);
    EXPECT_GT(r.estimates, 1000) << wind;
    ASSERT_FALSE(r.events.empty()) << wind;
    EXPECT_EQ(r.events.front().fault, "ice_accretion") << describe(r);
    EXPECT_GT(r.events.front().t, 400.0) << describe(r);
    EXPECT_LT(r.events.front().t, 400.0 + 300.0 + 660.0) << describe(r);
    std::printf(
        "[ measured ] medium speed, %.0f m/s: ice raised %.0f s after the onset, inertia rms error %.2f %%\n",
        wind, r.events.front().t - 400.0, 100.0 * r.rms);
    // AND with the benchmark turbine's absolute levels (2 rad/s of excitation, 30 rad/s, 3000 N m) this
    // turbine is never estimated: the ice goes unseen
    const auto a = run_plant(wind, 1500, true, {ice}, 0.0, 41, absolute, {}, p);
    EXPECT_EQ(a.estimates, 0) << wind;
    EXPECT_TRUE(a.events.empty()) << describe(a);
    // AND a healthy hour raises nothing
    const auto h = run_plant(wind, 3600, true, {}, 0.0, 43, shipped, {}, p);
    EXPECT_GT(h.estimates, 3000) << wind;
    EXPECT_TRUE(h.events.empty()) << describe(h);
  }
}

TEST(IceDetector, ASheddingIsNotRaisedAgainFromAReportedEstimateHeldSinceIt) {
  // GIVEN the medium-speed turbine's clean rotor at 12 m/s, just above its rated wind, and 7.6 % turbulence
  // as the multi-fault suite's healthy scenario 98_03 runs it (turbine WT02, seed 98003): its regression is
  // barely excited, the estimate stood at +5.6-6.9 % of J0 for 80 s and a warning was raised; then the
  // reported estimate was held (unexcited) at +6.7 % for 600 s while the fast one read the clean rotor
  const YAML::Node shipped_file =
      YAML::LoadFile(std::string(WINDFDI_SOURCE_DEPLOY_DIR) + "/config/ice_detect.yaml");
  const YamlSection shipped(shipped_file, "ice_detect.yaml");
  const plant::TurbineScenario t = healthy_suite_turbine("WT02", 12.0, 0.076, 0.272, 0.03);
  // ... with the first warning of stop 45 (first_excitation 1.3), which those windows (1.04-1.23 times the
  // regression's gate) passed
  YAML::Node stop45 = YAML::Clone(shipped_file);
  stop45["first_excitation"] = 1.3;
  const auto r = run_turbine(t, 2400, true, {}, 98003, YamlSection(stop45, "ice_detect.yaml"), {},
                             example_3mw_medium_speed());
  // THEN the shedding is raised at most once per warning: after one, the next needs a median of fresh
  // estimates from windows wholly after it (before: the same 33607 kg m^2 against the fast estimate three
  // times, 1689, 1975 and 2215 s, "about 2000-2900 kg shed" of one false 1500 kg)
  int warnings = 0, sheddings = 0;
  for (const auto& e : r.events) {
    warnings += e.raised && e.fault == "ice_accretion" && e.severity == "warning";
    sheddings += e.raised && e.fault == "ice_shedding";
  }
  ASSERT_GE(warnings, 1) << "the excursion no longer happens: this test no longer tests";
  EXPECT_LE(sheddings, warnings) << describe(r);
  std::printf(
      "[measured] medium speed, 12 m/s, TI 0.076, first_excitation 1.3: %d warning(s), %d shedding(s)\n",
      warnings, sheddings);
  // AND with the shipped first_excitation (1.5: such a window counts 0.07-0.4 of a second) nothing is raised
  const auto shipped_run = run_turbine(t, 2400, true, {}, 98003, shipped, {}, example_3mw_medium_speed());
  EXPECT_TRUE(shipped_run.events.empty()) << describe(shipped_run);
}

TEST(IceDetector, AStopLevelReadFromBarelyExcitedWindowsDoesNotStopTheTurbine) {
  // GIVEN the benchmark turbine at 12.5 m/s, its rated wind, and 7 % turbulence: 4000 kg of ice (+10.9 %
  // inertia, below the 12.3 % critical level) accreting over 900-1200 s, which its barely excited regression
  // reads above the stop level (12.3 % x 1.2) for minutes. (Judged suite seed 131, scenario 04, stopped the
  // example 2 MW rotor so at the same wind; of 40 such rotors at 12.5-20.9 m/s and 6.5-7 % turbulence this
  // one and one at 14 m/s went critical, none with critical_excitation 2.)
  const YAML::Node shipped_file =
      YAML::LoadFile(std::string(WINDFDI_SOURCE_DEPLOY_DIR) + "/config/ice_detect.yaml");
  auto ice = plant::FaultSpec::make("WT01", "rotor", "ice_accretion", 900).with_value(4000);
  ice.ramp_in = 300;
  const plant::TurbineScenario t = healthy_suite_turbine("WT01", 12.5, 0.07, 0.2, 0.03);
  auto critical_of = [](const PlantRun& r) -> const FaultEvent* {
    for (const auto& e : r.events)
      if (e.fault == "ice_accretion" && e.raised && e.severity == "critical") return &e;
    return nullptr;
  };
  // WHEN every fresh second counts fully toward critical_confirm_time (critical_excitation 1, before stop 50)
  YAML::Node every_second = YAML::Clone(shipped_file);
  every_second["critical_excitation"] = 1.0;
  every_second["power_step_spread"] = false;  // and the power step's threshold as before stop 65
  const auto before =
      run_turbine(t, 2700, true, {ice}, 2, YamlSection(every_second, "ice_detect.yaml"), {}, TurbineParams{});
  // THEN critical is raised (the arbiter stops the turbine 90 s later)
  ASSERT_NE(critical_of(before), nullptr) << "no overshoot: this test no longer tests\n" << describe(before);
  // WHEN a second counts by its excitation, fully only from critical_excitation (2) times the gate
  const auto r =
      run_turbine(t, 2700, true, {ice}, 2, YamlSection(shipped_file, "ice_detect.yaml"), {}, TurbineParams{});
  // THEN the ice is reported at severity fault, and never critical
  bool fault = false;
  for (const auto& e : r.events) fault |= e.fault == "ice_accretion" && e.raised && e.severity == "fault";
  EXPECT_TRUE(fault) << describe(r);
  EXPECT_EQ(critical_of(r), nullptr) << describe(r);
  std::printf("[ measured ] critical_excitation 1: critical at %.0f s; 2: none\n", critical_of(before)->t);
}

TEST(IceDetector, AnOvershootOfTheStopLevelIsLoweredWhenTheEstimateFallsBackBelowTheCriticalLevel) {
  // GIVEN the medium-speed turbine as suite seed 91's scenario 06 runs its WT03 (9 m/s, TI 0.085): 2531 kg of
  // ice (+10.9 % inertia, below the 12.3 % critical level) accreting over 2255-2555 s, which the estimate
  // overshoots to +15 % (above the stop level, 12.3 % x 1.2) for about a minute and then leaves, with every
  // fresh second counted fully toward critical_confirm_time (critical_excitation 1, as before stop 50)
  const YAML::Node shipped_file =
      YAML::LoadFile(std::string(WINDFDI_SOURCE_DEPLOY_DIR) + "/config/ice_detect.yaml");
  YAML::Node every_second = YAML::Clone(shipped_file);
  every_second["critical_excitation"] = 1.0;
  every_second["power_step_spread"] = false;  // and the power step's threshold as before stop 65
  auto ice = plant::FaultSpec::make("WT03", "rotor", "ice_accretion", 2255).with_value(2531);
  ice.ramp_in = 300;
  const auto t = healthy_suite_turbine("WT03", 9.0, 0.085, 0.213, 0.03);
  const auto r = run_turbine(t, 3000, true, {ice}, 91006, YamlSection(every_second, "ice_detect.yaml"), {},
                             example_3mw_medium_speed());
  const FaultEvent* critical = nullptr;
  const FaultEvent* lowered = nullptr;
  for (const auto& e : r.events) {
    if (e.fault != "ice_accretion" || !e.raised) continue;
    if (e.severity == "critical" && !critical) critical = &e;
    if (critical && e.severity == "fault" && e.t > critical->t && !lowered) lowered = &e;
  }
  // THEN the stop level is raised, but lowered to fault once the estimate has stayed confirm_time below the
  // critical level, before the arbiter's 90 s stop_confirm_time ran out (held down to 0.7 of the stop level,
  // it stayed critical and the turbine was stopped)
  ASSERT_NE(critical, nullptr) << "no overshoot: this test no longer tests\n" << describe(r);
  ASSERT_NE(lowered, nullptr) << describe(r);
  EXPECT_LT(lowered->t - critical->t, 90.0) << describe(r);
  std::printf("[ measured ] critical at %.0f s, lowered to fault %.0f s later\n", critical->t,
              lowered->t - critical->t);
  // AND with the shipped critical_excitation (those windows are 1.1-1.6 times the gate) it is never raised
  const auto shipped_run =
      run_turbine(t, 3000, true, {ice}, 91006, YamlSection(shipped_file, "ice_detect.yaml"), {},
                  example_3mw_medium_speed());
  for (const auto& e : shipped_run.events)
    EXPECT_FALSE(e.raised && e.severity == "critical") << describe(shipped_run);
}

TEST(IceDetector, AStoppingTurbineRaisesNoIce) {
  // GIVEN a turbine in 16 m/s ordered to a safe stop at 600 s (feather, torque to zero)
  TurbineParams p;
  AeroModel aero(p);
  plant::TurbineScenario t;
  t.id = "WT01";
  t.wind.mean = 16.0;
  t.wind.turbulence_intensity = 0.12;
  plant::TurbineSim sim(p, t, {}, 11, 100.0);
  const DetectorConfig cfg = load_detector_config(defaults(), p);
  IceDetector det(cfg, p);
  AeroPowerInput aero_power(aero, cfg.wind_window, cfg.estimator.sample_time);
  std::vector<FaultEvent> events;
  InertiaOutput o;
  plant::ControlInput stop;
  stop.mode = plant::OperatingMode::kSafeStop;
  for (int k = 0; k < 1500 * 100; ++k) {
    FrameSample s = k < 60000 ? sim.step() : sim.step(stop);
    s.aero_power = kNaN;
    FrameSample centre;
    bool gap = false;
    double power = kNaN;
    if (aero_power.push(s, false, centre, gap, power)) det.update(centre, power, gap, events);
    det.estimate_due(o);
  }
  // THEN the stop is not mistaken for ice (or its shedding)
  EXPECT_TRUE(events.empty()) << events.size() << " events, first " << events[0].fault;
}

}  // namespace

TEST(IceDetector, AGustThatCrossesTheStepThresholdOnAnIcedRotorIsNoShedding) {
  // GIVEN three benchmark rotors of the multi-fault suite's set 161 (judged in stop 54) with 4000 kg of ice
  // that stays, as scenarios 161_00 and 161_01 run them: 18.6 m/s (TI 0.156), 7 m/s (TI 0.152) and 20.8 m/s
  // (TI 0.151). The wind moves a minute's energy balance 1.1-1.4 % above the calibration before it, past
  // shed_power_step, and back within seconds
  struct Turbine {
    const char* id;
    double wind, turbulence_intensity, shear_exponent;
    uint64_t seed;
    double ramp_in;
  };
  for (const auto& c :
       {Turbine{"WT04", 18.6, 0.156, 0.220, 16100, 300.0}, Turbine{"WT02", 7.0, 0.152, 0.247, 16100, 600.0},
        Turbine{"WT02", 20.8, 0.151, 0.281, 16101, 600.0}}) {
    auto ice = plant::FaultSpec::make(c.id, "rotor", "ice_accretion", 900.0);
    ice.value = 4000.0;
    ice.has_value = true;
    ice.ramp_in = c.ramp_in;
    const auto turbine = healthy_suite_turbine(c.id, c.wind, c.turbulence_intensity, c.shear_exponent, 0.03);
    // THEN taken at once, as before stop 55, the step is a shedding (1455 and 1879 s; 2638 s; 1986 s) ...
    const auto at_once =
        run_turbine(turbine, 2700, true, {ice}, c.seed,
                    config("{shed_power_confirm: 0, power_step_spread: false}"), {}, TurbineParams{});
    const FaultEvent* e = shedding_raised(at_once, 0.0, 2700.0);
    ASSERT_NE(e, nullptr) << c.wind << " m/s\n" << describe(at_once);
    EXPECT_NE(e->detail.find("power coefficient up"), std::string::npos) << e->detail;
    // ... and as shipped, where the seconds after a step must keep it, the ice is reported and not shed (nor
    // by the inertia's witness, which read a 7.4 % fall at 20.8 m/s across the gust's calibration until the
    // test started afresh after a step the aerodynamics did not keep)
    const auto kept = run_turbine(turbine, 2700, true, {ice}, c.seed, defaults(), {}, TurbineParams{});
    EXPECT_EQ(shedding_raised(kept, 0.0, 2700.0), nullptr) << c.wind << " m/s\n" << describe(kept);
    EXPECT_TRUE(std::any_of(kept.events.begin(), kept.events.end(), [](const FaultEvent& x) {
      return x.raised && x.fault == "ice_accretion";
    })) << describe(kept);
  }
}

TEST(IceDetector, OnARotorWhoseIceTakesCpAnInertiaFallWithoutTheCpBackIsNoShedding) {
  // GIVEN two rotors of the multi-fault suite's set 161 (ice that stays, scenario 00): the benchmark rotor at
  // 14 m/s with 4000 kg, and the medium-speed one at 18.6 m/s with 2531 kg, whose estimates of the inertia
  // fell 4.5 % and 3.7 % of J0 over 90 and 120 s at 4.0 and 6.6 learned deviations
  struct Turbine {
    const char* id;
    double wind, turbulence_intensity, shear_exponent, ice, ramp_in;
    TurbineParams params;
  };
  for (const auto& c : {Turbine{"WT01", 14.0, 0.115, 0.146, 4000.0, 600.0, TurbineParams{}},
                        Turbine{"WT04", 18.6, 0.156, 0.220, 2531.0, 300.0, example_3mw_medium_speed()}}) {
    auto ice = plant::FaultSpec::make(c.id, "rotor", "ice_accretion", 900.0);
    ice.value = c.ice;
    ice.has_value = true;
    ice.ramp_in = c.ramp_in;
    const auto turbine = healthy_suite_turbine(c.id, c.wind, c.turbulence_intensity, c.shear_exponent, 0.03);
    // THEN without the Cp's testimony the fall is a shedding ...
    const auto alone =
        run_turbine(turbine, 2700, true, {ice}, 16100,
                    config("{shed_inertia_cp_share: 0, power_step_spread: false}"), {}, c.params);
    const FaultEvent* e = shedding_raised(alone, 0.0, 2700.0);
    ASSERT_NE(e, nullptr) << c.wind << " m/s\n" << describe(alone);
    EXPECT_NE(e->detail.find("inertia fell"), std::string::npos) << e->detail;
    // ... and as shipped, where the calibration must have given back a fifth of the Cp that much ice took and
    // stand near its highest of the fall's window, it is not (over the window: +0.03 % against the 3.3 % the
    // fall implies; and a calibration 6 % below its highest, stepped up and back down inside the window)
    const auto with_cp = run_turbine(turbine, 2700, true, {ice}, 16100, defaults(), {}, c.params);
    EXPECT_EQ(shedding_raised(with_cp, 0.0, 2700.0), nullptr) << c.wind << " m/s\n" << describe(with_cp);
  }
}
