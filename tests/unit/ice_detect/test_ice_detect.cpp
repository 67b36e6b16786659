// ice_detect tests: the estimator of seed 003 against known inertia, on the two-mass plant, and the detector.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "ice_detector.hpp"
#include "ice_service.hpp"
#include "turbine_sim.hpp"

using namespace windfdi;
using namespace windfdi::ice_detect;

namespace {

YamlSection defaults() { return YamlSection(YAML::Node(YAML::NodeType::Map), "(defaults)"); }

TEST(InertiaEstimator, NoiseFreeOneMassConvergesToTheTrueInertia) {
  // GIVEN the one-mass model J d omega/dt = P/omega - T_g (eq 2) with J = 6484 kg m^2, integrated finely,
  // and a torque balance that varies like gusts
  const double J = 6484.0, dt = 0.01;
  EstimatorConfig c;
  c.power_gain = 1.0;
  c.friction = 0.0;
  c.power_window = 0.0;
  c.filter_time = 0.0;
  InertiaEstimator est(c);
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

// Runs the detector on a plant turbine; `model_power`: aerodynamic power from the model on measured wind,
// rotor speed and pitch (the DDS path) instead of the recording's true value.
struct PlantRun {
  double rms = 0, max = 0;
  std::vector<FaultEvent> events;
};

PlantRun run_plant(double wind, int seconds, bool model_power, const std::vector<plant::FaultSpec>& faults = {},
                   double ice = 0.0, uint64_t seed = 7) {
  TurbineParams p;
  AeroModel aero(p);
  plant::TurbineScenario t;
  t.id = "WT01";
  t.wind.mean = wind;
  t.wind.turbulence_intensity = 0.12;
  t.wind.shear_variation = 0.05;
  t.ice_mass = ice;
  plant::TurbineSim sim(p, t, faults, seed, 100.0);
  IceDetector det(load_detector_config(defaults(), p), p);
  PlantRun r;
  InertiaOutput o;
  int n = 0;
  for (int k = 0; k < seconds * 100; ++k) {
    FrameSample s = sim.step();
    const double power = model_power ? (s.aero_power = kNaN, aero_power_of(s, aero)) : sim.truth().aero_power;
    det.update(s, power, false, r.events);
    if (det.estimate_due(o) && s.t > 300.0 && o.inertia > 0.0) {
      const double e = o.inertia / sim.truth().inertia - 1.0;
      r.rms += e * e;
      r.max = std::max(r.max, std::fabs(e));
      ++n;
    }
  }
  r.rms = std::sqrt(r.rms / std::max(n, 1));
  return r;
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
  }
}

TEST(IceDetector, AccretionRampIsFlaggedAndSized) {
  // GIVEN 2500 kg of ice accreting over 600 s from t = 300 s (+7 % inertia) at 10 m/s
  plant::FaultSpec f;
  f.turbine = "WT01";
  f.target = "rotor";
  f.type = "ice_accretion";
  f.value = 2500;
  f.has_value = true;
  f.ramp_in = 600;
  f.start = 300;
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
  EXPECT_LT(load_detector_config(defaults(), TurbineParams{}).warning_mass, 1830.0);
}

TEST(IceDetector, SheddingOfIceThatWasThereIsFlagged) {
  // GIVEN 3000 kg of ice of which 40 % (1200 kg, -3.3 % inertia) falls off at 700 s, at 10 m/s
  plant::FaultSpec f;
  f.turbine = "WT01";
  f.target = "rotor";
  f.type = "ice_shedding";
  f.fraction = 0.4;
  f.start = 700;
  const auto r = run_plant(10.0, 1000, true, {f}, 3000.0, 35);
  // THEN ice_shedding is raised within 120 s of the drop (the 60 s target is not met yet)
  bool found = false;
  for (const auto& e : r.events)
    if (e.fault == "ice_shedding" && e.raised && e.t >= 700.0 && e.t < 820.0) found = true;
  EXPECT_TRUE(found);
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

TEST(IceDetector, ModelPowerIsNanForMissingInputs) {
  TurbineParams p;
  AeroModel aero(p);
  FrameSample s;
  s.wind_hub = 10.0;
  s.rotor_speed = 1.3;
  s.pitch = {0.0, 0.0, 0.0};
  EXPECT_GT(aero_power_of(s, aero), 1e6);
  s.pitch[1] = kNaN;
  EXPECT_TRUE(std::isnan(aero_power_of(s, aero)));
  s.aero_power = 2e6;  // a recording's column wins
  EXPECT_DOUBLE_EQ(aero_power_of(s, aero), 2e6);
}

TEST(IceDetector, ConfigRejectsUnknownKeysAndBadRanges) {
  EXPECT_THROW(load_detector_config(YamlSection(YAML::Load("windw: 60"), "x.yaml"), TurbineParams{}), ConfigError);
  EXPECT_THROW(load_detector_config(YamlSection(YAML::Load("fault_mass: 10"), "x.yaml"), TurbineParams{}),
               ConfigError);  // below warning_mass
  EXPECT_EQ(load_detector_config(YamlSection(YAML::Load("window: 90"), "x.yaml"), TurbineParams{}).estimator.window,
            90.0);
}

}  // namespace

namespace {

TEST(IceDetector, AStoppingTurbineRaisesNoIce) {
  // GIVEN a turbine in 16 m/s ordered to a safe stop at 600 s (feather, torque to zero)
  TurbineParams p;
  AeroModel aero(p);
  plant::TurbineScenario t;
  t.id = "WT01";
  t.wind.mean = 16.0;
  t.wind.turbulence_intensity = 0.12;
  plant::TurbineSim sim(p, t, {}, 11, 100.0);
  IceDetector det(load_detector_config(defaults(), p), p);
  std::vector<FaultEvent> events;
  InertiaOutput o;
  plant::ControlInput stop;
  stop.mode = plant::OperatingMode::kSafeStop;
  for (int k = 0; k < 1500 * 100; ++k) {
    FrameSample s = k < 60000 ? sim.step() : sim.step(stop);
    s.aero_power = kNaN;
    det.update(s, aero_power_of(s, aero), false, events);
    det.estimate_due(o);
  }
  // THEN the stop is not mistaken for ice (or its shedding)
  EXPECT_TRUE(events.empty()) << events.size() << " events, first " << events[0].fault;
}

}  // namespace
