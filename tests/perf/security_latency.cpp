// One-way latency (round trip / 2) between two processes with DDS-Security off and on, in the same run.
// A ping process writes a one-sample TurbineFrame on bench/ping; an echo process (this program re-executed)
// writes it back on bench/pong; both with the sensor_stream QoS of wt/frame (reliable keep-last) on the
// loopback participant profile. With --security DIR the 'bench' role of make_credentials.sh --bench is used
// (governance of the farm: discovery, liveliness and data encrypted).
// Usage: security_latency --security DIR [--samples N] [--rate HZ] [--rounds R] [--domain D]
#include <signal.h>
#include <spdlog/spdlog.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <iostream>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "TurbineFramePubSubTypes.h"
#include "app.hpp"
#include "dds/participant.hpp"
#include "ping_pong.hpp"

using namespace eprosima::fastdds::dds;
using namespace windfdi;

namespace {

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

using Endpoints = bench::PingEndpoints;

bus::ParticipantOptions options(int domain, const std::string& security, const std::string& name) {
  bus::ParticipantOptions o;
  o.domain = domain;
  o.profile = "windfdi_participant_loopback";
  o.name = name;
  o.security_dir = security;
  if (!security.empty()) o.security_role = "bench";
  return o;
}

int run_echo(int domain, const std::string& security) {
  return bench::run_echo(options(domain, security, "bench-echo"));
}

struct Result {
  double p50 = 0, p99 = 0, mean = 0;
  std::size_t got = 0;
};

Result run_ping(const std::string& exe, int domain, const std::string& security, int samples, double rate) {
  std::vector<std::string> args = {exe, "--echo", "--domain", std::to_string(domain)};
  if (!security.empty()) args.insert(args.end(), {"--security", security});
  const pid_t child = bench::spawn(args);
  Result r;
  {
    bus::Participant p(options(domain, security, "bench-ping"));
    std::mutex m;
    std::condition_variable cv;
    uint64_t last_pong = UINT64_MAX;
    std::vector<double> rtt;
    std::vector<double> sent(static_cast<std::size_t>(samples), 0.0);
    Endpoints e(p, "bench/ping", "bench/pong", [&](windfdi::TurbineFrame& f) {
      const double t = now_s();
      const uint64_t seq = f.samples().empty() ? UINT64_MAX : f.samples()[0].sequence();
      std::lock_guard<std::mutex> lock(m);
      if (seq < sent.size()) rtt.push_back(t - sent[seq]);
      last_pong = seq;
      cv.notify_all();
    });
    const double deadline = now_s() + 30.0;
    while (!e.matched() && now_s() < deadline) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    if (!e.matched()) throw std::runtime_error("ping and echo did not match within 30 s");
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    windfdi::TurbineFrame f;
    f.turbine_id("WT01");
    f.samples().resize(1);
    f.samples()[0].rotor_speed(1.2);
    const double period = 1.0 / rate;
    double next = now_s();
    for (int k = 0; k < samples; ++k) {
      f.samples()[0].sequence(static_cast<uint64_t>(k));
      {
        std::lock_guard<std::mutex> lock(m);
        sent[static_cast<std::size_t>(k)] = now_s();
      }
      e.write(f);
      std::unique_lock<std::mutex> lock(m);
      cv.wait_for(lock, std::chrono::milliseconds(200),
                  [&] { return last_pong == static_cast<uint64_t>(k); });
      lock.unlock();
      next += period;
      const double wait = next - now_s();
      if (wait > 0) std::this_thread::sleep_for(std::chrono::duration<double>(wait));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    std::lock_guard<std::mutex> lock(m);
    std::sort(rtt.begin(), rtt.end());
    r.got = rtt.size();
    if (!rtt.empty()) {
      r.p50 = rtt[rtt.size() / 2] / 2.0;
      r.p99 = rtt[std::min(rtt.size() - 1, rtt.size() * 99 / 100)] / 2.0;
      double sum = 0;
      for (double x : rtt) sum += x;
      r.mean = sum / static_cast<double>(rtt.size()) / 2.0;
    }
  }
  kill(child, SIGTERM);
  int status = 0;
  waitpid(child, &status, 0);
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"DDS-Security latency: one-way latency with security off and on", "security_latency"};
  std::string security;
  int samples = 1000, rounds = 2, domain = 150 + static_cast<int>(getpid() % 50);
  double rate = 200.0;
  bool echo = false;
  app.add_option("--security", security, "credentials made by make_credentials.sh --bench (required)");
  app.add_option("--samples", samples, "round trips per measurement");
  app.add_option("--rate", rate, "round trips per second");
  app.add_option("--rounds", rounds, "off/on measurement pairs (the median is reported)");
  app.add_option("--domain", domain, "DDS domain id");
  app.add_flag("--echo", echo, "internal: run the echo process");
  CLI11_PARSE(app, argc, argv);
  spdlog::set_level(spdlog::level::warn);
  try {
    if (echo) return run_echo(domain, security);
    if (security.empty())
      throw std::runtime_error("--security DIR is required (make_credentials.sh DIR --bench)");
    bus::validate_security_files(bus::security_files(security, "bench"), domain);
    const std::string exe = "/proc/self/exe";
    char path[4096];
    const ssize_t n = readlink(exe.c_str(), path, sizeof path - 1);
    const std::string self = n > 0 ? std::string(path, static_cast<std::size_t>(n)) : argv[0];
    std::vector<Result> off, on;
    for (int r = 0; r < rounds; ++r) {
      for (bool sec : {false, true}) {
        const Result res = run_ping(self, domain, sec ? security : "", samples, rate);
        std::printf("round %d security %-3s: one-way p50 %.1f us, p99 %.1f us, mean %.1f us (%zu of %d)\n",
                    r + 1, sec ? "on" : "off", res.p50 * 1e6, res.p99 * 1e6, res.mean * 1e6, res.got,
                    samples);
        std::fflush(stdout);
        (sec ? on : off).push_back(res);
      }
    }
    const auto median = [](std::vector<Result> v, double Result::*f) {
      std::sort(v.begin(), v.end(), [&](const Result& a, const Result& b) { return a.*f < b.*f; });
      return v[v.size() / 2].*f;
    };
    const double off50 = median(off, &Result::p50), on50 = median(on, &Result::p50);
    const double off99 = median(off, &Result::p99), on99 = median(on, &Result::p99);
    std::printf(
        "security_latency: one-way p50 off %.1f us, on %.1f us (ratio %.2f); p99 off %.1f us, on %.1f us "
        "(ratio %.2f)\n",
        off50 * 1e6, on50 * 1e6, on50 / off50, off99 * 1e6, on99 * 1e6, on99 / off99);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "security_latency: %s\n", e.what());
    return 1;
  }
}
