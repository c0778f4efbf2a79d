#include "coordinator.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <thread>
#include <unordered_map>

#include "lpss/common/assignment.hpp"
#include "lpss/common/scene.hpp"
#include "lpssPubSubTypes.h"
#include "lpss_dds/convert.hpp"
#include "lpss_dds/participant.hpp"
#include "lpss_dds/topics.hpp"

namespace lpss::coordinator {
namespace {

using Clock = std::chrono::steady_clock;

/// A rebalance is made only if it brings the heaviest worker's load down to this share of what it is.
constexpr double kRebalanceGain = 0.85;

/// What the coordinator knows of a body: enough to validate commands and describe it.
struct BodyEntry {
    BodyDesc desc;
    BodySnapshot state;  ///< as of its last description
    std::uint32_t owner = 0;
};

}  // namespace

struct Coordinator::State {
    CoordinatorOptions options;
    Scene scene;
    SectorGrid grid{1.0};
    std::unique_ptr<dds::Participant> participant;
    dds::Inbox inbox;
    std::unique_ptr<dds::Writer<wire::FrameGo>> go_out;
    std::unique_ptr<dds::Writer<wire::Assignment>> assignment_out;
    std::unique_ptr<dds::Writer<wire::BodyDescription>> descriptions_out;
    std::unique_ptr<dds::Writer<wire::CommandResult>> results_out;
    std::unique_ptr<dds::Reader<wire::WorkerFrame>> marks_in;
    std::unique_ptr<dds::Reader<wire::Command>> commands_in;

    std::vector<BodyId> order;  ///< bodies in the order they were described
    std::unordered_map<BodyId, BodyEntry> bodies;
    SectorAssignment current;
    SectorAssignment next;
    std::set<std::uint32_t> live;
    std::map<std::pair<std::uint32_t, std::uint64_t>, wire::WorkerFrame> marks;
    std::map<std::uint32_t, Clock::time_point> last_heard;
    /// The load of each block with bodies, as its owner last reported it. A worker's report replaces what
    /// it reported before: a block it no longer reports has emptied, or another worker reports it.
    struct ReportedLoad {
        float load = 0.0f;
        std::uint32_t worker = 0;
    };
    std::map<SectorKey, ReportedLoad> block_loads;
    std::vector<wire::Handoff> grants;    ///< for the next frame
    std::vector<wire::Command> commands;  ///< accepted, for the next frame
    std::vector<std::uint64_t> command_order;
    std::uint64_t next_order = 1;
    std::uint64_t frame = 0;
    std::uint64_t handoffs = 0;
    Clock::time_point frame_started;

