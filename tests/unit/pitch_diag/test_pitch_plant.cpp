// pitch_diag on the plant (Wu & Li default mode): the benchmark turbine's own pitch loop in turbulent wind
// with 0.2 deg pitch noise, every Table 1 fault on every blade, a half-developed leakage, a pitch-sensor
// offset and a healthy hour.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "input_context.hpp"
#include "pitch_service.hpp"
#include "turbine_sim.hpp"

using namespace windfdi;
using namespace windfdi::pitch_diag;

namespace {

struct PlantRun {
  std::vector<FaultEvent> events;
  PitchEstimate last;
  int estimates = 0, excited = 0;  // estimates, and those with every blade's identification excited
  uint64_t rejected = 0;
};

PlantRun run_plant(double wind, double seconds, const std::vector<plant::FaultSpec>& faults, uint64_t seed,
                   double derated_rate = 0.0, bool tell_diagnoser = true,
                   const TurbineParams& turbine = TurbineParams{},
                   const PitchDiagConfig& config = PitchDiagConfig{}) {
  plant::TurbineScenario t;
  t.id = "WT01";
  t.wind.mean = wind;
  t.wind.turbulence_intensity = 0.12;
  t.wind.shear_variation = 0.03;
  plant::TurbineSim sim(turbine, t, faults, seed, 100.0);
  PitchDiagnoser diag{config};
  plant::ControlInput in;
  if (derated_rate > 0.0) {
    // Every blade derated from the start (the arbiter's fallback when pitch_diag is lost), as the input
    // context carries it from wt/control/config.
    in.pitch_rate_limit = {derated_rate, derated_rate, derated_rate};
    InputContextTracker tracker("pitch_diag");
    if (tell_diagnoser) tracker.on_reconfiguration(false, in.pitch_rate_limit);
    diag.set_context(tracker.context(), -100.0);
  }
  PlantRun r;
  std::vector<FaultEvent> ev;
  const auto n = static_cast<long>(seconds * 100.0);
  for (long k = 0; k < n; ++k) {
    ev.clear();
    diag.update(sim.step(in), false, ev);
    r.events.insert(r.events.end(), ev.begin(), ev.end());
    if (diag.estimate_due(r.last)) {
      ++r.estimates;
      r.excited += r.last.excited[0] && r.last.excited[1] && r.last.excited[2];
    }
  }
  r.rejected = diag.rejected();
  return r;
}

plant::FaultSpec actuator_fault(int blade, const std::string& type, double start) {
  return plant::FaultSpec::make("WT01", "pitch_actuator_" + std::to_string(blade + 1), type, start);
}

TEST(PitchDiagPlant, EveryFaultOnEveryBladeIsClassifiedInRegion3) {
  for (const char* fault : {"pump_wear", "hydraulic_leakage", "high_air_content"})
    for (int blade = 0; blade < 3; ++blade) {
      // GIVEN the plant at 16 m/s, 12 % turbulence, 0.2 deg pitch noise, and an abrupt Table 1 fault at 60 s
      const double t_on = 60.0;
      const auto r = run_plant(16.0, 100.0, {actuator_fault(blade, fault, t_on)}, 50 + blade);
      // THEN the first event raises that fault on that blade's actuator, after the onset and within 20 s
      // (the 10 s target is measured by tests/perf/pitch_diag_plant), and nothing else is raised
      ASSERT_FALSE(r.events.empty()) << fault << " blade " << blade;
      const auto& e = r.events.front();
      EXPECT_EQ(e.component, "pitch_actuator_" + std::to_string(blade + 1)) << fault;
      EXPECT_EQ(e.fault, fault) << "blade " << blade;
      EXPECT_TRUE(e.raised);
      EXPECT_GT(e.t, t_on);
      EXPECT_LT(e.t - t_on, 20.0) << fault << " blade " << blade;
      for (const auto& x : r.events) EXPECT_EQ(x.component, e.component) << x.fault << " at " << x.t;
      EXPECT_EQ(r.last.fault_class[blade], fault);
    }
}

TEST(PitchDiagPlant, PumpWearAfterAHoldAtFinePitchIsPumpWearNotLeakage) {
  // GIVEN the plant at 14 m/s (recording 902 of tests/perf/pitch_diag_plant): blade 2's reference sits at
  // fine pitch (0 deg, no excitation, estimate held) from before the onset until 61.5 s, and its actuator
  // takes on the pump-wear dynamics abruptly at 60 s. Pump wear is the leakage path at alpha 0.5, so only the
  // history tells them apart; the 17 s of hold since the blade last looked healthy must not read as a slow
  // drift along the leakage path.
  const double t_on = 60.0;
  const auto r = run_plant(14.0, t_on + 20.0, {actuator_fault(1, "pump_wear", t_on)}, 902);
  // THEN the first event raises pump_wear on pitch_actuator_2 within 10 s of the onset, and no leakage
  ASSERT_FALSE(r.events.empty());
  const auto& e = r.events.front();
  EXPECT_EQ(e.component, "pitch_actuator_2");
  EXPECT_EQ(e.fault, "pump_wear");
  EXPECT_TRUE(e.raised);
  EXPECT_GT(e.t, t_on);
  EXPECT_LE(e.t - t_on, 10.0);
  for (const auto& x : r.events) EXPECT_NE(x.fault, "hydraulic_leakage") << x.component << " at " << x.t;
}

TEST(PitchDiagPlant, HalfDevelopedLeakageIsReportedWithItsAlphaNotAsPumpWear) {
  // GIVEN a hydraulic leakage on blade 3 developing over 120 s to alpha 0.5: the dynamics of full pump wear
  plant::FaultSpec f = actuator_fault(2, "hydraulic_leakage", 30.0);
  f.alpha = 0.5;
  f.ramp_in = 120.0;
  const auto r = run_plant(16.0, 240.0, {f}, 71);
  // THEN the blade is read as a leakage at alpha 0.5 +- 0.15, and no event says pump wear
  EXPECT_EQ(r.last.fault_class[2], "hydraulic_leakage");
  EXPECT_NEAR(r.last.alpha[2], 0.5, 0.15);
  bool raised = false;
  for (const auto& e : r.events) {
    EXPECT_NE(e.fault, "pump_wear") << "t " << e.t;
    raised = raised || (e.raised && e.fault == "hydraulic_leakage" && e.component == "pitch_actuator_3");
  }
  EXPECT_TRUE(raised);
}

TEST(PitchDiagPlant, PitchSensorOffsetIsNotAnActuatorFault) {
  // GIVEN a constant +2 deg offset on blade 2's pitch sensor from 30 s (the level removal takes it out)
  auto f = plant::FaultSpec::make("WT01", "pitch_2", "offset", 30.0).with_value(2.0);
  const auto r = run_plant(16.0, 300.0, {f}, 72);
  // THEN nothing is raised
  EXPECT_TRUE(r.events.empty()) << r.events.front().component << " " << r.events.front().fault;
}

TEST(PitchDiagPlant, ASafeStopIsNotALeak) {
  // GIVEN a healthy turbine at 16 m/s ordered to a safe stop at 100 s: every blade's reference jumps to the
  // feathered position and the actuators ramp there at their 10 deg/s rate limit
  plant::TurbineScenario t;
  t.id = "WT01";
  t.wind.mean = 16.0;
  t.wind.turbulence_intensity = 0.12;
  plant::TurbineSim sim(TurbineParams{}, t, {}, 74, 100.0);
  PitchDiagnoser diag{PitchDiagConfig{}};
  std::vector<FaultEvent> events;
  plant::ControlInput stop;
  stop.mode = plant::OperatingMode::kSafeStop;
  for (int k = 0; k < 200 * 100; ++k) diag.update(k < 100 * 100 ? sim.step() : sim.step(stop), false, events);
  // THEN the ramp is recognised as rate-limited (not identified) and nothing is raised
  for (int b = 0; b < 3; ++b) EXPECT_GT(diag.saturated(b), 500u) << b;
  EXPECT_TRUE(events.empty()) << events.front().component << " " << events.front().fault << " at "
                              << events.front().t;
}

TEST(PitchDiagPlant, ADeratedActuatorIsJudgedWithItsRateLimit) {
  // GIVEN every blade derated to 5 deg/s (the arbiter's fallback when pitch_diag is lost) at 16 and 20 m/s in
  // 12 % turbulence, where the valves saturate often: 10 minutes on each of 4 seeds
  int told = 0, blind = 0;
  for (double wind : {16.0, 20.0})
    for (uint64_t seed = 80; seed < 84; ++seed) {
      for (const auto& e : run_plant(wind, 600.0, {}, seed, 5.0).events) told += e.raised;
      for (const auto& e : run_plant(wind, 600.0, {}, seed, 5.0, false).events) blind += e.raised;
    }
  // THEN with the commanded limit known (the bank's models saturate at it) nothing is reported. When the
  // limit was introduced it was 8 reports against 86 of the linear models alone; since the evidence and
  // restart rules of later stops the blind models raise nothing here either (measured in stop 48: 0 and 0),
  // so the limit's own benefit is shown by the leak below and
  // ARaisedPumpWearKeepsItsNameThroughTheArbitersDegradedMode
  std::cout << "[ measured ] derated healthy blades, 80 min: " << told << " reports with the limit, " << blind
            << " without\n";
  EXPECT_EQ(told, 0);
  // AND a leak on a derated blade is still found as a leak
  for (double wind : {16.0, 20.0}) {
    const auto leak = run_plant(wind, 160.0, {actuator_fault(2, "hydraulic_leakage", 100.0)}, 72, 5.0);
    const FaultEvent* first = nullptr;
    for (const auto& e : leak.events)
      if (e.raised && e.t > 100.0 && !first) first = &e;
    ASSERT_NE(first, nullptr) << wind;
    EXPECT_EQ(first->component, "pitch_actuator_3") << wind;
    EXPECT_EQ(first->fault, "hydraulic_leakage") << wind;
  }
}

TEST(PitchDiagPlant, BurstsOfLostSamplesRaiseNothing) {
  // GIVEN the healthy plant at 16 m/s, and a link that loses bursts of 1-30 samples about every 2 s (a loaded
  // host taking frames late, a reader history overflowing): each gap restarts every blade's history
  plant::TurbineScenario t;
  t.id = "WT01";
  t.wind.mean = 16.0;
  t.wind.turbulence_intensity = 0.12;
  t.wind.shear_variation = 0.03;
  plant::TurbineSim sim(TurbineParams{}, t, {}, 4160, 100.0);
  PitchDiagnoser diag{PitchDiagConfig{}};
  std::mt19937_64 rng(7);
  std::exponential_distribution<double> every(0.5);
  std::uniform_int_distribution<int> burst(1, 30);
  std::vector<FaultEvent> events;
  double next_gap = every(rng);
  for (long k = 0; k < 300 * 100; ++k) {
    const FrameSample& s = sim.step();
    if (s.t >= next_gap) {
      const int lost = burst(rng);
      for (int j = 1; j < lost; ++j, ++k) sim.step();
      next_gap = s.t + lost * 0.01 + every(rng);
      continue;
    }
    diag.update(s, false, events);
  }
  ASSERT_GT(diag.gaps(), 100u);
  // THEN nothing is raised (before the level filters continued across a gap, the restarted filters put the
  // tracking error and a noise sample into the measured pitch as an 8 s offset: high air content in 40 s)
  EXPECT_TRUE(events.empty()) << events.front().component << " " << events.front().fault << " at "
                              << events.front().t;
}

// The first event of a plant run at 16 m/s with `fault` on blade 1 from 60 s, losing 20 samples every 10 s.
std::vector<FaultEvent> run_with_losses(const std::string& fault, const PitchDiagConfig& config) {
  plant::TurbineScenario t;
  t.id = "WT01";
  t.wind.mean = 16.0;
  t.wind.turbulence_intensity = 0.12;
  t.wind.shear_variation = 0.03;
  plant::TurbineSim sim(TurbineParams{}, t, {actuator_fault(0, fault, 60.0)}, 4161, 100.0);
  PitchDiagnoser diag{config};
  std::vector<FaultEvent> events;
  for (long k = 0; k < 200 * 100; ++k) {
    const FrameSample& s = sim.step();
    if (k % 1000 >= 980) continue;  // lost
    diag.update(s, false, events);
  }
  EXPECT_GT(diag.gaps(), 15u);
  return events;
}

TEST(PitchDiagPlant, AFaultIsFoundThroughShortHolesOfLostSamples) {
  // GIVEN 20 samples lost every 10 s (a loaded host), pump wear or high air content on blade 1 from 60 s
  for (const std::string fault : {"pump_wear", "high_air_content"}) {
    const auto events = run_with_losses(fault, PitchDiagConfig{});
    // THEN it is raised, named right, within 10 s, and nothing else
    ASSERT_FALSE(events.empty()) << fault;
    EXPECT_EQ(events.front().fault, fault);
    EXPECT_EQ(events.front().component, "pitch_actuator_1");
    EXPECT_LT(events.front().t, 70.0) << fault;
    for (const auto& e : events) EXPECT_EQ(e.fault, fault) << e.component << " at " << e.t;
    // ... where restarting on every hole, with startup_settle before any decision, never raised it
    PitchDiagConfig restart;
    restart.max_bridged_gap = 0.0;
    EXPECT_TRUE(run_with_losses(fault, restart).empty()) << fault;
  }
}

TEST(PitchDiagPlant, AStartOnAPumpWornActuatorRaisesPumpWearNotALeak) {
  // GIVEN pitch_diag (re)started at 100 s on a turbine whose blade 1 has had pump wear since 10 s (the
  // reliability campaign's killed and restarted pitch_diag raised a leak there), 14-18 m/s, 80 seeds. Before:
  // a leak for 7-17 s in 6 of 80 (the young estimate past the pump-wear signature), and on seed 48 the raised
  // pump wear renamed a critical leak 56 s later (evidence gathered in a lull at fine pitch)
  int leaks = 0, runs = 0;
  std::string seen;
  for (uint64_t seed = 1; seed <= 80; ++seed) {
    plant::TurbineScenario t;
    t.id = "WT01";
    t.wind.mean = 14.0 + static_cast<double>(seed % 5);
    t.wind.turbulence_intensity = 0.1;
    t.wind.shear_variation = 0.03;
    plant::TurbineSim sim(TurbineParams{}, t, {actuator_fault(0, "pump_wear", 10.0)}, 7000 + seed, 100.0);
    PitchDiagnoser diag{PitchDiagConfig{}};
    // ... blade 1 derated to 5 deg/s, as the arbiter answers the pump wear raised before the restart
    plant::ControlInput in;
    in.pitch_rate_limit = {5.0, 10.0, 10.0};
    InputContextTracker tracker("pitch_diag");
    tracker.on_reconfiguration(false, in.pitch_rate_limit);
    std::vector<FaultEvent> events;
    for (long k = 0; k < 200 * 100; ++k) {
      const FrameSample& s = sim.step(k >= 60 * 100 ? in : plant::ControlInput{});
      // ... which reaches it a second after its first frame (the configuration is transient local)
      if (k == 101 * 100) diag.set_context(tracker.context(), s.t);
      if (k >= 100 * 100) diag.update(s, false, events);
    }
    ++runs;
    // THEN the first report is pump wear on blade 1, never a leak
    const bool leak = std::any_of(events.begin(), events.end(),
                                  [](const FaultEvent& e) { return e.fault == "hydraulic_leakage"; });
    leaks += leak;
    ASSERT_FALSE(events.empty()) << seed;
    EXPECT_EQ(events.front().fault, "pump_wear") << seed;
    EXPECT_FALSE(leak) << "seed " << seed;
    if (leak)
      for (const auto& e : events)
        std::printf("  seed %d: %.1f %s %s %s (%s)\n", static_cast<int>(seed), e.t,
                    e.raised ? "raised" : "cleared", e.fault.c_str(), e.severity.c_str(), e.detail.c_str());
  }
  std::printf("[measured] started on a pump-worn blade: a leak raised in %d of %d runs\n", leaks, runs);
}

TEST(PitchDiagPlant, AnotherTurbinesActuatorIsJudgedByItsOwnHealthyDynamics) {
  // GIVEN a turbine whose healthy pitch actuator is slower and better damped than Table 1's (8 rad/s, 0.7
  // against 11.11 rad/s, 0.6), and the shipped configuration loaded for it: the signatures (and the plant's
  // faults) are Table 1's as shares of the healthy actuator
  TurbineParams slow;
  slow.pitch_omega_n = 8.0;
  slow.pitch_zeta = 0.7;
  const YamlSection shipped = YamlSection::load_file(PITCH_DIAG_YAML);
  const PitchDiagConfig own = load_pitch_diag_config(shipped, slow);
  EXPECT_NEAR(own.classifier.signatures[1].omega_n, 7.27 * 8.0 / 11.11, 1e-9);
  EXPECT_NEAR(own.classifier.signatures[1].zeta, 0.75 * 0.7 / 0.6, 1e-9);
  // THEN ten healthy minutes in region 3 raise nothing ...
  const auto healthy = run_plant(16.0, 600.0, {}, 73, 0.0, true, slow, own);
  EXPECT_TRUE(healthy.events.empty()) << healthy.events.front().fault << " at " << healthy.events.front().t;
  // ... where Table 1's absolute signatures (the benchmark actuator's) call this healthy actuator faulty
  const auto absolute =
      run_plant(16.0, 600.0, {}, 73, 0.0, true, slow, load_pitch_diag_config(shipped, TurbineParams{}));
  EXPECT_FALSE(absolute.events.empty());
  // AND each fault on blade 2 is raised with its name within 20 s of its onset, nothing else
  for (const char* fault : {"pump_wear", "hydraulic_leakage", "high_air_content"}) {
    const auto r = run_plant(16.0, 100.0, {actuator_fault(1, fault, 60.0)}, 51, 0.0, true, slow, own);
    ASSERT_FALSE(r.events.empty()) << fault;
    EXPECT_EQ(r.events.front().fault, fault);
    EXPECT_EQ(r.events.front().component, "pitch_actuator_2") << fault;
    EXPECT_GT(r.events.front().t, 60.0) << fault;
    EXPECT_LT(r.events.front().t, 80.0) << fault;
    std::printf("[measured] actuator of 8 rad/s, 0.7: %s raised %.1f s after the onset\n", fault,
                r.events.front().t - 60.0);
  }
}

TEST(PitchDiagPlant, AHealthyHourRaisesNothing) {
  // GIVEN one hour of the healthy plant in region 3, where the pitch works hardest
  const auto r = run_plant(16.0, 3600.0, {}, 73);
  // THEN no event, and every blade reads "none"
  EXPECT_TRUE(r.events.empty()) << r.events.front().component << " " << r.events.front().fault << " at "
                                << r.events.front().t;
  for (int b = 0; b < 3; ++b) EXPECT_EQ(r.last.fault_class[b], "none");
  // ... and the diagnoser ran: 10 Hz estimates, nothing rejected, every blade excited for a good share
  std::printf("[measured] healthy hour at 16 m/s: %d estimates, %d with every blade excited\n", r.estimates,
              r.excited);
  EXPECT_GT(r.estimates, 35000);
  EXPECT_EQ(r.rejected, 0u);
  EXPECT_GT(r.excited, r.estimates / 10);
}

}  // namespace

