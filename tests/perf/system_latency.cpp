// System benchmarks: the measuring side. Run by system_latency.sh and farm_capacity.sh,
// which start the plant, the four diagnostic services and the arbiter on a private loopback domain.
//
// --mode latency (system_latency.sh)
//   Subscribes to wt/frame, wt/fault and wt/control/config as the services and the plant do (topic profiles
//   of deploy/qos/windfdi_qos.xml). For every sample of every frame it keeps the frame's source time stamp
//   (the plant's wall clock when it wrote the frame; same host, same clock). blade_load's FaultReport carries
//   in `t` the sample time of the sample that made the fault decidable (invalid for invalid_time), so
//     latency to the report        = arrival of the raised FaultReport here   - source time of the frame with
//     t latency to the configuration = arrival here of the first ControlConfiguration of that turbine whose
//                                    reasons newly contain (blade_load, blade_moment_sensor_3,
//                                    sensor_invalid)
//                                    - the same source time.
//   This program reads wt/control/config exactly as the plant does, so its arrival time stands for "at the
//   plant". Baseline: raw Fast DDS one-way latency (round trip / 2) between this process and an echo child
//   (this program re-executed, --mode echo) on bench/ping, bench/pong with the sensor_stream QoS (reliable
//   keep-last, as wt/frame; the approach of security_latency.cpp). It is measured twice in the same run:
//   idle (before "READY" is printed, nothing else running) and loaded (at 100 Hz in a thread while the
//   system runs, the denominator of the ratios).
// --mode health (farm_capacity.sh)
//   Subscribes to wt/health for --duration s and judges, over the window after --warmup s, whether every
//   service kept up with --turbines turbines at 100 Hz: samples in at >= 97 % of 100 Hz per turbine, no new
//   sequence gaps, lag (age of the newest processed frame) below 0.5 s and not growing (mean over the last
//   third of the window minus the first third < 0.1 s). The plant's samples_in is what it published, so the
//   same rate test tells whether the plant itself kept real time.
// --mode echo: internal.
#include <spdlog/spdlog.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <tuple>
#include <unordered_map>
#include <vector>

#include "ControlConfigurationPubSubTypes.h"
#include "FaultReportPubSubTypes.h"
#include "ServiceHealthPubSubTypes.h"
#include "TurbineFramePubSubTypes.h"
#include "app.hpp"
#include "dds/endpoints.hpp"
#include "dds/participant.hpp"
#include "ping_pong.hpp"

using namespace eprosima::fastdds::dds;
using namespace windfdi;

namespace {

double mono_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double pct(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const std::size_t i = std::min(
      v.size() - 1, static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size()))) - (q > 0 ? 1 : 0));
  return v[i];
}

bus::ParticipantOptions options(int domain, const std::string& name) {
  bus::ParticipantOptions o;
  o.domain = domain;
  // Loopback unless the run says otherwise (farm_shards.sh: UDP between network namespaces).
  const char* profile = std::getenv("WINDFDI_PARTICIPANT_PROFILE");
  o.profile = profile && *profile ? profile : "windfdi_participant_loopback";
  o.name = name;
  return o;
}

// ---------------------------------------------------------------- raw Fast DDS ping/pong (baseline)

using bench::PingEndpoints;

int run_echo(int domain) { return bench::run_echo(options(domain, "sysbench-echo")); }

class Pinger {
 public:
  explicit Pinger(bus::Participant& p)
      : e_(p, "bench/ping", "bench/pong", [this](TurbineFrame& f) {
          const double t = mono_s();
          const uint64_t seq = f.samples().empty() ? UINT64_MAX : f.samples()[0].sequence();
          std::lock_guard<std::mutex> lock(m_);
          if (seq == current_) rtt_.push_back(t - sent_);
          last_pong_ = seq;
          cv_.notify_all();
        }) {}
  bool wait_matched(double timeout) {
    const double end = mono_s() + timeout;
    while (!e_.matched() && mono_s() < end) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    return e_.matched();
  }
  std::vector<double> run(int samples, double rate, const std::atomic<bool>* stop = nullptr) {
    {
      std::lock_guard<std::mutex> lock(m_);
      rtt_.clear();
    }
    TurbineFrame f;
    f.turbine_id("PING");
    f.samples().resize(1);
    double next = mono_s();
    for (int k = 0; k < samples && !(stop && *stop); ++k) {
      f.samples()[0].sequence(seq_);
      {
        std::lock_guard<std::mutex> lock(m_);
        current_ = seq_;
        sent_ = mono_s();
      }
      e_.write(f);
      std::unique_lock<std::mutex> lock(m_);
      cv_.wait_for(lock, std::chrono::milliseconds(200), [&] { return last_pong_ == seq_; });
      lock.unlock();
      ++seq_;
      next += 1.0 / rate;
      const double wait = next - mono_s();
      if (wait > 0) std::this_thread::sleep_for(std::chrono::duration<double>(wait));
    }
    std::lock_guard<std::mutex> lock(m_);
    std::vector<double> out;
    for (double r : rtt_) out.push_back(r / 2.0);
    return out;
  }

