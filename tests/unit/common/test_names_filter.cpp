// Unit tests of canonical names, IDL conversions and the per-turbine content filter expression.
#include <gtest/gtest.h>

#include <fastdds/dds/core/LoanableSequence.hpp>

#include "ControlConfigurationPubSubTypes.h"
#include "LidarFramePubSubTypes.h"
#include "TurbineFramePubSubTypes.h"
#include "app.hpp"
#include "dds/convert.hpp"
#include "dds/participant.hpp"
#include "dds/turbine_filter.hpp"
#include "fault_event.hpp"
#include "names.hpp"
#include "turbine_limit.hpp"
#include "turbine_selection.hpp"
#include "yaml_config.hpp"

using namespace windfdi;

TEST(Names, FaultClassesFollowTheIdlEnumOrder) {
  // The string table and the IDL enum must agree value for value.
  EXPECT_EQ(bus::fault_class_name(windfdi::FAULT_NONE), "none");
  EXPECT_EQ(bus::fault_class_name(windfdi::FAULT_HYDRAULIC_LEAKAGE), "hydraulic_leakage");
  EXPECT_EQ(bus::fault_class_name(windfdi::FAULT_SERVICE_LOST), "service_lost");
  EXPECT_EQ(bus::severity_name(windfdi::SEVERITY_CRITICAL), "critical");
  windfdi::FaultClass c;
  EXPECT_TRUE(bus::fault_class_from_name("ice_shedding", c));
  EXPECT_EQ(c, windfdi::FAULT_ICE_SHEDDING);
  EXPECT_FALSE(bus::fault_class_from_name("ice_storm", c));
}

TEST(Names, ComponentsAndTheirClasses) {
  EXPECT_TRUE(is_component("pitch_actuator_3"));
  EXPECT_TRUE(is_component("sensor_bias"));  // a service, for service_lost
  EXPECT_FALSE(is_component("pitch_actuator_4"));
  EXPECT_EQ(fault_classes_for("rotor"), (std::vector<std::string>{"ice_accretion", "ice_shedding"}));
  EXPECT_TRUE(fault_classes_for("nacelle").empty());
}

TEST(Convert, FaultEventToReportAndBack) {
  FaultEvent e;
  e.t = 3.0;
  e.turbine_id = "WT01";
  e.source = "blade_load";
  e.component = "blade_moment_sensor_1";
  e.fault = "sensor_drift";
  e.severity = "warning";
  e.size = 0.05;
  const auto r = bus::to_idl(e);
  EXPECT_EQ(r.fault_class(), windfdi::FAULT_SENSOR_DRIFT);
  EXPECT_EQ(r.severity(), windfdi::SEVERITY_WARNING);
  const auto back = bus::to_event(r);
  EXPECT_EQ(back.fault, "sensor_drift");
  EXPECT_EQ(back.size, 0.05);
  e.fault = "melted";
  EXPECT_THROW(bus::to_idl(e), std::invalid_argument);
}

TEST(Convert, SampleRoundTrip) {
  FrameSample s;
  s.sequence = 42;
  s.t = 0.42;
  s.pitch = {1, 2, 3};
  s.valid_mask = kValidAll & ~kValidLidar;
  const auto back = bus::to_sample(bus::to_idl(s));
  EXPECT_EQ(back.sequence, 42u);
  EXPECT_EQ(back.pitch, s.pitch);
  EXPECT_EQ(back.valid_mask, s.valid_mask);
}

TEST(ContentFilter, TheExpressionIsTheSelection) {
  EXPECT_EQ(bus::turbine_filter_expression({"WT01", "WT07"}), "WT01 WT07");
  EXPECT_EQ(bus::turbine_filter_expression({"WT001..WT250", "WT400"}), "WT001..WT250 WT400");
}

