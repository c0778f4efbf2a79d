// DDS Security for a participant: an identity folder made by deploy/security/identities.sh turned into Fast
// DDS's security properties (PKI-DH authentication, access control by signed governance and permissions,
// AES-GCM-GMAC cryptography). docs/security.md says what each role may do.
#pragma once

#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>

#include <string>

#include "lpss/common/expected.hpp"

namespace lpss::dds {

/// The files an identity folder holds; crl.pem is optional (without it no certificate is taken as revoked).
inline constexpr const char* kIdentityFiles[] = {"identity_ca.pem",    "cert.pem",       "key.pem",
                                                 "permissions_ca.pem", "governance.p7s", "permissions.p7s"};

/// Turns on authentication, access control and encryption in `qos` with the identity in `folder`. Refused,
/// naming the file, when the folder lacks one; Fast DDS itself checks the certificates and signatures when
/// the participant is created.
Status apply_security(eprosima::fastdds::dds::DomainParticipantQos& qos, const std::string& folder);

/// What to add to "cannot create the readers and writers" of a worker or a coordinator under the identity in
/// `folder` (nothing without one): its permissions must allow lpss's topics in the partitions its sector
/// samples travel in (own_partition.hpp), which identities made before those partitions lack.
std::string refused_endpoints_hint(const std::string& folder);

}  // namespace lpss::dds
