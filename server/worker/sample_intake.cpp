#include "sample_intake.hpp"

#include <spdlog/spdlog.h>

#include "lpss_dds/convert.hpp"

namespace lpss::worker {

void SampleIntake::take(wire::SectorFrame f, std::uint64_t known, std::uint64_t ahead) {
    if (f.worker() == worker_ || f.frame() < floor_) return;
    if (std::string why = dds::implausible(f, known, ahead); !why.empty()) return refused_.refuse(why);
    if (!owners_.admit(f, refused_)) return;
    received_bytes_[f.frame()] += wire::SectorFrame::getCdrSerializedSize(f);
    if (chain_.stale(f)) return;
    // Not applied: the sector is asked for whole, as clients do, or it would stay broken until its owner sent
    // it whole for some other reason (seen: a worker degraded 2 s a frame for minutes).
    if (!chain_.accept(f)) {
        spdlog::warn("worker {}: sector sample of frame {} without its base", worker_, f.frame());
        wanted_whole_.want(dds::from_wire(f.sector()));
        return;
    }
    wanted_whole_.got(dds::from_wire(f.sector()));
    queued_[f.frame()].push_back(std::move(f));
}

void SampleIntake::learn(const SectorAssignment& assignment, std::uint64_t known, std::uint64_t ahead) {
    for (wire::SectorFrame& f : owners_.learn(assignment))
        take(std::move(f), known, ahead);
}

std::vector<const wire::SectorFrame*> SampleIntake::through(std::uint64_t up_to) {
    std::vector<const wire::SectorFrame*> batch;
    const auto end = queued_.upper_bound(up_to);
    for (auto it = queued_.begin(); it != end; ++it) {
        for (const wire::SectorFrame& f : it->second)
            batch.push_back(&f);
    }
    return batch;
}

void SampleIntake::applied(std::uint64_t up_to) {
    queued_.erase(queued_.begin(), queued_.upper_bound(up_to));
    chain_.forget_applied(up_to);
    owners_.applied(up_to, refused_);
}

const std::vector<wire::SectorFrame>* SampleIntake::of_frame(std::uint64_t frame) const {
    auto it = queued_.find(frame);
    return it == queued_.end() ? nullptr : &it->second;
}

std::uint64_t SampleIntake::take_received_bytes(std::uint64_t frame) {
    auto it = received_bytes_.find(frame);
    const std::uint64_t bytes = it == received_bytes_.end() ? 0 : it->second;
    received_bytes_.erase(received_bytes_.begin(), received_bytes_.upper_bound(frame));
    return bytes;
}

void SampleIntake::start_over(std::uint64_t floor) {
    floor_ = floor;
    queued_.clear();
    chain_ = dds::SectorChain();
    owners_ = dds::SampleOwners();
    wanted_whole_ = dds::WholeSectorAsks();
}

}  // namespace lpss::worker