// A frame of `id` serialized into `payload` as a writer does (SerializedPayload_t is not safely copyable).
void serialize_frame(const std::string& id, eprosima::fastrtps::rtps::SerializedPayload_t& payload) {
  windfdi::TurbineFrame frame;
  frame.t(12.5);
  frame.turbine_id(id);
  frame.samples().resize(10);
  windfdi::TurbineFramePubSubType type;
  payload.reserve(type.getSerializedSizeProvider(&frame)());
  EXPECT_TRUE(type.serialize(&frame, &payload));
}

TEST(ContentFilter, TheTurbineIdIsReadFromTheSerializedFrame) {
  for (const std::string id : {"WT07", "", "a-much-longer-turbine-identifier-0001"}) {
    eprosima::fastrtps::rtps::SerializedPayload_t payload;
    serialize_frame(id, payload);
    std::string_view got = "unset";
    EXPECT_TRUE(bus::turbine_id_of_payload(payload.data, payload.length, got)) << id;
    EXPECT_EQ(got, id);
  }
  // LidarFrame (filtered at the writer too) and ControlConfiguration have the same first members.
  windfdi::LidarFrame lidar;
  lidar.turbine_id("WT03");
  windfdi::LidarFramePubSubType lidar_type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(lidar_type.getSerializedSizeProvider(&lidar)());
  ASSERT_TRUE(lidar_type.serialize(&lidar, &payload));
  std::string_view got;
  EXPECT_TRUE(bus::turbine_id_of_payload(payload.data, payload.length, got));
  EXPECT_EQ(got, "WT03");
  windfdi::ControlConfiguration config;
  config.turbine_id("WT04");
  config.arbiter_id("arbiter-a");
  windfdi::ControlConfigurationPubSubType config_type;
  eprosima::fastrtps::rtps::SerializedPayload_t config_payload(
      config_type.getSerializedSizeProvider(&config)());
  ASSERT_TRUE(config_type.serialize(&config, &config_payload));
  EXPECT_TRUE(bus::turbine_id_of_payload(config_payload.data, config_payload.length, got));
  EXPECT_EQ(got, "WT04");
}

TEST(ContentFilter, ATruncatedOrForeignPayloadIsNoTurbine) {
  eprosima::fastrtps::rtps::SerializedPayload_t payload, second;
  serialize_frame("WT07", payload);
  serialize_frame("WT07", second);
  std::string_view got;
  EXPECT_FALSE(bus::turbine_id_of_payload(payload.data, 15, got));  // cut inside the string's length
  EXPECT_FALSE(bus::turbine_id_of_payload(payload.data, 18, got));  // cut inside the id
  payload.data[1] = 0x03;                                           // PL_CDR_LE: not a plain struct
  EXPECT_FALSE(bus::turbine_id_of_payload(payload.data, payload.length, got));
  second.data[15] = 0x7f;  // a string length past the payload
  EXPECT_FALSE(bus::turbine_id_of_payload(second.data, second.length, got));
}

TEST(ContentFilter, TheFactorysFilterPassesTheSelectedTurbinesOnly) {
  auto& factory = bus::TurbineFilterFactory::instance();
  eprosima::fastdds::dds::IContentFilter* filter = nullptr;
  const eprosima::fastdds::dds::LoanableSequence<const char*> none;
  ASSERT_EQ(factory.create_content_filter(bus::kTurbineFilterClass, "windfdi::TurbineFrame", nullptr,
                                          "WT001..WT250 WT400", none, filter),
            eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK);
  const eprosima::fastdds::dds::IContentFilter::FilterSampleInfo info;
  const eprosima::fastrtps::rtps::GUID_t reader;
  for (const auto& [id, pass] : std::vector<std::pair<std::string, bool>>{
           {"WT001", true}, {"WT120", true}, {"WT400", true}, {"WT251", false}, {"T001", false}}) {
    eprosima::fastrtps::rtps::SerializedPayload_t payload;
    serialize_frame(id, payload);
    EXPECT_EQ(filter->evaluate(payload, info, reader), pass) << id;
  }
  // A malformed range is refused and the filter in hand kept.
  auto* before = filter;
  EXPECT_NE(factory.create_content_filter(bus::kTurbineFilterClass, "windfdi::TurbineFrame", nullptr,
                                          "WT09..WT01", none, filter),
            eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK);
  EXPECT_EQ(filter, before);
  factory.delete_content_filter(bus::kTurbineFilterClass, filter);
}

