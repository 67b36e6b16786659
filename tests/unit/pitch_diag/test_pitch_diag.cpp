// pitch_diag core tests (Wu & Li, MIFG pitch-actuator diagnosis): ZOH mapping, identification,
// classification with alpha, the paper's p = 8 vs p = 1 claim, and the diagnoser on synthetic 0.2 deg data.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "allocation_counter.hpp"
#include "identifier.hpp"
#include "pitch_diagnoser.hpp"
#include "pitch_model.hpp"
#include "synthetic_pitch.hpp"

using namespace windfdi;
using namespace windfdi::pitch_diag;

namespace {

constexpr double kT = 0.01;

using synth::along;
using synth::table1;

/// A turbine with three synthetic blades; `truth(t, blade)` gives (omega_n, zeta) of each actuator.
struct Rig {
  std::vector<synth::SyntheticBlade> blades;
  PitchDiagnoser diag;
  std::vector<FaultEvent> events;  // all events so far
  PitchEstimate last;
  uint64_t update_allocations = 0;  // heap allocations inside diag.update
  uint64_t seq = 0;
  double t = 0.0;

  Rig(const PitchDiagConfig& cfg, double noise, uint64_t seed, double offset = 0.0) : diag(cfg) {
    for (int i = 0; i < 3; ++i) {
      synth::SyntheticConfig sc;
      sc.noise = noise;
      sc.seed = seed * 10 + i;
      sc.offset = offset;
      blades.emplace_back(sc);
    }
  }
  /// Blades with the reference of `profile` (its seed replaced).
  Rig(const PitchDiagConfig& cfg, synth::SyntheticConfig profile, uint64_t seed) : diag(cfg) {
    for (int i = 0; i < 3; ++i) {
      profile.seed = seed * 10 + i;
      blades.emplace_back(profile);
    }
  }
  using Truth = std::function<Signature(double t, int blade)>;
  /// Runs until `t_end`; `edit` may change the sample before it is fed.
  void run(double t_end, const Truth& truth, const std::function<void(FrameSample&)>& edit = nullptr) {
    FrameSample s;
    std::vector<FaultEvent> ev;
    while (t < t_end - 1e-9) {
      s.sequence = seq++;
      s.t = t;
      for (int i = 0; i < 3; ++i) {
        s.pitch_ref[i] = blades[i].reference(t);
        s.pitch[i] = blades[i].measure();
      }
      const FrameSample clean = s;
      if (edit) edit(s);
      ev.clear();
      const uint64_t before = windfdi::test::allocations();
      diag.update(s, false, ev);
      update_allocations += windfdi::test::allocations() - before;
      events.insert(events.end(), ev.begin(), ev.end());
      diag.estimate_due(last);
      for (int i = 0; i < 3; ++i) {
        const Signature g = truth(t, i);
        // The actuator follows the reference the diagnoser sees (unless that is invalid).
        const double u = std::isfinite(s.pitch_ref[i]) ? s.pitch_ref[i] : clean.pitch_ref[i];
        blades[i].step(u, g.omega_n, g.zeta);
      }
      t = std::round((t + kT) * 1e6) / 1e6;
    }
  }
};

Signature healthy(double, int) { return table1("none"); }

// ---------------------------------------------------------------------------------------------------------
// ZOH mapping

TEST(PitchModel, ThetaRoundTripForEveryTable1Row) {
  for (const auto& sig : table1_signatures()) {
    // GIVEN a Table 1 row; WHEN mapped to theta by the exact ZOH and back through the poles
    const Theta theta = theta_from_continuous(sig.omega_n, sig.zeta, kT);
    const ContinuousModel m = continuous_from_theta(theta, kT);
    // THEN omega_n and zeta come back to 1e-9 relative, and the DC gain is 1 (eqs 7-9 would give 100)
    ASSERT_TRUE(m.valid) << sig.name;
    EXPECT_NEAR(m.omega_n, sig.omega_n, 1e-9 * sig.omega_n) << sig.name;
    EXPECT_NEAR(m.zeta, sig.zeta, 1e-9) << sig.name;
    EXPECT_NEAR(m.gain, 1.0, 1e-9) << sig.name;
  }
}

TEST(PitchModel, RoundTripForRealPolePairs) {
  // GIVEN critically damped and overdamped actuators (real pole pairs)
  for (double zeta : {1.0, 1.0 + 1e-9, 1.3, 2.5}) {
    const Theta theta = theta_from_continuous(5.0, zeta, kT);
    const ContinuousModel m = continuous_from_theta(theta, kT);
    // THEN the mapping still inverts (1e-6: near zeta = 1 the poles are a double root)
    ASSERT_TRUE(m.valid) << zeta;
    EXPECT_NEAR(m.omega_n, 5.0, 1e-6 * 5.0) << zeta;
    EXPECT_NEAR(m.zeta, zeta, 1e-6) << zeta;
  }
}

TEST(PitchModel, ZohModelReproducesTheContinuousStepResponse) {
  // GIVEN the healthy actuator integrated finely (RK4, 10 substeps) and its ZOH theta, from rest
  synth::SyntheticConfig sc;
  sc.noise = 0.0;
  sc.turb_std = 0.0;
  sc.level_amp = 0.0;
  sc.level_mean = 0.0;
  sc.rate_limit = 1e9;
  synth::SyntheticBlade blade(sc);
  const auto& h = table1("none");
  const Theta th = theta_from_continuous(h.omega_n, h.zeta, kT);
  double y1 = 0, y2 = 0, u1 = 0, u2 = 0, peak = 0;
  for (int k = 0; k < 300; ++k) {
    const double u = 1.0;  // unit step at t = 0
    const double y = -th(0) * y1 - th(1) * y2 + th(2) * u1 + th(3) * u2;
    // THEN both agree to 1e-7 deg at every sample (RK4 error only) ...
    ASSERT_NEAR(y, blade.angle(), 1e-7) << k;
    peak = std::max(peak, y);
    blade.step(u, h.omega_n, h.zeta);
    y2 = y1, y1 = y, u2 = u1, u1 = u;
  }
  // ... and the overshoot is the analytic exp(-pi zeta / sqrt(1 - zeta^2)) = 9.48 % (sampling: within 0.1 %)
  EXPECT_NEAR(peak - 1.0, std::exp(-M_PI * 0.6 / 0.8), 1e-3);
}

TEST(PitchModel, ClassifyGivesAlphaAlongEachPath) {
  ClassifierConfig c;
  // GIVEN points at alpha = 0.6 on the high-air-content path and at the Table 1 signatures
  const auto& h = table1("none");
  const auto& ha = table1("high_air_content");
  const Signature point = along(h, ha, 0.6);
  Classification k = classify(point.omega_n, point.zeta, c);
  // THEN the class and alpha come back (1e-9), unambiguously
  EXPECT_EQ(k.fault_class, "high_air_content");
  EXPECT_NEAR(k.alpha, 0.6, 1e-9);
  EXPECT_FALSE(k.ambiguous);
  // AND the pump-wear point is also hydraulic leakage at alpha 0.50: both paths are reported
  const auto& pw = table1("pump_wear");
  k = classify(pw.omega_n, pw.zeta, c);
  ASSERT_TRUE(k.ambiguous);
  EXPECT_NEAR(k.path_alpha[0], 1.0, 1e-3);     // pump_wear
  EXPECT_NEAR(k.path_alpha[1], 0.4994, 1e-3);  // hydraulic_leakage: (11.11 - 7.27) / (11.11 - 3.42)
  // AND the healthy point is "none"
  EXPECT_EQ(classify(h.omega_n, h.zeta, c).fault_class, "none");
}

// ---------------------------------------------------------------------------------------------------------
// Identification

double converged_error(Method m, double omega_n, double zeta, double noise, double& zeta_err) {
  synth::SyntheticConfig sc;
  sc.noise = noise;
  sc.seed = 5;
  synth::SyntheticBlade b(sc);
  IdentifierConfig ic;
  ic.method = m;
  Identifier id(ic);
  for (int k = 0; k < 6000; ++k) {
    const double u = b.reference(k * kT);
    id.update(u, b.measure());
    b.step(u, omega_n, zeta);
  }
  const ContinuousModel cm = id.model();
  zeta_err = cm.valid ? std::abs(cm.zeta / zeta - 1.0) : 1e9;
  return cm.valid ? std::abs(cm.omega_n / omega_n - 1.0) : 1e9;
}

TEST(Identifier, DefaultModeConvergesNoiseFreeToTheTrueModel) {
  // GIVEN noise-free data of each Table 1 row and of points between them; WHEN the default (bank) runs 60 s
  const auto& h = table1("none");
  for (const auto& f : table1_signatures())
    for (double alpha : {0.35, 1.0}) {
      const Signature point = along(h, f, alpha);
      const double wn = point.omega_n, z = point.zeta;
      double ez;
      const double ew = converged_error(IdentifierConfig{}.method, wn, z, 0.0, ez);
      // THEN omega_n and zeta are within 1 %
      EXPECT_LT(ew, 0.01) << f.name << " alpha " << alpha;
      EXPECT_LT(ez, 0.01) << f.name << " alpha " << alpha;
    }
}

TEST(Identifier, OutputErrorModeConvergesOffThePaths) {
  // GIVEN noise-free data of an actuator on no fault path (9 rad/s, 0.7); WHEN oe_rls runs 60 s
  double ez;
  const double ew = converged_error(Method::kOeRls, 9.0, 0.7, 0.0, ez);
  // THEN it finds it within 1 % (the bank only knows its paths: this mode reports general dynamics)
  EXPECT_LT(ew, 0.01);
  EXPECT_LT(ez, 0.01);
}

TEST(Identifier, PaperModeFailsAtPitchNoiseAndDefaultDoesNot) {
  // GIVEN hydraulic leakage with 0.2 deg pitch noise (docs/papers.md, Wu & Li)
  const auto& hl = table1("hydraulic_leakage");
  double ez_paper, ez_bank;
  const double ew_paper = converged_error(Method::kPaperRls, hl.omega_n, hl.zeta, 0.2, ez_paper);
  const double ew_bank = converged_error(Method::kBank, hl.omega_n, hl.zeta, 0.2, ez_bank);
  // THEN equation-error RLS is off by more than 50 % (or maps to no pole pair), the default within 5 %
  EXPECT_GT(ew_paper, 0.5);
  EXPECT_LT(ew_bank, 0.05);
  EXPECT_LT(ez_bank, 0.05);
}

TEST(Identifier, PaperMifgLongerInnovationConvergesFaster) {
  // GIVEN the paper's setting: eq 10 regressor on the raw pitch (no level removal), lambda 0.97, noise-free,
  // the estimator starting at the healthy model while the actuator has pump wear (eq 31's alpha = 1)
  const Theta truth = theta_from_continuous(7.27, 0.75, kT);
  auto reduction = [&](int p) {
    synth::SyntheticConfig sc;
    sc.noise = 0.0;
    sc.seed = 3;
    synth::SyntheticBlade b(sc);
    IdentifierConfig ic;
    ic.method = Method::kPaperMifg;
    ic.p = p;
    ic.lambda = 0.97;
    ic.highpass_hz = 0.0;
    ic.pe_threshold = 0.0;
    Identifier id(ic);
    const double e0 = (id.theta() - truth).norm();
    for (int k = 0; k < 100000; ++k) {  // 1000 s
      const double u = b.reference(k * kT);
      id.update(u, b.measure());
      b.step(u, 7.27, 0.75);
    }
    return 1.0 - (id.theta() - truth).norm() / e0;
  };
  const double r1 = reduction(1), r8 = reduction(8);
  // THEN p = 8 removes more of the initial error than p = 1 (Figs 7-9): measured 2.3 % vs 1.6 %, so > 1.2x
  // ...
  EXPECT_GT(r8, 1.2 * r1);
  // ... but both remove under 10 % in 1000 s: the raw regressor is dominated by the pitch level (errata)
  EXPECT_LT(r8, 0.1);
  EXPECT_GT(r1, 0.0);
}

/// The bank started on an actuator (omega_n, zeta) that has run for 100 s under a reference of level 8 deg,
/// a swing of +-3 deg at 0.25 Hz (the 1P individual pitch demand) starting at its steepest, and a slow +-0.5
/// deg; 0.1 deg noise and `offset` deg of pitch-sensor offset. Returns the most evidence against the healthy
/// actuator while a decision could be taken (after the first 6 s) over 60 s; `model` the end's estimate.
double start_evidence(const IdentifierConfig& ic, double omega_n, double zeta, double offset,
                      ContinuousModel& model) {
  Identifier id(ic);
  const Theta th = theta_from_continuous(omega_n, zeta, kT);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.1);
  double x1 = 8.0, x2 = 8.0, u1 = 8.0, u2 = 8.0, most = 0.0;
  for (int k = -10000; k < 6000; ++k) {
    const double t = k * kT;
    const double u = 8.0 + 3.0 * std::sin(2.0 * M_PI * 0.25 * t) + 0.5 * std::sin(2.0 * M_PI * 0.031 * t);
    const double x = -th(0) * x1 - th(1) * x2 + th(2) * u1 + th(3) * u2;
    x2 = x1;
    x1 = x;
    u2 = u1;
    u1 = u;
    if (k < 0) continue;
    id.update(u, x + offset + noise(rng));
    if (k % 10 == 0 && t > 6.0 && id.decisive()) most = std::max(most, id.evidence());
  }
  model = id.model();
  return most;
}

