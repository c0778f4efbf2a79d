#include "lpss_dds/sample_intake.hpp"

#include <algorithm>

#include "lpss_dds/convert.hpp"

namespace lpss::dds {

SampleIntake::Taken SampleIntake::take(wire::SectorFrame f, std::uint64_t known, std::uint64_t ahead) {
    if (f.frame() < floor_) return Taken::refused;
    if (std::string why = implausible(f, known, ahead); !why.empty()) {
        refused_.refuse(why);
        return Taken::refused;
    }
    if (!owners_.admit(f, refused_)) return Taken::refused;
    if (count_bytes_) received_bytes_[f.frame()] += wire::SectorFrame::getCdrSerializedSize(f);
    if (chain_.stale(f)) return Taken::stale;
    const SectorKey key = from_wire(f.sector());
    if (!chain_.accept(f)) {
        wanted_whole_.want(key);
        return Taken::without_base;
    }
    wanted_whole_.got(key);
    queued_[f.frame()].push_back(std::move(f));
    return Taken::queued;
}

std::optional<wire::SectorRequest> SampleIntake::whole_request(std::uint64_t& next_number) {
    std::vector<wire::SectorKey> due = whole_due();
    if (due.empty()) return std::nullopt;
    wire::SectorRequest request;
    request.sectors(std::move(due));
    request.reader(asker_);
    request.request(next_number++);
    return request;
}

std::vector<const wire::SectorFrame*> SampleIntake::through(std::uint64_t up_to) const {
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

void SampleIntake::drop_queued(std::uint64_t up_to,
                               const std::function<bool(const wire::SectorFrame&)>& drop) {
    for (auto it = queued_.begin(); it != queued_.end() && it->first <= up_to; ++it)
        it->second.erase(std::remove_if(it->second.begin(), it->second.end(), drop), it->second.end());
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
    chain_ = SectorChain();
    owners_ = SampleOwners();
    wanted_whole_ = WholeSectorAsks();
}

}  // namespace lpss::dds
