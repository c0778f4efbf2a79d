// What a worker writes after it steps: a sample of each sector it owns where something changed (or whole,
// where a reader needs it so), and its mark of the frame (WorkerFrame): the sectors written and to whom,
// the bodies leaving its sectors, its load, times and memory.
#include "worker_state.hpp"

#include <spdlog/spdlog.h>

#include "handoff.hpp"
#include "lpss/common/process_memory.hpp"
#include "lpss_dds/convert.hpp"

namespace lpss::worker {
namespace {

/// Load reports come every this many frames.
constexpr std::uint64_t kLoadReportEvery = 60;

}  // namespace

void Worker::State::count_load(const SectorKey& key, const dds::SectorPublisher::Counts& before) {
    const dds::SectorPublisher::Counts after = publisher.counts(key);
    const double change =
        (double(after.bodies) + double(after.awake)) - (double(before.bodies) + double(before.awake));
    if (change == 0.0) return;
    const SectorKey block = block_of(key, halo.current().block_size);
    double& load = block_loads[block];
    load += change;
    if (load <= 0.0) block_loads.erase(block);
}

std::vector<wire::WrittenSector> Worker::State::publish() {
    World& w = *world;
    // Where something happened, and what readers asked for whole; at the frame before an assignment
    // change, every sector that changes owner or gains holders, whole (its new holders build it from that
    // sample, exactly: complete samples carry offsets in double).
    std::set<SectorKey> keys;
    for (const SectorKey& key : w.changed_sectors())
        keys.insert(key);
    // An owned sector asked for that holds nothing is answered too, with an empty sample: a reader that lost
    // the sample that emptied it waits for that.
    for (const SectorKey& key : whole_requested) {
        if (publisher.publishes(key) || halo.owns(key)) keys.insert(key);
    }
    keys.insert(adopted.begin(), adopted.end());
    // Readers that asked for an inventory and that this worker's sector writer reaches: every sector of
    // their region they lack, whole, a share a frame.
    inventories.take_up([this](const dds::GuidBytes& reader) { return frames_out->reaches(reader); },
                        publisher);
    const std::set<SectorKey> for_joiners = inventories.due_now(publisher);
    keys.insert(for_joiners.begin(), for_joiners.end());
    // At the frame before an assignment change, and when bodies may reach farther, every sector's
    // recipients are looked at again (neighbours change owners); those that change owner go whole.
    std::set<SectorKey> handed;
    const bool reach_changed_now = reach_changed;
    if (halo.switching_after(frame) || reach_changed) {
        publisher.for_each([&](const SectorKey& key, std::uint64_t, const dds::SectorPublisher::Counts&) {
            keys.insert(key);
            if (halo.switching_after(frame) && halo.next().owner_of(key) != options.id) handed.insert(key);
        });
        reach_changed = false;
    }
    if (reach_changed_now) {
        // Bodies reach farther: every body's near mask again (rare: a spawn of a larger body).
        for (const SectorKey& key : keys) {
            if (!publisher.publishes(key)) continue;
            std::vector<BodySnapshot> all = w.sector_bodies(key);
            publisher.set_near(key, all, halo.near(w, all, radii_of(w, all)));
        }
    }
    auto describe = [&w](BodyId id) { return dds::kind_of(*w.description(id)); };
    std::vector<wire::WrittenSector> written;
    for (const SectorKey& key : keys) {
        if (!halo.owns(key)) continue;  // a sector of ghosts
        // What changed; or everything, for a sector readers must get whole.
        const bool asked = whole_requested.count(key) || handed.count(key) || adopted.count(key) ||
                           for_joiners.count(key) || !publisher.publishes(key);
        const dds::SectorPublisher::Counts before = publisher.counts(key);
        std::optional<wire::SectorFrame> sample;
        auto send_whole = [&] {
            const std::vector<BodySnapshot> all = w.sector_bodies(key);
            if (all.empty() && !publisher.publishes(key) && !adopted.count(key) &&
                !whole_requested.count(key))
                return;  // nothing, never sent
            sample = publisher.whole(key, all, halo.near(w, all, radii_of(w, all)), frame, describe);
        };
        if (asked) {
            send_whole();
        } else {
            const SectorChanges changes = w.sector_changes(key);
            sample = publisher.update(key, changes.bodies, halo.near(w, changes.bodies, changes.radii),
                                      changes.left, frame, describe);
        }
        Halo::Addressing to = halo.address(key, publisher.near(key), !publisher.publishes(key), frame);
        // A worker that gains the sector builds its ghosts from a complete sample; one released learns it
        // from whatever sample comes, an empty one if nothing changed.
        if (to.gained && !(sample && sample->complete())) send_whole();
        if (!sample && to.changed() && publisher.publishes(key)) sample = publisher.nothing_new(key, frame);
        count_load(key, before);
        if (!sample) continue;
        sample->recipients(to.recipients);
        sample->released(std::move(to.released));
        sample->worker(options.id);
        sample->slot(0);  // one instance: see SectorFrame
        sample->epoch(halo.current().epoch);
        outgoing.push_back(std::move(*sample));
        wire::WrittenSector entry;
        entry.sector(sample->sector());
        entry.recipients(std::move(to.recipients));
        written.push_back(std::move(entry));
    }
    whole_requested.clear();
    adopted.clear();
    return written;
}

void Worker::State::mark(std::vector<wire::WrittenSector> written, double step_ms, double wait_ms,
                         double publish_ms) {
    World& w = *world;
    wire::WorkerFrame m = mark_of(frame);
    m.epoch(halo.current().epoch);
    m.written(std::move(written));
    // Inventories: what a reader that starts needs to know which sectors exist (the first share of those it
    // lacks went whole just before this mark, the rest go in the frames after).
    for (wire::SectorInventory& inventory : inventories.answers(publisher))
        m.inventories().push_back(std::move(inventory));

    const SectorAssignment& after = halo.switching_after(frame) ? halo.next() : halo.current();
    m.leaving(handoff_requests(w, options.id, after));

    const bool report_loads = frame % kLoadReportEvery == 0;
    if (report_loads) {
        for (const auto& [block, load] : block_loads) {
            wire::BlockLoad l;
            l.block(dds::to_wire(block));
            l.load(static_cast<float>(load));
            m.loads().push_back(l);
        }
        if (const std::optional<MemoryUse> memory = memory_use()) resident_bytes = memory->resident_bytes;
    }
    const FrameStats& s = w.last_frame_stats();
    const dds::SectorPublisher::Counts owned = publisher.totals();
    m.loads_reported(report_loads);
    m.bodies(owned.bodies);
    m.planes(static_cast<std::uint32_t>(planes.size()));
    m.awake(owned.awake);
    m.sector_count(static_cast<std::uint32_t>(publisher.sector_count()));
    m.ghosts(static_cast<std::uint32_t>(w.body_count() - owned.bodies - planes.size()));
    m.dormant(static_cast<std::uint32_t>(halo.dormant()));
    m.border_bodies(static_cast<std::uint32_t>(s.border_bodies));
    m.clones(static_cast<std::uint32_t>(s.clones));
    m.step_ms(static_cast<float>(step_ms));
    m.wait_ms(static_cast<float>(wait_ms));
    m.publish_ms(static_cast<float>(publish_ms));
    m.received_bytes(intake.take_received_bytes(frame - 1));
    m.resident_bytes(resident_bytes);
    m.degraded(degraded);
    m.started_ns(frame_started_ns);
    m.time_lost(time_lost);
    marks_out->write(m);
}

}  // namespace lpss::worker
