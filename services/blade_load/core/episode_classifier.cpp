// Fault-episode state machine of one blade-moment sensor: abrupt/drift, intermittent, clear (see the header).
#include "episode_classifier.hpp"

namespace windfdi::blade_load {

void EpisodeClassifier::update(double t, bool active, bool confirmed, const std::string& cls,
                               std::vector<Transition>& out, bool known, bool continues) {
  // Windows refilling after lost samples read as a quiet spell: a raised step "returned" and, confirmed again
  // a revolution later, was renamed sensor_intermittent (20 samples lost every 5-20 s).
  if (active || !known) {
    quiet_since_ = -1.0;
  } else if (quiet_since_ < 0) {
    quiet_since_ = t;
  }
  if (!active && !known) return;
  if (raised_.empty()) {
    if (confirmed) {
      raised_ = cls;
      raised_at_ = t;
      returned_ = false;
      out.push_back({raised_, true});
    }
    return;
  }
  if (!returned_) {
    if (!active && t - quiet_since_ >= c_.return_time) {
      returned_ = true;
      returned_at_ = quiet_since_;
    }
    return;
  }
  // Returned: the quiet spell started at quiet_since_ (or evidence is back without confirmation yet).
  if (confirmed) {
    const bool resumes = c_.drift_resumes && continues && raised_ == "sensor_drift" && cls == raised_;
    if (!resumes && raised_ != "sensor_intermittent" && t - returned_at_ <= c_.intermittent_window) {
      out.push_back({raised_, false});
      raised_ = "sensor_intermittent";
      raised_at_ = t;
      out.push_back({raised_, true});
    }
    returned_ = false;
    return;
  }
  if (!active && quiet_since_ >= 0 && t - quiet_since_ >= c_.clear_time) {
    out.push_back({raised_, false});
    raised_.clear();
    returned_ = false;
  }
}

}  // namespace windfdi::blade_load
