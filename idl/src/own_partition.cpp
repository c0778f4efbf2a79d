#include "lpss_dds/own_partition.hpp"

#include <cstdio>

namespace lpss::dds {

namespace {
constexpr const char* kPrefix = "lpss-from-";
}

std::string own_partition(const std::array<std::uint8_t, 12>& guid_prefix) {
    std::string out = kPrefix;
    char digits[3];
    for (std::uint8_t byte : guid_prefix) {
        std::snprintf(digits, sizeof(digits), "%02x", byte);
        out += digits;
    }
    return out;
}

std::vector<std::string> every_own_partition_but(const std::string& own) {
    // Own partitions all have the same length, so differing at some digit is the same as being another.
    const std::size_t start = std::string(kPrefix).size();
    std::vector<std::string> patterns;
    for (std::size_t n = start; n < own.size(); ++n)
        patterns.push_back(own.substr(0, n) + "[!" + own[n] + "]*");
    return patterns;
}

}  // namespace lpss::dds