 private:
  std::mutex m_;
  std::condition_variable cv_;
  uint64_t seq_ = 0, current_ = UINT64_MAX, last_pong_ = UINT64_MAX;
  double sent_ = 0;
  std::vector<double> rtt_;
  PingEndpoints e_;
};

pid_t start_echo(int domain) {
  char path[4096];
  const ssize_t n = readlink("/proc/self/exe", path, sizeof path - 1);
  if (n <= 0) throw std::runtime_error("cannot find my own executable");
  const std::string exe(path, static_cast<std::size_t>(n));
  return bench::spawn({exe, "--mode", "echo", "--domain", std::to_string(domain)});
}

void print_dist(const char* what, const std::vector<double>& v, std::size_t expected = 0) {
  std::printf("%-34s n=%zu%s p50 %8.1f us  p99 %8.1f us  max %8.1f us\n", what, v.size(),
              expected ? (" of " + std::to_string(expected)).c_str() : "", pct(v, 0.5) * 1e6,
              pct(v, 0.99) * 1e6, pct(v, 1.0) * 1e6);
}

// ---------------------------------------------------------------- latency mode

int run_latency(int domain, double duration, const std::string& component, const std::string& source) {
  install_signal_handlers();
  const pid_t echo = start_echo(domain);
  int rc = 0;
  {
    bus::Participant p(options(domain, "sysbench-latency"));
    Pinger pinger(p);
    if (!pinger.wait_matched(30)) throw std::runtime_error("ping and echo did not match within 30 s");
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    const int idle_n = 1000;
    const std::vector<double> idle = pinger.run(idle_n, 200.0);
    print_dist("raw one-way, idle (200 Hz)", idle, idle_n);

    bus::Wakeup wakeup;
    bus::Reader<TurbineFrame> frames(p, {}, &wakeup);
    bus::Reader<FaultReport> faults(p, {}, &wakeup);
    bus::Reader<ControlConfiguration> configs(p, {}, &wakeup);
    std::printf("READY\n");
    std::fflush(stdout);

    std::atomic<bool> stop{false};
    std::vector<double> loaded;
    std::thread ping_thread([&] { loaded = pinger.run(static_cast<int>(duration * 100), 100.0, &stop); });

    // (turbine, sample index) -> source time of the frame that carried it.
    std::unordered_map<std::string, std::unordered_map<long, double>> frame_time;
    struct Raised {
      std::string turbine;
      double t, arrival;
    };
    std::vector<Raised> raised;
    struct ConfigEvent {
      std::string turbine;
      double arrival;
      uint64_t revision;
    };
    std::vector<ConfigEvent> config_events;
    std::map<std::string, bool> had_reason;
    uint64_t n_frames = 0, n_reports = 0, n_configs = 0;

    std::vector<TurbineFrame> fv;
    std::vector<bus::SampleMeta> fm;
    std::vector<FaultReport> rv;
    std::vector<ControlConfiguration> cv;
    const double end = mono_s() + duration;
    while (!shutdown_requested() && mono_s() < end) {
      wakeup.wait_for(std::chrono::milliseconds(50));
      // Configurations first, then reports, then frames: a later item can only depend on an earlier one
      // that has already arrived here, so nothing is taken before what it depends on.
      cv.clear();
      configs.take(cv);
      const double now_c = wall_time();
      for (const auto& c : cv) {
        ++n_configs;
        bool has = false;
        for (const auto& r : c.reasons())
          if (r.source() == source && r.component() == component && r.fault_class() == FAULT_SENSOR_INVALID)
            has = true;
        bool& before = had_reason[c.turbine_id()];
        if (has && !before) config_events.push_back({c.turbine_id(), now_c, c.revision()});
        before = has;
      }
      rv.clear();
      faults.take(rv);
      const double now_r = wall_time();
      for (const auto& r : rv) {
        ++n_reports;
        if (r.state() == FAULT_STATE_RAISED && r.source() == source && r.component() == component &&
            r.fault_class() == FAULT_SENSOR_INVALID)
          raised.push_back({r.turbine_id(), r.t(), now_r});
      }
      fv.clear();
      fm.clear();
      frames.take(fv, &fm);
      for (std::size_t i = 0; i < fv.size(); ++i) {
        ++n_frames;
        auto& m = frame_time[fv[i].turbine_id()];
        for (const auto& s : fv[i].samples()) m[std::lround(s.t() * 100.0)] = fm[i].source_time;
      }
    }
    stop = true;
    ping_thread.join();
    // Reports and configurations that arrived in the same batch as their frame: take the frames now.
    fv.clear();
    fm.clear();
    frames.take(fv, &fm);
    for (std::size_t i = 0; i < fv.size(); ++i) {
      auto& m = frame_time[fv[i].turbine_id()];
      for (const auto& s : fv[i].samples()) m[std::lround(s.t() * 100.0)] = fm[i].source_time;
    }

    std::vector<double> to_report, to_config;
    std::size_t no_frame = 0, no_config = 0;
    for (std::size_t k = 0; k < raised.size(); ++k) {
      const auto& r = raised[k];
      const auto& m = frame_time[r.turbine];
      const auto it = m.find(std::lround(r.t * 100.0));
      if (it == m.end()) {
        ++no_frame;
        continue;
      }
      const double published = it->second;
      to_report.push_back(r.arrival - published);
      // The configuration caused by this report: the first new-reason configuration of the turbine after
      // the frame and before the next raise of the same turbine.
      double next_raise = 1e300;
      for (std::size_t j = k + 1; j < raised.size(); ++j)
        if (raised[j].turbine == r.turbine) {
          next_raise = raised[j].arrival;
          break;
        }
      bool found = false;
      for (const auto& c : config_events)
        if (c.turbine == r.turbine && c.arrival > published && c.arrival < next_raise) {
          to_config.push_back(c.arrival - published);
          found = true;
          break;
        }
      if (!found) ++no_config;
    }
    std::printf(
        "frames %llu, fault reports %llu, configurations %llu; raised %s/%s/sensor_invalid %zu "
        "(%zu without their frame, %zu without a new configuration)\n",
        static_cast<unsigned long long>(n_frames), static_cast<unsigned long long>(n_reports),
        static_cast<unsigned long long>(n_configs), source.c_str(), component.c_str(), raised.size(),
        no_frame, no_config);
    print_dist("raw one-way, loaded (100 Hz)", loaded);
    print_dist("decisive frame -> FaultReport", to_report);
    print_dist("decisive frame -> ControlConfig", to_config);
    const double b50 = pct(loaded, 0.5), b99 = pct(loaded, 0.99);
    std::printf(
        "system_latency: to FaultReport p50 %.2f ms (x%.0f raw), p99 %.2f ms (x%.0f raw); "
        "to ControlConfiguration p50 %.2f ms (x%.0f raw), p99 %.2f ms (x%.0f raw); "
        "raw one-way in the same run p50 %.1f us, p99 %.1f us (idle %.1f / %.1f us)\n",
        pct(to_report, 0.5) * 1e3, pct(to_report, 0.5) / b50, pct(to_report, 0.99) * 1e3,
        pct(to_report, 0.99) / b99, pct(to_config, 0.5) * 1e3, pct(to_config, 0.5) / b50,
        pct(to_config, 0.99) * 1e3, pct(to_config, 0.99) / b99, b50 * 1e6, b99 * 1e6, pct(idle, 0.5) * 1e6,
        pct(idle, 0.99) * 1e6);
    if (to_report.empty()) rc = 1;
  }
  kill(echo, SIGTERM);
  int status = 0;
  waitpid(echo, &status, 0);
  return rc;
}