    void pump();
    void describe(BodyId id);
    void publish_assignment();
    void accept_commands();
    void refuse(const wire::Command& c, const std::string& reason);
    void apply_to_registry(const wire::FrameGo& go);
    bool wait_for_frame(std::uint64_t f, const std::atomic<bool>& stop);
    void collect_handoffs(std::uint64_t f);
    SectorAssignment balanced() const;
    std::map<std::uint32_t, double> worker_loads(const SectorAssignment& assignment) const;
    void reassign(std::uint64_t from_frame, const char* why);
    void reassign(SectorAssignment fresh, std::uint64_t from_frame, const char* why);
    SectorAssignment assignment_for(std::uint64_t f) const { return next.from_frame <= f ? next : current; }
};

Coordinator::Coordinator(std::unique_ptr<State> state) : state_(std::move(state)) {}

Coordinator::~Coordinator() {
    if (!state_) return;
    state_->go_out.reset();
    state_->assignment_out.reset();
    state_->descriptions_out.reset();
    state_->results_out.reset();
    state_->marks_in.reset();
    state_->commands_in.reset();
}

Expected<std::unique_ptr<Coordinator>> Coordinator::create(const CoordinatorOptions& options) {
    if (options.workers < 1) return Error{"a cluster needs at least one worker"};
    if (options.block_size < 1) return Error{"block size must be at least 1"};
    Expected<Scene> scene = load_scene(options.scene_path);
    if (!scene) return Error{"scene refused:\n" + scene.error().message};
    auto state = std::make_unique<State>();
    state->options = options;
    state->scene = std::move(scene).value();
    state->grid = SectorGrid(state->scene.settings.sector_size);
    Expected<std::unique_ptr<dds::Participant>> participant =
        dds::Participant::create(options.domain, options.profile, "lpss-coordinator");
    if (!participant) return participant.error();
    state->participant = std::move(participant).value();
    dds::Participant& p = *state->participant;
    using namespace dds;
    state->go_out = std::make_unique<Writer<wire::FrameGo>>(p, p.topic<wire::FrameGoPubSubType>(kFrameGo),
                                                            writer_qos(kFrameDelivery));
    state->assignment_out = std::make_unique<Writer<wire::Assignment>>(
        p, p.topic<wire::AssignmentPubSubType>(kSectorOwners), writer_qos(kStateDelivery));
    state->descriptions_out = std::make_unique<Writer<wire::BodyDescription>>(
        p, p.topic<wire::BodyDescriptionPubSubType>(kBodyDescriptions), writer_qos(kStateDelivery));
    state->results_out = std::make_unique<Writer<wire::CommandResult>>(
        p, p.topic<wire::CommandResultPubSubType>(kCommandResults), writer_qos(kCommandDelivery));
    state->marks_in = std::make_unique<Reader<wire::WorkerFrame>>(
        p, p.topic<wire::WorkerFramePubSubType>(kWorkerFrames), reader_qos(kFrameDelivery), &state->inbox);
    state->commands_in = std::make_unique<Reader<wire::Command>>(
        p, p.topic<wire::CommandPubSubType>(kCommands), reader_qos(kCommandDelivery), &state->inbox);
    if (!state->go_out->ok() || !state->assignment_out->ok() || !state->descriptions_out->ok() ||
        !state->results_out->ok() || !state->marks_in->ok() || !state->commands_in->ok()) {
        return Error{"cannot create the coordinator's DDS readers and writers"};
    }
    return std::unique_ptr<Coordinator>(new Coordinator(std::move(state)));
}

void Coordinator::State::pump() {
    marks_in->take_all([&](const wire::WorkerFrame& m, const dds::fdds::SampleInfo& info) {
        if (!info.valid_data) return;
        last_heard[m.worker()] = Clock::now();
        if (m.loads_reported()) {
            for (auto it = block_loads.begin(); it != block_loads.end();)
                it = it->second.worker == m.worker() ? block_loads.erase(it) : std::next(it);
            for (const wire::BlockLoad& l : m.loads())
                block_loads[dds::from_wire(l.block())] = ReportedLoad{l.load(), m.worker()};
        }
        marks[{m.worker(), m.frame()}] = m;
    });
}

void Coordinator::State::describe(BodyId id) {
    const BodyEntry& e = bodies.at(id);
    descriptions_out->write(dds::describe(e.desc, e.state, e.owner));
}

void Coordinator::State::publish_assignment() { assignment_out->write(dds::to_wire(next, scene.settings)); }

void Coordinator::State::refuse(const wire::Command& c, const std::string& reason) {
    wire::CommandResult r;
    r.client(c.client());
    r.request(c.request());
    r.applied(false);
    r.order(0);
    r.frame(frame + 1);
    r.reason(reason);
    results_out->write(r);
}

void Coordinator::State::accept_commands() {
    commands_in->take_all([&](const wire::Command& c, const dds::fdds::SampleInfo& info) {
        if (!info.valid_data) return;
        auto known = bodies.find(c.body());
        auto finite = [](const wire::Vec3d& v) {
            return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z());
        };
        switch (c.kind()) {
            case wire::kCommandSpawn: {
                BodyDesc body = dds::from_wire(c.spawn());
                if (c.spawn_global()) body.position = dds::from_wire(c.spawn().offset());
                if (Status st = validate_body(body, scene.settings); !st)
                    return refuse(c, st.error().message);
                if (bodies.count(body.id))
                    return refuse(c, describe_body(body) + ": id is used by another body");
                break;
            }
            case wire::kCommandRemove:
                if (known == bodies.end()) return refuse(c, "unknown body id " + std::to_string(c.body()));
                break;
            case wire::kCommandImpulse:
            case wire::kCommandSetVelocity:
                if (known == bodies.end()) return refuse(c, "unknown body id " + std::to_string(c.body()));
                if (known->second.desc.is_static()) {
                    return refuse(c, describe_body(known->second.desc) + ": is static and cannot be pushed");
                }
                if (!finite(c.vector1()) || !finite(c.vector2())) {
                    return refuse(c, describe_body(known->second.desc) + ": command vectors must be finite");
                }
                break;
            default:
                return refuse(c, "unknown command kind " + std::to_string(c.kind()));
        }
        commands.push_back(c);
        command_order.push_back(next_order++);
        // Spawns and removals change the body set at once, so that later commands see them.
        if (c.kind() == wire::kCommandSpawn) {
            BodyDesc body = dds::from_wire(c.spawn());
            if (c.spawn_global()) body.position = dds::from_wire(c.spawn().offset());
            BodyEntry e;
            e.desc = body;
            e.state.id = body.id;
            if (const auto* g = std::get_if<Eigen::Vector3d>(&body.position)) {
                e.state.position = grid.from_global(*g).value();
            } else {
                e.state.position = grid.canonical(std::get<SectorPosition>(body.position)).value();
            }
            e.state.orientation = body.orientation.normalized();
            e.state.linear_velocity = body.linear_velocity;
            e.state.angular_velocity = body.angular_velocity;
            e.owner = is_plane(body.shape) ? 0 : assignment_for(frame + 1).owner_of(e.state.position.sector);
            bodies.emplace(body.id, e);
            order.push_back(body.id);
            describe(body.id);
        } else if (c.kind() == wire::kCommandRemove) {
            descriptions_out->dispose(
                dds::describe(known->second.desc, known->second.state, known->second.owner));
            bodies.erase(known);
            order.erase(std::find(order.begin(), order.end(), c.body()));
        }
    });
}

