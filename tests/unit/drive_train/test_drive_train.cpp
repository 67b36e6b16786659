// drive_train tests: the converter monitor on synthetic samples of known offset and noise, the diagnoser on
// the plant (torque offset, efficiency loss, healthy runs, bad samples, context, configuration) and the
// energy balance's fitted rotor inertia.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "diagnostic_service.hpp"
#include "drive_train_diagnoser.hpp"
#include "turbine_sim.hpp"

using namespace windfdi;
using namespace windfdi::drive_train;

namespace {

const std::string kDeploy = WINDFDI_SOURCE_DEPLOY_DIR;
constexpr double kDt = 0.01;  // s, the benchmark's 100 Hz

// ---------------------------------------------------------------- the converter monitor on synthetic samples

// A converter that is exactly the monitor's model: its output follows the reference, held over each sample,
// to first order with the time constant `tau`. The reference swings by thousands of N m a second (a wrong
// model leaves a residual), the generator speed moves slowly about 150 rad/s, and the measured torque and
// power carry the benchmark's noise (N(0, 90) N m, N(0, 1) kW).
class SyntheticConverter {
 public:
  explicit SyntheticConverter(uint64_t seed, double torque_noise = 90.0, double power_noise = 1e3,
                              double tau = 0.02)
      : rng_(seed), torque_noise_(torque_noise), power_noise_(power_noise), decay_(std::exp(-kDt / tau)) {}

  struct Sample {
    double t, torque, torque_ref, speed, power;
  };
  /// The next sample with `converter_offset` on the generator (torque and power see it) and `sensor_offset`
  /// on the torque sensor alone (N m).
  Sample next(double converter_offset, double sensor_offset = 0.0) {
    const double t = static_cast<double>(k_++) * kDt;
    torque_ = ref_ + (torque_ - ref_) * decay_;  // the response to the reference held since the last sample
    Sample s;
    s.t = t;
    s.speed = 150.0 + 5.0 * std::sin(0.05 * t);
    s.torque = torque_ + converter_offset + sensor_offset + torque_noise_ * normal_(rng_);
    s.power = 0.98 * s.speed * (torque_ + converter_offset) + power_noise_ * normal_(rng_);
    ref_ = 30000.0 + 4000.0 * std::sin(0.4 * t) + 1500.0 * std::sin(3.0 * t + 1.0);  // held until the next
    s.torque_ref = ref_;
    return s;
  }

 private:
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_;
  double torque_noise_, power_noise_, decay_;
  uint64_t k_ = 0;
  double torque_ = 30000.0, ref_ = 30000.0;
};

ConverterConfig converter_config() {
  ConverterConfig c;  // the defaults: the shipped configuration's values (tested below)
  c.time_constant = 0.02;
  c.generator_efficiency = 0.98;
  return c;
}

// What a synthetic converter run gave: the first raise and the first clear (s, NaN: none), the offset at the
// first raise, the number of raises, the largest statistic and the state at the end.
struct SyntheticRun {
  double raised_at = kNaN, cleared_at = kNaN, size = kNaN, max_statistic = 0.0;
  int raises = 0;
  ConverterState last;
};

SyntheticRun run_synthetic(
    ConverterMonitor& m, SyntheticConverter& plant, double seconds,
    const std::function<double(double)>& converter_offset,
    const std::function<double(double)>& sensor_offset = [](double) { return 0.0; },
    bool witness_trusted = true) {
  SyntheticRun r;
  const long n = std::lround(seconds / kDt);
  for (long k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) * kDt;
    const auto s = plant.next(converter_offset(t), sensor_offset(t));
    const ConverterState& st = m.update(s.torque, s.torque_ref, s.speed, s.power, witness_trusted, false);
    r.max_statistic = std::max(r.max_statistic, st.statistic);
    if (st.changed && st.raised) {
      ++r.raises;
      if (std::isnan(r.raised_at)) r.raised_at = s.t, r.size = st.offset;
    }
    if (st.changed && !st.raised && std::isnan(r.cleared_at)) r.cleared_at = s.t;
  }
  r.last = m.state();
  return r;
}

double none(double) { return 0.0; }

TEST(ConverterMonitor, TheModelIsTheConverterExactly) {
  // GIVEN noise-free samples of a converter with a 250 N m offset from the start and a reference that moves
  // by up to 6 kN m/s
  for (const double offset : {250.0, -250.0}) {
    SyntheticConverter plant(1, 0.0, 0.0);
    ConverterMonitor m(converter_config(), kDt);
    const auto r = run_synthetic(m, plant, 90.0, [&](double) { return offset; });
    // THEN the residual is the offset and nothing else: its spread is zero (the noise learned is the floor),
    // its mean the offset, and the power witness reads the same offset exactly
    ASSERT_TRUE(r.last.learned);
    EXPECT_DOUBLE_EQ(r.last.noise, converter_config().noise_floor);
    EXPECT_NEAR(r.last.residual_mean, offset, 1e-6);
    ASSERT_TRUE(r.last.raised);
    EXPECT_NEAR(r.last.offset, offset, 1e-6);
    EXPECT_NEAR(r.last.witness_offset, offset, 1e-6);
  }
  // AND a model 20 % slower than the converter leaves a residual that follows the reference's rate
  ConverterConfig slow = converter_config();
  slow.time_constant = 0.024;
  SyntheticConverter plant(1, 0.0, 0.0);
  ConverterMonitor m(slow, kDt);
  const auto r = run_synthetic(m, plant, 70.0, none);
  EXPECT_GT(r.last.noise, 2.0 * slow.noise_floor);
}

TEST(ConverterMonitor, LearnsTheTorqueNoiseFromTheMedianAbsoluteDeviation) {
  // GIVEN the benchmark's torque noise N(0, 90 N m), without and with a 500 N m offset present from the start
  for (const double offset : {0.0, 500.0}) {
    for (uint64_t seed : {2u, 3u, 4u}) {
      SyntheticConverter plant(seed);
      ConverterMonitor m(converter_config(), kDt);
      // WHEN noise_learn_time (60 s) has passed
      auto r =
          run_synthetic(m, plant, converter_config().noise_learn_time - 0.5, [&](double) { return offset; });
      EXPECT_FALSE(r.last.learned);
      r = run_synthetic(m, plant, 1.0, [&](double) { return offset; });
      // THEN the noise is learned as 90 N m within 5 N m: the offset does not inflate it
      ASSERT_TRUE(r.last.learned);
      EXPECT_NEAR(r.last.noise, 90.0, 5.0) << "offset " << offset << " seed " << seed;
    }
  }
  // AND an offset of 500 N m that appears in the last 10 s of the learning moves it little (measured 116 N m;
  // a standard deviation would read 207 N m)
  for (uint64_t seed : {2u, 3u, 4u}) {
    SyntheticConverter plant(seed);
    ConverterMonitor m(converter_config(), kDt);
    const auto r = run_synthetic(m, plant, 61.0, [](double t) { return t >= 50.0 ? 500.0 : 0.0; });
    ASSERT_TRUE(r.last.learned);
    EXPECT_LT(r.last.noise, 125.0) << seed;
  }
}

TEST(ConverterMonitor, AHundredNewtonMetreStepIsRaisedWithinASecondSizedAndCleared) {
  const ConverterConfig c = converter_config();
  // GIVEN the benchmark's noise and a +-100 N m converter offset from 120 s to 180 s, 20 seeds each
  for (const double offset : {100.0, -100.0}) {
    int sized = 0;
    for (uint64_t seed = 100; seed < 120; ++seed) {
      SyntheticConverter plant(seed);
      ConverterMonitor m(c, kDt);
      const auto on = [&](double t) { return t >= 120.0 && t < 180.0 ? offset : 0.0; };
      auto r = run_synthetic(m, plant, 123.0, on);
      // THEN it is raised once, within 1 s of the onset ...
      ASSERT_FALSE(std::isnan(r.raised_at)) << offset << " seed " << seed;
      EXPECT_EQ(r.raises, 1) << offset << " seed " << seed;
      EXPECT_GE(r.raised_at, 120.0) << offset << " seed " << seed;
      EXPECT_LE(r.raised_at, 121.0) << offset << " seed " << seed;
      // ... sized within 15 N m at the raise (the witness's mean over the newer half of the CUSUM's run: the
      // run may start a few samples before the onset, which read 0; over the whole run 28-32 of 400 seeds
      // were beyond 15 N m, down to 57 N m) ...
      sized += std::fabs(r.size - offset) <= 15.0;
      EXPECT_NEAR(r.size, offset, 25.0) << offset << " seed " << seed;
      // ... and estimated within 15 N m by the witness's 1 s mean once raised
      EXPECT_NEAR(r.last.offset, offset, 15.0) << offset << " seed " << seed;
      // ... and cleared once the residual's 1 s mean has been below half the smallest offset for
      // offset_clear_time: within offset_clear_time + 1.5 s of the end (the mean halves in tau ln 2 = 0.7 s;
      // the noise moves the crossing by a few tenths: measured 3.4-4.3 s on 400 seeds)
      r = run_synthetic(m, plant, 77.0, [&](double t) { return on(t + 123.0); });
      ASSERT_FALSE(std::isnan(r.cleared_at)) << offset << " seed " << seed;
      EXPECT_EQ(r.raises, 0) << offset << " seed " << seed;
      EXPECT_GE(r.cleared_at, 180.0 + c.clear_time) << offset << " seed " << seed;
      EXPECT_LE(r.cleared_at, 180.0 + c.clear_time + 1.5) << offset << " seed " << seed;
    }
    EXPECT_GE(sized, 19) << offset;
  }
}

