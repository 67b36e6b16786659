// One turbine's ice diagnosis as every service core is shaped: frame samples in (the aerodynamic power taken
// from the recording or the model on the centred anemometer average), inertia estimates and events out.
#pragma once

#include <vector>

#include "aero_power_input.hpp"
#include "ice_detector.hpp"

namespace windfdi::ice_detect {

class IceTurbine {
 public:
  /// `aero` must outlive this object (one model per process).
  IceTurbine(const DetectorConfig& config, const TurbineParams& turbine, const AeroModel& aero)
      : detector_(config, turbine),
        aero_power_(aero, config.wind_window, config.estimator.sample_time),
        fixed_pitch_(turbine.fixed_pitch) {}

  /// Feeds one sample; it is judged half an anemometer window later (AeroPowerInput). False when the
  /// sample judged now was rejected.
  bool update(const FrameSample& s, bool gap, std::vector<FaultEvent>& events) {
    FrameSample centre;
    bool centre_gap = false;
    double power = kNaN;
    if (!aero_power_.push(s, gap, centre, centre_gap, power)) return true;
    return detector_.update(centre, power, centre_gap, events);
  }
  bool estimate_due(InertiaOutput& out) { return detector_.estimate_due(out); }
  void set_context(const InputContext& context, double) {
    detector_.set_context(context);
    aero_power_.set_absent(context.absent, fixed_pitch_);
  }
  const IceDetector& detector() const { return detector_; }

 private:
  IceDetector detector_;
  AeroPowerInput aero_power_;
  double fixed_pitch_;  // deg, for a pitch the data does not carry
};

}  // namespace windfdi::ice_detect
