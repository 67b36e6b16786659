// Measures windfdi-pitch-diag on pitch references of another kind than the plant's: a closed-loop reference
// with slow swings of several degrees and little fast content, 0.2 deg pitch noise. Per Table 1 fault: runs
// whose first event is the right class on the right blade, the delay from the onset and from the moment the
// data first carry the fault (an oracle's 5 sigma), and false events on healthy files (also in their first
// 5 s). Usage: pitch_diag_slow_swing [seeds_per_blade=2] [healthy_seconds=600]; PITCH_DIAG_CONFIG=file reads
// the diagnoser from that pitch_diag YAML section instead of the defaults; VERBOSE=1 lists every run;
// TRACE=seed prints that run's bank state (information, evidence, class, alpha) every 0.5 s from 5 s before
// the onset.
#include <algorithm>
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

struct Profile {
  const char* name;
  synth::SyntheticConfig cfg;
};

std::vector<Profile> profiles() {
  std::vector<Profile> out;
  synth::SyntheticConfig c;  // 0.2 deg noise, 10 deg/s rate limit, 100 Hz
  // Slow swings of several degrees, a little fast content.
  c.turb_std = 3.0, c.f_lo = 0.02, c.f_hi = 0.2;
  c.fast_std = 0.1, c.fast_lo = 0.2, c.fast_hi = 1.0;
  out.push_back({"swing 3 deg 0.02-0.2 Hz + 0.1 deg fast", c});
  // Slower and larger, even less fast content.
  c.turb_std = 5.0, c.f_lo = 0.01, c.f_hi = 0.1, c.fast_std = 0.05;
  out.push_back({"swing 5 deg 0.01-0.1 Hz + 0.05 deg fast", c});
  // Smaller, a little quicker, no fast content at all.
  c.turb_std = 2.0, c.f_lo = 0.05, c.f_hi = 0.3, c.fast_std = 0.0;
  out.push_back({"swing 2 deg 0.05-0.3 Hz, no fast", c});
  // The plant-like reference of compare_methods (1.5 deg of 0.05-1 Hz over a 2-20 deg level): unchanged?
  out.push_back({"plant-like 1.5 deg 0.05-1 Hz", synth::SyntheticConfig{}});
  return out;
}

struct Run {
  bool right_first = false;
  double delay = NAN;        // onset to the right first event
  double information = NAN;  // onset to the oracle's expected 5 sigma
  double oracle = NAN;       // onset to its realised 5 sigma (on the noisy measurement)
  std::string first;         // first event, "" when none
  int false_events = 0, early_false = 0;
};

// One file: `fault` on blade `fb` from t_on on ("none": healthy). The oracle drives a healthy and a faulty
// actuator from the onset with the recorded reference, as pitch_diag_plant does.
Run run(const PitchDiagConfig& cfg, synth::SyntheticConfig sc, const std::string& fault, int fb, double t_on,
        double t_end, uint64_t seed) {
  std::vector<synth::SyntheticBlade> blades;
  for (int i = 0; i < 3; ++i) {
    sc.seed = seed * 10 + static_cast<uint64_t>(i);
    blades.emplace_back(sc);
  }
  synth::SyntheticConfig quiet = sc;
  quiet.noise = 0.0;
  synth::SyntheticBlade oracle_h(quiet), oracle_f(quiet);
  bool oracle_started = false;
  double evidence = 0.0, realised = 0.0;
  const Signature& h = synth::table1("none");
  const Signature& f = synth::table1(fault);
  PitchDiagnoser d(cfg);
  std::vector<FaultEvent> ev;
  FrameSample s;
  Run r;
  const long n = std::lround(t_end / sc.T);
  for (long k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) * sc.T;
    s.sequence = static_cast<uint64_t>(k);
    s.t = t;
    double wn[3], z[3];
    for (int i = 0; i < 3; ++i) {
      s.pitch_ref[i] = blades[i].reference(t);
      s.pitch[i] = blades[i].measure();
      const bool faulty = i == fb && t >= t_on;
      wn[i] = faulty ? f.omega_n : h.omega_n;
      z[i] = faulty ? f.zeta : h.zeta;
    }
    ev.clear();
    d.update(s, false, ev);
    for (const auto& e : ev) {
      if (!e.raised) continue;
      const bool right = fb >= 0 && t >= t_on && e.component == "pitch_actuator_" + std::to_string(fb + 1) &&
                         e.fault == fault;
      if (r.first.empty()) {
        r.first = e.component + " " + e.fault;
        r.right_first = right;
        if (right) r.delay = t - t_on;
      }
      if (!right) {
        ++r.false_events;
        if (t < 5.0) ++r.early_false;
      }
    }
    if (fb >= 0 && t >= t_on && (std::isnan(r.information) || std::isnan(r.oracle))) {
      if (!oracle_started) {
        // Both from the true actuator's state at the onset: only the dynamics after it differ.
        oracle_h.set_state(blades[fb].angle(), blades[fb].rate());
        oracle_f.set_state(blades[fb].angle(), blades[fb].rate());
        oracle_started = true;
      }
      // Expected: the summed squared difference of the two models. Realised: the same two models against this
      // sample's noisy measurement, the log-likelihood ratio (times 2) a detector knowing both models and the
      // onset would see; the bank's evidence() is the same quantity.
      const double y = s.pitch[static_cast<std::size_t>(fb)];
      evidence += std::pow((oracle_h.angle() - oracle_f.angle()) / sc.noise, 2);
      realised +=
          (std::pow(y - oracle_h.angle(), 2) - std::pow(y - oracle_f.angle(), 2)) / std::pow(sc.noise, 2);
      if (evidence >= 25.0 && std::isnan(r.information)) r.information = t - t_on;
      if (realised >= 25.0 && std::isnan(r.oracle)) r.oracle = t - t_on;
      const double u = s.pitch_ref[static_cast<std::size_t>(fb)];
      oracle_h.step(u, h.omega_n, h.zeta);
      oracle_f.step(u, f.omega_n, f.zeta);
    }
    static const long trace = std::getenv("TRACE") ? std::atol(std::getenv("TRACE")) : -1;
    if (static_cast<long>(seed) == trace && fb >= 0 && k % 50 == 0 && t >= t_on - 5.0) {
      const auto& b = d.blade(fb);
      const auto& id = b.identifier();
      std::printf("  t %6.1f exc %d dec %d w %.2f info %.5f ev %7.1f class %-18s alpha %.2f wn %.2f z %.3f\n",
                  t - t_on, id.excited(), id.decisive(), id.information_weight(), id.information(),
                  id.evidence(), b.classification().fault_class.c_str(), b.classification().alpha,
                  b.model().omega_n, b.model().zeta);
    }
    for (int i = 0; i < 3; ++i) blades[i].step(s.pitch_ref[i], wn[i], z[i]);
  }
  return r;
}

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

}  // namespace