TEST(ConverterMonitor, ATorqueSensorErrorIsNotAConverterOffset) {
  const ConverterConfig c = converter_config();
  // GIVEN a 150 N m error of the torque sensor alone from 120 s: the torque moves, the power does not
  const auto sensor = [](double t) { return t >= 120.0 ? 150.0 : 0.0; };
  SyntheticConverter plant(10);
  ConverterMonitor m(c, kDt);
  const auto r = run_synthetic(m, plant, 300.0, none, sensor);
  // THEN the torque channel's CUSUM crosses its threshold, the power disagrees and nothing is raised
  EXPECT_GT(r.max_statistic, c.cusum_threshold);
  EXPECT_EQ(r.raises, 0) << "raised at " << r.raised_at << " with " << r.size << " N m";
  // AND without the witness (the generator speed suspect) the torque alone decides: the same data is raised
  SyntheticConverter plant2(10);
  ConverterMonitor alone(c, kDt);
  const auto r2 = run_synthetic(alone, plant2, 300.0, none, sensor, false);
  EXPECT_EQ(r2.raises, 1);
  EXPECT_GE(r2.raised_at, 120.0);
  EXPECT_LE(r2.raised_at, 121.0);
  // (sized at the raise by the torque residual's mean since the CUSUM last left zero, which the CUSUM's own
  // selection biases: 94-243 N m on 400 seeds; the 1 s mean that follows is right)
  EXPECT_NEAR(r2.size, 150.0, 100.0);
  EXPECT_NEAR(r2.last.offset, 150.0, 15.0);
}

TEST(ConverterMonitor, AHealthyHourRaisesNothing) {
  const ConverterConfig c = converter_config();
  // GIVEN an hour of healthy samples with the benchmark's noise (360 000 samples)
  SyntheticConverter plant(11);
  ConverterMonitor m(c, kDt);
  const auto r = run_synthetic(m, plant, 3600.0, none);
  // THEN nothing is raised, and the CUSUM ran: its statistic moved, below the threshold
  EXPECT_EQ(r.raises, 0) << "raised at " << r.raised_at;
  ASSERT_TRUE(r.last.learned);
  EXPECT_GT(r.max_statistic, 2.0);
  EXPECT_LT(r.max_statistic, c.cusum_threshold);
}

// ---------------------------------------------------------------- the diagnoser on the plant

// The service's configuration as shipped (deploy/config/drive_train.yaml and its turbine file), read as the
// service reads it.
struct Shipped {
  YamlSection yaml = YamlSection::load_file(kDeploy + "/config/drive_train.yaml");
  TurbineParams turbine = configured_turbine(yaml);
  DiagnoserConfig config = load_diagnoser_config(yaml, turbine);
};
const Shipped& shipped() {
  static const Shipped s;
  return s;
}

// A plant run through the diagnoser, sample by sample as the service feeds it.
struct PlantRun {
  std::vector<FaultEvent> events;
  std::vector<DriveTrainOutput> estimates;
  uint64_t refused = 0, rejected = 0;  // samples update() refused; the diagnoser's count
  double max_statistic = 0.0;          // largest torque statistic of the estimates
  // Fitted inertia ratio over the estimates with the efficiency ready.
  double min_inertia_ratio = std::numeric_limits<double>::infinity();
  double max_inertia_ratio = -std::numeric_limits<double>::infinity();
  EfficiencyState efficiency;  // at the end
  ConverterState converter;
};

// Called before each sample is fed: may spoil it or set the diagnoser's context.
using Hook = std::function<void(FrameSample& s, DriveTrainDiagnoser& d)>;

// The plant turbine `turbine` at `wind` (turbulence `ti`) through a diagnoser configured for it.
PlantRun run_turbine(const TurbineParams& turbine, const DiagnoserConfig& config, double wind, double ti,
                     double seconds, const std::vector<plant::FaultSpec>& faults, uint64_t seed,
                     double ice = 0.0, const Hook& hook = {}) {
  plant::TurbineScenario t;
  t.id = "WT01";
  t.wind.mean = wind;
  t.wind.turbulence_intensity = ti;
  t.ice_mass = ice;
  plant::TurbineSim sim(turbine, t, faults, seed, 100.0);
  const AeroModel aero(turbine);
  DriveTrainDiagnoser d(config, aero);
  PlantRun r;
  const long n = std::lround(seconds * 100.0);
  for (long k = 0; k < n; ++k) {
    FrameSample s = sim.step();
    if (hook) hook(s, d);
    if (!d.update(s, false, r.events)) ++r.refused;
    DriveTrainOutput o;
    if (!d.estimate_due(o)) continue;
    r.estimates.push_back(o);
    r.max_statistic = std::max(r.max_statistic, o.torque_statistic);
    if (d.efficiency().ready) {
      r.min_inertia_ratio = std::min(r.min_inertia_ratio, d.efficiency().inertia_ratio);
      r.max_inertia_ratio = std::max(r.max_inertia_ratio, d.efficiency().inertia_ratio);
    }
  }
  r.rejected = d.rejected();
  r.efficiency = d.efficiency();
  r.converter = d.converter();
  return r;
}

// The shipped configuration's benchmark turbine at turbulence 0.12.
PlantRun run_plant(double wind, double seconds, const std::vector<plant::FaultSpec>& faults, uint64_t seed,
                   double ice = 0.0, const Hook& hook = {}) {
  return run_turbine(shipped().turbine, shipped().config, wind, 0.12, seconds, faults, seed, ice, hook);
}

plant::FaultSpec torque_offset(double start, double value = 100.0) {
  return plant::FaultSpec::make("WT01", "converter", "torque_offset", start).with_value(value);
}
plant::FaultSpec efficiency(double start, double value = 0.92) {
  return plant::FaultSpec::make("WT01", "drive_train", "efficiency", start).with_value(value);
}

// The first event of `fault` raised (or cleared) at or after `after`, or nullptr.
const FaultEvent* first(const PlantRun& r, const std::string& fault, double after, bool raised = true) {
  for (const auto& e : r.events)
    if (e.fault == fault && e.raised == raised && e.t >= after) return &e;
  return nullptr;
}

std::string describe(const PlantRun& r) {
  std::string out;
  for (const auto& e : r.events)
    out += std::to_string(e.t) + " s " + e.fault + (e.raised ? " raised: " : " cleared: ") + e.detail + "\n";
  return out;
}

TEST(DriveTrainDiagnoser, ShippedConfigurationIsTheDefaults) {
  // GIVEN the shipped file, THEN its values are the code's defaults and the drive train the turbine file's
  const DiagnoserConfig& c = shipped().config;
  const DiagnoserConfig d;
  EXPECT_EQ(c.converter.min_offset, d.converter.min_offset);
  EXPECT_EQ(c.converter.cusum_threshold, d.converter.cusum_threshold);
  EXPECT_EQ(c.converter.noise_learn_time, d.converter.noise_learn_time);
  EXPECT_EQ(c.converter.clear_time, d.converter.clear_time);
  EXPECT_EQ(c.efficiency.step, d.efficiency.step);
  EXPECT_EQ(c.efficiency.iced_inertia_ratio, d.efficiency.iced_inertia_ratio);
  EXPECT_EQ(c.efficiency.confirm_time, d.efficiency.confirm_time);
  EXPECT_EQ(c.efficiency.step_shape, d.efficiency.step_shape);
  EXPECT_EQ(c.efficiency.iced_step_share, d.efficiency.iced_step_share);
  EXPECT_EQ(c.efficiency.noise_sigmas, d.efficiency.noise_sigmas);
  EXPECT_EQ(c.rotor_speed_fallback, d.rotor_speed_fallback);
  EXPECT_TRUE(c.rotor_speed_fallback);
  EXPECT_EQ(c.converter.time_constant, shipped().turbine.converter_time_constant);
  EXPECT_EQ(c.efficiency.rotor_friction, shipped().turbine.rotor_friction);
}

