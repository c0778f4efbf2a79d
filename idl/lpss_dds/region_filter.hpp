// Interest in a region: a custom content filter on sector frames that keeps the sectors whose indices
// lie in [lo, hi] on each axis. It reads the key at the head of the serialized sample, so it needs no
// type object (fragile in Fast DDS 2.9, see ../shared/notes/fastdds-2.9.md).
#pragma once

#include <fastdds/dds/topic/IContentFilterFactory.hpp>

namespace lpss::dds {

inline constexpr const char* kRegionFilterClass = "LPSS_SECTOR_REGION";

/// Makes region filters from six parameters: i_lo i_hi j_lo j_hi k_lo k_hi.
class RegionFilterFactory : public eprosima::fastdds::dds::IContentFilterFactory {
public:
    ReturnCode_t create_content_filter(const char* filter_class_name, const char* type_name,
                                       const eprosima::fastdds::dds::TopicDataType* data_type,
                                       const char* filter_expression, const ParameterSeq& filter_parameters,
                                       eprosima::fastdds::dds::IContentFilter*& filter_instance) override;
    ReturnCode_t delete_content_filter(const char* filter_class_name,
                                       eprosima::fastdds::dds::IContentFilter* filter_instance) override;
};

}  // namespace lpss::dds
