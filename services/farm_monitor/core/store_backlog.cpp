// The farm store's backlog: ordered writes that survive a full or read-only disk.
#include "store_backlog.hpp"

#include <stdexcept>

namespace windfdi::farm {

StoreBacklog::StoreBacklog(FarmStore& store, std::size_t capacity, Written written)
    : store_(store), capacity_(capacity), written_(std::move(written)) {}

void StoreBacklog::add(Record record) {
  if (waiting_.size() >= capacity_) {
    ++dropped_;
    return;
  }
  waiting_.push_back(std::move(record));
}

void StoreBacklog::add_estimates(const std::vector<EstimateRecord>& batch) {
  if (batch.empty()) return;
  if (!error_.empty()) {
    estimates_dropped_ += batch.size();
    return;
  }
  try {
    store_.add_estimates(batch);
  } catch (const std::exception&) {
    // The events tell whether the store works; a batch of estimates lost is counted only.
    estimates_dropped_ += batch.size();
  }
}

bool StoreBacklog::write(const Record& record) {
  try {
    bool added = false;
    if (const auto* f = std::get_if<Fault>(&record))
      added = store_.add_fault(f->event, f->received_at);
    else if (const auto* c = std::get_if<ConfigRecord>(&record))
      added = store_.add_config(*c);
    else
      added = store_.add_health(std::get<HealthRecord>(record));
    if (added && written_) written_(record);
    return true;
  } catch (const std::exception& e) {
    error_ = e.what();
    return false;
  }
}

StoreBacklog::Change StoreBacklog::flush(double now) {
  const bool was_failing = !error_.empty();
  while (!waiting_.empty()) {
    if (!write(waiting_.front())) {
      if (was_failing) return Change::kNone;
      failing_since_ = now;
      return Change::kFailed;
    }
    waiting_.pop_front();
  }
  if (!was_failing) return Change::kNone;
  error_.clear();
  return Change::kRecovered;
}

std::string StoreBacklog::describe() const {
  if (error_.empty()) return "";
  return "store failing (" + error_ + "): " + std::to_string(waiting_.size()) + " events kept in memory" +
         (dropped_ ? ", " + std::to_string(dropped_) + " dropped" : "") +
         (estimates_dropped_ ? ", " + std::to_string(estimates_dropped_) + " estimates not stored" : "");
}

}  // namespace windfdi::farm