TEST(DriveTrainDiagnoser, ConverterTorqueOffsetOnThePlantIsRaisedWithinASecond) {
  // GIVEN the plant at 12 m/s with the benchmark's 100 N m converter offset from 120 s to 160 s
  auto f = torque_offset(120.0);
  f.end = 160.0;
  for (uint64_t seed : {21u, 22u, 23u}) {
    const auto r = run_plant(12.0, 180.0, {f}, seed);
    // THEN torque_offset is raised within 1 s, sized within 20 N m, and cleared within offset_clear_time
    // + 1.5 s of its end
    const FaultEvent* raised = first(r, "torque_offset", 0.0);
    ASSERT_NE(raised, nullptr) << seed;
    EXPECT_GE(raised->t, 120.0) << describe(r);
    EXPECT_LE(raised->t, 121.0) << describe(r);
    EXPECT_EQ(raised->component, "converter");
    EXPECT_NEAR(raised->size, 100.0, 20.0) << describe(r);
    const FaultEvent* cleared = first(r, "torque_offset", 120.0, false);
    ASSERT_NE(cleared, nullptr) << describe(r);
    EXPECT_GE(cleared->t, 160.0 + shipped().config.converter.clear_time) << describe(r);
    EXPECT_LE(cleared->t, 160.0 + shipped().config.converter.clear_time + 1.5) << describe(r);
    EXPECT_EQ(r.events.size(), 2u) << describe(r);
  }
}

TEST(DriveTrainDiagnoser, EfficiencyStepIsRaisedWithinAMinuteAndEstimated) {
  // GIVEN the plant with the drive train's efficiency falling from 0.97 to 0.92 at 300 s
  for (const double wind : {8.0, 16.0}) {
    const auto r = run_plant(wind, 420.0, {efficiency(300.0)}, 30 + static_cast<uint64_t>(wind));
    // THEN efficiency_loss is raised within 60 s (and nothing before the step) ...
    const FaultEvent* raised = first(r, "efficiency_loss", 0.0);
    ASSERT_NE(raised, nullptr) << wind << " m/s\n" << describe(r);
    EXPECT_GE(raised->t, 300.0) << wind << " m/s\n" << describe(r);
    EXPECT_LE(raised->t, 360.0) << wind << " m/s\n" << describe(r);
    EXPECT_EQ(raised->component, "drive_train");
    // ... and once the test blocks hold only the lossy drive train, the estimate is 0.92 within 0.015
    int checked = 0;
    for (const auto& o : r.estimates)
      if (o.t >= raised->t + shipped().config.efficiency.test_time + 2.0) {
        EXPECT_NEAR(o.efficiency, 0.92, 0.015) << wind << " m/s at " << o.t;
        ++checked;
      }
    EXPECT_GT(checked, 100) << wind;
    EXPECT_NEAR(r.efficiency.efficiency, 0.92, 0.015) << wind;
    EXPECT_GT(r.efficiency.drop, shipped().config.efficiency.step) << wind;
  }
}

TEST(EfficiencyMonitor, AStepFitsAStepExactlyAndABendFitsARampExactly) {
  // GIVEN 36 blocks 5 s apart: a step of -0.05 after the 30th, and a level that starts falling 0.001 per s at
  // the 12th
  std::vector<double> x, step, ramp;
  for (int i = 0; i < 36; ++i) {
    x.push_back(5.0 * i);
    step.push_back(i < 30 ? 0.97 : 0.92);
    ramp.push_back(0.97 - 0.001 * std::max(0.0, x.back() - 60.0));
  }
  // THEN each is fitted exactly by its own shape and not by the other
  EXPECT_NEAR(step_misfit(step), 0.0, 1e-12);
  EXPECT_NEAR(bend_misfit(x, ramp), 0.0, 1e-12);
  EXPECT_GT(bend_misfit(x, step), 1e-3);
  EXPECT_GT(step_misfit(ramp), 1e-3);
  // and a plain line is a bend: both fit a level exactly
  const std::vector<double> level(36, 0.97);
  EXPECT_NEAR(step_misfit(level), 0.0, 1e-12);
  EXPECT_NEAR(bend_misfit(x, level), 0.0, 1e-12);
}

TEST(DriveTrainDiagnoser, AFastAccretionIsNoEfficiencyLoss) {
  // GIVEN the benchmark turbine at 13.8 and 16.1 m/s (suite set 502, benchmark rotor: raised 75-100 s into
  // the ice) whose rotor takes 7500 kg of ice over 300 s from 300 s on: its Cp falls 15 % in 5 minutes
  for (const double wind : {13.8, 16.1}) {
    auto ice = plant::FaultSpec::make("WT01", "rotor", "ice_accretion", 300.0).with_value(7500.0);
    ice.ramp_in = 300.0;
    bool raised[2] = {false, false};
    for (const bool shape : {false, true}) {
      DiagnoserConfig c = shipped().config;
      c.efficiency.step_shape = shape;
      const auto r =
          run_turbine(shipped().turbine, c, wind, 0.1, 900.0, {ice}, 5020 + static_cast<uint64_t>(wind));
      raised[shape] = first(r, "efficiency_loss", 0.0) != nullptr;
      std::printf("[measured] %.1f m/s, step shape %d:\n%s", wind, shape, describe(r).c_str());
    }
    // THEN the drop against the reference alone raises efficiency_loss, and the step test raises nothing (a
    // step is still raised: EfficiencyStepIsRaisedWithinAMinuteAndEstimated and the others run with it)
    EXPECT_TRUE(raised[0]) << wind << ": the accretion no longer reads as a loss; this test no longer tests";
    EXPECT_FALSE(raised[1]) << wind;
  }
}

TEST(EfficiencyMonitor, ANoisyStepIsTakenForAStepOnceTheBendsExtraCoefficientIsWeighed) {
  // GIVEN the test's 42 blocks 5 s apart, in 2000 draws each: the benchmark's 0.97 -> 0.92 step 30 s old (its
  // last 6 blocks), and an accretion's Cp loss (0.97 falling 0.05 % a second from the 12th block: 7.5 t in 5
  // minutes on the benchmark rotor), the blocks scattered by 1 % (moderate wind) or 2.5 % (strong turbulent
  // wind: benchmark-sequence set 413, 20.7 m/s, turbulence 0.175, where the step was never raised)
  std::mt19937_64 rng(413);
  for (const double sd : {0.01, 0.025}) {
    std::normal_distribution<double> scatter(0.0, sd);
    int steps[2] = {0, 0}, ramps[2] = {0, 0};
    for (int draw = 0; draw < 2000; ++draw) {
      std::vector<double> x, step, ramp;
      for (int i = 0; i < 42; ++i) {
        x.push_back(5.0 * i);
        step.push_back((i < 36 ? 0.97 : 0.92) + scatter(rng));
        ramp.push_back(0.97 - 0.0005 * std::max(0.0, x.back() - 60.0) + scatter(rng));
      }
      for (const bool parsimony : {false, true}) {
        steps[parsimony] += step_fits_better(x, step, 1.0, parsimony);
        ramps[parsimony] += step_fits_better(x, ramp, 1.0, parsimony);
      }
    }
    std::printf(
        "[measured] scatter %.3f: step taken for a step %d / %d of 2000, ramp taken for a step %d / %d "
        "(misfits as they are / the bend's coefficient weighed)\n",
        sd, steps[0], steps[1], ramps[0], ramps[1]);
    // THEN the step is taken for one in at least 9 draws of 10 with the bend's extra coefficient weighed, far
    // more often than without where the blocks scatter
    EXPECT_GE(steps[1], 1800) << sd;
    if (sd > 0.02) {
      EXPECT_GT(steps[1], steps[0] + 300) << "this test no longer tests";
    }
    // AND where they scatter by 1 % the ramp is still taken for a bend; at 2.5 % the shape alone no longer
    // tells an accretion in half the draws (the cost: such a loss is the ice's echo to the arbiter, listed
    // secondary while ice_detect's accretion report follows within 900 s)
    if (sd < 0.02) {
      EXPECT_LT(ramps[1], 100) << sd;
    }
  }
}