TEST(PitchDiagPlant, ARaisedPumpWearKeepsItsNameThroughTheArbitersDegradedMode) {
  // GIVEN pump wear on blade 1 from 20 s, its blade derated to 5 deg/s once it is raised (the arbiter's
  // action), then from 120 s for 40 s degraded mode (70 % power: the arbiter's answer to a lost sensor_bias),
  // then normal again. The reliability campaign saw this rename the raised pump wear a hydraulic leakage for
  // 6 s (alpha 0.50 on the leak's path), then pump wear again.
  int runs = 0;
  for (const double wind : {13.0, 15.0, 16.0, 18.0})
    for (uint64_t seed = 1; seed <= 4; ++seed) {
      plant::TurbineScenario t;
      t.id = "WT01";
      t.wind.mean = wind;
      t.wind.turbulence_intensity = 0.1;
      plant::TurbineSim sim(TurbineParams{}, t, {actuator_fault(0, "pump_wear", 20.0)}, seed, 100.0);
      PitchDiagnoser diag{PitchDiagConfig{}};
      InputContextTracker context("pitch_diag");
      plant::ControlInput in;
      std::vector<FaultEvent> events, ev;
      bool derated = false;
      for (long k = 0; k < 240 * 100; ++k) {
        const double now = static_cast<double>(k) / 100.0;
        if (!derated && !events.empty() && events.front().raised) {
          derated = true;
          in.pitch_rate_limit[0] = 5.0;
          context.on_reconfiguration(false, in.pitch_rate_limit);
        }
        if (k == 120 * 100 || k == 160 * 100) {
          in.mode = k == 120 * 100 ? plant::OperatingMode::kDegraded : plant::OperatingMode::kNormal;
          context.on_reconfiguration(false, in.pitch_rate_limit);
        }
        diag.set_context(context.context(), now);
        ev.clear();
        diag.update(sim.step(in), false, ev);
        events.insert(events.end(), ev.begin(), ev.end());
      }
      // THEN pump wear is raised on blade 1 and nothing else is ever reported
      ++runs;
      std::string all;
      for (const auto& e : events)
        all +=
            e.component + " " + e.fault + (e.raised ? " raised " : " cleared ") + std::to_string(e.t) + "; ";
      ASSERT_FALSE(events.empty()) << wind << " m/s seed " << seed;
      EXPECT_EQ(events.front().fault, "pump_wear") << wind << " m/s seed " << seed << ": " << all;
      EXPECT_EQ(events.size(), 1u) << wind << " m/s seed " << seed << ": " << all;
    }
  EXPECT_EQ(runs, 16);
}