TEST(TurbineSelection, IdsAndRangesSelectTheirTurbines) {
  EXPECT_TRUE(windfdi::TurbineSelection().contains("WT07"));  // none: every turbine
  EXPECT_TRUE(windfdi::TurbineSelection().all());
  const windfdi::TurbineSelection selection({"WT001..WT250", "WT400"});
  EXPECT_FALSE(selection.all());
  for (const char* id : {"WT001", "WT010", "WT099", "WT250", "WT400"})
    EXPECT_TRUE(selection.contains(id)) << id;
  for (const char* id : {"WT000", "WT251", "WT399", "WT2500", "T001", ""})
    EXPECT_FALSE(selection.contains(id)) << id;
  // Byte order, as the DDS filter compares: an id without the padding falls where its characters say.
  EXPECT_TRUE(selection.contains("WT1"));
  EXPECT_EQ(selection.ids(), std::vector<std::string>{"WT400"});
}

TEST(TurbineSelection, AnIdWithASpaceOrNothingIsRefused) {
  // The filter expression separates the values by spaces: "WT 01" would select WT and 01.
  EXPECT_NE(windfdi::turbine_selection_error("WT 01"), "");
  EXPECT_NE(windfdi::turbine_selection_error(""), "");
  EXPECT_EQ(windfdi::turbine_selection_error("WT01"), "");
  EXPECT_EQ(windfdi::turbine_selection_error("WT01..WT09"), "");
}

TEST(TurbineSelection, AMalformedRangeIsAConfigErrorNamingIt) {
  for (const char* bad : {"..WT02", "WT01..", "WT09..WT01", "WT01..WT05..WT09"}) {
    try {
      windfdi::TurbineSelection({"WT01", bad});
      ADD_FAILURE() << bad << " accepted";
    } catch (const windfdi::ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    }
  }
}

TEST(TurbineLimit, FollowsTheFirstTurbinesUpToItsLimitAndCountsTheRest) {
  // GIVEN a limit of 3 turbines
  windfdi::TurbineLimit limit(3, "test");
  EXPECT_EQ(limit.describe(), "");
  // WHEN 3 turbines come, then 10 000 more (a hostile peer), then the first ones again
  for (const char* id : {"WT01", "WT02", "WT03"}) EXPECT_TRUE(limit.admit(id)) << id;
  for (int i = 0; i < 10000; ++i) EXPECT_FALSE(limit.admit("HOSTILE" + std::to_string(i)));
  // THEN the first three stay followed, "*" always is, and the others were refused and counted
  for (const char* id : {"WT01", "WT02", "WT03", "*"}) EXPECT_TRUE(limit.admit(id)) << id;
  EXPECT_EQ(limit.followed(), 3u);
  EXPECT_EQ(limit.refused(), 10000u);
  EXPECT_NE(limit.describe().find("10000 messages refused"), std::string::npos) << limit.describe();
  EXPECT_NE(limit.describe().find("first refused: HOSTILE0"), std::string::npos) << limit.describe();
}

TEST(TurbineLimit, AMalformedOrHugeIdIsNeverFollowed) {
  windfdi::TurbineLimit limit(1000, "test");
  // An id of a megabyte, with a space, with a control byte, or empty: refused with room to spare.
  const std::string huge(1 << 20, 'x');
  for (const std::string& id : {huge, std::string("WT 01"), std::string("WT\x01"), std::string()})
    EXPECT_FALSE(limit.admit(id)) << id.size();
  EXPECT_TRUE(limit.admit(std::string(windfdi::kMaxTurbineIdLength, 'a')));
  EXPECT_EQ(limit.followed(), 1u);
  // The description shortens what it names.
  EXPECT_LT(limit.describe().size(), 300u) << limit.describe();
}