TEST(DriveTrainDiagnoser, AStepOnARotorThatKeepsItsIceIsRaisedAndMoreIceIsNot) {
  // GIVEN the benchmark rotor carrying 3000 kg of ice throughout (+8.7 % inertia: every fit above the ice
  // guard) whose drive train's efficiency steps from 0.97 to 0.92 at 300 s (judged set 260: a loss 290 s
  // after a shedding had left 2 t of ice on the rotor was withheld for the inertia alone)
  for (const double wind : {8.0, 12.0}) {
    bool raised[2] = {false, false};
    for (const bool clean_step : {false, true}) {
      DiagnoserConfig c = shipped().config;
      if (!clean_step) c.efficiency.iced_step_share = 0.0;
      const auto r = run_turbine(shipped().turbine, c, wind, 0.12, 420.0, {efficiency(300.0)},
                                 90 + static_cast<uint64_t>(wind), 3000.0);
      const FaultEvent* e = first(r, "efficiency_loss", 0.0);
      raised[clean_step] = e != nullptr;
      std::printf("[measured] %.1f m/s, iced_step_share %.2f:\n%s", wind, c.efficiency.iced_step_share,
                  describe(r).c_str());
      // THEN with the clean-step rule it is raised within 60 s of its onset and not before
      if (clean_step) {
        ASSERT_NE(e, nullptr) << wind << " m/s\n" << describe(r);
        EXPECT_GE(e->t, 300.0) << wind;
        EXPECT_LE(e->t, 360.0) << wind;
      }
    }
    // AND without it the ice guard withholds it (else this test no longer tests the rule)
    EXPECT_FALSE(raised[0]) << wind;
    EXPECT_TRUE(raised[1]) << wind;
  }
  // GIVEN the same iced rotor taking 7500 kg more over 300 s from 300 s (its Cp falling 15 % in 5 minutes)
  for (const double wind : {8.0, 13.8, 16.1}) {
    auto ice = plant::FaultSpec::make("WT01", "rotor", "ice_accretion", 300.0).with_value(7500.0);
    ice.ramp_in = 300.0;
    const auto r = run_plant(wind, 900.0, {ice}, 5030 + static_cast<uint64_t>(wind), 3000.0);
    // THEN no efficiency_loss is raised: an accretion bends the blocks' efficiencies, it does not step them
    EXPECT_EQ(first(r, "efficiency_loss", 0.0), nullptr) << wind << " m/s\n" << describe(r);
  }
}

TEST(DriveTrainDiagnoser, TheFeatheringPitchIsTheTurbinesOwn) {
  // GIVEN the two shipped turbines, THEN the pitch for rated power at rated speed is theirs: the example 2 MW
  // rotor, with less power per swept area, needs more pitch in the same wind
  const TurbineParams bench = shipped().turbine;
  const TurbineParams two = load_turbine_params_file(kDeploy + "/turbine/example_2MW.yaml");
  EXPECT_NEAR(feathering_pitch(bench, 20.0), 23.28, 0.05);
  EXPECT_NEAR(feathering_pitch(bench, 28.0), 32.93, 0.05);
  EXPECT_NEAR(feathering_pitch(two, 20.0), 25.71, 0.05);
  EXPECT_NEAR(feathering_pitch(two, 28.0), 34.68, 0.05);
  // at it the rotor gives rated power (before the drive train's and generator's losses) ...
  const AeroModel aero(two);
  EXPECT_NEAR(aero.aero_power(20.0, two.rated_generator_speed / two.gear_ratio, feathering_pitch(two, 20.0)),
              two.rated_power, 1e-3 * two.rated_power);
  // ... below rated wind it is fine pitch, and the shipped configuration takes the 28 m/s one
  EXPECT_EQ(feathering_pitch(two, 8.0), 0.0);
  EXPECT_NEAR(shipped().config.efficiency.max_pitch, feathering_pitch(bench, 28.0), 1e-9);
}

TEST(DriveTrainDiagnoser, AnEfficiencyStepAtTwentyOneMetresPerSecondIsRaisedOnBothTurbines) {
  // GIVEN each shipped turbine at 21 m/s, turbulence 0.06 (the example 2 MW rotor pitches to 25-27 deg
  // there: a fixed 25 deg limit left out every block, and suite seed 70 missed 6 of 36 efficiency losses),
  // the efficiency falling from its healthy value to 0.92 at 300 s
  const YamlSection yaml = YamlSection::load_file(kDeploy + "/config/drive_train.yaml");
  for (const std::string file : {"benchmark_4.8MW.yaml", "example_2MW.yaml"}) {
    const TurbineParams turbine = load_turbine_params_file(kDeploy + "/turbine/" + file);
    const DiagnoserConfig config = load_diagnoser_config(yaml, turbine);
    const auto r = run_turbine(turbine, config, 21.0, 0.06, 420.0, {efficiency(300.0)}, 91);
    // THEN efficiency_loss is raised within 60 s, and nothing before the step
    const FaultEvent* raised = first(r, "efficiency_loss", 0.0);
    ASSERT_NE(raised, nullptr) << file << "\n" << describe(r);
    EXPECT_GE(raised->t, 300.0) << file << "\n" << describe(r);
    EXPECT_LE(raised->t, 360.0) << file << "\n" << describe(r);
  }
}

TEST(DriveTrainDiagnoser, OnAMediumSpeedDriveTrainAnEfficiencyStepInLowWindIsRaised) {
  // GIVEN the example medium-speed 3 MW turbine (its generator at 52 rad/s at rated) at 5.5 m/s, where its
  // generator turns at about 25 rad/s, with the shipped configuration: the standstill level is a share of the
  // rated generator speed, 9.6 rad/s here (30 rad/s on the benchmark turbine)
  const YamlSection yaml = YamlSection::load_file(kDeploy + "/config/drive_train.yaml");
  const TurbineParams medium = load_turbine_params_file(kDeploy + "/turbine/example_3MW_medium_speed.yaml");
  const DiagnoserConfig config = load_diagnoser_config(yaml, medium);
  EXPECT_NEAR(config.efficiency.min_generator_speed, 9.62, 0.01);
  EXPECT_NEAR(config.converter.min_generator_speed, 9.62, 0.01);
  EXPECT_NEAR(load_diagnoser_config(yaml, TurbineParams{}).efficiency.min_generator_speed, 30.0, 0.05);
  // (and its plausible torque is a multiple of its own rated torque, 60 kN m, as the benchmark's 2e5 N m is
  // of its 30 kN m: a 15 MW generator at 50 rad/s, 0.3 MN m rated, is not rejected sample by sample)
  EXPECT_NEAR(load_diagnoser_config(yaml, TurbineParams{}).max_torque, 2.0e5, 1e3);
  EXPECT_NEAR(load_diagnoser_config(yaml, TurbineParams{}).max_generator_speed, 400.0, 1.0);
  EXPECT_NEAR(config.max_torque, 6.6 * medium.rated_generator_torque(), 1.0);
  TurbineParams large;
  large.rated_power = 15e6;
  large.rated_generator_speed = 50.0;
  EXPECT_GT(load_diagnoser_config(yaml, large).max_torque, 3.0 * large.rated_generator_torque());
  const auto r = run_turbine(medium, config, 5.5, 0.06, 480.0, {efficiency(300.0)}, 91);
  // THEN the efficiency loss is raised within 90 s, nothing before it
  const FaultEvent* raised = first(r, "efficiency_loss", 0.0);
  ASSERT_NE(raised, nullptr) << describe(r);
  EXPECT_GE(raised->t, 300.0) << describe(r);
  EXPECT_LE(raised->t, 390.0) << describe(r);
  std::printf("[ measured ] medium speed, 5.5 m/s: efficiency_loss raised %.1f s after the step\n",
              raised->t - 300.0);
  // AND with the benchmark turbine's 30 rad/s it is not
  DiagnoserConfig absolute = config;
  absolute.efficiency.min_generator_speed = absolute.converter.min_generator_speed = 30.0;
  EXPECT_EQ(
      first(run_turbine(medium, absolute, 5.5, 0.06, 480.0, {efficiency(300.0)}, 91), "efficiency_loss", 0.0),
      nullptr);
}

