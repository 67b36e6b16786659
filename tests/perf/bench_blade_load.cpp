// blade_load kernel throughput: harmonic least-squares update (eq 7, recursive add/drop) per blade-sample, d
// = 4.
#include <benchmark/benchmark.h>

#include <cmath>

#include "harmonic_ls.hpp"

using namespace windfdi::blade_load;

// Update only (the service solves at 10 Hz, not per sample).
static void BM_UpdateOnly(benchmark::State& state) {
  HarmonicConfig c;
  c.harmonics = static_cast<int>(state.range(0));
  HarmonicEstimator est(c);
  double psi = 0.0;
  for (auto _ : state) {
    psi = std::fmod(psi + 0.015, 2 * M_PI);
    est.update(5e6 + 1e6 * std::cos(psi), psi, 1.5);
  }
  state.counters["blade_samples_per_s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_UpdateOnly)->Arg(4);

// Worst case: update and solve (SDD Gauss-Seidel) on every sample.
static void BM_UpdateAndSolve(benchmark::State& state) {
  HarmonicConfig c;
  c.harmonics = static_cast<int>(state.range(0));
  HarmonicEstimator est(c);
  double psi = 0.0;
  for (int k = 0; k < 1000; ++k) {
    psi = std::fmod(psi + 0.015, 2 * M_PI);
    est.update(5e6 + 1e6 * std::cos(psi), psi, 1.5);
  }
  for (auto _ : state) {
    psi = std::fmod(psi + 0.015, 2 * M_PI);
    est.update(5e6 + 1e6 * std::cos(psi), psi, 1.5);
    benchmark::DoNotOptimize(est.solve().valid);
  }
  state.counters["blade_samples_per_s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_UpdateAndSolve)->Arg(4);

BENCHMARK_MAIN();