TEST(Identifier, AStartAtASwingingReferenceIsNotASlowActuator) {
  // GIVEN a healthy actuator that lags a swinging reference by 0.4 deg when the identification starts (the
  // plant at 12 m/s: blade 3 of the suite's healthy scenario 93_01 started 0.8 deg off it)
  const IdentifierConfig ic;
  ContinuousModel m;
  const double evidence = start_evidence(ic, 11.11, 0.6, 0.0, m);
  // THEN nothing reaches the decision's evidence (evidence_min 25): the first level_window fits the level of
  // the pitch against the reference (the healthy model's residual as offset plus lag) before anything is
  // identified, and the estimate is the healthy actuator ...
  EXPECT_LT(evidence, 0.5 * ic.evidence_min);
  EXPECT_NEAR(m.omega_n, 11.11, 0.2);
  // ... where the first sample's tracking error taken as level (an offset decaying through the 0.02 Hz level
  // removal) read as a slower actuator (measured: 89 sigma^2 at 7 s toward omega_n 8.2)
  IdentifierConfig first_sample;
  first_sample.level_window = 0.0;
  EXPECT_GT(start_evidence(first_sample, 11.11, 0.6, 0.0, m), 2.0 * ic.evidence_min);
  // AND with a pitch-sensor offset of 1 deg, which the level fit takes as level too
  EXPECT_LT(start_evidence(ic, 11.11, 0.6, 1.0, m), 0.5 * ic.evidence_min);
  // AND a start on a faulty actuator still finds it: the fit's lag term takes up the fault's longer lag
  for (const auto& f : table1_signatures()) {
    if (f.name == "none") continue;
    EXPECT_GT(start_evidence(ic, f.omega_n, f.zeta, 0.0, m), 10.0 * ic.evidence_min) << f.name;
    EXPECT_NEAR(m.omega_n, f.omega_n, 0.1) << f.name;
    EXPECT_NEAR(m.zeta, f.zeta, 0.02) << f.name;
  }
}

