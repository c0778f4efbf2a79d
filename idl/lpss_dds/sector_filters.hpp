// Content filters on sector frames, evaluated by each reader on the serialized sample before it is
// deserialized (writers do not filter: see writer_qos). Both read the head of the serialized sample only,
// so they need no type object (fragile in Fast DDS 2.9, see ../shared/notes/fastdds-2.9.md):
// - a region: the sectors whose indices lie in [lo, hi] on each axis (clients that follow a region);
// - a recipient: the samples whose `recipients` hold a worker's id (each worker reads the sectors it owns
//   and those of its halo, which the writer names; the filter never changes, so no sample can slip past
//   a filter being updated).
#pragma once

#include <fastdds/dds/topic/IContentFilterFactory.hpp>

namespace lpss::dds {

inline constexpr const char* kRegionFilterClass = "LPSS_SECTOR_REGION";
inline constexpr const char* kRecipientFilterClass = "LPSS_SECTOR_RECIPIENT";

/// Makes region filters from six parameters (i_lo i_hi j_lo j_hi k_lo k_hi) and recipient filters from
/// one (the worker id).
class SectorFilterFactory final : public eprosima::fastdds::dds::IContentFilterFactory {
public:
    ReturnCode_t create_content_filter(const char* filter_class_name, const char* type_name,
                                       const eprosima::fastdds::dds::TopicDataType* data_type,
                                       const char* filter_expression, const ParameterSeq& filter_parameters,
                                       eprosima::fastdds::dds::IContentFilter*& filter_instance) override;
    ReturnCode_t delete_content_filter(const char* filter_class_name,
                                       eprosima::fastdds::dds::IContentFilter* filter_instance) override;
};

}  // namespace lpss::dds
