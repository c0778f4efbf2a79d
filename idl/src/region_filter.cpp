#include "lpss_dds/region_filter.hpp"

#include <cstdint>
#include <cstring>
#include <string>

namespace lpss::dds {
namespace {

namespace fdds = eprosima::fastdds::dds;
using ReturnCode = eprosima::fastrtps::types::ReturnCode_t;

class RegionFilter final : public fdds::IContentFilter {
public:
    std::int64_t lo[3] = {0, 0, 0};
    std::int64_t hi[3] = {0, 0, 0};

    bool evaluate(const SerializedPayload& payload, const FilterSampleInfo&, const GUID_t&) const override {
        // CDR encapsulation: two bytes of representation id (byte 1: 0 big endian, 1 little endian), two
        // of options; then the sample, whose first member is the key: three int64 sector indices.
        if (payload.length < 4 + 24) return false;
        const bool little = payload.data[1] == 1;
        for (int a = 0; a < 3; ++a) {
            std::uint64_t raw = 0;
            for (int b = 0; b < 8; ++b) {
                const std::uint64_t byte = payload.data[4 + 8 * a + b];
                raw |= little ? byte << (8 * b) : byte << (8 * (7 - b));
            }
            std::int64_t v;
            std::memcpy(&v, &raw, sizeof v);
            if (v < lo[a] || v > hi[a]) return false;
        }
        return true;
    }
};

}  // namespace

ReturnCode RegionFilterFactory::create_content_filter(const char*, const char*, const fdds::TopicDataType*,
                                                      const char*, const ParameterSeq& parameters,
                                                      fdds::IContentFilter*& filter_instance) {
    if (parameters.length() != 6) return ReturnCode::RETCODE_BAD_PARAMETER;
    auto* filter = filter_instance ? static_cast<RegionFilter*>(filter_instance) : new RegionFilter();
    try {
        for (int a = 0; a < 3; ++a) {
            filter->lo[a] = std::stoll(parameters[2 * a]);
            filter->hi[a] = std::stoll(parameters[2 * a + 1]);
        }
    } catch (...) {
        if (filter != filter_instance) delete filter;
        return ReturnCode::RETCODE_BAD_PARAMETER;
    }
    filter_instance = filter;
    return ReturnCode::RETCODE_OK;
}

ReturnCode RegionFilterFactory::delete_content_filter(const char*, fdds::IContentFilter* filter_instance) {
    delete static_cast<RegionFilter*>(filter_instance);
    return ReturnCode::RETCODE_OK;
}

}  // namespace lpss::dds
