#include "lpss_dds/sector_publisher.hpp"

#include "lpss_dds/convert.hpp"

namespace lpss::dds {
namespace {

bool same_state(const wire::BodyState& a, const wire::BodyState& b) {
    auto eq3 = [](const wire::Vec3f& x, const wire::Vec3f& y) {
        return x.x() == y.x() && x.y() == y.y() && x.z() == y.z();
    };
    return eq3(a.position(), b.position()) && eq3(a.linear_velocity(), b.linear_velocity()) &&
           eq3(a.angular_velocity(), b.angular_velocity()) && a.orientation().x() == b.orientation().x() &&
           a.orientation().y() == b.orientation().y() && a.orientation().z() == b.orientation().z() &&
           a.orientation().w() == b.orientation().w() && a.flags() == b.flags();
}

}  // namespace

void SectorPublisher::count(const Counts& counts, int sign) {
    totals_.bodies += static_cast<std::uint32_t>(sign) * counts.bodies;
    totals_.awake += static_cast<std::uint32_t>(sign) * counts.awake;
}

std::optional<wire::SectorFrame> SectorPublisher::update(const SectorKey& key,
                                                         const std::vector<BodySnapshot>& bodies,
                                                         std::uint64_t frame, bool whole,
                                                         const Describe& describe) {
    auto known = sectors_.find(key);
    if (known == sectors_.end() && bodies.empty() && !whole)
        return std::nullopt;  // nothing there, nothing sent
    std::vector<wire::BodyState> now;
    now.reserve(bodies.size());
    Counts counts;
    for (const BodySnapshot& b : bodies) {
        now.push_back(to_wire(b));
        counts.awake += b.awake ? 1u : 0u;
    }
    counts.bodies = static_cast<std::uint32_t>(now.size());

    wire::SectorFrame sample;
    sample.sector(to_wire(key));
    sample.frame(frame);
    const bool complete = whole || known == sectors_.end() || bodies.empty();
    if (complete) {
        sample.complete(true);
        sample.base(frame);
        sample.bodies(now);
        sample.kinds().reserve(bodies.size());
        sample.offsets().reserve(bodies.size());
        for (const BodySnapshot& b : bodies) {
            sample.kinds().push_back(describe(b.id));
            sample.offsets().push_back(to_wire(b.position.local));
        }
    } else {
        // Both sides sorted by id: one merge finds what changed, arrived and left.
        const std::vector<wire::BodyState>& before = known->second.states;
        std::size_t i = 0, j = 0;
        while (i < before.size() || j < now.size()) {
            if (j == now.size() || (i < before.size() && before[i].id() < now[j].id())) {
                sample.departed().push_back(before[i++].id());
            } else if (i == before.size() || now[j].id() < before[i].id()) {
                sample.bodies().push_back(now[j]);
                sample.kinds().push_back(describe(now[j].id()));
                ++j;
            } else {
                if (!same_state(before[i], now[j])) sample.bodies().push_back(now[j]);
                ++i, ++j;
            }
        }
        if (sample.bodies().empty() && sample.departed().empty()) return std::nullopt;
        sample.complete(false);
        sample.base(known->second.stamp);
    }

    if (known != sectors_.end()) count(known->second.counts, -1);
    if (bodies.empty()) {
        if (known != sectors_.end()) sectors_.erase(known);
        return sample;
    }
    Sector& sector = sectors_[key];
    sector.states = std::move(now);
    sector.stamp = frame;
    sector.complete = complete;
    sector.counts = counts;
    count(counts, +1);
    return sample;
}

void SectorPublisher::forget(const SectorKey& key) {
    auto it = sectors_.find(key);
    if (it == sectors_.end()) return;
    count(it->second.counts, -1);
    sectors_.erase(it);
}

std::vector<SectorKey> SectorPublisher::last_partial() const {
    std::vector<SectorKey> out;
    for (const auto& [key, sector] : sectors_) {
        if (!sector.complete) out.push_back(key);
    }
    return out;
}

std::uint64_t SectorPublisher::stamp(const SectorKey& key) const {
    auto it = sectors_.find(key);
    return it == sectors_.end() ? 0 : it->second.stamp;
}

SectorPublisher::Counts SectorPublisher::counts(const SectorKey& key) const {
    auto it = sectors_.find(key);
    return it == sectors_.end() ? Counts{} : it->second.counts;
}

}  // namespace lpss::dds
