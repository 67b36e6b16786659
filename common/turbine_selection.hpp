// Which turbines an executable serves: the --turbine values, each a turbine id or a range FIRST..LAST.
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace windfdi {

/// Why a --turbine value is not a valid id or range ("" when it is): empty, a space in it (the DDS filter
/// expression separates values by spaces), or a malformed or empty range.
std::string turbine_selection_error(const std::string& value);

/// The --turbine values parsed once, so that asking about a turbine (per sample, in the frame writer's
/// filter and the arbiter) neither re-validates nor allocates. A range FIRST..LAST holds every id with
/// FIRST <= id <= LAST in byte order, so numbers in ids need zero padding (WT001..WT250 holds WT010;
/// WT1..WT250 does not).
class TurbineSelection {
 public:
  /// No values: every turbine.
  TurbineSelection() = default;
  /// Throws ConfigError (key --turbine) naming the first invalid value.
  explicit TurbineSelection(const std::vector<std::string>& values);

  bool contains(std::string_view turbine_id) const;
  /// Whether no value was given (every turbine is served).
  bool all() const { return ids_.empty() && ranges_.empty(); }
  /// The plain ids among the values (ranges left out): the turbines known before any sample arrives.
  const std::vector<std::string>& ids() const { return ids_; }

 private:
  std::vector<std::string> ids_;
  std::vector<std::pair<std::string, std::string>> ranges_;  // FIRST, LAST
};

}  // namespace windfdi
