// Unit tests of a service's input uses against what a turbine's data carries.
#include <gtest/gtest.h>

#include <set>

#include "frame_sample.hpp"
#include "input_uses.hpp"
#include "replay_csv.hpp"
#include "yaml_config.hpp"

using namespace windfdi;

namespace {

std::function<bool(const std::string&)> carries(std::set<std::string> columns) {
  return [columns](const std::string& c) { return columns.count(c) > 0; };
}

const std::vector<InputUse> kUses = {
    {"the speeds", {"rotor_speed", "generator_speed"}, true, "no speed diagnosis"},
    {"the witness", {"power"}, false, "no common-mode bias"},
};

}  // namespace

TEST(InputUses, PerBladeMakesOneUsePerBladeWithItsColumnsAndNumber) {
  const auto uses = per_blade({"blade {blade}'s actuator", {"pitch", "pitch_ref"}, true, "{blade} not done"});
  ASSERT_EQ(uses.size(), 3u);
  EXPECT_EQ(uses[1].purpose, "blade 2's actuator");
  EXPECT_EQ(uses[1].columns, (std::vector<std::string>{"pitch_2", "pitch_ref_2"}));
  EXPECT_EQ(uses[2].without, "3 not done");
  EXPECT_TRUE(uses[0].essential);
}

TEST(InputUses, AnAbsentAidIsSaidAndTheServiceRuns) {
  const InputCheck c = check_inputs(kUses, carries({"rotor_speed", "generator_speed"}));
  EXPECT_TRUE(c.any_essential);
  EXPECT_EQ(c.present, (std::vector<std::string>{"rotor_speed", "generator_speed"}));
  ASSERT_EQ(c.lines.size(), 1u);
  EXPECT_EQ(c.lines[0], "lacks power (the witness): no common-mode bias");
  EXPECT_TRUE(c.missing.empty());
  EXPECT_NO_THROW(report_inputs("svc", kUses, carries({"rotor_speed", "generator_speed"}), "f.csv", true));
}

TEST(InputUses, NoEssentialUseIsAnErrorNamingTheMissingColumns) {
  const InputCheck c = check_inputs(kUses, carries({"rotor_speed", "power"}));
  EXPECT_FALSE(c.any_essential);
  EXPECT_EQ(c.missing, (std::vector<std::string>{"generator_speed"}));
  try {
    report_inputs("svc", kUses, carries({"rotor_speed", "power"}), "f.csv", true);
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), "f.csv");
    EXPECT_EQ(e.line(), 1);
    EXPECT_EQ(e.key(), "generator_speed");
  }
  // on DDS (not fatal) the same is logged, not thrown
  EXPECT_NO_THROW(report_inputs("svc", kUses, carries({}), "turbine WT01", false));
}

TEST(InputUses, AbsentChannelsAreTheMeasuredColumnsAHeaderLacks) {
  const uint32_t absent =
      absent_channels(carries({"rotor_speed", "pitch_1", "pitch_ref_1", "lidar_v_upper"}));
  EXPECT_EQ(absent & kValidRotorSpeed, 0u);
  EXPECT_NE(absent & kValidGeneratorSpeed, 0u);
  EXPECT_EQ(absent & kValidPitch1, 0u);
  EXPECT_NE(absent & (kValidPitch1 << 1), 0u);
  EXPECT_NE(absent & kValidLidar, 0u);  // both beams are needed
  EXPECT_EQ(valid_bit("aero_torque"), 0u);
  // a sample carries a channel when it is marked valid and finite
  FrameSample s;
  s.rotor_speed = 1.2;
  s.generator_speed = kNaN;
  s.valid_mask = kValidAll & ~kValidPower;
  const uint32_t present = channels_with_values(s);
  EXPECT_NE(present & kValidRotorSpeed, 0u);
  EXPECT_EQ(present & kValidGeneratorSpeed, 0u);
  EXPECT_EQ(present & kValidPower, 0u);
}
