// Topic names, types and QoS profile names of the design's topic table, one trait per IDL type.
#pragma once

#include "ControlConfigurationPubSubTypes.h"
#include "EstimatesPubSubTypes.h"
#include "FaultAckPubSubTypes.h"
#include "FaultReportPubSubTypes.h"
#include "LidarFramePubSubTypes.h"
#include "ServiceHealthPubSubTypes.h"
#include "TurbineFramePubSubTypes.h"

namespace windfdi::bus {

/// TopicTraits<T>::name is the topic, PubSub the generated type support, profile the QoS profile name
/// (the same name for the data_writer and data_reader profiles in deploy/qos/windfdi_qos.xml).
template <class T>
struct TopicTraits;

#define WINDFDI_TOPIC(Type, topic_name, profile_name)          \
  template <>                                                  \
  struct TopicTraits<windfdi::Type> {                          \
    using PubSub = windfdi::Type##PubSubType;                  \
    static constexpr const char* name = topic_name;            \
    static constexpr const char* profile = profile_name;       \
  }

WINDFDI_TOPIC(TurbineFrame, "wt/frame", "sensor_stream");
WINDFDI_TOPIC(LidarFrame, "wt/lidar", "sensor_stream");
WINDFDI_TOPIC(BladeLoadEstimate, "wt/estimate/blade_load", "estimate_best_effort");
WINDFDI_TOPIC(SensorBiasEstimate, "wt/estimate/sensor_bias", "estimate_reliable");
WINDFDI_TOPIC(PitchActuatorEstimate, "wt/estimate/pitch", "estimate_best_effort");
WINDFDI_TOPIC(InertiaEstimate, "wt/estimate/inertia", "estimate_best_effort");
WINDFDI_TOPIC(FaultReport, "wt/fault", "fault");
WINDFDI_TOPIC(ServiceHealth, "wt/health", "health");
WINDFDI_TOPIC(ControlConfiguration, "wt/control/config", "control");
WINDFDI_TOPIC(FaultAck, "wt/fault_ack", "fault_ack");

#undef WINDFDI_TOPIC

}  // namespace windfdi::bus
