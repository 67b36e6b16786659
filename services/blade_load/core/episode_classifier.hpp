// Fault-episode state machine of one blade-moment sensor (Stotsky 2014 classes): raise, return, intermittent,
// clear.
#pragma once

#include <string>
#include <vector>

namespace windfdi::blade_load {

struct EpisodeConfig {
  double return_time = 3.0;  ///< s without evidence: the episode is over (the sensor returned), > 0
  double intermittent_window =
      120.0;                  ///< s: a new confirmed episode within this after a return -> intermittent
  double clear_time = 120.0;  ///< s after a return with no new episode: the fault clears (>= window)
  /// A raised drift whose evidence came back after a return as a ramp in its own direction is the drift going
  /// on, not an intermittent gauge (whose episodes step away and back): the episode resumes under its name.
  /// One revolution's dip of a growing drift below the onset level (3.6 s at rated speed) ended its episode
  /// and its next revolutions renamed it sensor_intermittent (fault sets 385-389, 3 drifts). false: renamed
  bool drift_resumes = true;
};

/// One reported change: `fault` raised (true) or cleared (false).
struct Transition {
  std::string fault;
  bool raised = false;
};

/// Hysteresis per blade. `active`: evidence now (any test above its threshold); `confirmed`: evidence that
/// has persisted long enough to raise; `cls`: the class to raise when a new fault starts (sensor_abrupt /
/// _drift).
///   healthy --confirmed--> raised(cls), episode on
///   episode on --quiet for return_time--> returned (at the start of the quiet spell)
///   returned --confirmed within intermittent_window--> cleared(cls) + raised(sensor_intermittent), episode
///   on (a raised drift confirmed again as its own ramp: the episode resumes, drift_resumes)
///   returned --quiet for clear_time--> cleared
/// A class change is a clear of the old class and a raise of the new one: a FaultReport instance is
/// (turbine, source, component), so its last state is always the current class. Once intermittent, further
/// episodes produce no event (no storm); a flicker shorter than return_time never ends an episode, and one
/// shorter than the confirmation never starts one.
class EpisodeClassifier {
 public:
  explicit EpisodeClassifier(const EpisodeConfig& c = {}) : c_(c) {}
  /// `known` false: no test could judge now (the windows refill after lost samples): no evidence either way,
  /// so no quiet spell runs through it.
  /// `continues`: the confirmed evidence is the raised class's own ramp in its raised direction (see
  /// drift_resumes).
  void update(double t, bool active, bool confirmed, const std::string& cls, std::vector<Transition>& out,
              bool known = true, bool continues = false);
  const std::string& raised() const { return raised_; }
  bool returned() const { return returned_; }
  double raised_at() const { return raised_at_; }
  const EpisodeConfig& config() const { return c_; }
  void reset() { *this = EpisodeClassifier(c_); }

 private:
  EpisodeConfig c_;
  std::string raised_;
  double raised_at_ = 0.0;
  bool returned_ = false;
  double returned_at_ = 0.0;   // start of the quiet spell that ended the last episode
  double quiet_since_ = -1.0;  // start of the current evidence-free spell (-1: evidence now)
};

}  // namespace windfdi::blade_load
