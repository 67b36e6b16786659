// Topic names, types and QoS profile names of the design's topic table, one trait per IDL type; the
// diagnostic services' estimate topics are generated from services/services.list
// (windfdi_add_service_estimate).
#pragma once

#include "ControlConfigurationPubSubTypes.h"
#include "FaultAckPubSubTypes.h"
#include "FaultReportPubSubTypes.h"
#include "LidarFramePubSubTypes.h"
#include "ServiceHealthPubSubTypes.h"
#include "TurbineFramePubSubTypes.h"

namespace windfdi::bus {

/// TopicTraits<T>::name is the topic, PubSub the generated type support, profile the QoS profile name
/// (the same name for the data_writer and data_reader profiles in deploy/qos/windfdi_qos.xml).
/// writer_filtering: the writer evaluates remote readers' turbine filters itself and sends them only their
/// turbines. Fast DDS 2.9 does so in write() without the lock that guards a filtered reader's arrival and
/// departure, so a busy writer can crash when one comes or goes (sensor_bias, 6000 estimates/s to the plant's
/// filtered reader, crashed in 1 of ~35 plant stops; fixed upstream in 3.x). Only the sensor streams keep
/// it: their writers are slow (10 frames/s per turbine) and it spares a farm network every turbine's frames
/// at every other turbine's services; the others filter at the reader.
template <class T>
struct TopicTraits;

#define WINDFDI_TOPIC(Type, topic_name, profile_name, filter_at_writer) \
  template <>                                                           \
  struct TopicTraits<windfdi::Type> {                                   \
    using PubSub = windfdi::Type##PubSubType;                           \
    static constexpr const char* name = topic_name;                     \
    static constexpr const char* profile = profile_name;                \
    static constexpr bool writer_filtering = filter_at_writer;          \
  }

WINDFDI_TOPIC(TurbineFrame, "wt/frame", "sensor_stream", true);
WINDFDI_TOPIC(LidarFrame, "wt/lidar", "sensor_stream", true);
WINDFDI_TOPIC(FaultReport, "wt/fault", "fault", false);
WINDFDI_TOPIC(ServiceHealth, "wt/health", "health", false);
WINDFDI_TOPIC(ControlConfiguration, "wt/control/config", "control", false);
WINDFDI_TOPIC(FaultAck, "wt/fault_ack", "fault_ack", false);

}  // namespace windfdi::bus
