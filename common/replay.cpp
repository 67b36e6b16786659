// The replay contract's driver: recorded frames in, estimates CSV and fault events out.
#include "replay.hpp"

#include <cmath>

#include "replay_csv.hpp"

namespace windfdi {

ReplaySink::ReplaySink(const ReplayOptions& options, const std::vector<std::string>& columns) {
  if (!options.estimates.empty()) {
    std::vector<std::string> header = {"t", "turbine_id"};
    header.insert(header.end(), columns.begin(), columns.end());
    csv_ = std::make_unique<CsvWriter>(options.estimates, header);
  }
  if (!options.events.empty()) jsonl_ = std::make_unique<JsonlWriter>(options.events);
}

void ReplaySink::estimate(double t, const std::string& turbine_id, const std::vector<std::string>& values) {
  ++estimates_;
  if (!csv_) return;
  csv_->add(t).add(turbine_id);
  for (const auto& v : values) csv_->add(v);
  csv_->end_row();
}

void ReplaySink::event(const FaultEvent& e) {
  ++events_;
  if (jsonl_) jsonl_->write(to_json(e));
}

uint64_t SequenceTracker::lost_before(uint64_t sequence) {
  uint64_t lost = 0;
  if (started_ && sequence > next_) lost = sequence - next_;
  // A sequence that goes backwards is a restarted source: treat it as a discontinuity too.
  if (started_ && sequence < next_) lost = 1;
  started_ = true;
  next_ = sequence + 1;
  return lost;
}

double SampleTimeTracker::step(double t) {
  if (!std::isfinite(t)) return 0.0;
  const double step = started_ ? t - last_ : 0.0;
  started_ = true;
  last_ = t;
  return step < 0.0 || step > kMaxInterval ? step : 0.0;
}

ReplayStats run_replay(const ReplayOptions& options, const std::vector<std::string>& columns,
                       const ReplayProcess& process,
                       const std::function<void(const FrameCsvReader& reader)>& on_header) {
  FrameCsvReader reader(options.frames);
  if (on_header) on_header(reader);
  ReplaySink sink(options, columns);
  std::map<std::string, SequenceTracker> trackers;
  std::map<std::string, SampleTimeTracker> clocks;
  ReplayStats stats;
  FrameSample sample;
  std::string turbine;
  while (reader.next(sample, turbine)) {
    ++stats.samples;
    const uint64_t lost = trackers[turbine].lost_before(sample.sequence);
    stats.sequence_gaps += lost;
    const double step = clocks[turbine].step(sample.t);
    if (step != 0.0) ++stats.time_steps;
    if (!process(turbine, sample, lost > 0 || step != 0.0, sink)) ++stats.rejected;
  }
  stats.estimates = sink.estimates_written();
  stats.events = sink.events_written();
  return stats;
}

}  // namespace windfdi
