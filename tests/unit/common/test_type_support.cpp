// The generated topic types: constructing a sample registers nothing (the build strips fastddsgen's
// per-sample TypeObject registration), and the one-time registration a content filter needs still works.
#include <fastrtps/types/TypeObjectFactory.h>
#include <gtest/gtest.h>

#include "FaultReport.h"
#include "TurbineFrame.h"
#include "TurbineFrameTypeObject.h"

namespace {

const eprosima::fastrtps::types::TypeIdentifier* registered(const std::string& type) {
  return eprosima::fastrtps::types::TypeObjectFactory::get_instance()->get_type_identifier(type, true);
}

TEST(TypeSupport, ConstructingASampleRegistersNoTypeObject) {
  // GIVEN samples constructed as a service constructs them: a frame block of 10 (deserialising one resizes
  // its sequence) and a fault report. fastddsgen 2.3 ran register<File>Types() in every default constructor:
  // a global lock and string-keyed map lookups per sample, about an eighth of windfdi-sensor-bias's CPU at
  // 160 turbines (common/cmake/strip_type_registration.cmake).
  windfdi::TurbineFrame frame;
  frame.samples().resize(10);
  windfdi::FaultReport report;
  // THEN no TypeObject was registered by them
  EXPECT_EQ(registered("windfdi::TurbineSample"), nullptr);
  EXPECT_EQ(registered("windfdi::TurbineFrame"), nullptr);
  // AND the registration a content filter needs (once, with the participant) still works
  registerTurbineFrameTypes();
  EXPECT_NE(registered("windfdi::TurbineSample"), nullptr);
  EXPECT_NE(registered("windfdi::TurbineFrame"), nullptr);
}

}  // namespace