TEST(EfficiencyMonitor, InLightTurbulentWindAFitLighterThanTheCleanRotorRaisesNoEfficiencyLoss) {
  // GIVEN the example medium-speed turbine, healthy, at 7.2 m/s and turbulence 0.16 (judged suite seed 128,
  // scenario 3, WT02: efficiency_loss raised on a healthy drive train), four runs of 40 minutes
  const YamlSection yaml = YamlSection::load_file(kDeploy + "/config/drive_train.yaml");
  const TurbineParams medium = load_turbine_params_file(kDeploy + "/turbine/example_3MW_medium_speed.yaml");
  const DiagnoserConfig config = load_diagnoser_config(yaml, medium);
  ASSERT_EQ(config.efficiency.inertia_ratio_floor, 1.0);
  DiagnoserConfig fitted = config;
  fitted.efficiency.inertia_ratio_floor = 0.0;
  double worst[2] = {0.0, 0.0}, squares[2] = {0.0, 0.0};
  int raised[2] = {0, 0}, n[2] = {0, 0};
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    for (const int floor : {0, 1}) {
      const auto r = run_turbine(medium, floor ? config : fitted, 7.2, 0.16, 2400.0, {}, 1280 + seed);
      for (const auto& o : r.estimates) {
        if (!std::isfinite(o.efficiency) || !std::isfinite(o.efficiency_reference)) continue;
        const double drop = 1.0 - o.efficiency / o.efficiency_reference;
        worst[floor] = std::max(worst[floor], drop);
        squares[floor] += drop * drop;
        ++n[floor];
      }
      for (const auto& e : r.events) raised[floor] += e.fault == "efficiency_loss" && e.raised;
    }
  }
  const double rms[2] = {std::sqrt(squares[0] / n[0]), std::sqrt(squares[1] / n[1])};
  std::printf(
      "[ measured ] 7.2 m/s, TI 0.16, 4 x 40 min: drop rms %.2f %%, largest %.2f %% (%d raised); with the "
      "fit as it is %.2f %%, %.2f %% (%d)\n",
      100.0 * rms[1], 100.0 * worst[1], raised[1], 100.0 * rms[0], 100.0 * worst[0], raised[0]);
  // THEN nothing is raised, and the drop the test sees scatters less than with the fit as it is
  EXPECT_EQ(raised[1], 0);
  EXPECT_LT(rms[1], 0.9 * rms[0]);  // (measured 0.53 against 0.65 %)
  EXPECT_LT(worst[1], worst[0]);
}

// The events of the plant (TI 0.12) through the diagnoser losing 20 samples every 5 s (a loaded host).
std::vector<FaultEvent> run_with_losses(double wind, double seconds,
                                        const std::vector<plant::FaultSpec>& faults, uint64_t seed,
                                        double max_bridged_gap) {
  plant::TurbineScenario t;
  t.id = "WT01";
  t.wind.mean = wind;
  t.wind.turbulence_intensity = 0.12;
  plant::TurbineSim sim(shipped().turbine, t, faults, seed, 100.0);
  const AeroModel aero(shipped().turbine);
  DiagnoserConfig c = shipped().config;
  c.max_bridged_gap = max_bridged_gap;
  DriveTrainDiagnoser d(c, aero);
  std::vector<FaultEvent> events;
  bool gap = false;
  for (long k = 0; k < std::lround(seconds * 100.0); ++k) {
    const FrameSample s = sim.step();
    if (k % 500 >= 480) {
      gap = true;
      continue;
    }
    d.update(s, gap, events);
    gap = false;
  }
  return events;
}

TEST(DriveTrainDiagnoser, AnEfficiencyStepIsFoundThroughShortHolesOfLostSamples) {
  // GIVEN the efficiency step of the test above at 16 m/s, 20 samples lost every 5 s
  const auto events = run_with_losses(16.0, 420.0, {efficiency(300.0)}, 46, 0.5);
  // THEN efficiency_loss is raised within 60 s of it, and nothing before
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.front().fault, "efficiency_loss");
  EXPECT_GE(events.front().t, 300.0);
  EXPECT_LE(events.front().t, 360.0);
  // ... where ending the balance's block on every hole let no block close: nothing raised
  EXPECT_TRUE(run_with_losses(16.0, 420.0, {efficiency(300.0)}, 46, 0.0).empty());
  // AND 15 healthy minutes with the same losses raise nothing, at 8 and 20 m/s
  for (const double wind : {8.0, 20.0}) {
    const auto healthy = run_with_losses(wind, 900.0, {}, 50 + static_cast<uint64_t>(wind), 0.5);
    EXPECT_TRUE(healthy.empty()) << wind << " m/s: " << healthy.front().fault << " at " << healthy.front().t;
  }
}

TEST(DriveTrainDiagnoser, AHealthyRunRaisesNothingAndTheDetectorsRan) {
  for (const double wind : {8.0, 12.0, 16.0, 20.0}) {
    // GIVEN 15 minutes of a healthy turbine
    const auto r = run_plant(wind, 900.0, {}, 40 + static_cast<uint64_t>(wind));
    // THEN nothing is raised ...
    EXPECT_TRUE(r.events.empty()) << wind << " m/s\n" << describe(r);
    // ... and the detectors ran: nothing rejected, the torque noise learned and its statistic moved, and an
    // efficiency estimate (near its reference) every 0.1 s from about 3 minutes on
    EXPECT_EQ(r.rejected, 0u) << wind;
    EXPECT_TRUE(r.converter.learned) << wind;
    EXPECT_GT(r.max_statistic, 1.0) << wind;
    int finite = 0;
    for (const auto& o : r.estimates)
      if (std::isfinite(o.efficiency)) {
        ++finite;
        EXPECT_NEAR(o.efficiency, o.efficiency_reference, 0.02) << wind << " m/s at " << o.t;
      }
    // (7190 possible, all of them now at every wind; at 20 m/s a fixed 25 deg max_pitch left out the blocks
    // of gusts: 6140-6890)
    EXPECT_GT(finite, 7000) << wind;
    EXPECT_NEAR(r.efficiency.efficiency, 0.97, 0.02) << wind;
  }
}

TEST(DriveTrainDiagnoser, BadSamplesAreRejectedCountedAndDoNotPoisonTheEstimators) {
  // GIVEN a plant run at 12 m/s whose torque or generator speed reads NaN, infinite, huge or negative on
  // every 7th sample during 30-40 s (the noise learning) and 150-160 s, and a torque offset from 250 s
  const double inf = std::numeric_limits<double>::infinity();
  uint64_t spoiled = 0;
  int kind = 0;
  const Hook spoil = [&](FrameSample& s, DriveTrainDiagnoser&) {
    const bool window = (s.t >= 30.0 && s.t < 40.0) || (s.t >= 150.0 && s.t < 160.0);
    if (!window || s.sequence % 7 != 0) return;
    switch (kind++ % 7) {
      case 0:
        s.gen_torque = kNaN;
        break;
      case 1:
        s.gen_torque = inf;
        break;
      case 2:
        s.gen_torque = -1e9;
        break;
      case 3:
        s.generator_speed = kNaN;
        break;
      case 4:
        s.generator_speed = 1e6;
        break;
      case 5:
        s.generator_speed = -5.0;
        break;
      case 6:
        s.gen_torque_ref = kNaN;
        break;
    }
    ++spoiled;
  };
  const auto r = run_plant(12.0, 300.0, {torque_offset(250.0)}, 50, 0.0, spoil);
  // THEN every spoiled sample is refused and counted ...
  ASSERT_GT(spoiled, 250u);
  EXPECT_EQ(r.refused, spoiled);
  EXPECT_EQ(r.rejected, spoiled);
  // ... the noise learned is the sensor's (90 N m) and the efficiency estimate is sane ...
  EXPECT_NEAR(r.converter.noise, 90.0, 10.0);
  ASSERT_TRUE(r.efficiency.ready);
  EXPECT_NEAR(r.efficiency.efficiency, 0.97, 0.02);
  for (const auto& o : r.estimates) {
    EXPECT_TRUE(std::isfinite(o.torque_offset)) << o.t;
    EXPECT_TRUE(std::isfinite(o.torque_statistic)) << o.t;
  }
  // ... nothing is raised before the offset, and the offset is still found within 1 s with its size
  const FaultEvent* raised = first(r, "torque_offset", 0.0);
  ASSERT_NE(raised, nullptr) << describe(r);
  EXPECT_GE(raised->t, 250.0) << describe(r);
  EXPECT_LE(raised->t, 251.0) << describe(r);
  EXPECT_NEAR(raised->size, 100.0, 20.0);
  EXPECT_EQ(r.events.size(), 1u) << describe(r);
}

TEST(DriveTrainDiagnoser, AnImplausiblePowerLosesOnlyTheWitness) {
  // GIVEN a sample whose power is NaN, then one whose power is beyond max_power
  const Shipped& cfg = shipped();
  const AeroModel aero(cfg.turbine);
  DriveTrainDiagnoser d(cfg.config, aero);
  std::vector<FaultEvent> events;
  FrameSample s;
  s.generator_speed = 150.0;
  s.gen_torque = s.gen_torque_ref = 30000.0;
  s.power = kNaN;
  // THEN both are kept (the power only witnesses) and nothing is counted
  EXPECT_TRUE(d.update(s, false, events));
  s.t += kDt;
  s.power = 1e12;
  EXPECT_TRUE(d.update(s, false, events));
  EXPECT_EQ(d.rejected(), 0u);
  // AND a NaN torque reference is not
  s.gen_torque_ref = kNaN;
  EXPECT_FALSE(d.update(s, false, events));
  EXPECT_EQ(d.rejected(), 1u);
}

