// sensor_bias throughput: the drive-train + 3 pitch observers per turbine-sample (target >= 5 million/s per
// core), the full per-sample estimator (with the aerodynamic-torque model), and the LMI design time of both
// subsystems.
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "bias_estimator.hpp"
#include "deploy_dir.hpp"
#include "design_input.hpp"
#include "observers.hpp"

using namespace windfdi;
using namespace windfdi::sensor_bias;

static const std::string kDeploy = deploy_dir();

static void BM_ObserverKernel(benchmark::State& state) {
  const GainFile d = load_gain_file(kDeploy + "/sensor_bias/gains_drive_train_observer.yaml");
  const GainFile p = load_gain_file(kDeploy + "/sensor_bias/gains_pitch_observer.yaml");
  // The service's observers: drive train with bias rates (7 states), pitch (4; a random-walk file padded).
  AugmentedObserver<7, 3, 2> dt;  // rotor speed, generator speed, power witness
  load_observer(dt, d, 5, "drive train");
  std::array<AugmentedObserver<4, 1, 1>, 3> pitch;
  for (auto& o : pitch) load_observer(o, p, 3, "pitch");
  std::vector<double> w(4096);
  for (int i = 0; i < 4096; ++i) w[static_cast<std::size_t>(i)] = std::sin(0.01 * i);
  std::size_t i = 0;
  for (auto _ : state) {
    const double v = w[i];
    dt.step(Eigen::Vector3d(1.7 + 0.01 * v, 162.0 + v, 162.0 - v), Eigen::Vector2d(2.8e6 + 1e5 * v, 2.9e4));
    for (auto& o : pitch)
      o.step(Eigen::Matrix<double, 1, 1>(10.0 + v), Eigen::Matrix<double, 1, 1>(10.0 + v));
    i = (i + 1) & 4095;
  }
  benchmark::DoNotOptimize(dt.state());
  benchmark::DoNotOptimize(pitch[2].state());
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ObserverKernel)->Repetitions(3)->ReportAggregatesOnly(true);

// The whole per-sample estimator (input checks, witness, drive-train and 3 pitch observers, detection), with
// the aerodynamic torque from the estimator's model (the DDS path) or from the recording's column.
static void full_estimator(benchmark::State& state, bool with_aero_model) {
  TurbineParams tp;
  const YamlSection y = YamlSection::load_file(kDeploy + "/config/sensor_bias.yaml");
  const BiasConfig c = load_bias_config(y, kDeploy + "/sensor_bias");
  BiasEstimator est(c, load_gain_file(c.drive_train_gain_file), load_gain_file(c.pitch_gain_file), tp);
  std::vector<FaultEvent> ev;
  // Inputs precomputed (the sin() calls of generating them would otherwise be timed with the estimator).
  std::vector<FrameSample> in(4096);
  for (std::size_t k = 0; k < in.size(); ++k) {
    FrameSample& s = in[k];
    const double t = 0.01 * static_cast<double>(k);
    s.gen_torque = 2.9e4;
    s.pitch_ref = {5, 5, 5};
    s.rotor_speed = 1.7 + 0.01 * std::sin(t);
    s.generator_speed = 95 * s.rotor_speed;
    s.power = 0.98 * s.generator_speed * s.gen_torque;  // the witness in use, as on a running turbine
    s.wind_hub = 14.0 + std::sin(0.3 * t);
    s.pitch = {5.0, 5.0, 5.0};
    s.aero_torque =
        with_aero_model ? kNaN : 2.8e6 + 1e5 * std::sin(0.3 * t);  // NaN: the estimator's aero model
  }
  double t = 0;
  std::size_t k = 0;
  for (auto _ : state) {
    FrameSample& s = in[k];
    s.t = t;
    est.update(s, false, ev);
    ev.clear();
    t += 0.01;
    k = (k + 1) & 4095;
  }
  benchmark::DoNotOptimize(est.output());
  state.SetItemsProcessed(state.iterations());
}
static void BM_FullEstimator(benchmark::State& state) { full_estimator(state, true); }
BENCHMARK(BM_FullEstimator)->Repetitions(3)->ReportAggregatesOnly(true);
static void BM_FullEstimatorRecordedAeroTorque(benchmark::State& state) { full_estimator(state, false); }
BENCHMARK(BM_FullEstimatorRecordedAeroTorque)->Repetitions(3)->ReportAggregatesOnly(true);

static void BM_DesignBothSubsystems(benchmark::State& state) {
  const DesignInput d = load_design_input_file(kDeploy + "/sensor_bias/design_drive_train_observer.yaml");
  const DesignInput p = load_design_input_file(kDeploy + "/sensor_bias/design_pitch_observer.yaml");
  for (auto _ : state) {
    const QbSolution a = d.fixed_alpha ? qb_solve(d.problem, d.alpha) : qb_design(d.problem, d.search);
    const QbSolution b = p.fixed_alpha ? qb_solve(p.problem, p.alpha) : qb_design(p.problem, p.search);
    benchmark::DoNotOptimize(a.K);
    benchmark::DoNotOptimize(b.K);
  }
}
BENCHMARK(BM_DesignBothSubsystems)->Unit(benchmark::kMillisecond)->Iterations(3);

BENCHMARK_MAIN();
