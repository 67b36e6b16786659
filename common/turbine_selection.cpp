// Which turbines an executable serves: ids and FIRST..LAST ranges.
#include "turbine_selection.hpp"

#include <algorithm>

#include "yaml_config.hpp"

namespace windfdi {

bool is_turbine_range(const std::string& value) { return value.find("..") != std::string::npos; }

namespace {
std::pair<std::string, std::string> split_range(const std::string& value) {
  const auto dots = value.find("..");
  return {value.substr(0, dots), value.substr(dots + 2)};
}
}  // namespace

std::string turbine_selection_error(const std::string& value) {
  if (value.empty()) return "an empty turbine id";
  if (value.find_first_of(" \t\n\r") != std::string::npos)
    return "'" + value + "': a turbine id has no spaces";
  if (!is_turbine_range(value)) return "";
  const auto [first, last] = split_range(value);
  if (first.empty() || last.empty() || is_turbine_range(last))
    return "'" + value + "' is not a range FIRST..LAST of two ids (e.g. WT001..WT250)";
  if (last < first) return "'" + value + "': FIRST comes after LAST in byte order, the range is empty";
  return "";
}

std::pair<std::string, std::string> turbine_range(const std::string& value) {
  const std::string error = turbine_selection_error(value);
  if (!error.empty()) throw ConfigError("--turbine", 0, value, error);
  return split_range(value);
}

bool turbine_selected(const std::vector<std::string>& selection, const std::string& turbine_id) {
  if (selection.empty()) return true;
  return std::any_of(selection.begin(), selection.end(), [&](const std::string& value) {
    if (!is_turbine_range(value)) return value == turbine_id;
    const auto [first, last] = turbine_range(value);
    return first <= turbine_id && turbine_id <= last;
  });
}

std::vector<std::string> turbine_ids(const std::vector<std::string>& selection) {
  std::vector<std::string> ids;
  for (const auto& value : selection)
    if (!is_turbine_range(value)) ids.push_back(value);
  return ids;
}

}  // namespace windfdi
