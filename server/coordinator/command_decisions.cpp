// Clients' commands: each checked against the world (command_check), then accepted into the next frame's
// start in their global order, or refused with a reason; over a client's rate, answered as such.
#include <spdlog/spdlog.h>

#include <unordered_map>

#include "command_check.hpp"
#include "commands.hpp"
#include "coordinator_state.hpp"
#include "lpss_dds/topics.hpp"

namespace lpss::coordinator {

void Coordinator::State::refuse(const wire::Command& c, const std::string& reason,
                                std::uint64_t first_request) {
    wire::CommandResult r = worker::answer(c, 0, frame + 1, Error{reason});
    r.first_request(first_request);
    results_out->write(r);
}

void Coordinator::State::accept_commands() {
    commands_in->take_all([&](const wire::Command& c, const dds::fdds::SampleInfo& info) {
        if (info.valid_data) accept(c);
    });
    answer_over_rate();
}

void Coordinator::State::answer_over_rate() {
    if (!over_rate) return;
    const wire::Command& last = over_rate->last;
    refuse(last,
           "client '" + last.client() + "' sends more than " +
               std::to_string(static_cast<long long>(command_rate.per_second())) +
               " commands a second: refused (rate limit)",
           over_rate->first_request);
    over_rate.reset();
}

void Coordinator::State::refuse_lost(const wire::Command& c) {
    auto [last, first] = last_request.try_emplace(c.client(), c.request());
    if (first) return;
    const std::uint64_t previous = std::exchange(last->second, c.request());
    if (c.request() <= previous + 1) return;  // the next one, or a client started again under its name
    wire::Command lost = c;
    lost.request(c.request() - 1);
    refuse(lost,
           "client '" + c.client() + "': commands " + std::to_string(previous + 1) + " to " +
               std::to_string(c.request() - 1) + " were lost on the way (more than " +
               std::to_string(dds::kCommandDelivery.depth) + " of its commands in flight at once): refused",
           previous + 1);
}

void Coordinator::State::accept(const wire::Command& c) {
    refuse_lost(c);
    decide(c);
}

void Coordinator::State::decide(const wire::Command& c) {
    if (c.kind() != wire::kCommandReady && !command_rate.allow(c.client(), Clock::now())) {
        // Answered once for a run of them: a flood must not cost a write per command.
        if (over_rate && over_rate->last.client() == c.client() &&
            c.request() == over_rate->last.request() + 1) {
            over_rate->last = c;
            return;
        }
        answer_over_rate();
        over_rate = OverRate{c, c.request()};
        return;
    }
    if (over_rate && over_rate->last.client() == c.client()) answer_over_rate();
    if (c.kind() == wire::kCommandReady) {
        if (ready_clients.insert(c.client()).second)
            spdlog::info("coordinator: client {} is ready ({} so far)", c.client(), ready_clients.size());
        results_out->write(worker::answer(c, 0, frame + 1, {}));  // said again until this comes
        return;
    }
    BodyDesc body;
    if (std::string why = refusal(c, settings, statics, body); !why.empty()) return refuse(c, why);
    commands.push_back(c);
    command_order.push_back(next_order++);
    // Spawns and removals change the body set at once, so that later commands see them.
    if (c.kind() == wire::kCommandSpawn) {
        statics.emplace(body.id, body.is_static());
        if (!is_plane(body.shape) && bounding_radius(body.shape) > largest_radius) {
            largest_radius = bounding_radius(body.shape);  // reaches farther: FrameGo says so
            publish_assignment();
        }
        if (is_plane(body.shape)) {
            BodySnapshot anchor;
            anchor.id = body.id;
            anchor.position = std::holds_alternative<Eigen::Vector3d>(body.position)
                                  ? grid.from_global(std::get<Eigen::Vector3d>(body.position)).value()
                                  : grid.canonical(std::get<SectorPosition>(body.position)).value();
            anchor.orientation = body.orientation.normalized();
            wire::BodyDescription d = dds::describe(body, anchor);
            d.rank(~std::uint64_t{0});
            planes_out->write(d);
            plane_descriptions[body.id] = d;
            planes[body.id] = body;
        }
    } else if (c.kind() == wire::kCommandRemove) {
        statics.erase(c.body());
        if (auto plane = planes.find(c.body()); plane != planes.end()) {
            wire::BodyDescription d;
            d.id(c.body());
            if (!planes_out->dispose(d))
                spdlog::error("coordinator: cannot dispose the description of plane {}", c.body());
            planes.erase(plane);
            plane_descriptions.erase(c.body());
        }
    }
}

}  // namespace lpss::coordinator
