// DDS-Security for windfdi's participants: credential files by role (deploy/security/make_credentials.sh),
// checked before any DDS entity exists, and the Fast DDS properties that enable the builtin plugins.
#pragma once

#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>
#include <string>

namespace windfdi::bus {

/// The credential files of one participant (absolute paths), laid out by deploy/security/make_credentials.sh:
/// DIR/ca.pem (identity CA and permissions CA), DIR/governance.p7s,
/// DIR/<role>/{cert.pem,key.pem,permissions.p7s}.
struct SecurityFiles {
  std::string identity_ca, certificate, private_key;    ///< PKI-DH authentication
  std::string permissions_ca, governance, permissions;  ///< Access-Permissions
};

/// The security role of a participant name: windfdi-plant -> plant, windfdi-<service> -> <service>,
/// windfdi-arbiter -> arbiter, windfdi-farm[-ack] -> farm; empty when the name implies none (test peers).
std::string security_role_for(const std::string& participant_name);

/// The files of `role` under `dir`; a ConfigError when the role is empty or not a plain name.
SecurityFiles security_files(const std::string& dir, const std::string& role);

/// Checks, before any DDS entity exists, what Fast DDS would check later with a less helpful message: every
/// file exists and is readable; the CA and the certificate parse and are within their validity dates; the
/// certificate is issued by the CA; the key belongs to the certificate; governance and permissions are S/MIME
/// documents signed by the permissions CA; the permissions grant this certificate's subject and are within
/// their validity dates; with `domain` >= 0, governance and grant cover that domain. Throws ConfigError
/// naming the offending file.
void validate_security_files(const SecurityFiles& files, int domain = -1);

/// Adds the DDS-Security properties (PKI-DH, Access-Permissions, AES-GCM-GMAC, file: URIs) to `qos`.
void add_security_properties(eprosima::fastdds::dds::DomainParticipantQos& qos, const SecurityFiles& files);

/// The security files named by the dds.sec.* properties of `qos` (e.g. from an XML profile); false when the
/// QoS enables no security plugin. A ConfigError when a plugin is enabled but a file property is missing.
bool security_files_from_qos(const eprosima::fastdds::dds::DomainParticipantQos& qos, SecurityFiles& files);

}  // namespace windfdi::bus
