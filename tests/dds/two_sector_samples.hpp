// Two sectors owned by two workers, and complete samples of them as a worker writes them: what the tests
// of readers' checks (SampleOwners, SampleIntake) judge samples against.
#pragma once

#include <cstdint>

#include "lpss.h"
#include "lpss/common/assignment.hpp"
#include "lpss_dds/convert.hpp"

namespace lpss::dds::testing {

inline const SectorKey kWest{0, 0, 0};
inline const SectorKey kEast{10, 0, 0};

/// Workers 1 and 2, one sector each, under `epoch` from `from_frame` on.
inline SectorAssignment two_sector_assignment(std::uint32_t epoch, std::uint64_t from_frame) {
    SectorAssignment a = SectorAssignment::balanced({{kWest, 1.0}, {kEast, 1.0}}, {1, 2}, 1);
    a.epoch = epoch;
    a.from_frame = from_frame;
    return a;
}

/// A complete sample of `key` with no body, as `worker` writes it under `epoch`.
inline wire::SectorFrame empty_sample(const SectorKey& key, std::uint64_t frame, std::uint32_t worker,
                                      std::uint32_t epoch) {
    wire::SectorFrame s;
    s.sector(to_wire(key));
    s.frame(frame);
    s.base(frame);
    s.complete(true);
    s.worker(worker);
    s.epoch(epoch);
    return s;
}

}  // namespace lpss::dds::testing
