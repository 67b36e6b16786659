// ice_detect kernel throughput: inertia-estimator samples per second on one core (target >= 10 million).
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "inertia_estimator.hpp"

static void BM_InertiaEstimator(benchmark::State& state) {
  windfdi::ice_detect::EstimatorConfig c;
  windfdi::ice_detect::InertiaEstimator est(c);
  std::vector<double> omega(4096), power(4096), torque(4096);
  for (int i = 0; i < 4096; ++i) {
    omega[i] = 150.0 + 2.0 * std::sin(0.01 * i);
    power[i] = omega[i] * (37000.0 + 3000.0 * std::sin(0.013 * i));
    torque[i] = 30000.0 + 90.0 * std::cos(0.7 * i);
  }
  std::size_t i = 0;
  for (auto _ : state) {
    est.update(omega[i], power[i], torque[i]);
    i = (i + 1) & 4095;
  }
  benchmark::DoNotOptimize(est.inertia());
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_InertiaEstimator)->Repetitions(3)->ReportAggregatesOnly(true);

BENCHMARK_MAIN();
