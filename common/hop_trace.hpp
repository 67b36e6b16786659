// Hop-by-hop latency trace: wall-clock time stamps of each fault's way through the processes (WINDFDI_TRACE).
#pragma once

#include <cstdio>
#include <memory>
#include <string>

namespace windfdi {

/// Off unless the environment variable WINDFDI_TRACE names a directory; then each process writes
/// DIR/<process>.<pid>.csv with the columns hop,turbine_id,key,wall_time (s since the Unix epoch, the
/// machine's clock: the processes of one host share it). Only fault reports and configurations are traced,
/// never a sample, so the hot path pays nothing. tests/perf/hop_table.py joins the files into the table.
///
/// Keys: a fault report is `component/fault/t` (t, its decisive sample's time, to the millisecond); a
/// configuration is its revision; the arbiter's `report_config` row links the two (`report key>revision`).
class HopTrace {
 public:
  explicit HopTrace(const std::string& process);
  HopTrace(const HopTrace&) = delete;
  HopTrace& operator=(const HopTrace&) = delete;

  bool on() const { return file_ != nullptr; }
  void record(const char* hop, const std::string& turbine_id, const std::string& key, double wall_time);

  /// The key of a fault report: component/fault/t.
  static std::string report_key(const std::string& component, const std::string& fault, double t);

 private:
  struct Close {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };
  std::unique_ptr<std::FILE, Close> file_;
};

}  // namespace windfdi
