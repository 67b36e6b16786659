// The value of the arbiter's fault-tolerant IPC: true blade loads when blade 2's root moment sensor
// fails (gain 1.1, stuck, intermittent, dead, gain 2) with IPC left on the strain gauges (no arbiter) versus
// switched to the LIDAR load model after a detection-and-reaction delay, and with IPC off. Loads: the true
// first-harmonic amplitude and a damage-equivalent load (rainflow, Woehler exponent 10 for glass-fibre
// blades, 1 Hz equivalent cycles). Medians over seeds. Usage: ipc_value [DELAY_S=5] [SEEDS=3]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "turbine_sim.hpp"

using namespace windfdi::plant;

namespace {

// Damage-equivalent load of a series: rainflow ranges (three-point algorithm on turning points), half
// cycles for the residue, DEL = (sum n_i S_i^m / N_eq)^(1/m).
double damage_equivalent_load(const std::vector<double>& x, double m, double n_eq) {
  std::vector<double> tp;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (tp.size() >= 2 && (x[i] - tp.back()) * (tp.back() - tp[tp.size() - 2]) >= 0)
      tp.back() = x[i];
    else if (tp.empty() || x[i] != tp.back())
      tp.push_back(x[i]);
  }
  std::vector<double> stack;
  double damage = 0.0;
  for (double p : tp) {
    stack.push_back(p);
    while (stack.size() >= 3) {
      const double r1 = std::fabs(stack[stack.size() - 2] - stack[stack.size() - 3]);
      const double r2 = std::fabs(stack.back() - stack[stack.size() - 2]);
      if (r2 < r1) break;
      if (stack.size() == 3) {
        damage += 0.5 * std::pow(r1, m);  // half cycle at the start of the residue
        stack.erase(stack.begin());
      } else {
        damage += std::pow(r1, m);
        stack.erase(stack.end() - 3, stack.end() - 1);
      }
    }
  }
  for (std::size_t i = 1; i < stack.size(); ++i)
    damage += 0.5 * std::pow(std::fabs(stack[i] - stack[i - 1]), m);
  return std::pow(damage / n_eq, 1.0 / m);
}

struct Loads {
  double a1 = 0, del = 0;  // blade 2 (the faulty sensor's blade), over the evaluation period
};

// The failures of blade 2's strain gauge that are compared: a gain error (the paper's abrupt fault), a gauge
// stuck at its reading (a broken bridge) and an intermittent contact.
struct SensorFailure {
  const char* name;
  const char* type;
  double gain;
};
const SensorFailure kFailures[] = {{"gain 1.1", "gain", 1.1},
                                   {"stuck", "stuck", 1.0},
                                   {"intermittent 1.3", "intermittent", 1.3},
                                   {"dead (reads 0)", "gain", 0.0},
                                   {"gain 2", "gain", 2.0}};

Loads run(const SensorFailure* fault, int policy, double delay, uint64_t seed) {
  // policy 0: IPC on the strain gauges throughout; 1: the arbiter switches IPC to the LIDAR model
  TurbineScenario t;
  t.id = "WT01";
  t.wind.mean = 16.0;
  t.wind.turbulence_intensity = 0.1;
  t.wind.shear_exponent = 0.25;
  std::vector<FaultSpec> faults;
  const double onset = 100.0;
  if (fault != nullptr) {
    auto f = FaultSpec::make("WT01", "blade_moment_2", fault->type, onset);
    f.gain = fault->gain;
    f.period = 20.0;
    f.duty = 0.3;
    faults.push_back(f);
  }
  TurbineSim sim(windfdi::TurbineParams{}, t, faults, seed, 100.0);
  std::vector<double> moment;
  double a1 = 0;
  int n = 0;
  for (int k = 0; k < 700 * 100; ++k) {
    ControlInput in;
    if (policy == 1 && k * 0.01 >= onset + delay) in.ipc_source = IpcSource::kLidarModel;
    if (policy == 2) in.ipc_source = IpcSource::kOff;
    sim.step(in);
    if (k * 0.01 < onset + 100.0) continue;  // evaluate once settled in the new configuration
    moment.push_back(sim.truth().blade_moment[1]);
    a1 += sim.truth().a1[1];
    ++n;
  }
  return {a1 / n, damage_equivalent_load(moment, 10.0, 500.0)};
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  const double delay = argc > 1 ? std::atof(argv[1]) : 5.0;
  const int seeds = argc > 2 ? std::atoi(argv[2]) : 3;
  const char* names[] = {"healthy sensor, IPC on strain gauges", "failed sensor, no arbiter (strain gauges)",
                         "failed sensor, arbiter -> LIDAR-model IPC", "failed sensor, IPC off"};
  std::printf(
      "blade 2 true loads, 16 m/s, shear 0.25, TI 0.1, blade 2's gauge fails at 100 s, switch after %.0f s, "
      "median of %d seeds (evaluated 200-700 s)\n",
      delay, seeds);
  for (const auto& failure : kFailures) {
    std::vector<double> a1[4], del[4];
    for (int s = 1; s <= seeds; ++s) {
      const Loads cases[] = {run(nullptr, 0, delay, s), run(&failure, 0, delay, s),
                             run(&failure, 1, delay, s), run(&failure, 2, delay, s)};
      for (int c = 0; c < 4; ++c) {
        a1[c].push_back(cases[c].a1);
        del[c].push_back(cases[c].del);
      }
    }
    std::printf("gauge failure: %s\n", failure.name);
    for (int c = 0; c < 4; ++c)
      std::printf("  %-44s 1P amplitude %7.0f kN m   DEL(m=10) %7.0f kN m   (%.2f / %.2f of healthy)\n",
                  names[c], median(a1[c]) / 1e3, median(del[c]) / 1e3, median(a1[c]) / median(a1[0]),
                  median(del[c]) / median(del[0]));
  }
  return 0;
}