void Coordinator::State::apply_to_registry(const wire::FrameGo& go) {
    for (const wire::Handoff& h : go.handoffs()) {
        auto it = bodies.find(h.body());
        if (it == bodies.end()) continue;
        BodySnapshot s = dds::from_wire(h.state(), dds::from_wire(h.sector()));
        s.position.local = dds::from_wire(h.precise_position());
        it->second.state = s;
        it->second.owner = h.to_worker();
        describe(h.body());
    }
}

bool Coordinator::State::wait_for_frame(std::uint64_t f, const std::atomic<bool>& stop) {
    // Every live worker's end of frame f. A worker silent for too long is taken as gone: its sectors go to
    // the others, who already hold its bodies as ghosts of their last published state.
    for (;;) {
        pump();
        bool all = true;
        for (std::uint32_t w : live)
            all = all && marks.count({w, f});
        if (all) return true;
        if (stop.load()) return false;
        for (std::uint32_t w : std::set<std::uint32_t>(live)) {
            if (marks.count({w, f})) continue;
            // Silence counts from the frame's start (or the last word, if later); the first frame may take
            // as long as the workers take to load the world.
            const auto since = std::max(last_heard[w], frame_started);
            if (Clock::now() - since > (f == 1 ? options.worker_wait : options.worker_timeout)) {
                spdlog::error(
                    "coordinator: worker {} stopped answering at frame {}; its sectors go to the others", w,
                    f);
                live.erase(w);
                if (live.empty()) return false;
                reassign(f + 1, "a worker is gone");
            }
        }
        inbox.wait(std::chrono::milliseconds(5));
    }
}

void Coordinator::State::collect_handoffs(std::uint64_t f) {
    // Requests of frame f become grants of frame f + 1, each body once, to the owner of the sector it enters
    // under the assignment in force then.
    const SectorAssignment then = assignment_for(f + 1);
    std::set<BodyId> granted;
    for (std::uint32_t w : live) {
        auto it = marks.find({w, f});
        if (it == marks.end()) continue;
        for (wire::Handoff h : it->second.leaving()) {
            if (!bodies.count(h.body()) || !granted.insert(h.body()).second) continue;
            const std::uint32_t to = then.owner_of(dds::from_wire(h.sector()));
            if (to == h.from_worker()) continue;
            h.to_worker(to);
            grants.push_back(h);
            ++handoffs;
        }
    }
    for (auto it = marks.begin(); it != marks.end();)
        it = it->first.second < f ? marks.erase(it) : std::next(it);
}