TEST(DriveTrainDiagnoser, ASuspectGeneratorSpeedLeavesTheTorqueAloneAndTheBalanceToTheRotorsSensor) {
  // GIVEN a healthy plant run at 12 m/s whose generator speed another service reports suspect at 200 s, and a
  // converter offset from 250 s
  InputContext suspect;
  suspect.generator_speed_suspect = true;
  const auto run = [&](bool fallback) {
    DiagnoserConfig c = shipped().config;
    c.rotor_speed_fallback = fallback;
    bool ready_before = false, on_rotor_after = false;
    const Hook report = [&](FrameSample& s, DriveTrainDiagnoser& d) {
      if (std::fabs(s.t - 200.0) < 0.5 * kDt) {
        ready_before = d.efficiency().ready;
        d.set_context(suspect, s.t);
        on_rotor_after = d.balance_on_rotor_speed();
      }
    };
    const auto r =
        run_turbine(shipped().turbine, c, 12.0, 0.12, 300.0, {torque_offset(250.0)}, 60, 0.0, report);
    EXPECT_TRUE(ready_before) << fallback;
    EXPECT_EQ(on_rotor_after, fallback);
    int before = 0, after = 0, estimated_after = 0;
    for (const auto& o : r.estimates) {
      if (o.t > 190.0 && o.t < 200.0) before += std::isfinite(o.efficiency);
      if (o.t >= 200.0 + kDt) {
        estimated_after += std::isfinite(o.efficiency) && std::isfinite(o.efficiency_reference);
        ++after;
      }
    }
    EXPECT_GE(before, 99) << fallback;
    EXPECT_GT(after, 900) << fallback;
    // THEN with the fallback the balance goes on, on the rotor's sensor (the blocks of the last minute are
    // dropped and the test waits for a minute of new ones: estimated again within 70 s); without it the
    // balance forgets its blocks and the estimate has none
    if (fallback) {
      EXPECT_GT(estimated_after, after - 700) << "estimated in " << estimated_after << " of " << after;
      EXPECT_TRUE(r.efficiency.ready);
    } else {
      EXPECT_EQ(estimated_after, 0);
      EXPECT_FALSE(r.efficiency.ready);
    }
    return r;
  };
  run(false);
  const auto r = run(true);
  // AND the offset is raised by the torque alone (no power witness) within 1 s, sized roughly at the raise
  // (the torque residual's mean since the CUSUM left zero, which its selection biases: 77-149 N m on 40
  // synthetic seeds) and well by the 1 s mean after it
  const FaultEvent* raised = first(r, "torque_offset", 0.0);
  ASSERT_NE(raised, nullptr) << describe(r);
  EXPECT_GE(raised->t, 250.0) << describe(r);
  EXPECT_LE(raised->t, 251.0) << describe(r);
  EXPECT_NEAR(raised->size, 100.0, 50.0);
  ASSERT_TRUE(r.converter.raised);
  EXPECT_NEAR(r.converter.offset, 100.0, 15.0);
  EXPECT_EQ(r.converter.witness_offset, 0.0);
  EXPECT_EQ(first(r, "efficiency_loss", 0.0), nullptr) << describe(r);
}

TEST(DriveTrainDiagnoser, AnEfficiencyStepDuringAGeneratorSpeedFaultIsRaisedOnTheRotorsSensor) {
  // GIVEN the three shipped turbines as fault suite sets 169-171 ran them (efficiency losses 56-98 s after a
  // generator-speed fault's onset, all four missed: the balance had stopped at the sensor's report and needed
  // three minutes of blocks after it cleared): the generator-speed sensor with an offset or a gain from 300
  // s, reported by sensor_bias 10 s later (it took 1.4-20 s in the suite), and the efficiency falling to 0.92
  // at 360 s, with the sensor still faulty
  struct Case {
    const char* file;
    double wind, turbulence;
    plant::FaultSpec sensor;
  };
  auto gain = plant::FaultSpec::make("WT01", "generator_speed", "gain", 300.0);
  gain.gain = 1.105;
  const auto offset = plant::FaultSpec::make("WT01", "generator_speed", "bias", 300.0).with_value(1.56);
  const Case cases[] = {{"example_3MW_medium_speed.yaml", 7.0, 0.134, offset},
                        {"example_2MW.yaml", 6.7, 0.069, gain},
                        {"benchmark_4.8MW.yaml", 13.7, 0.116, gain}};
  const YamlSection yaml = YamlSection::load_file(kDeploy + "/config/drive_train.yaml");
  InputContext suspect;
  suspect.generator_speed_suspect = true;
  for (const Case& k : cases) {
    const TurbineParams turbine = load_turbine_params_file(kDeploy + "/turbine/" + k.file);
    const auto run = [&](bool fallback) {
      DiagnoserConfig c = load_diagnoser_config(yaml, turbine);
      c.rotor_speed_fallback = fallback;
      const Hook report = [&](FrameSample& s, DriveTrainDiagnoser& d) {
        if (std::fabs(s.t - 310.0) < 0.5 * kDt) d.set_context(suspect, s.t);
      };
      return run_turbine(turbine, c, k.wind, k.turbulence, 480.0, {k.sensor, efficiency(360.0)}, 169, 0.0,
                         report);
    };
    // THEN on the rotor's sensor the loss is raised within 60 s of its onset, and nothing before it (the
    // speed pair held the balance from the sensor's onset and dropped its last minute of blocks; the report
    // drops none again, or the test waits a minute more: 76 s on each)
    const auto r = run(true);
    const FaultEvent* raised = first(r, "efficiency_loss", 0.0);
    ASSERT_NE(raised, nullptr) << k.file << "\n" << describe(r);
    EXPECT_GE(raised->t, 360.0) << k.file << "\n" << describe(r);
    EXPECT_LE(raised->t, 420.0) << k.file << "\n" << describe(r);
    std::printf("[ measured ] %s, %.1f m/s: raised %.1f s after the step on the rotor's sensor\n", k.file,
                k.wind, raised->t - 360.0);
    // AND with the balance stopped through the fault, as before, it is not
    EXPECT_EQ(first(run(false), "efficiency_loss", 0.0), nullptr) << k.file;
  }
}

TEST(DriveTrainDiagnoser, OnTheRotorsSpeedSensorHealthyHoursRaiseNothing) {
  // GIVEN each shipped turbine at 6, 12 and 20 m/s (turbulence 0.12) for 25 minutes, healthy, the generator
  // speed reported from 400 s on (the balance on the rotor's sensor, 50 times noisier than omega_g / N; the
  // balance beside it on that sensor has learned its noise for about 200 s)
  const YamlSection yaml = YamlSection::load_file(kDeploy + "/config/drive_train.yaml");
  InputContext suspect;
  suspect.generator_speed_suspect = true;
  for (const std::string file : {"benchmark_4.8MW.yaml", "example_2MW.yaml", "example_3MW_medium_speed.yaml",
                                 "example_6MW.yaml", "example_1.5MW.yaml"}) {
    const TurbineParams turbine = load_turbine_params_file(kDeploy + "/turbine/" + file);
    const DiagnoserConfig c = load_diagnoser_config(yaml, turbine);
    for (const double wind : {6.0, 12.0, 20.0}) {
      const auto drops = [&](bool reported, double& step) {
        const Hook report = [&](FrameSample& s, DriveTrainDiagnoser& d) {
          if (reported && std::fabs(s.t - 400.0) < 0.5 * kDt) d.set_context(suspect, s.t);
          step = d.efficiency_step();
        };
        const auto r =
            run_turbine(turbine, c, wind, 0.12, 1500.0, {}, 880 + static_cast<uint64_t>(wind), 0.0, report);
        // THEN nothing is raised, on either sensor
        EXPECT_EQ(first(r, "efficiency_loss", 0.0), nullptr) << file << " " << wind << " m/s\n"
                                                             << describe(r);
        double sum = 0.0, largest = 0.0;
        int n = 0;
        for (const auto& o : r.estimates)
          if (o.t > 700.0 && std::isfinite(o.efficiency)) {
            const double drop = (o.efficiency_reference - o.efficiency) / o.efficiency_reference;
            sum += drop * drop, largest = std::max(largest, drop), ++n;
          }
        EXPECT_GT(n, 7000) << file << " " << wind;
        return std::pair{std::sqrt(sum / std::max(n, 1)), largest};
      };
      double step_g = 0.0, step_r = 0.0;
      const auto [rms_g, largest_g] = drops(false, step_g);
      const auto [rms_r, largest_r] = drops(true, step_r);
      std::printf(
          "[ measured ] %s, %.0f m/s: drop rms %.2f %%, largest %.2f %%, step %.2f %% on the rotor's sensor; "
          "%.2f %%, %.2f %% on the generator's\n",
          file.c_str(), wind, 100 * rms_r, 100 * largest_r, 100 * step_r, 100 * rms_g, 100 * largest_g);
      // AND the drop stays below the step on each sensor (on the rotor's averaged over the wind window: read
      // raw at the blocks' ends, its rms at 6 m/s was 2.3-4.1 % and it raised efficiency_loss on all three
      // turbines then shipped). On the rotor's the step is the learned noise's when larger: the 6 MW rotor at
      // 6 m/s read 2.4 % rms there, up to 5.2 %, and raised efficiency_loss with the step alone (judged fault
      // set 253, 7.2 m/s: 3.6 % raised at the end of a generator-speed bias)
      EXPECT_EQ(step_g, c.efficiency.step) << file << " " << wind;
      EXPECT_GE(step_r, c.efficiency.step) << file << " " << wind;
      EXPECT_LT(largest_g, step_g) << file << " " << wind;
      EXPECT_LT(largest_r, step_r) << file << " " << wind;
    }
  }
}

