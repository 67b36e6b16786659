// Turbine-level fault isolation over the fault-signature table.
#include "isolation.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "names.hpp"

namespace windfdi::isolation {

const std::vector<Signature>& signature_table() {
  // Rows: root cause -> a residual of another service that it moves. Columns of the documented table are
  // the responders; a service's own residual for its own fault is not listed (that report is the root).
  static const std::vector<Signature> t = {
      // sensor_bias reports a speed-sensor fault up to type_decision_time (rotor speed 60 s, generator speed
      // below rated 20 s) after its onset, while it weighs gain against offset: a responder that reacts
      // at the onset (blade_load's lambda, ice_detect's inertia, drive_train's balance) may lead it by that
      // much more. The pitch responds to the controller, which acts on the report (a switch to the
      // corrected speed) or, for the generator speed above rated, within its 5 s wait: those rows keep
      // shorter leads, so that a leak a minute before a speed report is still its own root.
      // The controller moves the pitch on a wrong speed until the arbiter switches it to the corrected
      // speed on the speed's report; the switch's transient is seconds. An actuator report raised 20 s or
      // more after the speed's is the actuator's own: 18 such in fault suite sets 120-172, all real
      // (25-167 s after the speed's report, pump wear or air in the oil), and no echo raised later than
      // the report. Kept secondary, the arbiter would not have derated the blade until the speed cleared.
      {"rotor_speed_sensor", "*", "blade_load", "blade_moment_sensor_*",
       "the LIDAR load model's tip-speed ratio uses the rotor speed", 80.0},
      {"rotor_speed_sensor", "*", "pitch_diag", "pitch_actuator_*",
       "the speed controller moves every pitch reference on a wrong speed", 40.0, false, 20.0},
      {"rotor_speed_sensor", "*", "sensor_bias", "pitch_sensor_*", "the same pitch transient", 40.0},
      {"rotor_speed_sensor", "*", "ice_detect", "rotor", "the inertia is estimated from the speed", 80.0},
      {"generator_speed_sensor", "*", "blade_load", "blade_moment_sensor_*",
       "the controller's pitch and speed move the blade loads", 40.0},
      {"generator_speed_sensor", "*", "pitch_diag", "pitch_actuator_*",
       "the pitch controller runs on the generator speed", 0.0, false, 20.0},
      {"generator_speed_sensor", "*", "sensor_bias", "pitch_sensor_*", "the same pitch transient"},
      {"generator_speed_sensor", "*", "ice_detect", "rotor", "the inertia is estimated from the speed", 40.0},
      // Once the generator speed is reported the balance takes the rotor's sensor, drops its last minute of
      // blocks and judges again only after a minute of new ones: a loss it raises 30 s or more after the
      // report is the drive train's own (four such in fault suite sets 168-171).
      {"generator_speed_sensor", "*", "drive_train", "drive_train",
       "the energy balance takes the rotor's speed (for Cp) and acceleration from the generator speed", 40.0,
       false, 30.0},
      {"generator_speed_sensor", "*", "sensor_bias", "rotor_speed_sensor",
       "the drive-train observer places part of a generator-speed error on the rotor-speed bias", 40.0},
      // sensor_bias confirms a pitch-sensor fault only on a static offset or gain of (pitch - reference),
      // which no Table 1 actuator fault has (static gain 1): with both reports standing the sensor is the
      // root whichever came first. pitch_diag read a 1.06 deg pitch-sensor bias as a critical leak 0.2 s
      // after its onset, sensor_bias confirmed the bias 13 s later, and the leak stopped the turbine (suite
      // seed 60, the example 2 MW turbine).
      {"pitch_sensor_i", "*", "pitch_diag", "pitch_actuator_i",
       "the measured pitch is the identified actuator output", 30.0, true},
      {"pitch_sensor_i", "*", "blade_load", "blade_moment_sensor_i",
       "the blade's load model takes its pitch"},
      {"pitch_actuator_i", "*", "sensor_bias", "pitch_sensor_i",
       "the pitch observer predicts with the healthy actuator model"},
      {"pitch_actuator_i", "*", "blade_load", "blade_moment_sensor_i",
       "the blade's load follows its real pitch"},
      {"rotor", "ice_accretion,ice_shedding", "blade_load", "blade_moment_sensor_*",
       "ice changes the blades' aerodynamics and mass"},
      // Once the ice is weighed, the balance's reference blocks carry it: it raises a drop on an iced rotor
      // only where a step fits far better than the bend of growing ice (drive_train iced_step_share). In the
      // fault suite's 25 tuning sets and the 5 judged sets 270-274, all 6 efficiency losses raised 163-2291 s
      // after an ice report were real, and every echo of ice came before its report.
      {"rotor", "ice_accretion", "drive_train", "drive_train",
       "ice lowers the rotor's Cp, which the drive train's energy balance reads as an efficiency loss before "
       "ice_detect has weighed the ice by the rotor's inertia",
       900.0, false, 60.0},
  };
  return t;
}

namespace {

// Blade number ('1'..'3') of a blade component, or 0.
char blade_of(const std::string& component) {
  const int i = blade_index(component);
  return i < 0 ? 0 : static_cast<char>('1' + i);
}

// Matches `component` against a row pattern; `bound` is the blade the other side fixed (0: none).
bool matches(const char* pattern, const std::string& component, char bound) {
  const std::size_t n = std::strlen(pattern);
  if (n >= 2 && pattern[n - 2] == '_' && (pattern[n - 1] == '*' || pattern[n - 1] == 'i')) {
    const char blade = blade_of(component);
    if (!blade || component.compare(0, n - 1, pattern, n - 1) != 0 || component.size() != n) return false;
    return pattern[n - 1] == '*' || bound == 0 || blade == bound;
  }
  return component == pattern;
}

bool class_listed(const char* classes, const std::string& fault) {
  if (std::strcmp(classes, "*") == 0) return true;
  const std::string list = std::string(",") + classes + ",";
  return list.find("," + fault + ",") != std::string::npos;
}

const Signature* row_for(const Report& root, const Report& responder) {
  if (root.component == responder.component) return nullptr;
  for (const auto& s : signature_table()) {
    if (responder.source != s.responder_source || !class_listed(s.root_classes, root.fault)) continue;
    const std::size_t n = std::strlen(s.root_component);
    const bool per_blade = n >= 2 && s.root_component[n - 1] == 'i' && s.root_component[n - 2] == '_';
    const char blade = per_blade ? blade_of(root.component) : 0;
    if (matches(s.root_component, root.component, 0) &&
        matches(s.responder_component, responder.component, blade))
      return &s;
  }
  return nullptr;
}

bool is_blade_sensor_family(const std::string& c) {
  return c.rfind("blade_moment_sensor_", 0) == 0 || c.rfind("pitch_sensor_", 0) == 0;
}

}  // namespace

bool explains(const Report& root, const Report& responder) { return row_for(root, responder) != nullptr; }

double longest_lead(const IsolationConfig& config) {
  double lead = config.lead;
  for (const auto& s : signature_table()) lead = std::max(lead, s.lead);
  return lead;
}

std::vector<Verdict> isolate(const std::vector<Report>& reports, const IsolationConfig& c) {
  const std::size_t n = reports.size();
  std::vector<Verdict> out(n);
  // The responder's report within the row's lead before its root's and its trail after it.
  const auto echo = [&](const Signature* row, const Report& root, const Report& responder) {
    const double lead = row->lead > 0.0 ? row->lead : c.lead;
    return responder.t_detected >= root.t_detected - lead &&
           (row->trail <= 0.0 || responder.t_detected <= root.t_detected + row->trail);
  };
  for (std::size_t r = 0; r < n; ++r) {
    const Report& R = reports[r];
    for (std::size_t s = 0; s < n; ++s) {
      const Report& S = reports[s];
      const Signature* row = s == r ? nullptr : row_for(S, R);
      if (!row || !echo(row, S, R)) continue;  // R came long before S (or after its trail): not S's echo
      const Signature* back = row_for(R, S);
      if (back && echo(back, R, S)) {
        // Each explains the other: a row that outranks the other decides; else the one seen first is the
        // root, a sensor winning a tie.
        const bool s_root =
            row->outranks != back->outranks
                ? row->outranks
                : S.t_detected < R.t_detected ||
                      (S.t_detected == R.t_detected && S.component.find("sensor") != std::string::npos);
        if (!s_root) continue;
      }
      out[r] = {true, S.component + " " + S.fault, row->why};
      break;
    }
  }
  // The same service on every blade's sensor at once: one common cause (the shared model, the wind, a shared
  // input), not three sensor faults.
  for (std::size_t r = 0; r < n; ++r) {
    const Report& R = reports[r];
    if (out[r].secondary || !is_blade_sensor_family(R.component) || !blade_of(R.component)) continue;
    const std::string family = R.component.substr(0, R.component.size() - 1);
    bool seen[3] = {false, false, false};
    for (const auto& S : reports)
      if (S.source == R.source && S.component.compare(0, family.size(), family) == 0 &&
          S.component.size() == family.size() + 1 &&
          std::fabs(S.t_detected - R.t_detected) <= c.common_window)
        seen[blade_of(S.component) - '1'] = true;
    if (seen[0] && seen[1] && seen[2])
      out[r] = {true, "common cause on every blade",
                "the same residual on all three blades at once is one shared cause, not three sensor faults"};
  }
  return out;
}

}  // namespace windfdi::isolation