SectorAssignment Coordinator::State::balanced() const {
    std::vector<std::pair<SectorKey, double>> loads;
    for (const auto& [block, reported] : block_loads) {
        // A block's load stands for its first sector: balanced() groups sectors into the same blocks.
        loads.push_back(
            {SectorKey{block.i * next.block_size, block.j * next.block_size, block.k * next.block_size},
             static_cast<double>(reported.load)});
    }
    if (loads.empty()) {
        for (const auto& [id, e] : bodies) {
            if (!is_plane(e.desc.shape)) loads.push_back({e.state.position.sector, 1.0});
        }
    }
    return SectorAssignment::balanced(loads, std::vector<std::uint32_t>(live.begin(), live.end()),
                                      options.block_size);
}

std::map<std::uint32_t, double> Coordinator::State::worker_loads(const SectorAssignment& assignment) const {
    std::map<std::uint32_t, double> per_worker;
    for (const auto& [block, reported] : block_loads) {
        const std::int64_t n = current.block_size;  // the blocks the workers reported in
        per_worker[assignment.owner_of({block.i * n, block.j * n, block.k * n})] += reported.load;
    }
    return per_worker;
}

void Coordinator::State::reassign(std::uint64_t from_frame, const char* why) {
    reassign(balanced(), from_frame, why);
}

void Coordinator::State::reassign(SectorAssignment fresh, std::uint64_t from_frame, const char* why) {
    fresh.epoch = next.epoch + 1;
    fresh.from_frame = from_frame;
    next = fresh;
    publish_assignment();
    spdlog::info("coordinator: assignment epoch {} from frame {} ({})", next.epoch, from_frame, why);
}

