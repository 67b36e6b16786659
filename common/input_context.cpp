// A turbine's suspect inputs from other services' fault reports.
#include "input_context.hpp"

#include "names.hpp"

namespace windfdi {

bool InputContextTracker::on_fault(const FaultEvent& e) {
  if (e.source == own_) return false;
  const std::string key = e.source + "/" + e.component + "/" + e.fault;
  const auto it = raised_.find(key);
  if (it != raised_.end() && it->second == e.raised) return false;  // a repeat (transient-local replay)
  if (it == raised_.end() && !e.raised) return false;
  raised_[key] = e.raised;
  const InputContext before = context_;
  rebuild();
  if (!before.same_transient_inputs(context_)) ++context_.transitions;
  return !(before == context_);
}

void InputContextTracker::rebuild() {
  InputContext c;
  c.transitions = context_.transitions;
  c.turbine_stopped = context_.turbine_stopped;
  c.pitch_rate_limit = context_.pitch_rate_limit;
  for (const auto& [key, raised] : raised_) {
    if (!raised) continue;
    const auto a = key.find('/'), b = key.find('/', a + 1);
    const std::string component = key.substr(a + 1, b - a - 1);
    const int blade = blade_index(component);
    if (component == "rotor_speed_sensor") c.rotor_speed_suspect = true;
    if (component == "generator_speed_sensor") c.generator_speed_suspect = true;
    if (blade >= 0 && component.rfind("pitch_sensor_", 0) == 0) c.pitch_sensor_suspect[blade] = true;
    if (blade >= 0 && component.rfind("pitch_actuator_", 0) == 0) c.pitch_actuator_suspect[blade] = true;
    if (component == "drive_train") c.drive_train_suspect = true;
  }
  context_ = c;
}

}  // namespace windfdi
