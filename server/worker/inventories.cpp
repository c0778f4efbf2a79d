#include "inventories.hpp"

#include <algorithm>
#include <iterator>

#include "lpss_dds/convert.hpp"

namespace lpss::worker {

void Inventories::ask(const wire::SectorRequest& r) {
    Request asked{r.reader(),
                  r.request(),
                  dds::from_wire(r.lo()),
                  dds::from_wire(r.hi()),
                  std::nullopt,
                  std::chrono::steady_clock::now(),
                  r.held_through()};
    if (r.frames_reader().size() == 16) {
        asked.frames_reader.emplace();
        std::copy(r.frames_reader().begin(), r.frames_reader().end(), asked.frames_reader->begin());
    }
    asked_[r.reader()] = std::move(asked);
}

void Inventories::take_up(const std::function<bool(const dds::GuidBytes&)>& reaches,
                          const dds::SectorPublisher& publisher) {
    // DDS's history holds a worker's last samples, not every sector's (see SectorFrame in idl/lpss.idl):
    // every sector of the region the reader lacks goes whole.
    for (auto it = asked_.begin(); it != asked_.end();) {
        const Request& r = it->second;
        if (r.frames_reader && !reaches(*r.frames_reader)) {
            it = std::chrono::steady_clock::now() - r.asked > kPatience ? asked_.erase(it) : std::next(it);
            continue;
        }
        answering_.push_back(r);
        it = asked_.erase(it);
    }
    if (answering_.empty()) return;
    // A sector whose latest sample is no newer than what the reader holds is listed with that frame and not
    // sent: the reader has it (a whole-world client of a million resting bodies, which falls behind while it
    // builds its first frame, was sent every body again, 20,000 a frame from each worker).
    publisher.for_each([&](const SectorKey& key, std::uint64_t stamp, const dds::SectorPublisher::Counts&) {
        for (const Request& r : answering_) {
            const bool held = r.held_through != 0 && stamp <= r.held_through;
            if (r.covers(key) && !held && queued_.insert(key).second) {
                due_.push_back(key);
                break;
            }
        }
    });
}

std::set<SectorKey> Inventories::due_now(const dds::SectorPublisher& publisher) {
    std::set<SectorKey> now;
    std::size_t taken = 0;
    for (std::uint32_t bodies = 0; taken < due_.size() && bodies < kBodiesPerFrame; ++taken) {
        const SectorKey& key = due_[taken];
        queued_.erase(key);
        if (!publisher.publishes(key)) continue;  // given away or emptied since: its new sample says so
        bodies += publisher.counts(key).bodies;
        now.insert(key);
    }
    due_.erase(due_.begin(), due_.begin() + static_cast<std::ptrdiff_t>(taken));
    return now;
}

std::vector<wire::SectorInventory> Inventories::answers(const dds::SectorPublisher& publisher) {
    std::vector<wire::SectorInventory> out;
    for (const Request& r : answering_) {
        wire::SectorInventory inventory;
        inventory.reader(r.reader);
        inventory.request(r.request);
        publisher.for_each(
            [&](const SectorKey& key, std::uint64_t stamp, const dds::SectorPublisher::Counts&) {
                if (!r.covers(key)) return;
                wire::SectorStamp s;
                s.sector(dds::to_wire(key));
                s.frame(stamp);
                inventory.sectors().push_back(s);
            });
        out.push_back(std::move(inventory));
    }
    answering_.clear();
    return out;
}

}  // namespace lpss::worker