// ---------------------------------------------------------------------------------------------------------
// Diagnoser on synthetic 0.2 deg data

TEST(PitchDiagnoser, EveryFaultOnEveryBladeIsClassifiedWithin10s) {
  for (const char* fault : {"pump_wear", "hydraulic_leakage", "high_air_content"})
    for (int blade = 0; blade < 3; ++blade) {
      // GIVEN 0.2 deg pitch noise and an abrupt Table 1 fault on one blade at t = 40 s
      Rig rig(PitchDiagConfig{}, 0.2, 300 + blade);
      const double t_on = 40.0;
      rig.run(t_on + 12.0,
              [&](double t, int b) { return b == blade && t >= t_on ? table1(fault) : table1("none"); });
      // THEN exactly one event: that fault raised on that blade's actuator within 10 s of the onset
      ASSERT_EQ(rig.events.size(), 1u)
          << fault << " blade " << blade << (rig.events.empty() ? "" : " first: " + rig.events[0].fault);
      const auto& e = rig.events[0];
      EXPECT_EQ(e.component, "pitch_actuator_" + std::to_string(blade + 1));
      EXPECT_EQ(e.fault, fault);
      EXPECT_TRUE(e.raised);
      EXPECT_GT(e.t, t_on);
      EXPECT_LE(e.t - t_on, 10.0) << fault << " blade " << blade;
      EXPECT_GT(e.size, 0.8);  // alpha of a fully developed fault (1 +- 0.2)
      EXPECT_EQ(rig.last.fault_class[blade], fault);
    }
}

TEST(PitchDiagnoser, HalfDevelopedLeakageIsReportedWithItsAlphaNotAsPumpWear) {
  // GIVEN a hydraulic leakage developing gradually on blade 2 to alpha 0.5 over 120 s (eq 12), 0.2 deg noise;
  // at alpha 0.5 its dynamics are those of full pump wear (Table 1)
  Rig rig(PitchDiagConfig{}, 0.2, 41);
  const auto& h = table1("none");
  const auto& hl = table1("hydraulic_leakage");
  rig.run(200.0, [&](double t, int b) {
    if (b != 1 || t < 30.0) return h;
    const double alpha = std::min(0.5, 0.5 * (t - 30.0) / 120.0);
    return along(h, hl, alpha);
  });
  // THEN the estimate says hydraulic leakage at alpha 0.5 +- 0.1, and says that it is ambiguous with pump
  // wear
  EXPECT_EQ(rig.last.fault_class[1], "hydraulic_leakage");
  EXPECT_NEAR(rig.last.alpha[1], 0.5, 0.1);
  EXPECT_TRUE(rig.last.ambiguous[1]);
  EXPECT_EQ(rig.last.alt_class[1], "pump_wear");
  // AND no event ever says pump wear; the leakage is raised (warning, then fault is not reached at 0.5 < 0.6)
  bool leakage = false;
  for (const auto& e : rig.events) {
    EXPECT_NE(e.fault, "pump_wear") << "t " << e.t;
    EXPECT_EQ(e.component, "pitch_actuator_2");
    if (e.raised && e.fault == "hydraulic_leakage") {
      leakage = true;
      EXPECT_NE(e.detail.find("pump_wear"), std::string::npos) << e.detail;
    }
  }
  EXPECT_TRUE(leakage);
  // AND the other blades stay "none"
  EXPECT_EQ(rig.last.fault_class[0], "none");
  EXPECT_EQ(rig.last.fault_class[2], "none");
}

TEST(PitchDiagnoser, ARampIsNamedByWhereItGoesPumpWearOver30sAndALeakOver30s) {
  // GIVEN pump wear ramped in over 30 s on blade 1, or a leak ramped in over 30 s (the multi-fault suite's
  // ramps): both pass along the shared path, the pump wear at half the leak's pace; 0.2 deg noise, 4 seeds
  const auto& h = table1("none");
  for (const char* fault : {"pump_wear", "hydraulic_leakage"})
    for (int seed = 0; seed < 4; ++seed) {
      Rig rig(PitchDiagConfig{}, 0.2, 500 + seed);
      const auto& f = table1(fault);
      const double t_on = 40.0, ramp = 30.0;
      rig.run(t_on + ramp + 20.0, [&](double t, int b) {
        if (b != 0 || t < t_on) return h;
        const double alpha = std::min(1.0, (t - t_on) / ramp);
        return along(h, f, alpha);
      });
      // THEN the first event names the fault, never the other reading, within 10 s of the ramp's end; the
      // pump wear within 12 s: it is named once it has stood still at its point (shared_settle_band, stop 75:
      // 79.7-81.6 s here against 76.9-79.1 s without, where a leak moving slowly through the point was named
      // pump_wear, ALeakMovingSlowlyThroughThePumpWearPointIsNotSettledThere)
      ASSERT_FALSE(rig.events.empty()) << fault << " seed " << seed;
      const auto& e = rig.events.front();
      EXPECT_EQ(e.component, "pitch_actuator_1");
      EXPECT_EQ(e.fault, fault) << "seed " << seed << " at " << e.t << ": " << e.detail;
      const double named_within = std::string(fault) == "pump_wear" ? 12.0 : 10.0;
      EXPECT_LE(e.t, t_on + ramp + named_within) << fault << " seed " << seed;
      for (const auto& x : rig.events) EXPECT_EQ(x.fault, fault) << "seed " << seed << " at " << x.t;
    }
}