TEST(PitchDiagPlant, ALeakRampedOutKeepsItsNameUntilItClears) {
  // GIVEN the benchmark's hydraulic leakage on one blade (ramped in over 30 s, held 40 s, ramped out over 30
  // s) in region 3, the blade derated to 5 deg/s once anything is raised on it (the arbiter's action). On its
  // way back the leak passes the pump-wear point, and the suite's benchmark sequences renamed it pump_wear or
  // high_air_content there (7 of 100, sets 380-384).
  auto renamed_runs = [](double recede_share) {
    PitchDiagConfig config;
    config.recede_share = recede_share;
    int renamed = 0, leaks = 0;
    double longest_critical = 0.0;
    for (const double wind : {15.0, 16.0, 17.0, 18.0, 19.0, 20.0, 21.0, 22.0})
      for (int blade = 0; blade < 3; ++blade) {
        plant::TurbineScenario t;
        t.id = "WT01";
        t.wind.mean = wind;
        t.wind.turbulence_intensity = 0.08 + 0.01 * blade;
        t.wind.shear_variation = 0.03;
        plant::FaultSpec leak = actuator_fault(blade, "hydraulic_leakage", 40.0);
        leak.ramp_in = 30.0;
        leak.end = leak.start + 70.0;
        leak.ramp_out = 30.0;
        plant::TurbineSim sim(TurbineParams{}, t, {leak}, 300 + static_cast<uint64_t>(wind) * 3 + blade,
                              100.0);
        PitchDiagnoser diag{config};
        InputContextTracker context("pitch_diag");
        plant::ControlInput in;
        std::vector<FaultEvent> events, ev;
        for (long k = 0; k < 200 * 100; ++k) {
          const bool leak_raised = std::any_of(events.begin(), events.end(), [](const FaultEvent& e) {
            return e.raised && e.fault == "hydraulic_leakage";
          });
          if ((in.pitch_rate_limit[blade] == 0.0 && !events.empty()) ||
              (leak_raised && in.mode != plant::OperatingMode::kDegraded)) {
            in.pitch_rate_limit[static_cast<std::size_t>(blade)] = 5.0;
            if (leak_raised) in.mode = plant::OperatingMode::kDegraded;
            context.on_reconfiguration(false, in.pitch_rate_limit);
          }
          diag.set_context(context.context(), static_cast<double>(k) / 100.0);
          ev.clear();
          diag.update(sim.step(in), false, ev);
          events.insert(events.end(), ev.begin(), ev.end());
        }
        const auto first_leak = std::find_if(events.begin(), events.end(), [](const FaultEvent& e) {
          return e.raised && e.fault == "hydraulic_leakage";
        });
        leaks += first_leak != events.end();
        renamed += std::any_of(first_leak, events.end(), [](const FaultEvent& e) {
          return e.raised && e.fault != "hydraulic_leakage";
        });
        // Critical until it clears or is reported again below critical, receding: no cause to stop
        double critical_from = -1.0;
        for (const auto& e : events) {
          if (e.fault != "hydraulic_leakage") continue;
          if (e.raised && e.severity == "critical" && critical_from < 0.0) critical_from = e.t;
          if (critical_from >= 0.0 && (!e.raised || e.severity != "critical")) {
            longest_critical = std::max(longest_critical, e.t - critical_from);
            critical_from = -1.0;
          }
        }
      }
    return std::tuple{renamed, leaks, longest_critical};
  };
  // THEN every leak is raised, and none is renamed once raised; without the rule some are (the test's own
  // check that the scenes reach the renaming)
  // AND no leak is critical for longer than 60 s (the arbiter stops on 90 s): it is reported again below
  // critical as it recedes
  const auto [renamed, leaks, critical] = renamed_runs(PitchDiagConfig{}.recede_share);
  EXPECT_EQ(leaks, 24);
  EXPECT_EQ(renamed, 0);
  EXPECT_LT(critical, 60.0);
  const auto [renamed_without, leaks_without, critical_without] = renamed_runs(0.0);
  EXPECT_GE(renamed_without, 2) << "of " << leaks_without;
  std::printf(
      "[measured] ramped-out leaks renamed: %d of %d, %d of %d without; longest critical %.1f s, %.1f s "
      "without\n",
      renamed, leaks, renamed_without, leaks_without, critical, critical_without);
}

