// How many turbines an instance keeps state for, and which.
#include "turbine_limit.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

#include "app.hpp"

namespace windfdi {

namespace {
bool well_formed_id(std::string_view id) {
  if (id.empty() || id.size() > kMaxTurbineIdLength) return false;
  return std::all_of(id.begin(), id.end(), [](char c) { return c > ' ' && c < 127; });
}

std::string shortened(std::string_view id) {
  std::string out(id.substr(0, kMaxTurbineIdLength));
  for (auto& c : out)
    if (c <= ' ' || c >= 127) c = '?';
  return id.size() > kMaxTurbineIdLength ? out + "... (" + std::to_string(id.size()) + " bytes)" : out;
}
}  // namespace

TurbineLimit::TurbineLimit(std::size_t max_turbines, std::string where)
    : max_(max_turbines), where_(std::move(where)) {}

bool TurbineLimit::admit(std::string_view turbine_id) {
  if (turbine_id == "*" || followed_.find(turbine_id) != followed_.end()) return true;
  const bool well_formed = well_formed_id(turbine_id);
  if (well_formed && followed_.size() < max_) {
    followed_.emplace(turbine_id);
    return true;
  }
  if (refused_++ == 0) first_refused_ = shortened(turbine_id);
  if (worth_logging(refused_))
    spdlog::warn("{}: {} (this one: {}; {})", where_, describe(), shortened(turbine_id),
                 well_formed ? "raise --max-turbines if the farm has more turbines"
                             : "a turbine id is 1 to 64 printable bytes without spaces");
  return false;
}

std::string TurbineLimit::describe() const {
  if (refused_ == 0) return "";
  return std::to_string(refused_) + " messages refused for turbines past --max-turbines " +
         std::to_string(max_) + " or with malformed ids, " + std::to_string(followed_.size()) +
         " followed; first refused: " + first_refused_;
}

bool ForeignReports::refuse(const FaultEvent& e) {
  const std::string why = foreign_report_reason(e);
  if (why.empty()) return false;
  if (worth_logging(++count_))
    spdlog::warn("{}: ignoring a FaultReport ({} so far): {}", shortened(e.turbine_id), count_, why);
  return true;
}

}  // namespace windfdi