int Coordinator::run(const std::atomic<bool>& stop) {
    State& s = *state_;
    const CoordinatorOptions& o = s.options;
    spdlog::info("coordinator: scene {} with {} bodies, waiting for {} worker(s) on domain {}", o.scene_path,
                 s.scene.bodies.size(), o.workers, s.participant->domain());
    // The workers announce themselves with frame 0.
    const auto wait_start = Clock::now();
    for (;;) {
        s.pump();
        std::vector<std::uint32_t> missing;
        for (std::uint32_t w = 1; w <= o.workers; ++w) {
            if (!s.marks.count({w, 0})) missing.push_back(w);
        }
        if (missing.empty()) break;
        if (stop.load()) return 0;
        if (Clock::now() - wait_start > o.worker_wait) {
            std::string list;
            for (std::uint32_t w : missing)
                list += (list.empty() ? "" : ", ") + std::to_string(w);
            spdlog::error("coordinator: worker(s) {} did not appear on domain {} within {} s", list,
                          s.participant->domain(), o.worker_wait.count() / 1000);
            return 3;
        }
        s.inbox.wait(std::chrono::milliseconds(50));
    }
    for (std::uint32_t w = 1; w <= o.workers; ++w)
        s.live.insert(w);

    // The first assignment: bodies per sector, balanced along the Morton curve.
    std::vector<std::pair<SectorKey, double>> loads;
    for (const BodyDesc& b : s.scene.bodies) {
        BodyEntry e;
        e.desc = b;
        e.state.id = b.id;
        if (const auto* g = std::get_if<Eigen::Vector3d>(&b.position)) {
            e.state.position = s.grid.from_global(*g).value();
        } else {
            e.state.position = s.grid.canonical(std::get<SectorPosition>(b.position)).value();
        }
        e.state.orientation = b.orientation;
        e.state.linear_velocity = b.linear_velocity;
        e.state.angular_velocity = b.angular_velocity;
        if (!is_plane(b.shape)) loads.push_back({e.state.position.sector, 1.0});
        s.bodies.emplace(b.id, e);
        s.order.push_back(b.id);
    }
    std::vector<std::uint32_t> workers(s.live.begin(), s.live.end());
    s.current = SectorAssignment::balanced(loads, workers, o.block_size);
    s.current.epoch = 1;
    s.current.from_frame = 1;
    s.next = s.current;
    for (BodyId id : s.order) {
        BodyEntry& e = s.bodies.at(id);
        e.owner = is_plane(e.desc.shape) ? 0 : s.current.owner_of(e.state.position.sector);
        s.describe(id);
    }
    s.publish_assignment();

    const auto start = Clock::now();
    auto last_log = start;
    for (std::uint64_t f = 1;; ++f) {
        s.frame = f - 1;
        const bool finished = (o.frames > 0 && f > o.frames) || stop.load();
        s.accept_commands();
        wire::FrameGo go;
        go.coordinator(1);
        go.frame(f);
        if (s.next.from_frame <= f) s.current = s.next;
        go.epoch(s.current.epoch);
        go.next(dds::to_wire(s.next, s.scene.settings));
        go.bodies(static_cast<std::uint32_t>(s.order.size()));
        go.stop(finished);
        go.handoffs(s.grants);
        go.commands(s.commands);
        go.command_sequence(s.command_order);
        if (o.realtime)
            std::this_thread::sleep_until(start +
                                          std::chrono::duration_cast<Clock::duration>(
                                              std::chrono::duration<double>((f - 1) * s.scene.settings.dt)));
        s.go_out->write(go);
        s.frame_started = Clock::now();
        if (finished) {
            spdlog::info("coordinator: stopping after frame {} ({} handoffs)", f - 1, s.handoffs);
            // Give the workers a moment to read the stop before this participant goes.
            std::this_thread::sleep_for(std::chrono::milliseconds(300));
            return 0;
        }
        s.apply_to_registry(go);
        s.grants.clear();
        s.commands.clear();
        s.command_order.clear();
        s.frame = f;
        if (!s.wait_for_frame(f, stop)) {
            if (s.live.empty()) {
                spdlog::error("coordinator: every worker is gone");
                return 5;
            }
            continue;  // stopping: the next round sends the stop
        }
        s.collect_handoffs(f);
        if (o.rebalance_every > 0 && f % o.rebalance_every == 0 && s.live.size() > 1 &&
            s.next.epoch == s.current.epoch) {
            auto heaviest = [](const std::map<std::uint32_t, double>& loads) {
                double most = 0.0;
                for (const auto& [w, l] : loads)
                    most = std::max(most, l);
                return most;
            };
            const std::map<std::uint32_t, double> now = s.worker_loads(s.current);
            double total = 0.0;
            for (const auto& [w, l] : now)
                total += l;
            const double most = heaviest(now);
            const double mean = total / static_cast<double>(s.live.size());
            if (mean > 0.0 && most > o.rebalance_threshold * mean) {
                // Moving sectors costs handoffs: only for a clear gain, else a load that shifts back and
                // forth would move the same sectors back and forth.
                SectorAssignment fresh = s.balanced();
                const double after = heaviest(s.worker_loads(fresh));
                if (after <= kRebalanceGain * most) {
                    spdlog::info(
                        "coordinator: frame {}: the busiest worker carries {:.0f} against a mean of "
                        "{:.0f}; a new assignment brings it to {:.0f}",
                        f, most, mean, after);
                    s.reassign(std::move(fresh), f + 2, "load shifted");
                } else {
                    spdlog::debug(
                        "coordinator: frame {}: load uneven ({:.0f} against a mean of {:.0f}), but a "
                        "new assignment would carry {:.0f} at most: kept",
                        f, most, mean, after);
                }
            }
        }
        if (Clock::now() - last_log > std::chrono::seconds(5)) {
            last_log = Clock::now();
            spdlog::info("coordinator: frame {}, {:.1f} frames/s, {} handoffs so far", f,
                         static_cast<double>(f) / std::chrono::duration<double>(Clock::now() - start).count(),
                         s.handoffs);
        }
    }
}

}  // namespace lpss::coordinator
