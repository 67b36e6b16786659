// How many turbines an instance keeps state for, and which: a bound against peers that name any number.
#pragma once

#include <cstdint>
#include <set>
#include <string>
#include <string_view>

#include "fault_event.hpp"

namespace windfdi {

/// How many turbines an instance keeps state for when no --max-turbines is given: twice the 500 turbines one
/// instance serves in the capacity benchmark (README "Farm capacity").
constexpr std::size_t kDefaultMaxTurbines = 1000;
/// The longest turbine id an instance takes (bytes); the IDL's strings are unbounded.
constexpr std::size_t kMaxTurbineIdLength = 64;

/// The turbines an instance keeps state for: at most `max_turbines`, the first it hears of. A peer on an
/// unsecured domain can name any number of turbines (10 000 made-up ids in the reliability campaign) with ids
/// of any length, and each would cost a diagnoser, its histories and a health report a second. Not
/// thread-safe: one loop admits.
class TurbineLimit {
 public:
  /// `where`: what refuses, for the log ("pitch_diag", "arbiter").
  TurbineLimit(std::size_t max_turbines, std::string where);

  /// Whether `turbine_id` is followed: already, or from now on because there is room and the id is well
  /// formed (1..kMaxTurbineIdLength printable bytes, no space). "*" (every turbine) always is. A refusal is
  /// counted and logged: the first, then at 10, 100, 1000... refusals.
  bool admit(std::string_view turbine_id);
  std::size_t followed() const { return followed_.size(); }
  uint64_t refused() const { return refused_; }
  /// "" while nothing was refused, else how many messages and why (the first refused id, shortened).
  std::string describe() const;

 private:
  std::size_t max_;
  std::string where_;
  std::set<std::string, std::less<>> followed_;
  uint64_t refused_ = 0;
  std::string first_refused_;
};

/// Drops FaultReports no windfdi service could have sent (foreign_report_reason), counting them and logging
/// at the 1st, 10th, 100th... one; the services, the arbiter and the farm monitor check a report with it
/// before its turbine is admitted, so a foreign report takes no place among the turbines followed.
class ForeignReports {
 public:
  /// True when `e` is foreign (and then counted and, at a power of ten, logged).
  bool refuse(const FaultEvent& e);

 private:
  uint64_t count_ = 0;
};

}  // namespace windfdi
