// The farm store's writes in order, kept in memory while the disk cannot take them (full, read-only).
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <string>
#include <variant>

#include "farm_store.hpp"

namespace windfdi::farm {

/// Events go to the store through this backlog: written at once while the store works, kept in arrival
/// order while it fails, and written as soon as it works again, so a full or read-only disk loses nothing
/// that memory can hold. Estimates are samples, not events: they are not kept through a fault.
class StoreBacklog {
 public:
  struct Fault {
    FaultEvent event;
    double received_at = 0.0;
  };
  using Record = std::variant<Fault, ConfigRecord, HealthRecord>;
  /// Called for each record the store took as new (the node logs it).
  using Written = std::function<void(const Record&)>;

  /// `capacity`: records kept while the store fails; past it the newest are dropped and counted.
  explicit StoreBacklog(FarmStore& store, std::size_t capacity = 200000, Written written = nullptr);

  void add(Record record);
  /// Stores the estimates unless the store is failing (then they are dropped and counted).
  void add_estimates(const std::vector<EstimateRecord>& batch);
  enum class Change { kNone, kFailed, kRecovered };
  /// Writes what waits, oldest first, until the store fails; says whether the store just failed or just
  /// recovered (an estimate batch that failed counts: the next flush tries the events).
  Change flush(double now);

  /// "" while the store works; else its error (e.g. "database or disk is full").
  const std::string& error() const { return error_; }
  std::size_t waiting() const { return waiting_.size(); }
  uint64_t dropped() const { return dropped_; }
  uint64_t estimates_dropped() const { return estimates_dropped_; }
  /// Wall time the current failure began.
  double failing_since() const { return failing_since_; }
  /// One line for the farm monitor's health and log ("" while the store works).
  std::string describe() const;

 private:
  bool write(const Record& record);  // false: the store failed (error_ set)

  FarmStore& store_;
  std::size_t capacity_;
  Written written_;
  std::deque<Record> waiting_;
  std::string error_;
  double failing_since_ = 0.0;
  uint64_t dropped_ = 0, estimates_dropped_ = 0;
};

}  // namespace windfdi::farm