TEST(PitchDiagPlant, AHighAirContentThatEndedClearsWithinTwoMinutesOnEveryTurbine) {
  // GIVEN the benchmark's high air content (100 s) on blade 1 of the benchmark, 1.5 MW and 6 MW turbines in
  // region 3, the blade derated to 5 deg/s once it is raised (the arbiter's action)
  auto clear_delays = [](bool refuted_once) {
    std::vector<double> delays;
    for (const char* name : {"", "example_1.5MW.yaml", "example_6MW.yaml"}) {
      const TurbineParams turbine =
          *name ? load_turbine_params_file(std::string(WINDFDI_SOURCE_DEPLOY_DIR) + "/turbine/" + name)
                : TurbineParams{};
      PitchDiagConfig config = load_pitch_diag_config(YamlSection::load_file(PITCH_DIAG_YAML), turbine);
      config.clear_refuted_once = refuted_once;
      for (const double wind : {15.0, 18.0, 21.0}) {
        plant::TurbineScenario t;
        t.id = "WT01";
        t.wind.mean = wind;
        t.wind.turbulence_intensity = 0.1;
        t.wind.shear_variation = 0.03;
        plant::FaultSpec f = actuator_fault(0, "high_air_content", 40.0);
        f.end = 140.0;
        plant::TurbineSim sim(turbine, t, {f}, 500 + static_cast<uint64_t>(wind), 100.0);
        PitchDiagnoser diag{config};
        InputContextTracker context("pitch_diag");
        plant::ControlInput in;
        std::vector<FaultEvent> ev;
        bool raised = false;
        double cleared = 1e9;
        for (long k = 0; k < 900 * 100 && cleared > 1e8; ++k) {
          ev.clear();
          diag.set_context(context.context(), static_cast<double>(k) / 100.0);
          diag.update(sim.step(in), false, ev);
          for (const auto& e : ev) {
            if (!e.raised) cleared = e.t;
            if (e.raised && !raised) {
              raised = true;
              in.pitch_rate_limit[0] = 5.0;
              context.on_reconfiguration(false, in.pitch_rate_limit);
            }
          }
        }
        EXPECT_TRUE(raised) << name << " " << wind << " m/s";
        delays.push_back(cleared - f.end);
      }
    }
    return delays;
  };
  // THEN each clears within 120 s of the fault's end; with the evidence asked on every decision of the spell
  // (before stop 73) at least one stays longer, the bank's evidence wavering about clear_evidence
  const auto once = clear_delays(true);
  for (const double d : once) EXPECT_LT(d, 120.0);
  const auto every = clear_delays(false);
  EXPECT_GT(*std::max_element(every.begin(), every.end()), 150.0);
  std::printf("[measured] clear after the end (s), rule / every decision:");
  for (std::size_t i = 0; i < once.size(); ++i) std::printf(" %.0f/%.0f", once[i], every[i]);
  std::printf("\n");
}
