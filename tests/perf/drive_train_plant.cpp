// Measures windfdi-drive-train against the benchmark's converter torque offset and drive-train efficiency
// loss on the two-mass plant in turbulent wind (12 %), fed sample by sample as the service feeds it: false
// alarms in healthy hours, delay and size of a 100 N m torque offset, delay and estimate of a 0.97 -> 0.92
// efficiency. Usage: drive_train_plant [healthy_hours_per_wind=10] [seeds=3] [--config FILE] [--turbine FILE]
// [--events] [--seed-offset N]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "drive_train_diagnoser.hpp"
#include "plant_measurement_args.hpp"
#include "turbine_sim.hpp"

using namespace windfdi;
using namespace windfdi::drive_train;

namespace {

constexpr double kDt = 0.01;  // s, 100 Hz
const double kWinds[] = {8.0, 12.0, 16.0, 20.0};
bool print_events = false;  // --events: every run's events
uint64_t seed_offset = 0;   // --seed-offset: added to every run's seed

struct Run {
  std::vector<FaultEvent> events;
  double efficiency_at = kNaN;  // the efficiency estimate at `probe` s
};

Run run(const DiagnoserConfig& cfg, const TurbineParams& p, double wind, double seconds,
        const std::vector<plant::FaultSpec>& faults, uint64_t seed, double probe = -1.0) {
  plant::TurbineScenario t;
  t.id = "WT01";
  t.wind.mean = wind;
  t.wind.turbulence_intensity = 0.12;
  plant::TurbineSim sim(p, t, faults, seed + seed_offset, 1.0 / kDt);
  const AeroModel aero(p);
  DriveTrainDiagnoser d(cfg, aero);
  Run r;
  DriveTrainOutput o;
  const long n = std::lround(seconds / kDt);
  for (long k = 0; k < n; ++k) {
    const FrameSample& s = sim.step();
    d.update(s, false, r.events);
    if (d.estimate_due(o) && probe >= 0.0 && std::isnan(r.efficiency_at) && o.t >= probe)
      r.efficiency_at = o.efficiency;
  }
  if (print_events)
    for (const auto& e : r.events)
      std::printf("  wind %.0f seed %lu: %.2f %s %s %s\n", wind, static_cast<unsigned long>(seed), e.t,
                  e.fault.c_str(), e.raised ? "raised" : "cleared", e.detail.c_str());
  return r;
}

// The first raise of `fault` at or after `after`, or nullptr; `early`: raises of it before `after`.
const FaultEvent* first_raise(const Run& r, const std::string& fault, double after, int* early = nullptr) {
  for (const auto& e : r.events) {
    if (!e.raised || e.fault != fault) continue;
    if (e.t >= after) return &e;
    if (early) ++*early;
  }
  return nullptr;
}

// "median / max" of the finite values (the missed ones counted apart).
std::string med_max(std::vector<double> v, const char* format) {
  std::vector<double> ok;
  for (double x : v)
    if (std::isfinite(x)) ok.push_back(x);
  if (ok.empty()) return "-";
  std::sort(ok.begin(), ok.end());
  char a[32], b[32], out[80];
  std::snprintf(a, sizeof a, format, ok[(ok.size() - 1) / 2]);
  std::snprintf(b, sizeof b, format, ok.back());
  std::snprintf(out, sizeof out, "%s / %s", a, b);
  return out;
}

// Median and maximum of |x| (an error's size).
std::string abs_med_max(const std::vector<double>& v, const char* format) {
  std::vector<double> a;
  for (double x : v) a.push_back(std::fabs(x));
  return med_max(a, format);
}

}  // namespace