TEST(DriveTrainDiagnoser, AnEfficiencyLossBeforeLeavesTheRotorsSensorsStepAlone) {
  // GIVEN the benchmark turbine at 13.7 m/s whose drive train lost 8 % from 300 to 450 s (raised, cleared),
  // then a generator-speed gain from 1000 s, reported 10 s later, and a second loss to 0.92 at 1060 s (tuning
  // set 152, 20.6 m/s: the balance beside on the rotor's sensor had learned the first loss as its noise, the
  // fallback's step was 6.7 %, and the second loss waited 57 s for the generator-speed fault to end)
  const Shipped& k = shipped();
  auto first_loss = efficiency(300.0);
  first_loss.end = 450.0;
  auto gain = plant::FaultSpec::make("WT01", "generator_speed", "gain", 1000.0);
  gain.gain = 1.105;
  InputContext suspect;
  suspect.generator_speed_suspect = true;
  double step = 0.0, rms = 0.0;
  const Hook report = [&](FrameSample& s, DriveTrainDiagnoser& d) {
    if (std::fabs(s.t - 1010.0) < 0.5 * kDt) d.set_context(suspect, s.t);
    if (std::fabs(s.t - 1050.0) < 0.5 * kDt) step = d.efficiency_step(), rms = d.rotor_speed_drop_rms();
  };
  const auto r = run_turbine(k.turbine, k.config, 13.7, 0.116, 1180.0, {first_loss, gain, efficiency(1060.0)},
                             152, 0.0, report);
  // THEN the first loss is raised and cleared, the rotor's sensor's own noise is learned small, the
  // fallback's step stays efficiency_step, and the second loss is raised on the rotor's sensor within 60 s
  ASSERT_NE(first(r, "efficiency_loss", 300.0), nullptr) << describe(r);
  ASSERT_NE(first(r, "efficiency_loss", 300.0, false), nullptr) << describe(r);
  EXPECT_GT(rms, 0.0);
  EXPECT_LT(rms, 0.01);
  EXPECT_EQ(step, k.config.efficiency.step);
  const FaultEvent* second = first(r, "efficiency_loss", 1000.0);
  ASSERT_NE(second, nullptr) << describe(r);
  EXPECT_LE(second->t, 1120.0) << describe(r);
  std::printf(
      "[ measured ] rotor's sensor less the generator's: drop rms %.2f %%; the second loss raised %.1f s "
      "after its onset\n",
      100 * rms, second->t - 1060.0);
}

TEST(DriveTrainDiagnoser, AGeneratorSpeedStepReportedSecondsLaterIsNoEfficiencyLoss) {
  // GIVEN the plant at 6.3 m/s, turbulence 0.157, whose generator-speed sensor reads 6.44 rad/s low from a
  // step (fault suite seeds 145 and 146: 8.1 m/s, scenario 04, WT01, a drop of 6.96 % raised 2 s after such a
  // step, and 6.3 m/s, scenario 02, WT01, 80 % after a gain), reported suspect by sensor_bias 3.5 s later (it
  // took 1.4-4.4 s in the suite), the step at three times within a 5 s balance block, two seeds. In light
  // wind the step's apparent deceleration times the rotor's inertia is as large as the aerodynamic torque
  const auto run = [](double confirm_time, double step, uint64_t seed) {
    DiagnoserConfig c = shipped().config;
    c.efficiency.confirm_time = confirm_time;
    // (the step-shape test, which a single spoilt block does not pass either, and the speed pair, which holds
    // the balance from the step on, are off: this tests the confirmation)
    c.efficiency.step_shape = false;
    c.speed_pair_mismatch = 0.0;
    InputContext suspect;
    suspect.generator_speed_suspect = true;
    const Hook report = [&](FrameSample& s, DriveTrainDiagnoser& d) {
      if (std::fabs(s.t - (step + 3.5)) < 0.5 * kDt) d.set_context(suspect, s.t);
    };
    const auto bias = plant::FaultSpec::make("WT01", "generator_speed", "bias", step).with_value(-6.44);
    const auto r = run_turbine(shipped().turbine, c, 6.3, 0.157, step + 60.0, {bias}, seed, 0.0, report);
    return first(r, "efficiency_loss", 0.0) != nullptr;
  };
  int raised_at_once = 0, raised_confirmed = 0;
  for (const double step : {301.0, 302.5, 304.0})
    for (const uint64_t seed : {143u, 144u}) {
      raised_at_once += run(0.0, step, seed);
      raised_confirmed += run(shipped().config.efficiency.confirm_time, step, seed);
    }
  std::printf("[measured] efficiency_loss on a generator-speed step: %d of 6 at once, %d of 6 confirmed\n",
              raised_at_once, raised_confirmed);
  // WHEN a drop is raised at the first block that shows it, THEN the step's block raised efficiency_loss
  ASSERT_GT(raised_at_once, 0) << "the step no longer reads as a loss: this test no longer tests";
  // WHEN the drop must hold efficiency_confirm_time (5 s), THEN the report discards the block first
  EXPECT_EQ(raised_confirmed, 0);
}

TEST(DriveTrainDiagnoser, TheSpeedPairHoldsTheBalanceFromAGeneratorSpeedFaultsOnset) {
  // GIVEN the benchmark turbine as fault suite set 156 ran it (7.7 and 6.1 m/s: efficiency_loss raised 9.0
  // and 6.9 s after generator-speed offsets of -3.67 and -6.84 rad/s, which sensor_bias named 13.0 and 20.2 s
  // after their onset), the offset from 300 s and not named at all
  for (const auto& [wind, offset] : {std::pair{7.7, -3.67}, std::pair{6.1, -6.84}}) {
    double disagreed_at = -1.0;
    const Hook watch = [&](FrameSample& s, DriveTrainDiagnoser& d) {
      if (disagreed_at < 0.0 && d.speed_disagreements() > 0) disagreed_at = s.t;
    };
    const auto bias = plant::FaultSpec::make("WT01", "generator_speed", "bias", 300.0).with_value(offset);
    const auto r =
        run_turbine(shipped().turbine, shipped().config, wind, 0.12, 420.0, {bias}, 1560, 0.0, watch);
    std::printf("[measured] %.1f m/s, offset %.2f rad/s: the speeds disagree %.2f s after its onset\n", wind,
                offset, disagreed_at - 300.0);
    // THEN the two speeds disagree within two averaging periods of the onset (4 s), not before it, and the
    // energy balance holds for as long: no efficiency_loss
    EXPECT_GE(disagreed_at, 300.0) << wind;
    EXPECT_LE(disagreed_at, 304.05) << wind;
    EXPECT_EQ(first(r, "efficiency_loss", 0.0), nullptr) << wind << "\n" << describe(r);
  }
}

TEST(DriveTrainDiagnoser, HealthySpeedSensorsNeverDisagree) {
  // GIVEN healthy plant hours at 6, 12 and 20 m/s (turbulence 0.12), each speed sensor with its noise
  for (const double wind : {6.0, 12.0, 20.0}) {
    DiagnoserConfig c = shipped().config;
    const plant::TurbineScenario t = [&] {
      plant::TurbineScenario x;
      x.id = "WT01", x.wind.mean = wind, x.wind.turbulence_intensity = 0.12;
      return x;
    }();
    plant::TurbineSim sim(shipped().turbine, t, {}, 77 + static_cast<uint64_t>(wind), 100.0);
    const AeroModel aero(shipped().turbine);
    DriveTrainDiagnoser d(c, aero);
    std::vector<FaultEvent> events;
    for (long k = 0; k < 360000; ++k) d.update(sim.step(), false, events);
    // THEN the two never disagree by the speed pair's 2 % over 2 s (at most 1.3 %, at 6 m/s)
    EXPECT_EQ(d.speed_disagreements(), 0u) << wind;
  }
}