TEST(PitchDiagnoser, ALeakMovingSlowlyThroughThePumpWearPointIsNotSettledThere) {
  // GIVEN a leak on blade 1 that reaches the pump-wear point's band at a ramp's pace (leak alpha 0.4 in 12 s)
  // and then goes on at 0.0175 a second: about 11 s in the band taken as the pump-wear point (pump-wear alpha
  // 0.7 to 1.15), more than shared_settle_time, moving 0.28 of pump-wear alpha over those 8 s (the
  // benchmark's leak ramped in over 30 s, lagged by the estimate, was named pump_wear so). 0.2 deg noise, 4
  // seeds
  const auto& h = table1("none");
  const auto& leak = table1("hydraulic_leakage");
  auto events_of = [&](const PitchDiagConfig& config, int seed) {
    Rig rig(config, 0.2, 900 + static_cast<uint64_t>(seed));
    const double t_on = 40.0;
    rig.run(120.0, [&](double t, int b) {
      if (b != 0 || t < t_on) return h;
      const double since = t - t_on;
      const double alpha = since < 12.0 ? 0.4 * since / 12.0 : std::min(1.0, 0.4 + 0.0175 * (since - 12.0));
      return along(h, leak, alpha);
    });
    return rig.events;
  };
  PitchDiagConfig band_off;
  band_off.shared_settle_band = 0.0;
  int named_leak = 0, named_pump_wear_without_band = 0;
  for (int seed = 0; seed < 4; ++seed) {
    const auto events = events_of(PitchDiagConfig{}, seed);
    const auto without = events_of(band_off, seed);
    ASSERT_FALSE(events.empty()) << "seed " << seed;
    std::printf("[measured] seed %d: first %s at %.1f s (band off: %s at %.1f s)\n", seed,
                events.front().fault.c_str(), events.front().t,
                without.empty() ? "-" : without.front().fault.c_str(),
                without.empty() ? 0.0 : without.front().t);
    // THEN with the band every event names the leak
    bool only_leak = true;
    for (const auto& e : events) only_leak = only_leak && e.fault == "hydraulic_leakage";
    named_leak += only_leak;
    named_pump_wear_without_band += !without.empty() && without.front().fault == "pump_wear";
  }
  EXPECT_EQ(named_leak, 4);
  // AND without it the point counted as settled at the pump-wear signature in some (the rule is what fixed
  // it)
  EXPECT_GE(named_pump_wear_without_band, 1);
}

TEST(PitchDiagnoser, ACrossingTheEstimateWasHeldThroughIsARampNotAbrupt) {
  // GIVEN blade 1's reference standing still for 2.5 s of every 4 s over 16 s (the estimate held: no
  // excitation) while its actuator moves along the shared path: a leak ramped in over 30 s from 40 s, stills
  // from 42 s (judged suite set 178: at 8 % turbulence the estimate was held 2.9-4.0 s on its way from
  // healthy, caught up at the pump-wear point in 2 s and was named pump_wear); or an abrupt pump wear at 40
  // s, stills from 41 s. 0.2 deg noise, 12 seeds
  const auto& h = table1("none");
  struct Case {
    const char* fault;
    double ramp, still_from;
  };
  auto first_event = [&](const PitchDiagConfig& config, const Case& c, int seed) {
    Rig rig(config, 0.2, 700 + static_cast<uint64_t>(seed));
    const auto& f = table1(c.fault);
    const double t_on = 40.0;
    double still = 0.0;
    rig.run(
        110.0,
        [&](double t, int b) {
          if (b != 0 || t < t_on) return h;
          const double alpha = c.ramp > 0.0 ? std::min(1.0, (t - t_on) / c.ramp) : 1.0;
          return along(h, f, alpha);
        },
        [&](FrameSample& s) {
          const double since = s.t - c.still_from;
          if (since >= 0.0 && since < 16.0 && std::fmod(since, 4.0) < 2.5)
            s.pitch_ref[0] = still;
          else
            still = s.pitch_ref[0];
        });
    return rig.events.empty() ? FaultEvent{} : rig.events.front();
  };
  const Case ramped_leak{"hydraulic_leakage", 30.0, 42.0}, pump_wear{"pump_wear", 0.0, 41.0};
  PitchDiagConfig unseen_ignored, hold_before_ignored;
  unseen_ignored.abrupt_unseen_max = 1e9;
  hold_before_ignored.unseen_from_last_healthy = false;
  int leak_first = 0, leak_first_ignored = 0, leak_first_before_ignored = 0;
  for (int seed = 0; seed < 12; ++seed) {
    const FaultEvent leak = first_event(PitchDiagConfig{}, ramped_leak, seed);
    const FaultEvent ignored = first_event(unseen_ignored, ramped_leak, seed);
    const FaultEvent before_ignored = first_event(hold_before_ignored, ramped_leak, seed);
    const FaultEvent wear = first_event(PitchDiagConfig{}, pump_wear, seed);
    std::printf(
        "[measured] seed %d: ramped leak first %s at %.1f s (held time ignored: %s; the hold before leaving "
        "healthy ignored: %s), abrupt pump wear %s at %.1f s\n",
        seed, leak.fault.c_str(), leak.t, ignored.fault.c_str(), before_ignored.fault.c_str(),
        wear.fault.c_str(), wear.t);
    const auto is_leak = [](const FaultEvent& e) {
      return e.component == "pitch_actuator_1" && e.fault == "hydraulic_leakage";
    };
    leak_first += is_leak(leak);
    leak_first_ignored += is_leak(ignored);
    leak_first_before_ignored += is_leak(before_ignored);
    // THEN the abrupt pump wear is still named pump wear (later where its crossing was held)
    EXPECT_EQ(wear.component, "pitch_actuator_1") << "seed " << seed;
    EXPECT_EQ(wear.fault, "pump_wear") << "seed " << seed << " at " << wear.t << ": " << wear.detail;
  }
  // AND the ramped leak is named a leak first in 12 of 12, 8 of 12 with the held time ignored, 11 of 12 with
  // only the holds after the first decision off healthy counted (seed 4: the estimate looked healthy again
  // after a still and jumped past half-way to the point across the next one, as a fault that appears during a
  // hold does; since stop 63 that hold counts, and such a pump wear waits as a ramp too)
  EXPECT_EQ(leak_first, 12);
  EXPECT_LE(leak_first_ignored, leak_first - 2);
  EXPECT_LT(leak_first_before_ignored, leak_first);
}

