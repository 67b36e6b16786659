// The typed service adapter: a core of the common shape and one field list give the replay columns, the
// CSV values and the DDS sample, consistently.
#include <gtest/gtest.h>

#include "diagnostic_service.hpp"
#include "ice_detect_estimate_topic.hpp"

using namespace windfdi;

namespace {

struct ToyEstimate {
  double t = 0.0;
  double inertia = 0.0;
  double ice_mass = 0.0;
  bool excited = false;
};

/// Rejects a NaN rotor speed, raises one event at t = 1 s, an estimate every second sample.
class ToyCore {
 public:
  bool update(const FrameSample& s, bool, std::vector<FaultEvent>& events) {
    if (std::isnan(s.rotor_speed)) return false;
    if (s.t == 1.0) {
      FaultEvent e;
      e.t = s.t;
      e.component = "rotor";
      e.fault = "ice_accretion";
      events.push_back(e);
    }
    last_ = {s.t, 400.0 + s.t, 10.0 * s.t, s.t > 0.5};
    due_ = (++n_ % 2) == 0;
    return true;
  }
  bool estimate_due(ToyEstimate& out) {
    if (!due_) return false;
    due_ = false;
    out = last_;
    return true;
  }
  void set_context(const InputContext& c, double) { stopped = c.turbine_stopped; }
  bool stopped = false;

 private:
  ToyEstimate last_;
  bool due_ = false;
  int n_ = 0;
};

using Idl = windfdi::InertiaEstimate;

TypedService<ToyCore, ToyEstimate, Idl> toy() {
  TypedService<ToyCore, ToyEstimate, Idl> s;
  s.name = "toy";
  s.fields = {
      number_field<ToyEstimate, Idl>(
          "inertia", [](const ToyEstimate& e) { return e.inertia; }, [](Idl& o, double v) { o.inertia(v); }),
      number_field<ToyEstimate, Idl>(
          "ice_mass", [](const ToyEstimate& e) { return e.ice_mass; },
          [](Idl& o, double v) { o.ice_mass(v); }),
      flag_field<ToyEstimate, Idl>(
          "excited", [](const ToyEstimate& e) { return e.excited; }, [](Idl& o, bool v) { o.excited(v); }),
      // DDS only: no column
      {{}, nullptr, [](const ToyEstimate&, Idl& o) { o.inertia_clean(400.0); }},
  };
  s.configure = [](const YamlSection&) {};
  s.make = [](const std::string&) { return std::make_unique<ToyCore>(); };
  return s;
}

}  // namespace

TEST(ServiceAdapter, OneFieldListGivesTheColumnsTheValuesAndTheSample) {
  const TypedService<ToyCore, ToyEstimate, Idl> typed = toy();
  const ServiceSpec spec = service_spec(typed);
  // THEN the replay columns are the fields' in order, the DDS-only field has none
  EXPECT_EQ(spec.estimate_columns, (std::vector<std::string>{"inertia", "ice_mass", "excited"}));
  auto d = spec.make("WT07");
  std::vector<FaultEvent> events;
  std::vector<std::string> values;
  FrameSample s;
  s.rotor_speed = 1.2;
  // WHEN samples arrive: the core's answers pass through (rejection, events, estimates at its rate)
  s.t = 0.5;
  EXPECT_TRUE(d->update(s, false, events));
  EXPECT_FALSE(d->estimate_due());
  s.t = 1.0;
  EXPECT_TRUE(d->update(s, false, events));
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].fault, "ice_accretion");
  ASSERT_TRUE(d->estimate_due());
  d->estimate_values(values);
  EXPECT_EQ(values, (std::vector<std::string>{format_number(401.0), format_number(10.0), "1"}));
  s.rotor_speed = kNaN;
  EXPECT_FALSE(d->update(s, false, events));
  // AND the DDS sample carries the same estimate, the turbine id and the DDS-only field
  const auto& typed_d = static_cast<CoreDiagnoser<ToyCore, ToyEstimate, Idl>&>(*d);
  const Idl e = typed_d.sample("WT07");
  EXPECT_EQ(e.turbine_id(), "WT07");
  EXPECT_DOUBLE_EQ(e.t(), 1.0);
  EXPECT_DOUBLE_EQ(e.inertia(), 401.0);
  EXPECT_DOUBLE_EQ(e.ice_mass(), 10.0);
  EXPECT_TRUE(e.excited());
  EXPECT_DOUBLE_EQ(e.inertia_clean(), 400.0);
}
