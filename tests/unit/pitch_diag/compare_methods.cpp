// Measures the Wu & Li identification methods on the same synthetic data: omega_n / zeta error,
// classification accuracy and detection delay per method and noise level (README.md of the core records it).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "pitch_diagnoser.hpp"
#include "synthetic_pitch.hpp"

using namespace windfdi;
using namespace windfdi::pitch_diag;

namespace {

struct Result {
  double se_w = 0, se_z = 0;
  int n_est = 0, invalid = 0;
  int ticks = 0, correct = 0;
  int detected = 0, wrong_first = 0, scenarios = 0;
  double delay_sum = 0, delay_max = 0;
  int false_events = 0;
};

// One turbine run: blade `fb` gets `fault` (abrupt, alpha 1) from t_on on; returns into r.
void run(const PitchDiagConfig& cfg, double noise, const std::string& fault, int fb, double t_on,
         double t_end, uint64_t seed, Result& r) {
  const auto sig = table1_signatures();
  std::vector<synth::SyntheticBlade> blades;
  for (int i = 0; i < 3; ++i) {
    synth::SyntheticConfig sc;
    sc.noise = noise;
    sc.seed = seed * 10 + i;
    blades.emplace_back(sc);
  }
  PitchDiagnoser d(cfg);
  std::vector<FaultEvent> ev;
  FrameSample s;
  bool first_seen = false;
  const long n = std::lround(t_end / 0.01);
  for (long k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) * 0.01;
    s.sequence = k;
    s.t = t;
    double wn[3], z[3];
    for (int i = 0; i < 3; ++i) {
      s.pitch_ref[i] = blades[i].reference(t);
      s.pitch[i] = blades[i].measure();
      wn[i] = sig[0].omega_n;
      z[i] = sig[0].zeta;
      if (i == fb && t >= t_on)
        for (const auto& g : sig)
          if (g.name == fault) wn[i] = g.omega_n, z[i] = g.zeta;
    }
    ev.clear();
    d.update(s, false, ev);
    for (const auto& e : ev) {
      if (!e.raised) continue;
      const bool right = fb >= 0 && e.component == "pitch_actuator_" + std::to_string(fb + 1) &&
                         e.fault == fault && t >= t_on;
      if (right && !first_seen) {
        ++r.detected;
        r.delay_sum += t - t_on;
        r.delay_max = std::max(r.delay_max, t - t_on);
      }
      if (!right) {
        ++r.false_events;
        if (!first_seen && fb >= 0) ++r.wrong_first;
      }
      first_seen = true;
    }
    PitchEstimate est;
    if (d.estimate_due(est) && t >= t_on + 10.0) {
      for (int i = 0; i < 3; ++i) {
        const std::string truth = (i == fb) ? fault : "none";
        ++r.ticks;
        r.correct += est.fault_class[i] == truth;
        if (!est.valid[i]) {
          ++r.invalid;
          continue;
        }
        r.se_w += std::pow(est.omega_n[i] / wn[i] - 1.0, 2);
        r.se_z += std::pow(est.zeta[i] / z[i] - 1.0, 2);
        ++r.n_est;
      }
    }
    for (int i = 0; i < 3; ++i) blades[i].step(s.pitch_ref[i], wn[i], z[i]);
  }
  if (fb >= 0) ++r.scenarios;
}

}  // namespace

int main(int argc, char** argv) {
  const double healthy_time = argc > 1 ? std::atof(argv[1]) : 600.0;
  std::printf("%-10s %5s | %8s %8s %7s | %8s | %6s %6s %8s %8s | %s\n", "method", "noise", "wn_rms%",
              "z_rms%", "inval%", "class%", "det", "wrong", "delay_s", "dmax_s", "false/healthy");
  for (Method m : {Method::kPaperMifg, Method::kPaperRls, Method::kAmMifg, Method::kAmRls, Method::kOeRls,
                   Method::kBank}) {
    for (double noise : {0.0, 0.2}) {
      PitchDiagConfig cfg;
      cfg.identifier.method = m;
      // Optional overrides for sweeps: PD_LAMBDA (rls_lambda and bank_lambda), PD_CONFIRM (confirm_time).
      if (const char* v = std::getenv("PD_LAMBDA"))
        cfg.identifier.rls_lambda = cfg.identifier.bank_lambda = std::atof(v);
      if (const char* v = std::getenv("PD_CONFIRM")) cfg.confirm_time = std::atof(v);
      if (const char* v = std::getenv("PD_METHOD"))
        if (std::string(v) != method_name(m)) continue;
      if (m == Method::kPaperMifg || m == Method::kPaperRls) {
        cfg.identifier.highpass_hz = 0.0;  // the paper's raw signals
        cfg.identifier.p0 = 1.0;
      }
      Result r;
      const char* faults[] = {"pump_wear", "hydraulic_leakage", "high_air_content"};
      uint64_t seed = 100;
      for (const char* f : faults)
        for (int b = 0; b < 3; ++b) run(cfg, noise, f, b, 60.0, 120.0, ++seed, r);
      Result h;
      run(cfg, noise, "none", -1, 0.0, healthy_time, 7, h);
      std::printf(
          "%-10s %5.2f | %8.2f %8.2f %7.1f | %8.1f | %3d/%-2d %6d %8.2f %8.2f | %d events in %.0f s\n",
          method_name(m), noise, 100 * std::sqrt(r.se_w / std::max(1, r.n_est)),
          100 * std::sqrt(r.se_z / std::max(1, r.n_est)), 100.0 * r.invalid / std::max(1, r.ticks),
          100.0 * r.correct / std::max(1, r.ticks), r.detected, r.scenarios, r.wrong_first,
          r.detected ? r.delay_sum / r.detected : NAN, r.delay_max, h.false_events, healthy_time);
      std::fflush(stdout);
    }
  }
}