TEST(PitchDiagnoser, APointPastThePumpWearSignatureIsTheLeak) {
  // GIVEN blade 3's dynamics jumping at 40 s to a point past the pump-wear signature on the shared path (pump
  // wear at alpha 1.2, leakage at 0.6: where the demo's estimate of an abrupt leak sat for 4 s), then on
  // to the full leak at 50 s; 0.2 deg noise
  const auto& h = table1("none");
  const auto& hl = table1("hydraulic_leakage");
  const Signature overshoot = along(h, hl, 0.6);
  auto trajectory = [&](double t, int b) { return b != 2 || t < 40.0 ? h : t < 50.0 ? overshoot : hl; };
  Rig rig(PitchDiagConfig{}, 0.2, 43);
  rig.run(60.0, trajectory);
  // THEN the first report is the leak, not the pump wear the point would be abruptly on its own path
  ASSERT_FALSE(rig.events.empty());
  EXPECT_EQ(rig.events.front().fault, "hydraulic_leakage") << rig.events.front().detail;
  for (const auto& e : rig.events) EXPECT_NE(e.fault, "pump_wear") << "t " << e.t;
  // (without the rule, short_max_alpha at its clamp, the same data reported pump_wear first)
  PitchDiagConfig no_rule;
  no_rule.short_max_alpha = 1.5;
  Rig old(no_rule, 0.2, 43);
  old.run(60.0, trajectory);
  ASSERT_FALSE(old.events.empty());
  EXPECT_EQ(old.events.front().fault, "pump_wear");
}

/// Another generator's reference: slow swings of several degrees (3 deg rms, 0.02-0.2 Hz) about 12 deg and
/// little fast content (0.1 deg of 0.2-1 Hz), 0.2 deg pitch noise (tests/perf/pitch_diag_slow_swing).
synth::SyntheticConfig slow_swing() {
  synth::SyntheticConfig c;
  c.level_mean = 12.0, c.level_amp = 3.0, c.level_period = 300.0;
  c.turb_std = 3.0, c.f_lo = 0.02, c.f_hi = 0.2;
  c.fast_std = 0.1, c.fast_lo = 0.2, c.fast_hi = 1.0;
  return c;
}

TEST(PitchDiagnoser, OnASlowSwingEveryFaultIsClassifiedWithin10s) {
  for (const char* fault : {"pump_wear", "hydraulic_leakage", "high_air_content"}) {
    // GIVEN a slow-swing reference (its third differences far too small for eq 20's four-parameter test)
    // and an abrupt Table 1 fault on blade 2 at 60 s
    const double t_on = 60.0;
    const auto truth = [&](double t, int b) { return b == 1 && t >= t_on ? table1(fault) : table1("none"); };
    Rig rig(PitchDiagConfig{}, slow_swing(), 515);
    rig.run(t_on + 20.0, truth);
    // THEN the bank's information test lets it learn: exactly that fault on that blade, pump wear and the
    // leak within 10 s, high air content within 12 s (its lag differs from the healthy one by 0.05 s: on this
    // reference an oracle knowing both models needs 1.1 s for 5 sigma here, 2.8 s in the median of
    // pitch_diag_slow_swing, and the bank's confirmation 3 s more)
    ASSERT_FALSE(rig.events.empty()) << fault;
    const auto& e = rig.events.front();
    EXPECT_EQ(e.component, "pitch_actuator_2") << fault;
    EXPECT_EQ(e.fault, fault);
    EXPECT_GT(e.t, t_on);
    EXPECT_LE(e.t - t_on, std::string(fault) == "high_air_content" ? 12.0 : 10.0) << fault;
    for (const auto& x : rig.events) EXPECT_EQ(x.fault, fault) << "at " << x.t;
    // AND with eq 20 alone (information_min 0, the paper's test) the same data raise nothing within 10 s
    PitchDiagConfig eq20_only;
    eq20_only.identifier.information_min = 0.0;
    Rig old(eq20_only, slow_swing(), 515);
    old.run(t_on + 10.0, truth);
    EXPECT_TRUE(old.events.empty()) << fault;
  }
}

TEST(PitchDiagnoser, OnASlowSwingWithALittleFastContentHighAirContentIsNotForgottenWhereEq20Holds) {
  // GIVEN the slow-swing reference with its 0.1 deg of fast content, which passes eq 20 now and then, and
  // high air content abrupt at 60 s, 40 runs (seeds 500-539, the blade seed % 3)
  const double t_on = 60.0;
  int within[2] = {0, 0};
  for (uint64_t seed = 500; seed < 540; ++seed) {
    const int blade = static_cast<int>(seed % 3);
    const auto truth = [&](double t, int i) {
      return i == blade && t >= t_on ? table1("high_air_content") : table1("none");
    };
    double first[2] = {NAN, NAN};
    for (const bool information_evidence : {false, true}) {
      PitchDiagConfig cfg;
      cfg.identifier.information_evidence = information_evidence;
      Rig rig(cfg, slow_swing(), seed);
      rig.run(t_on + 30.0, truth);
      ASSERT_FALSE(rig.events.empty()) << seed << " " << information_evidence;
      const auto& e = rig.events.front();
      EXPECT_EQ(e.component, "pitch_actuator_" + std::to_string(blade + 1)) << seed;
      EXPECT_EQ(e.fault, "high_air_content") << seed;
      first[information_evidence] = e.t - t_on;
      within[information_evidence] += e.t - t_on <= 10.0;
    }
    // THEN the decision that also reads the residuals remembered in information is never later: they keep
    // the 0.05 s of extra lag that eq 20's 2 s memory forgets as fast as it comes
    EXPECT_LE(first[1], first[0] + 1e-9) << seed;
  }
  std::printf(
      "[measured] high air content within 10 s of its onset: %d of 40, %d with the 2 s memory alone "
      "wherever eq 20 holds\n",
      within[1], within[0]);
  // AND more runs are raised within 10 s (measured 30 of 40 against 23)
  EXPECT_GE(within[1], 28);
  EXPECT_LE(within[0], 25) << "the 2 s memory is no longer slower: this test no longer tests";
}

TEST(PitchDiagnoser, AnEstimateDecidedOnTheResidualsRememberedInInformationIsPublishedAsExcited) {
  // GIVEN the slow-swing reference and high air content on blade 1 from 60 s (seed 501: 74 of its 899
  // estimates are decided on the information memory alone)
  Rig rig(PitchDiagConfig{}, slow_swing(), 501);
  const auto truth = [](double t, int i) {
    return i == 0 && t >= 60.0 ? table1("high_air_content") : table1("none");
  };
  int by_information = 0, held_but_moved = 0, published = 0;
  double previous_omega_n = NAN, previous_t = 0.0;
  for (int sample = 1; sample <= 9000; ++sample) {  // one sample at a time: every estimate is seen
    rig.run(sample * kT, truth);
    if (rig.last.t == previous_t) continue;
    previous_t = rig.last.t;
    ++published;
    // THEN an estimate the 2 s memory did not decide but the information memory did is flagged excited ...
    by_information += rig.last.excited[0] && !rig.diag.blade(0).identifier().decisive();
    // ... and one flagged not excited is the estimate held from before
    held_but_moved +=
        !rig.last.excited[0] && std::isfinite(previous_omega_n) && rig.last.omega_n[0] != previous_omega_n;
    previous_omega_n = rig.last.omega_n[0];
  }
  std::printf("[measured] %d estimates, %d of them decided on the residuals remembered in information\n",
              published, by_information);
  EXPECT_GT(published, 800);
  EXPECT_GT(by_information, 0);
  EXPECT_EQ(held_but_moved, 0);
}

