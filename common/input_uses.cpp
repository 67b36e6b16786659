// What a diagnostic service does with each of a turbine's measured inputs, and what it cannot do without
// them.
#include "input_uses.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

#include "yaml_config.hpp"

namespace windfdi {

namespace {

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

void add_once(std::vector<std::string>& to, const std::string& name) {
  if (std::find(to.begin(), to.end(), name) == to.end()) to.push_back(name);
}

}  // namespace

std::vector<InputUse> per_blade(const InputUse& pattern) {
  std::vector<InputUse> out;
  for (int b = 1; b <= 3; ++b) {
    const std::string n = std::to_string(b);
    const auto fill = [&](std::string text) {
      for (auto at = text.find("{blade}"); at != std::string::npos; at = text.find("{blade}"))
        text.replace(at, 7, n);
      return text;
    };
    InputUse u{fill(pattern.purpose), {}, pattern.essential, fill(pattern.without)};
    for (const auto& c : pattern.columns) u.columns.push_back(c + "_" + n);
    out.push_back(u);
  }
  return out;
}

InputCheck check_inputs(const std::vector<InputUse>& uses,
                        const std::function<bool(const std::string&)>& present) {
  InputCheck c;
  for (const auto& use : uses) {
    std::vector<std::string> lacking;
    for (const auto& column : use.columns) {
      if (present(column))
        add_once(c.present, column);
      else
        lacking.push_back(column);
    }
    if (lacking.empty()) {
      c.any_essential |= use.essential;
      continue;
    }
    c.lines.push_back("lacks " + joined(lacking) + " (" + use.purpose + "): " + use.without);
    if (use.essential)
      for (const auto& l : lacking) add_once(c.missing, l);
  }
  return c;
}

void report_inputs(const std::string& service, const std::vector<InputUse>& uses,
                   const std::function<bool(const std::string&)>& present, const std::string& source,
                   bool fatal) {
  if (uses.empty()) return;
  const InputCheck c = check_inputs(uses, present);
  spdlog::info("{}: {} carries {}", service, source,
               c.present.empty() ? "none of its inputs" : joined(c.present));
  for (const auto& line : c.lines) spdlog::warn("{}: {} {}", service, source, line);
  if (c.any_essential) return;
  const std::string message = "carries none of the inputs that " + service +
                              " needs for any of its diagnoses; missing: " + joined(c.missing);
  if (fatal) throw ConfigError(source, 1, joined(c.missing), message);
  spdlog::error("{}: {} {}: nothing will be diagnosed there", service, source, message);
}

}  // namespace windfdi