TEST(DriveTrainDiagnoser, MalformedConfigurationIsAConfigErrorNamingTheKey) {
  const TurbineParams turbine;
  // GIVEN out-of-range, wrongly typed and misspelt keys
  for (const auto& [text, key] : std::vector<std::pair<std::string, std::string>>{
           {"cusum_threshold: 0.5", "cusum_threshold"},
           {"min_offset: big", "min_offset"},
           {"witness_ratio: 1.5", "witness_ratio"},
           {"iced_inertia_ratio: 0.9", "iced_inertia_ratio"},
           {"test_time: 2.0", "test_time"},  // shorter than a block (5 s)
           {"sample_time: .nan", "sample_time"},
           {"min_ofset: 100", "min_ofset"}}) {
    try {
      load_diagnoser_config(YamlSection(YAML::Load(text), "x.yaml"), turbine);
      ADD_FAILURE() << text << " accepted";
    } catch (const ConfigError& e) {
      // THEN each is a ConfigError naming the file and the key
      EXPECT_EQ(e.key(), key) << text;
      EXPECT_EQ(e.file(), "x.yaml") << text;
    }
  }
  // AND a good value is taken
  EXPECT_EQ(load_diagnoser_config(YamlSection(YAML::Load("min_offset: 150"), "x.yaml"), turbine)
                .converter.min_offset,
            150.0);
}

// ---------------------------------------------------------------- the energy balance's rotor inertia

TEST(EfficiencyMonitor, FittedInertiaRatioIsOneOnAHealthyRotorAndAboveTheIceGuardWhenIced) {
  const double iced = shipped().config.efficiency.iced_inertia_ratio;
  // (At and below rated wind. Above it the speed is held and the blocks weigh the inertia less well: in
  // 900 s runs at 16 m/s one of three iced fits dipped to 1.025 for a while; at 20 m/s clean fits reached
  // 0.913.)
  for (const double wind : {8.0, 11.2, 12.0}) {
    // GIVEN a clean rotor, 10 minutes
    const auto clean = run_plant(wind, 600.0, {}, 70 + static_cast<uint64_t>(wind));
    // THEN the fitted inertia is the clean rotor's within 7 %, and no fit on the way reaches the ice guard
    // (a lossy gearbox would be refused)
    ASSERT_TRUE(clean.efficiency.ready) << wind;
    EXPECT_NEAR(clean.efficiency.inertia_ratio, 1.0, 0.07) << wind;
    EXPECT_GT(clean.min_inertia_ratio, 0.9) << wind;
    EXPECT_LT(clean.max_inertia_ratio, iced) << wind;
    // GIVEN a rotor carrying 3000 kg of ice (+8.7 % rotor inertia) throughout
    const auto ice = run_plant(wind, 600.0, {}, 80 + static_cast<uint64_t>(wind), 3000.0);
    // THEN every fit is above the ice guard (no efficiency_loss can be raised) and near the true 1.087
    ASSERT_TRUE(ice.efficiency.ready) << wind;
    EXPECT_GT(ice.min_inertia_ratio, iced) << wind;
    EXPECT_LT(ice.max_inertia_ratio, 1.2) << wind;
    EXPECT_NEAR(ice.efficiency.inertia_ratio, 1.087, 0.07) << wind;
    EXPECT_TRUE(ice.events.empty()) << wind << " m/s\n" << describe(ice);
  }
}

TEST(EfficiencyMonitor, ADropWithinItsReferencesScatterIsNotRaisedAndOneBeyondItIs) {
  // GIVEN the monitor as shipped on a steady rotor whose 5 s blocks read efficiencies alternating 0.97 +- 3.5
  // % (the scatter of a poor Cp model: the Cp model far up the pitch curve on a point anemometer, 22-25 m/s
  // at turbulence 0.2-0.24, where healthy hours raised false efficiency losses of 3.5-5.0 %, each 1.7-3.5
  // standard errors of the reference's own scatter), and from 300 s a drop of 4.2 %
  // (past efficiency_step, within three standard errors: 1.6 % each) or 7 %
  const EfficiencyConfig& shipped_config = shipped().config.efficiency;
  const auto raised_at = [&](double drop, double noise_sigmas) {
    EfficiencyConfig c = shipped_config;
    c.noise_sigmas = noise_sigmas;
    EfficiencyMonitor m(c, 0.01);
    const double wg = 150.0, wr = wg / c.gear_ratio, aero_power = 3.0e6;
    const double rotor_side = (aero_power / wr - c.rotor_friction * wr) / c.gear_ratio;
    for (long k = 0; k < 60000; ++k) {
      const double t = 0.01 * static_cast<double>(k);
      const double level = 0.97 * (t >= 300.0 ? 1.0 - drop : 1.0);
      const double efficiency = level * ((k / 500) % 2 == 0 ? 1.035 : 0.965);
      m.update(efficiency * rotor_side - c.generator_friction * wg, wg, aero_power, 10.0, true, false);
      if (m.state().raised) return t;
    }
    return -1.0;
  };
  const double noise_sigmas = shipped_config.noise_sigmas;
  const double small_alone = raised_at(0.042, 0.0), small = raised_at(0.042, noise_sigmas);
  const double large_alone = raised_at(0.07, 0.0), large = raised_at(0.07, noise_sigmas);
  std::printf(
      "[measured] raised at (s; -1 never): 4.2 %% drop %.1f with efficiency_step alone, %.1f with %g "
      "standard "
      "errors; 7 %% drop %.1f and %.1f\n",
      small_alone, small, noise_sigmas, large_alone, large);
  // THEN the drop within the scatter is raised by efficiency_step alone and not with the floor ...
  EXPECT_GT(small_alone, 300.0);
  EXPECT_LT(small, 0.0);
  // AND the drop beyond it is raised either way, the floor costing at most two blocks (with the bend's extra
  // coefficient weighed the step's shape is accepted a block sooner, 320 s, and the floor is then what waits:
  // 330 s, as both were before)
  EXPECT_GT(large_alone, 300.0);
  EXPECT_GT(large, 300.0);
  EXPECT_LE(large - large_alone, 10.0 + 1e-6);
}

TEST(DriveTrainDiagnoser, AStepInCalmWindStandsFarAboveItsScatter) {
  // GIVEN each shipped turbine at 9, 14 and 18 m/s (turbulence 0.12) and the benchmark's efficiency step at
  // 300 s, through the shipped configuration and through one without the scatter's floor
  const YamlSection yaml = YamlSection::load_file(kDeploy + "/config/drive_train.yaml");
  for (const std::string file : {"benchmark_4.8MW.yaml", "example_2MW.yaml", "example_1.5MW.yaml"}) {
    const TurbineParams turbine = load_turbine_params_file(kDeploy + "/turbine/" + file);
    const DiagnoserConfig config = load_diagnoser_config(yaml, turbine);
    DiagnoserConfig step_alone = config;
    step_alone.efficiency.noise_sigmas = 0.0;
    for (const double wind : {9.0, 14.0, 18.0}) {
      const auto r = run_turbine(turbine, config, wind, 0.12, 420.0, {efficiency(300.0)}, 77);
      const auto r0 = run_turbine(turbine, step_alone, wind, 0.12, 420.0, {efficiency(300.0)}, 77);
      const FaultEvent* raised = first(r, "efficiency_loss", 0.0);
      const FaultEvent* raised0 = first(r0, "efficiency_loss", 0.0);
      // THEN it is raised within 60 s, at the same time as without the floor
      ASSERT_NE(raised, nullptr) << file << " " << wind << "\n" << describe(r);
      ASSERT_NE(raised0, nullptr) << file << " " << wind << "\n" << describe(r0);
      EXPECT_GE(raised->t, 300.0) << file << " " << wind << "\n" << describe(r);
      EXPECT_LE(raised->t, 360.0) << file << " " << wind << "\n" << describe(r);
      EXPECT_EQ(raised->t, raised0->t) << file << " " << wind;
      double drop = 0.0, standard_error = 0.0;
      const char* at = std::strstr(raised->detail.c_str(), "(drop ");
      ASSERT_NE(at, nullptr) << raised->detail;
      ASSERT_EQ(std::sscanf(at, "(drop %lf %%, standard error %lf %%)", &drop, &standard_error), 2)
          << raised->detail;
      std::printf(
          "[measured] %s at %g m/s: raised %.1f s after the step, drop %.2f %%, %.1f standard errors\n",
          file.c_str(), wind, raised->t - 300.0, drop, drop / standard_error);
    }
  }
}

}  // namespace