int main(int argc, char** argv) {
  const int seeds = argc > 1 ? std::max(1, std::atoi(argv[1])) : 2;
  const double healthy_time = argc > 2 ? std::atof(argv[2]) : 600.0;
  PitchDiagConfig cfg;
  if (const char* file = std::getenv("PITCH_DIAG_CONFIG"))
    cfg = load_pitch_diag_config(YamlSection(YAML::LoadFile(file), file));
  const bool verbose = std::getenv("VERBOSE") != nullptr;
  const double t_on = 60.0, t_end = 120.0;  // onset after the 30 s start-up settle and 30 s healthy
  std::printf("%-42s %-18s | %5s %6s %6s %6s | %6s %6s %6s | %s\n", "profile", "fault", "right", "<=10s",
              "med_s", "max_s", "info_s", "<=10si", "orc_s", "false / healthy");
  for (const auto& prof : profiles()) {
    int healthy_false = 0, healthy_early = 0;
    for (int k = 0; k < 5; ++k) {
      const Run r = run(cfg, prof.cfg, "none", -1, 0.0, healthy_time, 900 + static_cast<uint64_t>(k));
      healthy_false += r.false_events;
      healthy_early += r.early_false;
    }
    uint64_t seed = 500;
    for (const char* fault : {"pump_wear", "hydraulic_leakage", "high_air_content"}) {
      int right = 0, runs = 0, within = 0, within_info = 0;
      std::vector<double> delays, infos, oracles;
      for (int b = 0; b < 3; ++b)
        for (int k = 0; k < seeds; ++k) {
          const Run r = run(cfg, prof.cfg, fault, b, t_on, t_end, ++seed);
          ++runs;
          right += r.right_first;
          if (r.right_first) delays.push_back(r.delay);
          within += r.right_first && r.delay <= 10.0;
          within_info += r.right_first && r.delay - r.information <= 10.0;
          infos.push_back(std::isnan(r.information) ? 1e9 : r.information);
          oracles.push_back(std::isnan(r.oracle) ? 1e9 : r.oracle);
          if (verbose)
            std::printf(
                "    %s blade %d seed %lu: first '%s' delay %.1f s, information %.1f s, oracle %.1f s\n",
                fault, b + 1, static_cast<unsigned long>(seed), r.first.c_str(), r.delay, r.information,
                r.oracle);
        }
      std::printf(
          "%-42s %-18s | %2d/%-2d %6d %6.1f %6.1f | %6.1f %6d %6.1f | %d (%d in the first 5 s) in 5 x %.0f "
          "s\n",
          prof.name, fault, right, runs, within, median(delays),
          delays.empty() ? NAN : *std::max_element(delays.begin(), delays.end()), median(infos), within_info,
          median(oracles), healthy_false, healthy_early, healthy_time);
      std::fflush(stdout);
    }
  }
}