// No event in an hour of healthy actuators, and every blade's estimate healthy within `tolerance` at the end.
void expect_a_quiet_healthy_hour(Rig& rig, double tolerance) {
  rig.run(3600.0, healthy);
  EXPECT_TRUE(rig.events.empty()) << rig.events.size() << " events, first " << rig.events[0].fault << " at "
                                  << rig.events[0].t;
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(rig.last.fault_class[i], "none");
    EXPECT_NEAR(rig.last.omega_n[i], 11.11, tolerance * 11.11);
  }
}

TEST(PitchDiagnoser, OnASlowSwingAHealthyHourRaisesNothing) {
  // GIVEN an hour of healthy actuators on the slow-swing reference
  Rig rig(PitchDiagConfig{}, slow_swing(), 78);
  // THEN no event, and the estimates are healthy within 10 % (a slow swing carries less information)
  expect_a_quiet_healthy_hour(rig, 0.1);
}

TEST(PitchDiagnoser, ASampleAllocatesNothing) {
  // GIVEN a diagnoser that has followed healthy actuators for a minute (its bank and windows in use)
  Rig rig(PitchDiagConfig{}, 0.2, 79);
  rig.run(60.0, healthy);
  // WHEN it takes ten minutes more
  rig.update_allocations = 0;
  rig.run(660.0, healthy);
  // THEN no sample allocated (the bank's arrays were three allocations per sample and blade; issue 21)
  EXPECT_EQ(rig.update_allocations, 0u);
}

TEST(PitchDiagnoser, HealthyHourRaisesNothing) {
  // GIVEN one hour of healthy actuators at 100 Hz with 0.2 deg noise
  Rig rig(PitchDiagConfig{}, 0.2, 77);
  // THEN no event, and the estimates are healthy within 5 % at the end
  expect_a_quiet_healthy_hour(rig, 0.05);
}

TEST(PitchDiagnoser, ConstantSensorOffsetRaisesNothing) {
  // GIVEN a +3 deg pitch-sensor offset on every blade from the start, and a +2 deg step offset appearing on
  // blade 3 at t = 60 s (Witczak et al.'s pitch sensor bias), healthy actuators, 0.2 deg noise
  Rig rig(PitchDiagConfig{}, 0.2, 55, 3.0);
  rig.run(300.0, healthy, [&](FrameSample& s) {
    if (s.t >= 60.0) s.pitch[2] += 2.0;
  });
  // THEN nothing is raised: the level removal takes the offset out, it is no actuator fault
  EXPECT_TRUE(rig.events.empty()) << rig.events[0].fault << " on " << rig.events[0].component;
  for (int i = 0; i < 3; ++i) EXPECT_EQ(rig.last.fault_class[i], "none");
}

TEST(PitchDiagnoser, AStuckPitchReadingHoldsTheBladeInsteadOfReadingASlowActuator) {
  // GIVEN healthy actuators and blade 1's pitch reading stuck at 5 deg (the benchmark's fault 1) from 60 s
  Rig rig(PitchDiagConfig{}, 0.2, 91);
  rig.run(300.0, healthy, [&](FrameSample& s) {
    if (s.t >= 60.0) s.pitch[0] = 5.0;
  });
  // THEN no actuator fault is raised, and the blade was held (counted) from about 60.2 s on
  EXPECT_TRUE(rig.events.empty()) << rig.events[0].fault << " on " << rig.events[0].component;
  EXPECT_GT(rig.diag.held(0), static_cast<uint64_t>(0.9 * 239.8 / 0.01));
  EXPECT_EQ(rig.diag.held(1), 0u);
}

TEST(PitchDiagnoser, ABladeWhosePitchSensorIsReportedIsHeldUntilTheReportClears) {
  // GIVEN a leak on blade 3 from 60 s, while sensor_bias reports pitch_sensor_3 from 55 s to 120 s
  Rig rig(PitchDiagConfig{}, 0.2, 92);
  const auto leak = [](double t, int b) {
    return b == 2 && t >= 60.0 ? table1("hydraulic_leakage") : table1("none");
  };
  rig.run(55.0, leak);
  InputContext suspect;
  suspect.pitch_sensor_suspect[2] = true;
  rig.diag.set_context(suspect, rig.t);
  rig.run(120.0, leak);
  // THEN nothing is raised while the reading is suspect
  EXPECT_TRUE(rig.events.empty()) << rig.events[0].fault << " at " << rig.events[0].t;
  // WHEN the report clears THEN the leak is raised after the context hold (10 s) and hold_settle (10 s)
  rig.diag.set_context(InputContext{}, rig.t);
  rig.run(160.0, leak);
  ASSERT_FALSE(rig.events.empty());
  EXPECT_EQ(rig.events[0].fault, "hydraulic_leakage");
  EXPECT_EQ(rig.events[0].component, "pitch_actuator_3");
  EXPECT_GE(rig.events[0].t, 140.0);
}

TEST(PitchDiagnoser, NothingIsConfirmedWhileSettlingAfterAStartOnAFaultyActuator) {
  // GIVEN pitch_diag started on a turbine whose blade 2 has already lost air (a restart on a running turbine)
  Rig rig(PitchDiagConfig{}, 0.2, 93);
  const auto air = [](double, int b) { return b == 1 ? table1("high_air_content") : table1("none"); };
  rig.run(30.0, air);
  // THEN nothing for startup_settle (30 s) ...
  EXPECT_TRUE(rig.events.empty()) << rig.events[0].fault << " at " << rig.events[0].t;
  // ... and the fault once it has settled
  rig.run(45.0, air);
  ASSERT_FALSE(rig.events.empty());
  EXPECT_EQ(rig.events[0].fault, "high_air_content");
}

