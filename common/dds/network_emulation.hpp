// A lossy or partitioned network made inside a participant's UDP transport, for the reliability campaign.
#pragma once

#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>
#include <string>

namespace windfdi::bus {

/// WINDFDI_NETWORK_EMULATION=FILE (tests only) gives the participant a UDP transport that drops messages as
/// FILE says, re-read every 100 ms: "loss P" drops P % of what it sends at random, "down" everything sent and
/// received, an absent or empty file nothing. Shared memory is taken off, so that every message crosses it.
/// Kernel netem is not in every container (it is not in the CI's); this needs nothing of the host. Returns
/// false (QoS untouched) when the variable is unset.
bool emulate_network(eprosima::fastdds::dds::DomainParticipantQos& qos, const std::string& name);

/// What a FILE's text asks for: the share of messages to drop (0..1), or -1 when the text is malformed.
double emulated_drop_share(const std::string& text);

}  // namespace windfdi::bus
