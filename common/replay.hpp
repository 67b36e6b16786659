// The replay contract's driver: recorded frames in, estimates CSV and fault events (JSON Lines) out.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "csv.hpp"
#include "fault_event.hpp"
#include "frame_sample.hpp"
#include "jsonl.hpp"
#include "replay_csv.hpp"

namespace windfdi {

struct ReplayOptions {
  std::string frames;     ///< --replay: input CSV (plain or .gz)
  std::string estimates;  ///< --estimates: output CSV (empty: none)
  std::string events;     ///< --events: output JSON Lines (empty: none)
};

/// Where a service writes what it produces during a replay.
class ReplaySink {
 public:
  ReplaySink(const ReplayOptions& options, const std::vector<std::string>& estimate_columns);
  /// One estimate row: `t`, `turbine_id`, then one value per estimate column (numbers or text).
  void estimate(double t, const std::string& turbine_id, const std::vector<std::string>& values);
  void event(const FaultEvent& e);
  uint64_t estimates_written() const { return estimates_; }
  uint64_t events_written() const { return events_; }

 private:
  std::unique_ptr<CsvWriter> csv_;
  std::unique_ptr<JsonlWriter> jsonl_;
  uint64_t estimates_ = 0, events_ = 0;
};

/// Counts of a replay run, logged at the end.
struct ReplayStats {
  uint64_t samples = 0;
  uint64_t rejected = 0;
  uint64_t sequence_gaps = 0;
  uint64_t time_steps = 0;  ///< sample time stepped back or jumped forward (SampleTimeTracker)
  uint64_t estimates = 0;
  uint64_t events = 0;
};

/// Per-sample callback: returns false when the sample was rejected (NaN, out of range); `gap` is true
/// when samples were lost before this one or its time stepped (the core restarts its history).
using ReplayProcess =
    std::function<bool(const std::string& turbine_id, const FrameSample& sample, bool gap, ReplaySink& sink)>;

/// Reads every sample of `options.frames` in order and hands it to `process`. A malformed file throws
/// ConfigError (exit code 2) naming file, line and column.
/// `on_header` (optional) sees the recording's header before anything is written (it may throw).
ReplayStats run_replay(const ReplayOptions& options, const std::vector<std::string>& estimate_columns,
                       const ReplayProcess& process,
                       const std::function<void(const FrameCsvReader& reader)>& on_header = nullptr);

/// Detects lost samples from per-turbine sequence numbers.
class SequenceTracker {
 public:
  /// Number of samples lost before `sequence` (0 when consecutive or first).
  uint64_t lost_before(uint64_t sequence);
  void reset() { started_ = false; }

 private:
  bool started_ = false;
  uint64_t next_ = 0;
};

/// A turbine's sample times. A step back, or forward by more than kMaxInterval between consecutive samples,
/// is a restarted turbine controller or its clock stepped (NTP): the history restarts as after lost samples,
/// so that no sample-time window or confirmation timer reads the step as time that passed.
class SampleTimeTracker {
 public:
  static constexpr double kMaxInterval = 5.0;  ///< s between consecutive samples (recordings of 1 Hz pass)
  /// The step from the last sample's time when it is a discontinuity, else 0 (a NaN time is no step).
  double step(double t);

 private:
  bool started_ = false;
  double last_ = 0.0;
};

}  // namespace windfdi