TEST(PitchDiagnoser, BadSamplesAreCountedAndDoNotChangeTheEstimate) {
  Rig rig(PitchDiagConfig{}, 0.2, 9);
  rig.run(30.0, healthy);
  const Theta before = rig.diag.blade(0).identifier().theta();
  // GIVEN 5 NaN pitch samples, 3 infinite references and 2 out-of-range (96 deg) pitches on blade 1
  int k = 0;
  rig.run(30.1, healthy, [&](FrameSample& s) {
    if (k < 5)
      s.pitch[0] = kNaN;
    else if (k < 8)
      s.pitch_ref[0] = INFINITY;
    else if (k < 10)
      s.pitch[0] = 96.0;
    ++k;
  });
  // THEN all 10 are counted, only on blade 1, and the estimate did not move (exactly)
  EXPECT_EQ(rig.diag.rejected(0), 10u);
  EXPECT_EQ(rig.diag.rejected(1), 0u);
  EXPECT_EQ(rig.diag.rejected(), 10u);
  EXPECT_EQ(rig.diag.blade(0).identifier().theta(), before);
  // AND identification resumes afterwards without an event
  rig.run(60.0, healthy);
  EXPECT_TRUE(rig.events.empty());
  EXPECT_EQ(rig.last.fault_class[0], "none");
}

TEST(PitchDiagnoser, SequenceGapRestartsTheRegressor) {
  Rig rig(PitchDiagConfig{}, 0.2, 13);
  rig.run(20.0, healthy);
  // GIVEN 50 lost samples (the sequence jumps)
  rig.seq += 50;
  rig.run(60.0, healthy);
  // THEN the gap is counted once and nothing is raised
  EXPECT_EQ(rig.diag.gaps(), 1u);
  EXPECT_TRUE(rig.events.empty());
}

TEST(PitchDiagnoser, LowExcitationHoldsTheEstimateFlagged) {
  // GIVEN an identified high-air-content fault on blade 1 ...
  PitchDiagConfig cfg;
  Rig rig(cfg, 0.2, 21);
  const auto fault = [](double, int b) { return b == 0 ? table1("high_air_content") : table1("none"); };
  rig.run(40.0, fault);
  ASSERT_TRUE(rig.last.excited[0]);
  ASSERT_EQ(rig.last.fault_class[0], "high_air_content");
  // WHEN the reference then stands still at 12 deg (no turbulence: only the measured noise moves)
  const auto still = [](FrameSample& s) {
    for (int i = 0; i < 3; ++i) s.pitch_ref[i] = 12.0;
  };
  rig.run(70.0, fault, still);
  // THEN after the eq 20 window the blades are flagged not excited ...
  EXPECT_FALSE(rig.last.excited[0]);
  EXPECT_FALSE(rig.last.excited[1]);
  const double held = rig.last.omega_n[0];
  // ... and the estimate is held exactly while it stays so, still high air content, with no event
  rig.run(150.0, fault, still);
  EXPECT_FALSE(rig.last.excited[0]);
  EXPECT_EQ(rig.last.omega_n[0], held);
  EXPECT_EQ(rig.last.fault_class[0], "high_air_content");
  EXPECT_NEAR(held, 5.73, 0.05 * 5.73);
}

TEST(PitchDiagnoser, RaisesAfterConfirmationAndClearsWithHysteresis) {
  // GIVEN pump wear on blade 3 from 30 s to 60 s, then healthy again
  PitchDiagConfig cfg;
  Rig rig(cfg, 0.2, 33);
  const auto truth = [](double t, int b) {
    return b == 2 && t >= 30.0 && t < 60.0 ? table1("pump_wear") : table1("none");
  };
  rig.run(60.0, truth);
  // THEN pump wear is raised (after confirm_time of settled data) ...
  ASSERT_EQ(rig.events.size(), 1u);
  EXPECT_EQ(rig.events[0].fault, "pump_wear");
  EXPECT_GE(rig.events[0].t - rig.events[0].t_detected, cfg.confirm_time - 1e-9);
  // ... still raised until clear_time has passed below alpha_clear ...
  rig.run(60.0 + cfg.clear_time, truth);
  EXPECT_EQ(rig.events.size(), 1u);
  // ... and cleared within clear_time + 10 s of the repair
  rig.run(60.0 + cfg.clear_time + 10.0, truth);
  ASSERT_EQ(rig.events.size(), 2u);
  EXPECT_FALSE(rig.events[1].raised);
  EXPECT_EQ(rig.events[1].fault, "pump_wear");
  EXPECT_EQ(rig.events[1].component, "pitch_actuator_3");
}

// ---------------------------------------------------------------------------------------------------------
// Configuration

YamlSection yaml(const std::string& text) { return YamlSection(YAML::Load(text), "test.yaml"); }

// The 6 MW example's healthy pitch actuator (9 rad/s, 0.65, 8 deg/s): its turbine, the synthetic blades'
// profile with its rate limit, and its healthy signature as the truth of every blade.
struct SlowActuator {
  TurbineParams turbine;
  synth::SyntheticConfig profile;
  SlowActuator() {
    turbine.pitch_omega_n = 9.0;
    turbine.pitch_zeta = 0.65;
    turbine.pitch_rate_limit = 8.0;
    profile.rate_limit = turbine.pitch_rate_limit;
  }
  Signature healthy(double, int) const {
    return Signature{"none", turbine.pitch_omega_n, turbine.pitch_zeta};
  }
};

TEST(PitchDiagnoser, AHealthyActuatorAtItsTurbinesRateLimitIsNoFault) {
  // GIVEN a turbine whose healthy actuator (9 rad/s, 0.65) runs into its 8 deg/s rate limit when the
  // reference steps by 4.5 deg (a controller's answer to a speed sensor coming back), every 15 s on top of
  // the slow swing and turbulence, and the shipped configuration loaded for that turbine
  const SlowActuator slow;
  const TurbineParams& turbine = slow.turbine;
  const synth::SyntheticConfig& profile = slow.profile;
  const YamlSection shipped = YamlSection::load_file(PITCH_DIAG_YAML);
  const auto own = [&](double t, int b) { return slow.healthy(t, b); };
  const auto steps = [](FrameSample& s) {
    const double jump = std::fmod(s.t, 30.0) < 15.0 ? 0.0 : 4.5;
    for (int i = 0; i < 3; ++i) s.pitch_ref[i] += jump;
  };
  int with_limit = 0, without = 0;
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    // WHEN ten minutes are judged with the bank's models saturating at the turbine's rate limit, and without
    Rig limited(load_pitch_diag_config(shipped, turbine), profile, seed);
    limited.run(600.0, own, steps);
    PitchDiagConfig linear_config = load_pitch_diag_config(shipped, turbine);
    linear_config.pitch_rate_limit = std::numeric_limits<double>::infinity();
    Rig linear(linear_config, profile, seed);
    linear.run(600.0, own, steps);
    for (const auto& e : limited.events) with_limit += e.raised;
    for (const auto& e : linear.events) without += e.raised;
  }
  std::printf(
      "[ measured ] 8 deg/s actuator, 30 min of 4.5 deg reference steps: %d raises with its rate limit, "
      "%d with linear models\n",
      with_limit, without);
  // THEN nothing is raised, where the linear models read the rate-limited ramps as a slow actuator
  EXPECT_EQ(with_limit, 0);
  EXPECT_GT(without, 0);
}

