#include "lpss_dds/sector_filters.hpp"

#include <cstdint>
#include <cstring>
#include <string>

namespace lpss::dds {
namespace {

namespace fdds = eprosima::fastdds::dds;
using ReturnCode = eprosima::fastrtps::types::ReturnCode_t;

// CDR encapsulation: two bytes of representation id (byte 1: 0 big endian, 1 little endian), two of
// options; then the sample: SectorFrame's key (uint32 writer, uint32 slot), its sector (three int64
// indices, aligned on 8 with nothing to pad), then its recipients (a uint32 count and as many uint32 worker
// ids): fixed offsets.
constexpr std::uint32_t kHeader = 4;
constexpr std::uint32_t kSector = kHeader + 8;
constexpr std::uint32_t kRecipients = kSector + 24;

std::uint64_t read(const fdds::IContentFilter::SerializedPayload& payload, std::uint32_t at, int bytes) {
    const bool little = payload.data[1] == 1;
    std::uint64_t raw = 0;
    for (int b = 0; b < bytes; ++b) {
        const std::uint64_t byte = payload.data[at + b];
        raw |= little ? byte << (8 * b) : byte << (8 * (bytes - 1 - b));
    }
    return raw;
}

/// Filters know which they are: one factory makes both kinds.
class SectorFilter : public fdds::IContentFilter {
public:
    virtual ~SectorFilter() = default;  // deleted through this type by the factory
    virtual bool recipient() const = 0;
};

class RegionFilter final : public SectorFilter {
public:
    std::int64_t lo[3] = {0, 0, 0};
    std::int64_t hi[3] = {0, 0, 0};

    bool recipient() const override { return false; }
    bool evaluate(const SerializedPayload& payload, const FilterSampleInfo&, const GUID_t&) const override {
        if (payload.length < kSector + 24) return false;
        for (int a = 0; a < 3; ++a) {
            const std::uint64_t raw = read(payload, kSector + 8 * a, 8);
            std::int64_t v;
            std::memcpy(&v, &raw, sizeof v);
            if (v < lo[a] || v > hi[a]) return false;
        }
        return true;
    }
};

class RecipientFilter final : public SectorFilter {
public:
    std::uint32_t worker = 0;

    bool recipient() const override { return true; }
    bool evaluate(const SerializedPayload& payload, const FilterSampleInfo&, const GUID_t&) const override {
        if (payload.length < kRecipients + 4) return false;
        const std::uint64_t count = read(payload, kRecipients, 4);
        if (count > (payload.length - kRecipients - 4) / 4) return false;  // not a sector frame
        for (std::uint64_t n = 0; n < count; ++n) {
            if (read(payload, kRecipients + 4 + 4 * static_cast<std::uint32_t>(n), 4) == worker) return true;
        }
        return false;
    }
};

}  // namespace

ReturnCode SectorFilterFactory::create_content_filter(const char* filter_class_name, const char*,
                                                      const fdds::TopicDataType*, const char*,
                                                      const ParameterSeq& parameters,
                                                      fdds::IContentFilter*& filter_instance) {
    const bool recipient = std::strcmp(filter_class_name, kRecipientFilterClass) == 0;
    if (!recipient && std::strcmp(filter_class_name, kRegionFilterClass) != 0)
        return ReturnCode::RETCODE_BAD_PARAMETER;
    if (parameters.length() != (recipient ? 1 : 6)) return ReturnCode::RETCODE_BAD_PARAMETER;
    // Fast DDS hands back the filter it made before when the parameters change.
    auto* existing = static_cast<SectorFilter*>(filter_instance);
    if (existing != nullptr && existing->recipient() != recipient) return ReturnCode::RETCODE_BAD_PARAMETER;
    try {
        if (recipient) {
            auto* filter = existing ? static_cast<RecipientFilter*>(existing) : new RecipientFilter();
            const unsigned long id = std::stoul(parameters[0]);
            filter->worker = static_cast<std::uint32_t>(id);
            filter_instance = filter;
        } else {
            std::int64_t lo[3], hi[3];
            for (int a = 0; a < 3; ++a) {
                lo[a] = std::stoll(parameters[2 * a]);
                hi[a] = std::stoll(parameters[2 * a + 1]);
            }
            auto* filter = existing ? static_cast<RegionFilter*>(existing) : new RegionFilter();
            std::memcpy(filter->lo, lo, sizeof lo);
            std::memcpy(filter->hi, hi, sizeof hi);
            filter_instance = filter;
        }
    } catch (...) {
        return ReturnCode::RETCODE_BAD_PARAMETER;
    }
    return ReturnCode::RETCODE_OK;
}

ReturnCode SectorFilterFactory::delete_content_filter(const char*, fdds::IContentFilter* filter_instance) {
    delete static_cast<SectorFilter*>(filter_instance);
    return ReturnCode::RETCODE_OK;
}

}  // namespace lpss::dds
