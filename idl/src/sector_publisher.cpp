#include "lpss_dds/sector_publisher.hpp"

#include <algorithm>

#include "lpss_dds/convert.hpp"

namespace lpss::dds {
namespace {

wire::SectorFrame sample_of(const SectorKey& key, std::uint64_t frame, std::uint64_t base, bool complete) {
    wire::SectorFrame sample;
    sample.sector(to_wire(key));
    sample.frame(frame);
    sample.base(base);
    sample.complete(complete);
    return sample;
}

}  // namespace

void SectorPublisher::count(Sector& sector, const Body& body, int sign) {
    const auto s = static_cast<std::uint32_t>(sign);
    sector.counts.bodies += s;
    totals_.bodies += s;
    if (body.state.awake()) {
        sector.counts.awake += s;
        totals_.awake += s;
    }
    for (std::uint32_t bits = body.near; bits != 0; bits &= bits - 1)  // most bodies come near nothing
        sector.near[static_cast<std::size_t>(__builtin_ctz(bits))] += s;
}

wire::SectorFrame SectorPublisher::whole(const SectorKey& key, const std::vector<BodySnapshot>& bodies,
                                         const std::vector<std::uint32_t>& near, std::uint64_t frame,
                                         const Describe& describe) {
    wire::SectorFrame sample = sample_of(key, frame, frame, true);
    adopt(key, bodies, near, frame);
    if (bodies.empty()) return sample;
    const Sector& sector = sectors_.at(key);
    sample.bodies().reserve(bodies.size());
    sample.kinds().reserve(bodies.size());
    sample.offsets().reserve(bodies.size());
    for (std::size_t n = 0; n < bodies.size(); ++n) {
        sample.bodies().push_back(to_wire(sector.bodies[n].state));
        sample.kinds().push_back(describe(bodies[n].id));
        sample.offsets().push_back(to_wire(bodies[n].position.local));
    }
    return sample;
}

void SectorPublisher::adopt(const SectorKey& key, const std::vector<BodySnapshot>& bodies,
                            const std::vector<std::uint32_t>& near, std::uint64_t frame) {
    forget(key);
    if (bodies.empty()) return;
    Sector& sector = sectors_[key];
    sector.bodies.reserve(bodies.size());
    for (std::size_t n = 0; n < bodies.size(); ++n) {
        Body body{pack(bodies[n]), near[n]};
        count(sector, body, +1);
        sector.bodies.push_back(std::move(body));
    }
    sector.stamp = frame;
}

std::optional<wire::SectorFrame> SectorPublisher::update(const SectorKey& key,
                                                         const std::vector<BodySnapshot>& changed,
                                                         const std::vector<std::uint32_t>& near,
                                                         const std::vector<BodyId>& left, std::uint64_t frame,
                                                         const Describe& describe) {
    auto found = sectors_.find(key);
    if (found == sectors_.end()) return std::nullopt;  // never published: the caller sends it whole
    Sector& sector = found->second;
    wire::SectorFrame sample = sample_of(key, frame, sector.stamp, false);
    sample.bodies().reserve(changed.size());
    auto by_id = [](const Body& b, BodyId id) { return b.state.id < id; };
    for (std::size_t n = 0; n < changed.size(); ++n) {
        const Body now{pack(changed[n]), near[n]};
        auto at = std::lower_bound(sector.bodies.begin(), sector.bodies.end(), changed[n].id, by_id);
        if (at != sector.bodies.end() && at->state.id == changed[n].id) {
            if (!at->state.same_motion(now.state)) sample.bodies().push_back(to_wire(now.state));
            count(sector, *at, -1);
            count(sector, now, +1);
            *at = now;
        } else {
            sample.bodies().push_back(to_wire(now.state));
            sample.kinds().push_back(describe(changed[n].id));
            count(sector, now, +1);
            sector.bodies.insert(at, now);
        }
    }
    for (BodyId id : left) {
        auto at = std::lower_bound(sector.bodies.begin(), sector.bodies.end(), id, by_id);
        if (at == sector.bodies.end() || at->state.id != id) continue;
        sample.departed().push_back(id);
        count(sector, *at, -1);
        sector.bodies.erase(at);
    }
    if (sample.bodies().empty() && sample.departed().empty()) return std::nullopt;
    if (sector.bodies.empty()) {
        // Emptied: said in a complete sample, which a reader can use alone. A partial one would be of no use
        // to a reader that missed its base, and the sector, forgotten here, is never sent whole again (seen:
        // late joiners that waited for ever on a sector a body had left).
        sectors_.erase(found);
        return sample_of(key, frame, frame, true);
    }
    sector.stamp = frame;
    return sample;
}

wire::SectorFrame SectorPublisher::nothing_new(const SectorKey& key, std::uint64_t frame) {
    Sector& sector = sectors_.at(key);
    wire::SectorFrame sample = sample_of(key, frame, sector.stamp, false);
    sector.stamp = frame;
    return sample;
}

void SectorPublisher::set_near(const SectorKey& key, const std::vector<BodySnapshot>& bodies,
                               const std::vector<std::uint32_t>& near) {
    auto found = sectors_.find(key);
    if (found == sectors_.end()) return;
    Sector& sector = found->second;
    for (std::size_t n = 0; n < bodies.size(); ++n) {
        auto at = std::lower_bound(sector.bodies.begin(), sector.bodies.end(), bodies[n].id,
                                   [](const Body& b, BodyId id) { return b.state.id < id; });
        if (at == sector.bodies.end() || at->state.id != bodies[n].id) continue;
        count(sector, *at, -1);
        at->near = near[n];
        count(sector, *at, +1);
    }
}

void SectorPublisher::forget(const SectorKey& key) {
    auto it = sectors_.find(key);
    if (it == sectors_.end()) return;
    totals_.bodies -= it->second.counts.bodies;
    totals_.awake -= it->second.counts.awake;
    sectors_.erase(it);
}

std::uint64_t SectorPublisher::stamp(const SectorKey& key) const {
    auto it = sectors_.find(key);
    return it == sectors_.end() ? 0 : it->second.stamp;
}

SectorPublisher::Counts SectorPublisher::counts(const SectorKey& key) const {
    auto it = sectors_.find(key);
    return it == sectors_.end() ? Counts{} : it->second.counts;
}

std::uint32_t SectorPublisher::near(const SectorKey& key) const {
    auto it = sectors_.find(key);
    if (it == sectors_.end()) return 0;
    std::uint32_t mask = 0;
    for (int bit = 0; bit < 27; ++bit) {
        if (it->second.near[static_cast<std::size_t>(bit)] > 0) mask |= 1u << bit;
    }
    return mask;
}

}  // namespace lpss::dds