// ---------------------------------------------------------------- health mode

int run_health(int domain, double duration, double warmup, int turbines) {
  install_signal_handlers();
  bus::Participant p(options(domain, "sysbench-health"));
  bus::Wakeup wakeup;
  bus::Reader<ServiceHealth> health(p, {}, &wakeup);
  const double start = wall_time();
  std::vector<ServiceHealth> all, v;
  while (!shutdown_requested() && wall_time() < start + duration) {
    wakeup.wait_for(std::chrono::milliseconds(200));
    v.clear();
    health.take(v);
    for (auto& h : v)
      if (h.t() >= start + warmup) all.push_back(h);
  }
  // Per (service, turbine): the reports of the window in time order.
  std::map<std::string, std::map<std::string, std::vector<ServiceHealth>>> by;
  for (auto& h : all)
    // "*": a farm-wide instance before it has seen a turbine; the arbiter, counting fault reports, may
    // report nothing else in a healthy farm.
    if (h.turbine_id() != "*" || h.service() == "arbiter") by[h.service()][h.turbine_id()].push_back(h);
  const double expected_rate = 100.0 * turbines;
  bool all_ok = true;
  for (const char* svc : {"plant", "blade_load", "sensor_bias", "pitch_diag", "ice_detect", "arbiter"}) {
    auto it = by.find(svc);
    if (it == by.end()) {
      std::printf("%-12s no health reports in the window\n", svc);
      all_ok = false;
      continue;
    }
    double rate = 0, max_lag = 0, growth = 0;
    uint64_t gaps = 0, rejected = 0;
    std::vector<double> lags;
    for (auto& [id, hs] : it->second) {
      std::sort(hs.begin(), hs.end(), [](const auto& a, const auto& b) { return a.t() < b.t(); });
      if (hs.size() >= 2 && hs.back().t() > hs.front().t())
        rate += static_cast<double>(hs.back().samples_in() - hs.front().samples_in()) /
                (hs.back().t() - hs.front().t());
      gaps += hs.back().sequence_gaps() - hs.front().sequence_gaps();
      rejected += hs.back().samples_rejected() - hs.front().samples_rejected();
      const std::size_t third = hs.size() / 3;
      double first = 0, last = 0;
      for (std::size_t i = 0; i < hs.size(); ++i) {
        lags.push_back(hs[i].lag());
        max_lag = std::max(max_lag, hs[i].lag());
        if (third && i < third) first += hs[i].lag() / static_cast<double>(third);
        if (third && i >= hs.size() - third) last += hs[i].lag() / static_cast<double>(third);
      }
      growth = std::max(growth, last - first);
    }
    const bool frames_in = std::string(svc) != "arbiter";  // the arbiter counts fault reports, not samples
    const int seen = static_cast<int>(it->second.size());
    bool ok = gaps == 0;
    if (frames_in) ok = ok && seen == turbines && rate >= 0.97 * expected_rate;
    if (frames_in && std::string(svc) != "plant") ok = ok && max_lag < 0.5 && growth < 0.1;
    all_ok = all_ok && ok;
    if (frames_in)
      std::printf(
          "%-12s %s turbines %d/%d, samples in %.0f/s of %.0f/s (%.1f %%), new gaps %llu, rejected %llu, "
          "lag p50 %.3f s max %.3f s, lag growth %.3f s\n",
          svc, ok ? "OK  " : "LAGS", seen, turbines, rate, expected_rate, 100 * rate / expected_rate,
          static_cast<unsigned long long>(gaps), static_cast<unsigned long long>(rejected), pct(lags, 0.5),
          max_lag, growth);
    else
      std::printf("%-12s %s health reports from %d instance(s), new gaps %llu\n", svc, ok ? "OK  " : "LAGS",
                  seen, static_cast<unsigned long long>(gaps));
  }
  std::printf("KEEPS_UP %d\n", all_ok ? 1 : 0);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"System benchmarks: end-to-end latency and farm capacity (measuring side)", "system_latency"};
  std::string mode = "latency", component = "blade_moment_sensor_3", source = "blade_load";
  double duration = 120, warmup = 10;
  int turbines = 1, domain = 150 + static_cast<int>(getpid() % 50);
  app.add_option("--mode", mode, "latency, health or echo (internal)");
  app.add_option("--duration", duration, "seconds to measure (latency: after READY; health: in all)");
  app.add_option("--warmup", warmup, "health: seconds ignored at the start");
  app.add_option("--turbines", turbines, "health: turbines the plant simulates");
  app.add_option("--component", component, "latency: the FaultReport component measured");
  app.add_option("--source", source, "latency: the service that raises it");
  app.add_option("--domain", domain, "DDS domain id");
  CLI11_PARSE(app, argc, argv);
  spdlog::set_level(spdlog::level::warn);
  try {
    if (mode == "echo") return run_echo(domain);
    if (mode == "latency") return run_latency(domain, duration, component, source);
    if (mode == "health") return run_health(domain, duration, warmup, turbines);
    throw std::runtime_error("unknown --mode " + mode);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "system_latency: %s\n", e.what());
    return 1;
  }
}
