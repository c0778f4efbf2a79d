#include "lost_frame.hpp"

#include <set>

#include "commands.hpp"
#include "halo.hpp"
#include "handoff.hpp"
#include "lpss/engine/world.hpp"
#include "lpss_dds/convert.hpp"
#include "lpss_dds/sector_publisher.hpp"

namespace lpss::worker {

Expected<LostFrame> step_lost_frame(const LostFrameInput& in) {
    const std::uint32_t self = in.worker;
    Halo halo(self);
    halo.follow(in.assignment, in.assignment, in.largest_radius);
    EngineOptions engine;
    engine.owns = [&halo](const SectorKey& key) { return halo.owns(key); };
    Expected<World> created = World::create(in.settings, engine);
    if (!created) return created.error();
    World world = std::move(created).value();

    // The sectors as last published, the planes in the scene's order (their ids), then the frame's start as
    // the worker would have made it: handoffs, then commands.
    std::vector<const wire::SectorFrame*> samples;
    for (const wire::SectorFrame& s : in.sectors)
        samples.push_back(&s);
    std::vector<std::pair<std::uint64_t, BodyDesc>> planes;
    std::set<BodyId> plane_ids;
    for (const BodyDesc& p : in.planes) {
        planes.push_back({p.id, p});
        plane_ids.insert(p.id);
    }
    halo.apply(world, samples, planes);
    apply_handoffs(world, in.handoffs, self);
    LostFrame out;
    const Holding holding{[&halo](const SectorKey& key) { return halo.owns(key); },
                          [&world](const SectorKey& key) { return world.has_sector(key); }};
    for (std::size_t n = 0; n < in.commands.size(); ++n) {
        const wire::Command& c = in.commands[n];
        if (std::optional<Status> st = apply_command(world, c, holding, plane_ids))
            out.results.push_back(
                answer(c, n < in.command_order.size() ? in.command_order[n] : 0, in.frame, *st));
    }

    world.step();

    dds::SectorPublisher publisher;
    auto describe = [&world](BodyId id) { return dds::kind_of(*world.description(id)); };
    std::set<SectorKey> owned;
    for (const SectorKey& key : world.sectors()) {
        if (halo.owns(key)) owned.insert(key);
    }
    // Its sectors that were there at the frame before and emptied: readers must learn so.
    for (const wire::SectorFrame& s : in.sectors) {
        if (halo.owns(dds::from_wire(s.sector()))) owned.insert(dds::from_wire(s.sector()));
    }
    for (const SectorKey& key : owned) {
        const std::vector<BodySnapshot> all =
            world.has_sector(key) ? world.sector_bodies(key) : std::vector<BodySnapshot>{};
        out.bodies += all.size();
        out.sectors.push_back(
            publisher.whole(key, all, halo.near(world, all, radii_of(world, all)), in.frame, describe));
    }
    out.leaving = handoff_requests(world, self, in.assignment);
    return out;
}

}  // namespace lpss::worker
