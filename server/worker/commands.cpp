#include "commands.hpp"

#include "lpss_dds/convert.hpp"

namespace lpss::worker {

std::optional<Status> apply_command(World& w, const wire::Command& c, const Holding& holding,
                                    std::set<BodyId>& planes) {
    switch (c.kind()) {
        case wire::kCommandSpawn: {
            BodyDesc body = dds::from_wire(c.spawn());
            if (c.spawn_global()) body.position = dds::from_wire(c.spawn().offset());
            Expected<SectorPosition> at = [&]() -> Expected<SectorPosition> {
                if (const auto* g = std::get_if<Eigen::Vector3d>(&body.position))
                    return w.grid().from_global(*g);
                return w.grid().canonical(std::get<SectorPosition>(body.position));
            }();
            const bool mine = at && holding.owns(at->sector);
            const bool held = is_plane(body.shape) || !at || mine || holding.holds(at->sector);
            Status st = held ? w.add_body(body) : Status{};
            if (st.ok() && is_plane(body.shape)) planes.insert(body.id);
            if (mine) return st;
            return std::nullopt;
        }
        case wire::kCommandRemove: {
            // Every worker holds planes as its own: the owner of the plane's sector answers for it.
            std::optional<BodySnapshot> before = w.body(c.body());
            const bool mine = before && (planes.count(c.body()) ? holding.owns(before->position.sector)
                                                                : !w.is_ghost(c.body()));
            Status st = before ? w.remove_body(c.body()) : Status{};
            if (st.ok()) planes.erase(c.body());
            if (mine) return st;
            return std::nullopt;
        }
        case wire::kCommandImpulse:
        case wire::kCommandSetVelocity: {
            if (!w.contains(c.body()) || w.is_ghost(c.body())) return std::nullopt;
            const Eigen::Vector3d a = dds::from_wire(c.vector1()), b = dds::from_wire(c.vector2());
            return c.kind() == wire::kCommandImpulse ? w.apply_impulse(c.body(), a, b)
                                                     : w.set_velocity(c.body(), a, b);
        }
        default:
            return std::nullopt;  // refused by the coordinator already
    }
}

wire::CommandResult answer(const wire::Command& c, std::uint64_t order, std::uint64_t frame,
                           const Status& outcome) {
    wire::CommandResult r;
    r.client(c.client());
    r.request(c.request());
    r.applied(outcome.ok());
    r.order(order);
    r.frame(frame);
    r.reason(outcome.ok() ? "" : outcome.error().message);
    return r;
}

}  // namespace lpss::worker
