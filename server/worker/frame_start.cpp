// What a frame's start changes in a worker before it steps: the assignment announced and the one in force
// (sectors given away and taken over), the handoffs granted, and the commands in their global order.
#include "worker_state.hpp"

#include <spdlog/spdlog.h>

#include "handoff.hpp"
#include "lpss_dds/convert.hpp"

namespace lpss::worker {

void Worker::State::apply_command(const wire::Command& c, std::uint64_t order) {
    const Holding holding{[this](const SectorKey& key) { return halo.owns(key); },
                          [this](const SectorKey& key) { return halo.holds(key); }};
    if (std::optional<Status> st = worker::apply_command(*world, c, holding, planes))
        results_out->write(answer(c, order, frame, *st));
}

void Worker::State::announce(const wire::FrameGo& go) {
    const SectorAssignment announced = dds::from_wire(go.next());
    const double radius = go.next().largest_radius();
    if (announced.epoch != halo.next().epoch || radius != halo.largest_radius()) {
        if (radius != halo.largest_radius()) reach_changed = true;
        halo.follow(halo.current(), announced, radius);
        learn(announced);
    }
}

void Worker::State::apply_go(const wire::FrameGo& go) {
    // The assignment in force from this frame on.
    announce(go);
    const SectorAssignment current = halo.current();
    if (halo.next().epoch != current.epoch && halo.next().from_frame <= go.frame()) {
        const SectorAssignment switched = halo.next();
        auto member = [this](const SectorAssignment& a) {
            return std::find(a.workers.begin(), a.workers.end(), options.id) != a.workers.end();
        };
        // Left out after having sectors: the coordinator took this worker as gone (it was stopped, or cut
        // off, longer than its lease) and its sectors are simulated elsewhere now. It must not go on.
        if (member(current) && !member(switched)) {
            left_out = true;
            return;
        }
        halo.follow(switched, switched, halo.largest_radius());
        world->set_ownership([this](const SectorKey& key) { return halo.owns(key); });
        // Sectors given away are their new owner's to publish, whole first; their ghosts stay here until
        // the new owner says whether this worker still holds them.
        std::vector<SectorKey> given;
        publisher.for_each([&](const SectorKey& key, std::uint64_t, const dds::SectorPublisher::Counts&) {
            if (!halo.owns(key)) given.push_back(key);
        });
        for (const SectorKey& key : given) {
            const dds::SectorPublisher::Counts before = publisher.counts(key);
            publisher.forget(key);
            halo.forget(key);
            count_load(key, before);
        }
        // Sectors taken over: whole in this frame, and the worker that had them learns whether it still
        // holds them.
        for (const SectorKey& key : world->sectors()) {
            if (!halo.owns(key) || publisher.publishes(key)) continue;
            adopted.insert(key);
            const std::uint32_t before = current.owner_of(key);
            if (before != 0 && before != options.id) halo.reached(key, before);
        }
        spdlog::info("worker {}: assignment epoch {} from frame {}", options.id, switched.epoch, go.frame());
    }
    apply_handoffs(*world, go.handoffs(), options.id);
    for (std::size_t n = 0; n < go.commands().size(); ++n) {
        const std::uint64_t order = n < go.command_sequence().size() ? go.command_sequence()[n] : 0;
        apply_command(go.commands()[n], order);
    }
}

}  // namespace lpss::worker
