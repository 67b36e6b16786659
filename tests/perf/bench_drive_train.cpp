// drive_train kernel throughput on recorded plant samples: samples per second on one core (target >= 10
// million).
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "aero_power_input.hpp"
#include "drive_train_diagnoser.hpp"
#include "turbine_sim.hpp"

using namespace windfdi;
using namespace windfdi::drive_train;

namespace {

constexpr std::size_t kSamples = 1 << 16;  // 655 s of the plant at 100 Hz

// A healthy turbine at 12 m/s in 12 % turbulence, recorded once per process.
const std::vector<FrameSample>& recording() {
  static const std::vector<FrameSample> samples = [] {
    plant::TurbineScenario t;
    t.id = "WT01";
    t.wind.mean = 12.0;
    t.wind.turbulence_intensity = 0.12;
    plant::TurbineSim sim(TurbineParams{}, t, {}, 3, 100.0);
    std::vector<FrameSample> out(kSamples);
    for (auto& s : out) s = sim.step();
    return out;
  }();
  return samples;
}

DiagnoserConfig config() {
  return load_diagnoser_config(YamlSection(YAML::Node(YAML::NodeType::Map), "(defaults)"), TurbineParams{});
}

// The converter test alone: measured torque, its reference, generator speed and power.
void BM_ConverterMonitor(benchmark::State& state) {
  const auto& rec = recording();
  std::vector<double> torque(kSamples), ref(kSamples), speed(kSamples), power(kSamples);
  for (std::size_t i = 0; i < kSamples; ++i)
    torque[i] = rec[i].gen_torque, ref[i] = rec[i].gen_torque_ref, speed[i] = rec[i].generator_speed,
    power[i] = rec[i].power;
  ConverterMonitor m(config().converter, 0.01);
  // The recording's wrap is a gap (the model restarts); the noise is learned before the timing starts.
  for (std::size_t i = 0; i < kSamples; ++i) m.update(torque[i], ref[i], speed[i], power[i], true, i == 0);
  std::size_t i = 0;
  for (auto _ : state) {
    m.update(torque[i], ref[i], speed[i], power[i], true, i == 0);
    i = (i + 1) & (kSamples - 1);
  }
  benchmark::DoNotOptimize(m.state().statistic);
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ConverterMonitor)->Repetitions(3)->ReportAggregatesOnly(true);

// The aerodynamic power of each sample (centred 2 s anemometer average, the turbine model blade by blade).
void BM_AeroPowerInput(benchmark::State& state) {
  const auto& rec = recording();
  const DiagnoserConfig c = config();
  const AeroModel aero{TurbineParams{}};
  AeroPowerInput input(aero, c.wind_window, c.sample_time);
  FrameSample out;
  bool gap = false;
  double power = 0.0, sum = 0.0;
  std::size_t i = 0;
  for (auto _ : state) {
    FrameSample s = rec[i];
    s.aero_power = kNaN;
    if (input.push(s, i == 0, out, gap, power)) sum += power;
    i = (i + 1) & (kSamples - 1);
  }
  benchmark::DoNotOptimize(sum);
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_AeroPowerInput)->Repetitions(3)->ReportAggregatesOnly(true);

// The energy balance alone, on the recording's torque and speed with its true aerodynamic power.
void BM_EfficiencyMonitor(benchmark::State& state) {
  const auto& rec = recording();
  EfficiencyMonitor m(config().efficiency, 0.01);
  for (std::size_t i = 0; i < kSamples; ++i)
    m.update(rec[i].gen_torque, rec[i].generator_speed, rec[i].aero_power, rec[i].pitch[0], i != 0, false);
  std::size_t i = 0;
  for (auto _ : state) {
    const FrameSample& s = rec[i];
    m.update(s.gen_torque, s.generator_speed, s.aero_power, s.pitch[0], i != 0, false);
    i = (i + 1) & (kSamples - 1);
  }
  benchmark::DoNotOptimize(m.state().efficiency);
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_EfficiencyMonitor)->Repetitions(3)->ReportAggregatesOnly(true);

// The whole diagnoser as the service calls it per sample: validation, converter test, power model, energy
// balance (update only; `WithEstimate` adds the 10 Hz estimate and a copy of the sample to move its time on).
void diagnoser(benchmark::State& state, bool with_estimate) {
  const auto& rec = recording();
  const AeroModel aero{TurbineParams{}};
  DriveTrainDiagnoser d(config(), aero);
  std::vector<FaultEvent> events;
  DriveTrainOutput o;
  for (std::size_t i = 0; i < kSamples; ++i) d.update(rec[i], i == 0, events);
  std::size_t i = 0;
  if (!with_estimate) {
    for (auto _ : state) {
      d.update(rec[i], i == 0, events);
      i = (i + 1) & (kSamples - 1);
    }
  } else {
    // The estimate is due by sample time: each lap of the recording goes on in time.
    const double lap = static_cast<double>(kSamples) * 0.01;
    double offset = lap;
    for (auto _ : state) {
      FrameSample s = rec[i];
      s.t += offset;
      d.update(s, i == 0, events);
      d.estimate_due(o);
      i = (i + 1) & (kSamples - 1);
      if (i == 0) offset += lap;
    }
  }
  benchmark::DoNotOptimize(d.efficiency().efficiency);
  state.counters["events"] = static_cast<double>(events.size());
  state.SetItemsProcessed(state.iterations());
}
void BM_DriveTrainDiagnoser(benchmark::State& state) { diagnoser(state, false); }
void BM_DriveTrainDiagnoserWithEstimate(benchmark::State& state) { diagnoser(state, true); }
BENCHMARK(BM_DriveTrainDiagnoser)->Repetitions(3)->ReportAggregatesOnly(true);
BENCHMARK(BM_DriveTrainDiagnoserWithEstimate)->Repetitions(3)->ReportAggregatesOnly(true);

}  // namespace

BENCHMARK_MAIN();
