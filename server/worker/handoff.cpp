#include "handoff.hpp"

#include <spdlog/spdlog.h>

#include "lpss_dds/convert.hpp"

namespace lpss::worker {

std::vector<wire::Handoff> handoff_requests(const World& world, std::uint32_t self,
                                            const SectorAssignment& after) {
    std::vector<wire::Handoff> out;
    for (const Departure& d : world.departures()) {
        const std::uint32_t owner = after.owner_of(d.to.sector);
        if (owner == self) continue;  // it enters a sector this worker owns from the next frame on
        BodySnapshot state = *world.body(d.id);
        state.position = d.to;
        wire::Handoff h;
        h.body(d.id);
        h.from_worker(self);
        h.to_worker(owner);
        h.sector(dds::to_wire(d.to.sector));
        h.state(dds::to_wire(state));
        h.precise_position(dds::to_wire(d.to.local));
        h.kind(dds::kind_of(*world.description(d.id)));
        out.push_back(std::move(h));
    }
    return out;
}

void apply_handoffs(World& world, const std::vector<wire::Handoff>& granted, std::uint32_t self) {
    for (const wire::Handoff& h : granted) {
        BodySnapshot state = dds::from_wire(h.state(), dds::from_wire(h.sector()));
        state.position.local = dds::from_wire(h.precise_position());
        if (!world.contains(h.body())) {
            if (h.to_worker() != self) continue;  // a body this worker does not hold, going elsewhere
            if (Status st = world.add_body(dds::placed(dds::from_wire(h.kind()), state)); !st) {
                spdlog::error("worker {}: handoff of body {}: {}", self, h.body(), st.error().message);
                continue;
            }
        }
        if (Status st = world.set_state(state); !st)
            spdlog::warn("worker {}: handoff of body {}: {}", self, h.body(), st.error().message);
    }
}

}  // namespace lpss::worker
