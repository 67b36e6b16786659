// Which turbines an executable serves: the --turbine values, each a turbine id or a range FIRST..LAST.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace windfdi {

/// Whether a --turbine value is a range "FIRST..LAST".
bool is_turbine_range(const std::string& value);

/// The bounds of a range "FIRST..LAST": every id with FIRST <= id <= LAST in byte order, so numbers in ids
/// need zero padding (WT001..WT250 holds WT010; WT1..WT250 does not). Throws ConfigError (key --turbine) for
/// an empty bound or FIRST after LAST.
std::pair<std::string, std::string> turbine_range(const std::string& value);

/// Why a --turbine value is not a valid id or range ("" when it is): empty, a space in it (the DDS filter
/// expression separates values by spaces), or a malformed or empty range.
std::string turbine_selection_error(const std::string& value);

/// Whether `turbine_id` is selected by the --turbine values (none: every turbine).
bool turbine_selected(const std::vector<std::string>& selection, const std::string& turbine_id);

/// The plain ids among the --turbine values (ranges left out).
std::vector<std::string> turbine_ids(const std::vector<std::string>& selection);

}  // namespace windfdi
