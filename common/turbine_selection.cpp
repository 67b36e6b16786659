// Which turbines an executable serves: ids and FIRST..LAST ranges.
#include "turbine_selection.hpp"

#include <algorithm>

#include "yaml_config.hpp"

namespace windfdi {

namespace {
constexpr std::string_view kRangeDots = "..";

std::pair<std::string, std::string> split_range(const std::string& value, std::size_t dots) {
  return {value.substr(0, dots), value.substr(dots + kRangeDots.size())};
}
}  // namespace

std::string turbine_selection_error(const std::string& value) {
  if (value.empty()) return "an empty turbine id";
  if (value.find_first_of(" \t\n\r") != std::string::npos)
    return "'" + value + "': a turbine id has no spaces";
  const auto dots = value.find(kRangeDots);
  if (dots == std::string::npos) return "";
  const auto [first, last] = split_range(value, dots);
  if (first.empty() || last.empty() || last.find(kRangeDots) != std::string::npos)
    return "'" + value + "' is not a range FIRST..LAST of two ids (e.g. WT001..WT250)";
  if (last < first) return "'" + value + "': FIRST comes after LAST in byte order, the range is empty";
  return "";
}

TurbineSelection::TurbineSelection(const std::vector<std::string>& values) {
  for (const auto& value : values) {
    const std::string error = turbine_selection_error(value);
    if (!error.empty()) throw ConfigError("--turbine", 0, value, error);
    const auto dots = value.find(kRangeDots);
    if (dots == std::string::npos)
      ids_.push_back(value);
    else
      ranges_.push_back(split_range(value, dots));
  }
}

bool TurbineSelection::contains(std::string_view turbine_id) const {
  if (all()) return true;
  if (std::find(ids_.begin(), ids_.end(), turbine_id) != ids_.end()) return true;
  return std::any_of(ranges_.begin(), ranges_.end(), [&](const auto& range) {
    return std::string_view(range.first) <= turbine_id && turbine_id <= std::string_view(range.second);
  });
}

}  // namespace windfdi