int main(int argc, char** argv) {
  const auto args = perf::parse_plant_measurement_args(argc, argv, 10.0, 3);
  const double hours = args.first;
  const int seeds = args.seeds;
  print_events = args.print_events;
  seed_offset = args.seed_offset;
  const TurbineParams p = args.turbine();
  const DiagnoserConfig cfg = load_diagnoser_config(args.config(), p);

  std::printf(
      "drive_train on the two-mass plant, 12 %% turbulence, benchmark noise, 100 Hz; %.3g healthy h per wind "
      "(1 h runs), %d seeds per fault and wind\n\n",
      hours, seeds);
  std::printf(
      "| wind m/s | false torque_offset | false efficiency_loss | torque_offset delay s (samples), median / "
      "max | torque_offset size error N m, median / max | missed (early) | efficiency_loss delay s, median / "
      "max | efficiency error 90 s after onset, median / max | missed (early) |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  std::vector<double> all_offset_delay, all_offset_size, all_eff_delay, all_eff_error;
  int all_false_offset = 0, all_false_eff = 0, all_offset_missed = 0, all_eff_missed = 0,
      all_offset_early = 0, all_eff_early = 0;
  for (const double wind : kWinds) {
    // (a) Healthy hours: every raise is a false alarm.
    int false_offset = 0, false_eff = 0;
    for (int h = 0; h * 1.0 < hours; ++h) {
      const double seconds = std::min(3600.0, (hours - h) * 3600.0);
      const Run r = run(cfg, p, wind, seconds, {}, 1000 + 100 * static_cast<uint64_t>(wind) + h);
      for (const auto& e : r.events) {
        false_offset += e.raised && e.fault == "torque_offset";
        false_eff += e.raised && e.fault == "efficiency_loss";
      }
    }
    // (b) A 100 N m converter offset at a random time after the noise is learned; (c) the efficiency step
    // at a random time after the balance's reference is full.
    std::vector<double> offset_delay, offset_samples, offset_size, eff_delay, eff_error;
    int offset_missed = 0, eff_missed = 0, offset_early = 0, eff_early = 0;
    for (int s = 0; s < seeds; ++s) {
      const uint64_t seed = 2000 + 100 * static_cast<uint64_t>(wind) + static_cast<uint64_t>(s);
      std::mt19937_64 rng(seed + seed_offset);
      const double onset = std::round(std::uniform_real_distribution<double>(120.0, 600.0)(rng) / kDt) * kDt;
      const auto f = plant::FaultSpec::make("WT01", "converter", "torque_offset", onset).with_value(100.0);
      const Run r = run(cfg, p, wind, onset + 30.0, {f}, seed);
      const FaultEvent* e = first_raise(r, "torque_offset", onset - 1e-9, &offset_early);
      if (e) {
        offset_delay.push_back(e->t - onset);
        offset_samples.push_back(std::round((e->t - onset) / kDt));
        offset_size.push_back(e->size - 100.0);
      } else {
        ++offset_missed;
      }

      const double eff_onset =
          std::round(std::uniform_real_distribution<double>(300.0, 900.0)(rng) / kDt) * kDt;
      const auto g = plant::FaultSpec::make("WT01", "drive_train", "efficiency", eff_onset).with_value(0.92);
      const Run q = run(cfg, p, wind, eff_onset + 120.0, {g}, seed + 50, eff_onset + 90.0);
      const FaultEvent* x = first_raise(q, "efficiency_loss", eff_onset - 1e-9, &eff_early);
      if (x) {
        eff_delay.push_back(x->t - eff_onset);
      } else {
        ++eff_missed;
      }
      eff_error.push_back(q.efficiency_at - 0.92);
    }
    std::printf("| %.0f | %d | %d | %s (%s) | %s | %d of %d (%d) | %s | %s | %d of %d (%d) |\n", wind,
                false_offset, false_eff, med_max(offset_delay, "%.2f").c_str(),
                med_max(offset_samples, "%.0f").c_str(), abs_med_max(offset_size, "%.1f").c_str(),
                offset_missed, seeds, offset_early, med_max(eff_delay, "%.1f").c_str(),
                abs_med_max(eff_error, "%.4f").c_str(), eff_missed, seeds, eff_early);
    all_offset_delay.insert(all_offset_delay.end(), offset_delay.begin(), offset_delay.end());
    all_offset_size.insert(all_offset_size.end(), offset_size.begin(), offset_size.end());
    all_eff_delay.insert(all_eff_delay.end(), eff_delay.begin(), eff_delay.end());
    all_eff_error.insert(all_eff_error.end(), eff_error.begin(), eff_error.end());
    all_false_offset += false_offset, all_false_eff += false_eff;
    all_offset_missed += offset_missed, all_eff_missed += eff_missed;
    all_offset_early += offset_early, all_eff_early += eff_early;
  }
  std::vector<double> all_samples;
  for (double d : all_offset_delay) all_samples.push_back(std::round(d / kDt));
  const int runs = seeds * 4;
  std::printf("| all | %d | %d | %s (%s) | %s | %d of %d (%d) | %s | %s | %d of %d (%d) |\n",
              all_false_offset, all_false_eff, med_max(all_offset_delay, "%.2f").c_str(),
              med_max(all_samples, "%.0f").c_str(), abs_med_max(all_offset_size, "%.1f").c_str(),
              all_offset_missed, runs, all_offset_early, med_max(all_eff_delay, "%.1f").c_str(),
              abs_med_max(all_eff_error, "%.4f").c_str(), all_eff_missed, runs, all_eff_early);
  std::printf(
      "| benchmark requirement | not given | not given | not given | not given | not given | not given | not "
      "given | not given |\n");
  std::printf(
      "\nFalse alarms: raises in %.3g healthy h per wind. Early: raises before the onset in the fault runs. "
      "Delay: first raise at or after the onset (samples after the first faulty one). Size and efficiency "
      "errors: absolute. Requirements: docs/papers.md states none for the benchmark's faults 8 and 9.\n",
      hours);
  return 0;
}
