#include "lpss_dds/security.hpp"

#include <cstdlib>
#include <filesystem>
#include <utility>
#include <vector>

namespace lpss::dds {

Status apply_security(eprosima::fastdds::dds::DomainParticipantQos& qos, const std::string& folder) {
    namespace fs = std::filesystem;
    std::error_code error;
    const fs::path root = fs::absolute(folder, error);
    if (error || !fs::is_directory(root))
        return Error{"--security " + folder +
                     ": not a folder (make identities with deploy/security/identities.sh)"};
    for (const char* file : kIdentityFiles) {
        if (!fs::is_regular_file(root / file))
            return Error{"--security " + folder + ": the identity lacks " + file +
                         " (make identities with deploy/security/identities.sh)"};
    }
    auto uri = [&](const char* file) { return "file://" + (root / file).string(); };
    std::vector<std::pair<std::string, std::string>> properties = {
        {"dds.sec.auth.plugin", "builtin.PKI-DH"},
        {"dds.sec.auth.builtin.PKI-DH.identity_ca", uri("identity_ca.pem")},
        {"dds.sec.auth.builtin.PKI-DH.identity_certificate", uri("cert.pem")},
        {"dds.sec.auth.builtin.PKI-DH.private_key", uri("key.pem")},
        {"dds.sec.access.plugin", "builtin.Access-Permissions"},
        {"dds.sec.access.builtin.Access-Permissions.permissions_ca", uri("permissions_ca.pem")},
        {"dds.sec.access.builtin.Access-Permissions.governance", uri("governance.p7s")},
        {"dds.sec.access.builtin.Access-Permissions.permissions", uri("permissions.p7s")},
        {"dds.sec.crypto.plugin", "builtin.AES-GCM-GMAC"},
    };
    // A revocation list, when there is one, is checked against every peer's certificate.
    if (fs::is_regular_file(root / "crl.pem"))
        properties.emplace_back("dds.sec.auth.builtin.PKI-DH.identity_crl", uri("crl.pem"));
    // Fast DDS says why it refuses an identity only through its security log: LPSS_DDS_SECURITY_LOG=FILE
    // turns it on (every level, to FILE).
    if (const char* log = std::getenv("LPSS_DDS_SECURITY_LOG"); log != nullptr && *log != '\0') {
        properties.emplace_back("dds.sec.log.plugin", "builtin.DDS_LogTopic");
        properties.emplace_back("dds.sec.log.builtin.DDS_LogTopic.logging_level", "DEBUG_LEVEL");
        properties.emplace_back("dds.sec.log.builtin.DDS_LogTopic.log_file", log);
    }
    for (auto& [name, value] : properties)
        qos.properties().properties().emplace_back(name, value);
    return {};
}

std::string refused_endpoints_hint(const std::string& folder) {
    if (folder.empty()) return "";
    return " (does the identity in " + folder +
           " permit its role's topics in the partitions \"\" and \"lpss-from-*\"? identities made by "
           "deploy/security/identities.sh before 2026-12-05 do not: make them again)";
}

}  // namespace lpss::dds