TEST(PitchDiagnoser, APitchMovedThroughAContextHoldIsNoActuatorFault) {
  // GIVEN the 6 MW example's healthy actuator (9 rad/s, 0.65, 8 deg/s) on a reference with little fast
  // content (0.3 deg at 0.1-0.3 Hz on a slow swing about 20 deg) and, every 120 s, the judged suite set 200
  // episode: the reference jumps 7 deg in a second (the controller's answer to a generator-speed reading 14 %
  // high), then ramps down at 0.6 deg/s for 30 s (degraded mode), and back; a second after the jump the
  // context changes (sensor_bias's report, the arbiter's reconfiguration) and every blade is held for
  // context_hold
  const SlowActuator slow;
  const TurbineParams& turbine = slow.turbine;
  const YamlSection shipped = YamlSection::load_file(PITCH_DIAG_YAML);
  synth::SyntheticConfig profile = slow.profile;
  profile.level_mean = 20.0;
  profile.level_amp = 3.0;
  profile.turb_std = 0.3;
  profile.f_lo = 0.1;
  profile.f_hi = 0.3;
  const auto own = [&](double t, int b) { return slow.healthy(t, b); };
  const double period = 120.0, first = 100.0;
  const auto episode = [&](FrameSample& s) {
    const double into = s.t < first ? -1.0 : std::fmod(s.t - first, period);
    double shape = 0.0;  // deg added to every blade's reference
    if (into >= 0.0 && into < 1.0) shape = 7.0 * into;
    if (into >= 1.0 && into < 31.0) shape = 7.0 - 0.6 * (into - 1.0);
    if (into >= 31.0 && into < 61.0) shape = -11.0 * (1.0 - (into - 31.0) / 30.0);
    for (int i = 0; i < 3; ++i) s.pitch_ref[i] += shape;
  };
  auto raises = [&](bool hold_level_restart, uint64_t seed) {
    PitchDiagConfig config = load_pitch_diag_config(shipped, turbine);
    config.hold_level_restart = hold_level_restart;
    Rig rig(config, profile, seed);
    InputContext context;
    for (double jump = first; jump < 1300.0; jump += period) {
      rig.run(jump + 1.0, own, episode);
      ++context.transitions;
      rig.diag.set_context(context, rig.t);
    }
    rig.run(1300.0, own, episode);
    int n = 0;
    for (const auto& e : rig.events) n += e.raised;
    return n;
  };
  int before = 0, now = 0;
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    // WHEN the level removal runs on through the hold as if the held stretch were one step (before stop 62)
    before += raises(false, seed);
    // WHEN it starts again after the hold with its level fit (the default)
    now += raises(true, seed);
  }
  std::printf("[ measured ] 30 holds after the pitch jumped: %d raises before, %d now\n", before, now);
  // THEN healthy actuators were raised before, and nothing is now
  EXPECT_GT(before, 0) << "the hold no longer misleads the bank: this test no longer tests";
  EXPECT_EQ(now, 0);
}

TEST(PitchDiagConfig, DefaultsAndShippedFileLoad) {
  // GIVEN an empty section THEN the defaults: bank, lambda 0.97, p 8, Table 1
  const PitchDiagConfig c = load_pitch_diag_config(yaml("{}"));
  EXPECT_EQ(c.identifier.method, Method::kBank);
  EXPECT_EQ(c.identifier.p, 8);
  EXPECT_DOUBLE_EQ(c.identifier.lambda, 0.97);
  EXPECT_EQ(c.classifier.signatures.size(), 4u);
  // AND the shipped deploy/config/pitch_diag.yaml loads and equals the defaults where it restates them
  const PitchDiagConfig f = load_pitch_diag_config(YamlSection::load_file(PITCH_DIAG_YAML));
  EXPECT_EQ(f.identifier.method, c.identifier.method);
  EXPECT_DOUBLE_EQ(f.identifier.bank_lambda, c.identifier.bank_lambda);
  EXPECT_DOUBLE_EQ(f.confirm_time, c.confirm_time);
  EXPECT_EQ(f.classifier.signatures[2].name, "hydraulic_leakage");
  EXPECT_DOUBLE_EQ(f.identifier.information_min, c.identifier.information_min);
  EXPECT_DOUBLE_EQ(f.identifier.information_ref, c.identifier.information_ref);
  EXPECT_DOUBLE_EQ(f.identifier.evidence_max, c.identifier.evidence_max);
  EXPECT_DOUBLE_EQ(f.past_short_evidence, c.past_short_evidence);
  EXPECT_DOUBLE_EQ(f.recede_share, c.recede_share);
  EXPECT_EQ(f.clear_refuted_once, c.clear_refuted_once);
}

TEST(PitchDiagConfig, RejectsUnknownKeysAndOutOfRangeValues) {
  // GIVEN a typo, a value out of range, a bad method and a bad signature list THEN each is a ConfigError
  EXPECT_THROW(load_pitch_diag_config(yaml("confirm_tme: 3")), ConfigError);
  EXPECT_THROW(load_pitch_diag_config(yaml("lambda: 1.5")), ConfigError);
  EXPECT_THROW(load_pitch_diag_config(yaml("information_ref: -0.01")), ConfigError);
  EXPECT_THROW(load_pitch_diag_config(yaml("recede_share: 1.5")), ConfigError);
  EXPECT_THROW(load_pitch_diag_config(yaml("evidence_max: -1")), ConfigError);
  EXPECT_THROW(load_pitch_diag_config(yaml("p: 2.5")), ConfigError);
  EXPECT_THROW(load_pitch_diag_config(yaml("method: kalman")), ConfigError);
  EXPECT_THROW(load_pitch_diag_config(yaml("signatures: [{name: pump_wear, omega_n: 7, zeta: 0.7}]")),
               ConfigError);
  EXPECT_THROW(load_pitch_diag_config(yaml("signatures: [{name: none, omega_n: 11, zeta: 0.6, x: 1}]")),
               ConfigError);
  EXPECT_THROW(load_pitch_diag_config(yaml("evidence_min: -1")), ConfigError);
  EXPECT_THROW(load_pitch_diag_config(yaml("evidence_min: 2e4")), ConfigError);
  EXPECT_THROW(load_pitch_diag_config(yaml("bank_pe_gate: maybe")), ConfigError);
  // AND a valid override is taken, and the bank's "none" test follows alpha_detect
  EXPECT_EQ(load_pitch_diag_config(yaml("method: paper_mifg\np: 16")).identifier.p, 16);
  const auto g = load_pitch_diag_config(yaml("evidence_min: 9\nbank_pe_gate: true\nalpha_detect: 0.3"));
  EXPECT_DOUBLE_EQ(g.identifier.evidence_min, 9.0);
  EXPECT_TRUE(g.identifier.bank_pe_gate);
  EXPECT_DOUBLE_EQ(g.identifier.decide_alpha, 0.3);
}

}  // namespace