TEST(Logging, AFloodIsLoggedAtPowersOfTen) {
  std::vector<uint64_t> logged;
  for (uint64_t n = 0; n <= 100000; ++n)
    if (windfdi::worth_logging(n)) logged.push_back(n);
  EXPECT_EQ(logged, (std::vector<uint64_t>{1, 10, 100, 1000, 10000, 100000}));
}

TEST(ForeignReport, OnlyWhatAWindfdiServiceCouldSendIsKept) {
  windfdi::FaultEvent e;
  e.source = "pitch_diag";
  e.component = "pitch_actuator_2";
  e.fault = "pump_wear";
  e.severity = "warning";
  EXPECT_EQ(windfdi::foreign_report_reason(e), "");
  auto with = [&](auto change) {
    windfdi::FaultEvent f = e;
    change(f);
    return windfdi::foreign_report_reason(f);
  };
  EXPECT_NE(with([](auto& f) { f.source = std::string(1 << 20, 'x'); }), "");
  EXPECT_NE(with([](auto& f) { f.component = "flux_capacitor"; }), "");
  EXPECT_NE(with([](auto& f) { f.fault = "sensor_drift"; }), "");  // no class of an actuator
  EXPECT_NE(with([](auto& f) { f.severity = "apocalyptic"; }), "");
  // A detail of a megabyte arrives cut.
  windfdi::FaultReport r = bus::to_idl(e);
  r.detail(std::string(1 << 20, 'x'));
  EXPECT_EQ(bus::to_event(r).detail.size(), windfdi::kMaxReportDetail);
}

TEST(Names, BladeIndexOfPerBladeComponentsOnly) {
  EXPECT_EQ(windfdi::blade_index("pitch_actuator_1"), 0);
  EXPECT_EQ(windfdi::blade_index("pitch_sensor_2"), 1);
  EXPECT_EQ(windfdi::blade_index("blade_moment_sensor_3"), 2);
  EXPECT_EQ(windfdi::blade_index("pitch_actuator_4"), -1);
  EXPECT_EQ(windfdi::blade_index("rotor_speed_sensor"), -1);
  EXPECT_EQ(windfdi::blade_index("wt3"), -1);  // a digit that is not a blade suffix
  EXPECT_EQ(windfdi::blade_index(""), -1);
}

TEST(Convert, ControlSettingsRoundTripAndKeepTheirCanonicalNames) {
  using control::IceMode;
  using control::IpcSource;
  using control::OperatingMode;
  using control::to_string;
  for (auto m : {OperatingMode::kNormal, OperatingMode::kDegraded, OperatingMode::kSafeStop})
    EXPECT_EQ(bus::from_idl(bus::to_idl(m)), m);
  for (auto s : {IpcSource::kStrainGauge, IpcSource::kLidarModel, IpcSource::kOff})
    EXPECT_EQ(bus::from_idl(bus::to_idl(s)), s);
  for (auto i : {IceMode::kNormal, IceMode::kAdapted, IceMode::kStop})
    EXPECT_EQ(bus::from_idl(bus::to_idl(i)), i);
  EXPECT_STREQ(to_string(OperatingMode::kSafeStop), "safe_stop");
  EXPECT_STREQ(to_string(IpcSource::kLidarModel), "lidar_model");
  EXPECT_STREQ(to_string(IceMode::kAdapted), "adapted");
  // A value beyond the enum (a newer peer) reads as the most conservative setting
  EXPECT_EQ(bus::from_idl(static_cast<windfdi::OperatingMode>(7)), OperatingMode::kSafeStop);
  EXPECT_EQ(bus::from_idl(static_cast<windfdi::IpcSource>(5)), IpcSource::kOff);
}
