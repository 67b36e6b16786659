// Throughput of the Wu & Li pitch_diag kernel: blade-samples per second per core, per method and
// innovation length p (Table 3 of the paper timed the same sweep p = 1 .. 32).
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "identifier.hpp"
#include "pitch_diagnoser.hpp"

using namespace windfdi;
using namespace windfdi::pitch_diag;

namespace {

// Precomputed reference and noisy pitch (the data generation is not timed).
struct Data {
  std::vector<double> u, y;
  Data() {
    const int n = 1 << 16;
    const Theta th = theta_from_continuous(7.27, 0.75, 0.01);
    double y1 = 10, y2 = 10, u1 = 10, u2 = 10;
    uint64_t s = 12345;
    for (int k = 0; k < n; ++k) {
      const double t = k * 0.01;
      const double uk = 11 + 1.5 * std::sin(0.7 * t) + 0.8 * std::sin(3.1 * t + 1) + 0.4 * std::sin(5.3 * t);
      const double yk = -th(0) * y1 - th(1) * y2 + th(2) * u1 + th(3) * u2;
      s = s * 6364136223846793005ull + 1442695040888963407ull;
      u.push_back(uk);
      y.push_back(yk + 0.2 * (static_cast<double>(s >> 11) * 0x1.0p-53 - 0.5) * 3.46);
      y2 = y1, y1 = yk, u2 = u1, u1 = uk;
    }
  }
};
const Data& data() {
  static const Data d;
  return d;
}

void BM_Identifier(benchmark::State& state, Method m) {
  IdentifierConfig c;
  c.method = m;
  c.p = static_cast<int>(state.range(0));
  Identifier id(c);
  const auto& d = data();
  const std::size_t n = d.u.size();
  std::size_t k = 0;
  for (auto _ : state) {
    id.update(d.u[k], d.y[k]);
    if (++k == n) k = 0;
  }
  benchmark::DoNotOptimize(id.theta());
  state.SetItemsProcessed(state.iterations());  // items = blade-samples
}

// The whole turbine diagnoser (validation, three blades, 10 Hz classification): items = blade-samples.
void BM_Diagnoser(benchmark::State& state) {
  PitchDiagConfig c;
  PitchDiagnoser diag(c);
  const auto& d = data();
  const std::size_t n = d.u.size();
  FrameSample s;
  std::vector<FaultEvent> ev;
  PitchEstimate est;
  std::size_t k = 0;
  uint64_t seq = 0;
  for (auto _ : state) {
    s.sequence = seq;
    s.t = static_cast<double>(seq) * 0.01;
    ++seq;
    for (int i = 0; i < 3; ++i) {
      s.pitch_ref[i] = d.u[(k + 997 * i) % n];
      s.pitch[i] = d.y[(k + 997 * i) % n];
    }
    diag.update(s, false, ev);
    diag.estimate_due(est);
    ev.clear();
    if (++k == n) k = 0;
  }
  state.SetItemsProcessed(3 * state.iterations());
}

}  // namespace

BENCHMARK_CAPTURE(BM_Identifier, paper_mifg, Method::kPaperMifg)->Arg(1)->Arg(3)->Arg(8)->Arg(16)->Arg(32);
BENCHMARK_CAPTURE(BM_Identifier, am_mifg, Method::kAmMifg)->Arg(1)->Arg(3)->Arg(8)->Arg(16)->Arg(32);
BENCHMARK_CAPTURE(BM_Identifier, paper_rls, Method::kPaperRls)->Arg(8);
BENCHMARK_CAPTURE(BM_Identifier, am_rls, Method::kAmRls)->Arg(8);
BENCHMARK_CAPTURE(BM_Identifier, oe_rls, Method::kOeRls)->Arg(8);
BENCHMARK_CAPTURE(BM_Identifier, bank_default, Method::kBank)->Arg(1)->Arg(3)->Arg(8)->Arg(16)->Arg(32);
BENCHMARK(BM_Diagnoser);

BENCHMARK_MAIN();
