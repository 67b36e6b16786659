// Plant simulator speed: simulated seconds per wall second for one turbine on one core.
#include <benchmark/benchmark.h>

#include "turbine_sim.hpp"

using namespace windfdi::plant;

static void BM_TurbineStep(benchmark::State& state) {
  TurbineScenario t;
  t.id = "WT01";
  t.wind.mean = static_cast<double>(state.range(0));
  t.wind.turbulence_intensity = 0.1;
  TurbineSim sim(windfdi::TurbineParams{}, t, {}, 1, 100.0);
  for (auto _ : state) benchmark::DoNotOptimize(sim.step().generator_speed);
  // One step is 10 ms of simulated time.
  state.counters["x_real_time"] =
      benchmark::Counter(0.01 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_TurbineStep)->Arg(8)->Arg(16)->Repetitions(3)->ReportAggregatesOnly(true);

BENCHMARK_MAIN();
