#include "worker.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <deque>
#include <map>
#include <optional>
#include <set>
#include <thread>
#include <unordered_map>

#include "lpss/common/assignment.hpp"
#include "lpss/engine/world.hpp"
#include "lpssPubSubTypes.h"
#include "lpss_dds/convert.hpp"
#include "lpss_dds/participant.hpp"
#include "lpss_dds/sector_chain.hpp"
#include "lpss_dds/sector_mirror.hpp"
#include "lpss_dds/topics.hpp"

namespace lpss::worker {
namespace {

using Clock = std::chrono::steady_clock;

bool same_state(const wire::BodyState& a, const wire::BodyState& b) {
    auto eq3 = [](const wire::Vec3f& x, const wire::Vec3f& y) {
        return x.x() == y.x() && x.y() == y.y() && x.z() == y.z();
    };
    return eq3(a.position(), b.position()) && eq3(a.linear_velocity(), b.linear_velocity()) &&
           eq3(a.angular_velocity(), b.angular_velocity()) && a.orientation().x() == b.orientation().x() &&
           a.orientation().y() == b.orientation().y() && a.orientation().z() == b.orientation().z() &&
           a.orientation().w() == b.orientation().w() && a.flags() == b.flags();
}

/// A sector with news is sent whole every this many frames (each sector on its own phase), so that a reader
/// that missed the base of its partial samples gets the sector back within this many frames.
constexpr std::uint64_t kCompleteEvery = 30;

/// What readers hold of one owned sector: its members as last sent, and what changed since the complete
/// sample before its last one. Partial samples repeat all of it and name that sample as their base, so a
/// reader needs only some sample from the base on and the newest: it can lose any partial sample and one
/// complete sample (a slow reader, whose samples newer ones replaced in the writer's history) unharmed.
struct SectorPublication {
    std::vector<BodyId> members;    ///< sorted
    std::uint64_t last = 0;         ///< frame of the last complete sample; 0: none yet, the next is complete
    std::uint64_t before_last = 0;  ///< frame of the one before it (0: none, partial samples rest on `last`)
    bool last_complete = false;
    std::set<BodyId> changed;           ///< since before_last, and in the sector now
    std::set<BodyId> departed;          ///< since before_last, and not in the sector now
    std::set<BodyId> changed_recently;  ///< the same since last: the next complete sample's partial ones
    std::set<BodyId> departed_recently;

    void body_changed(BodyId id) {
        changed.insert(id);
        changed_recently.insert(id);
        departed.erase(id);
        departed_recently.erase(id);
    }
    void body_left(BodyId id) {
        departed.insert(id);
        departed_recently.insert(id);
        changed.erase(id);
        changed_recently.erase(id);
    }
    std::uint64_t base() const { return before_last ? before_last : last; }
    void sent_complete(std::uint64_t frame) {
        before_last = last;
        last = frame;
        changed = std::move(changed_recently);
        departed = std::move(departed_recently);
        changed_recently.clear();
        departed_recently.clear();
    }
};

double ms_since(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

}  // namespace

struct Worker::State {
    WorkerOptions options;
    std::unique_ptr<dds::Participant> participant;
    dds::Inbox inbox;
    std::unique_ptr<dds::Writer<wire::SectorFrame>> frames_out;
    std::unique_ptr<dds::Writer<wire::WorkerFrame>> marks_out;
    std::unique_ptr<dds::Writer<wire::CommandResult>> results_out;
    std::unique_ptr<dds::Reader<wire::SectorFrame>> frames_in;
    std::unique_ptr<dds::Reader<wire::WorkerFrame>> marks_in;
    std::unique_ptr<dds::Reader<wire::FrameGo>> go_in;
    std::unique_ptr<dds::Reader<wire::BodyDescription>> descriptions_in;
    std::unique_ptr<dds::Reader<wire::SectorRequest>> requests_in;

    std::optional<World> world;
    SectorAssignment current;
    SectorAssignment next;
    std::uint64_t frame = 0;
    std::uint32_t degraded = 0;

    // Received and not yet used.
    std::map<std::uint64_t, wire::FrameGo> gos;
    std::vector<BodyDesc> early_descriptions;  ///< before the world exists, in arrival order
    /// Other workers' samples, applied frame by frame; whether each was usable (SectorChain).
    std::deque<std::pair<wire::SectorFrame, bool>> ghost_updates;
    dds::SectorChain chain;
    /// (worker, frame) -> that worker's sectors and the frame of each one's latest sample
    std::map<std::pair<std::uint32_t, std::uint64_t>, std::vector<std::pair<SectorKey, std::uint64_t>>> marks;

    // What this worker last told the others.
    std::unordered_map<BodyId, wire::BodyState> published;
    std::map<SectorKey, SectorPublication> publications;  ///< owned sectors as readers hold them
    std::map<SectorKey, std::uint64_t> stamps;  ///< owned sectors and the frame of their latest sample
    std::set<SectorKey> touched;                ///< sectors changed by commands and handoffs this frame
    std::set<SectorKey> requested;              ///< sectors a reader asked to have whole
    std::set<BodyId> planes;                    ///< in no sector's samples: readers count them in marks

    // The halo: the engine holds this worker's own sectors and, as ghosts, the bodies of the sectors next
    // to them, the only ones that can be cloned into its sectors. The rest of the world is kept as wire
    // states and descriptions, so that a body entering the halo, or handed over, can be built.
    dds::SectorMirror others;                      ///< other workers' sectors as of the last frame applied
    std::unordered_map<BodyId, BodyDesc> catalog;  ///< every body's description
    std::unordered_map<SectorKey, bool, SectorKeyHash> halo_cache;  ///< for the assignment in force
    std::set<SectorKey> arrivals;  ///< sectors whose samples were applied this frame
    std::vector<BodyId> leavers;   ///< bodies that left a sector with those samples
    bool halo_moved = false;       ///< the assignment changed: the whole halo is checked again
    std::unordered_map<SectorKey, std::uint32_t, SectorKeyHash> publisher;  ///< of each sector's last sample
    std::set<std::uint32_t> gone;  ///< workers dropped from the assignment: nobody hands their bodies over

    bool owns(const SectorKey& key) const { return current.owner_of(key) == options.id; }
    bool in_halo(const SectorKey& key);
    bool wanted(const SectorKey& key) { return owns(key) || in_halo(key); }
    Status build(BodyId id, const BodySnapshot& state);
    void sync_halo(bool full);
    void pump();
    bool start_world(const wire::FrameGo& go);
    void apply_go(const wire::FrameGo& go);
    void apply_command(const wire::Command& command, std::uint64_t order);
    void result(const wire::Command& command, std::uint64_t order, bool applied, const std::string& reason);
    bool border_data_ready(std::uint64_t previous);
    void apply_ghost_updates(std::uint64_t up_to);
    void publish(bool full);
    void mark(double step_ms, double wait_ms);
};

Worker::Worker(std::unique_ptr<State> state) : state_(std::move(state)) {}

Worker::~Worker() {
    // Endpoints go before the participant that made them.
    if (!state_) return;
    state_->frames_out.reset();
    state_->marks_out.reset();
    state_->results_out.reset();
    state_->frames_in.reset();
    state_->marks_in.reset();
    state_->go_in.reset();
    state_->descriptions_in.reset();
    state_->requests_in.reset();
}

Expected<std::unique_ptr<Worker>> Worker::create(const WorkerOptions& options) {
    if (options.id == 0) return Error{"worker ids start at 1"};
    auto state = std::make_unique<State>();
    state->options = options;
    Expected<std::unique_ptr<dds::Participant>> participant = dds::Participant::create(
        options.domain, options.profile, "lpss-worker-" + std::to_string(options.id));
    if (!participant) return participant.error();
    state->participant = std::move(participant).value();
    dds::Participant& p = *state->participant;
    using namespace dds;
    state->frames_out = std::make_unique<Writer<wire::SectorFrame>>(
        p, p.topic<wire::SectorFramePubSubType>(kSectorFrames), writer_qos(kSectorFrameDelivery));
    state->marks_out = std::make_unique<Writer<wire::WorkerFrame>>(
        p, p.topic<wire::WorkerFramePubSubType>(kWorkerFrames), writer_qos(kFrameDelivery));
    state->results_out = std::make_unique<Writer<wire::CommandResult>>(
        p, p.topic<wire::CommandResultPubSubType>(kCommandResults), writer_qos(kCommandDelivery));
    state->frames_in =
        std::make_unique<Reader<wire::SectorFrame>>(p, p.topic<wire::SectorFramePubSubType>(kSectorFrames),
                                                    reader_qos(kSectorFrameReading), &state->inbox);
    state->marks_in = std::make_unique<Reader<wire::WorkerFrame>>(
        p, p.topic<wire::WorkerFramePubSubType>(kWorkerFrames), reader_qos(kFrameDelivery), &state->inbox);
    state->go_in = std::make_unique<Reader<wire::FrameGo>>(p, p.topic<wire::FrameGoPubSubType>(kFrameGo),
                                                           reader_qos(kFrameDelivery), &state->inbox);
    state->descriptions_in = std::make_unique<Reader<wire::BodyDescription>>(
        p, p.topic<wire::BodyDescriptionPubSubType>(kBodyDescriptions), reader_qos(kDescriptionReading),
        &state->inbox);
    state->requests_in = std::make_unique<Reader<wire::SectorRequest>>(
        p, p.topic<wire::SectorRequestPubSubType>(kSectorRequests), reader_qos(kCommandDelivery),
        &state->inbox);
    if (!state->frames_out->ok() || !state->marks_out->ok() || !state->results_out->ok() ||
        !state->frames_in->ok() || !state->marks_in->ok() || !state->go_in->ok() ||
        !state->descriptions_in->ok() || !state->requests_in->ok()) {
        return Error{"cannot create the worker's DDS readers and writers"};
    }
    return std::unique_ptr<Worker>(new Worker(std::move(state)));
}

void Worker::State::pump() {
    go_in->take_all([&](const wire::FrameGo& go, const dds::fdds::SampleInfo& info) {
        if (info.valid_data && go.frame() > frame) gos[go.frame()] = go;
    });
    descriptions_in->take_all([&](const wire::BodyDescription& d, const dds::fdds::SampleInfo& info) {
        // Descriptions fill the world at the start; later bodies arrive as commands, in order, and
        // removals too.
        if (!info.valid_data || world) return;
        BodyDesc body = dds::from_wire(d);
        spdlog::debug("worker {}: description of body {}", options.id, body.id);
        if (!world) {
            auto same = [&](const BodyDesc& b) { return b.id == body.id; };
            if (std::find_if(early_descriptions.begin(), early_descriptions.end(), same) ==
                early_descriptions.end()) {
                early_descriptions.push_back(body);
            }
        }
    });
    requests_in->take_all([&](const wire::SectorRequest& r, const dds::fdds::SampleInfo& info) {
        if (!info.valid_data) return;
        for (const wire::SectorKey& key : r.sectors())
            requested.insert(dds::from_wire(key));  // publish() keeps those it owns
    });
    marks_in->take_all([&](const wire::WorkerFrame& m, const dds::fdds::SampleInfo& info) {
        if (!info.valid_data || m.worker() == options.id) return;
        std::vector<std::pair<SectorKey, std::uint64_t>> stamps;
        for (const wire::SectorStamp& st : m.sectors())
            stamps.emplace_back(dds::from_wire(st.sector()), st.frame());
        marks[{m.worker(), m.frame()}] = std::move(stamps);
    });
    frames_in->take_all([&](const wire::SectorFrame& f, const dds::fdds::SampleInfo& info) {
        if (!info.valid_data || f.worker() == options.id) return;
        // A refused sample still carries true states of the bodies it holds; its sector's others may be
        // stale, so it does not count as the sector's border data (a complete sample will).
        const bool usable = chain.accept(f);
        if (!usable) spdlog::debug("worker {}: partial sample without its base", options.id);
        ghost_updates.emplace_back(f, usable);
    });
}

bool Worker::State::start_world(const wire::FrameGo& go) {
    // Every body of the world, owned or ghost, in the order the coordinator described them (the scene's).
    const auto deadline = Clock::now() + options.coordinator_wait;
    while (early_descriptions.size() < go.bodies() && Clock::now() < deadline) {
        inbox.wait(std::chrono::milliseconds(50));
        pump();
    }
    if (early_descriptions.size() < go.bodies()) {
        spdlog::error("worker {}: only {} of {} body descriptions arrived", options.id,
                      early_descriptions.size(), go.bodies());
        return false;
    }
    const WorldSettings settings = dds::from_wire(go.next().settings());
    current = dds::from_wire(go.next());
    next = current;
    EngineOptions engine;
    engine.threads = options.threads;
    engine.owns = [this](const SectorKey& key) { return owns(key); };
    Expected<World> created = World::create(settings, engine);
    if (!created) {
        spdlog::error("worker {}: the coordinator's settings are refused: {}", options.id,
                      created.error().message);
        return false;
    }
    world.emplace(std::move(created).value());
    // Its own bodies, the ghosts of its halo and the planes; the others only described.
    std::vector<BodyDesc> held;
    for (BodyDesc& body : early_descriptions) {
        if (is_plane(body.shape)) planes.insert(body.id);
        const auto* at = std::get_if<SectorPosition>(&body.position);
        Expected<SectorPosition> place =
            at ? world->grid().canonical(*at)
               : world->grid().from_global(std::get<Eigen::Vector3d>(body.position));
        if (is_plane(body.shape) || !place || wanted(place->sector)) held.push_back(body);
        catalog[body.id] = std::move(body);
    }
    if (Status st = world->add_bodies(held); !st) {
        spdlog::error("worker {}: bodies refused: {}", options.id, st.error().message);
        return false;
    }
    early_descriptions.clear();
    std::size_t ghosts = 0;
    for (const BodySnapshot& b : world->snapshot())
        ghosts += world->is_ghost(b.id) ? 1 : 0;
    spdlog::info("worker {}: {} of {} bodies, {} of them its own", options.id, world->body_count(),
                 catalog.size(), world->body_count() - ghosts);
    return true;
}

void Worker::State::result(const wire::Command& command, std::uint64_t order, bool applied,
                           const std::string& reason) {
    wire::CommandResult r;
    r.client(command.client());
    r.request(command.request());
    r.applied(applied);
    r.order(order);
    r.frame(frame);
    r.reason(reason);
    results_out->write(r);
}

void Worker::State::apply_command(const wire::Command& c, std::uint64_t order) {
    World& w = *world;
    switch (c.kind()) {
        case wire::kCommandSpawn: {  // every worker adds it (its owner as its own, the others as a ghost)
            BodyDesc body = dds::from_wire(c.spawn());
            if (c.spawn_global()) body.position = dds::from_wire(c.spawn().offset());
            Expected<SectorPosition> at = [&]() -> Expected<SectorPosition> {
                if (const auto* g = std::get_if<Eigen::Vector3d>(&body.position))
                    return w.grid().from_global(*g);
                return w.grid().canonical(std::get<SectorPosition>(body.position));
            }();
            const bool mine = at && owns(at->sector);
            // Its owner and the workers whose halo it is in hold it; the others only know it.
            const bool held = is_plane(body.shape) || !at || wanted(at->sector);
            Status st = held ? w.add_body(body) : Status{};
            if (mine) result(c, order, st.ok(), st.ok() ? "" : st.error().message);
            if (!st.ok()) break;
            catalog[body.id] = body;
            if (at) touched.insert(at->sector);
            if (is_plane(body.shape)) planes.insert(body.id);
            break;
        }
        case wire::kCommandRemove: {  // every worker removes its copy
            // Every worker holds planes as its own: the owner of the plane's sector answers for it.
            std::optional<BodySnapshot> before = w.body(c.body());
            const bool mine =
                before && (planes.count(c.body()) ? owns(before->position.sector) : !w.is_ghost(c.body()));
            Status st = before ? w.remove_body(c.body()) : Status{};
            if (mine) result(c, order, st.ok(), st.ok() ? "" : st.error().message);
            if (before) touched.insert(before->position.sector);
            if (st.ok()) {
                planes.erase(c.body());
                catalog.erase(c.body());
            }
            break;
        }
        case wire::kCommandImpulse:
        case wire::kCommandSetVelocity: {  // the owner applies
            if (!w.contains(c.body()) || w.is_ghost(c.body())) break;
            const Eigen::Vector3d a = dds::from_wire(c.vector1()), b = dds::from_wire(c.vector2());
            Status st = c.kind() == wire::kCommandImpulse ? w.apply_impulse(c.body(), a, b)
                                                          : w.set_velocity(c.body(), a, b);
            result(c, order, st.ok(), st.ok() ? "" : st.error().message);
            break;
        }
        default:
            break;  // refused by the coordinator already
    }
}

void Worker::State::apply_go(const wire::FrameGo& go) {
    // The assignment in force from this frame on.
    SectorAssignment announced = dds::from_wire(go.next());
    if (announced.epoch != next.epoch) next = announced;
    if (next.epoch != current.epoch && next.from_frame <= go.frame()) {
        for (std::uint32_t w : current.workers) {
            if (std::find(next.workers.begin(), next.workers.end(), w) == next.workers.end()) gone.insert(w);
        }
        current = next;
        world->set_ownership([this](const SectorKey& key) { return owns(key); });
        halo_cache.clear();
        halo_moved = true;
        spdlog::info("worker {}: assignment epoch {} from frame {}", options.id, current.epoch, go.frame());
    }
    // Bodies changing hands: every worker moves its copy to the state the old owner handed over, exactly;
    // the new owner's copy becomes its own body, the old owner's a ghost.
    for (const wire::Handoff& h : go.handoffs()) {
        BodySnapshot state = dds::from_wire(h.state(), dds::from_wire(h.sector()));
        state.position.local = dds::from_wire(h.precise_position());
        if (!world->contains(h.body())) {
            // Handed over from outside the halo (sectors that move in a rebalance): built here.
            if (h.to_worker() != options.id) continue;
            if (Status st = build(h.body(), state); !st)
                spdlog::error("worker {}: handoff of body {}: {}", options.id, h.body(), st.error().message);
            touched.insert(state.position.sector);
            continue;
        }
        if (Status st = world->set_state(state); !st)
            spdlog::warn("worker {}: handoff: {}", options.id, st.error().message);
        touched.insert(state.position.sector);
    }
    for (std::size_t n = 0; n < go.commands().size(); ++n) {
        const std::uint64_t order = n < go.command_sequence().size() ? go.command_sequence()[n] : 0;
        apply_command(go.commands()[n], order);
    }
}

bool Worker::State::border_data_ready(std::uint64_t previous) {
    if (previous == 0) return true;
    // The samples of the halo: only its bodies can reach this worker's sectors. When the assignment
    // changes with this frame, the new halo is not known yet here: every sector then.
    const bool switching = next.epoch != current.epoch && next.from_frame <= previous + 1;
    for (std::uint32_t other : current.workers) {
        if (other == options.id) continue;
        auto it = marks.find({other, previous});
        if (it == marks.end()) return false;  // which sectors it wrote is not known yet
        for (const auto& [key, stamp] : it->second) {
            if ((switching || in_halo(key)) && chain.newest(key) < stamp) return false;
        }
    }
    return true;
}

void Worker::State::apply_ghost_updates(std::uint64_t up_to) {
    // Samples of later frames stay queued: a faster worker's future must not leak into this frame.
    std::deque<std::pair<wire::SectorFrame, bool>> later;
    for (const auto& [f, usable] : ghost_updates) {
        if (f.frame() > up_to) {
            later.emplace_back(f, usable);
            continue;
        }
        const SectorKey key = dds::from_wire(f.sector());
        for (const wire::BodyState& b : f.bodies()) {
            if (world->contains(b.id()) && world->is_ghost(b.id())) {
                if (Status st = world->set_state(dds::from_wire(b, key)); !st) {
                    spdlog::warn("worker {}: ghost {}: {}", options.id, b.id(), st.error().message);
                }
            }
        }
        if (usable) {
            others.apply(f, &leavers);
            publisher[key] = f.worker();
            arrivals.insert(key);
        }
    }
    ghost_updates.swap(later);
    chain.forget_applied(up_to);
}

bool Worker::State::in_halo(const SectorKey& key) {
    auto cached = halo_cache.find(key);
    if (cached != halo_cache.end()) return cached->second;
    bool next_to_own = false;
    if (!owns(key)) {
        for (int di = -1; di <= 1 && !next_to_own; ++di)
            for (int dj = -1; dj <= 1 && !next_to_own; ++dj)
                for (int dk = -1; dk <= 1 && !next_to_own; ++dk)
                    next_to_own = owns(SectorKey{key.i + di, key.j + dj, key.k + dk});
    }
    return halo_cache[key] = next_to_own;
}

Status Worker::State::build(BodyId id, const BodySnapshot& state) {
    auto known = catalog.find(id);
    if (known == catalog.end()) return Error{"no description of body " + std::to_string(id)};
    BodyDesc body = known->second;
    body.position = state.position;
    body.orientation = state.orientation;
    body.linear_velocity = state.linear_velocity;
    body.angular_velocity = state.angular_velocity;
    if (Status st = world->add_body(body); !st) return st;
    return body.mass > 0.0 ? world->set_state(state) : Status{};
}

void Worker::State::sync_halo(bool full) {
    World& w = *world;
    // Ghosts that left the halo go: they cannot touch this worker's sectors any more.
    auto drop_if_outside = [&](BodyId id) {
        if (!w.contains(id) || !w.is_ghost(id) || planes.count(id)) return;
        if (!in_halo(w.body(id)->position.sector)) (void)w.remove_body(id);
    };
    if (full) {
        for (const BodySnapshot& b : w.snapshot())
            drop_if_outside(b.id);
    } else {
        for (BodyId id : leavers)
            drop_if_outside(id);
    }
    // Bodies of halo sectors become ghosts. Of sectors newly owned, the static bodies, which no handoff
    // brings, become this worker's own; and all bodies of a worker that is gone, from its last samples.
    auto adopt = [&](const SectorKey& key, const dds::SectorMirror::Bodies& bodies) {
        const bool own = owns(key);
        if (!own && !in_halo(key)) return;
        auto last = publisher.find(key);
        const bool orphaned = own && last != publisher.end() && gone.count(last->second);
        for (const auto& [id, state] : bodies) {
            if (w.contains(id)) continue;
            auto known = catalog.find(id);
            if (known == catalog.end() || (own && !orphaned && known->second.mass > 0.0)) continue;
            if (Status st = build(id, dds::from_wire(state, key)); !st)
                spdlog::warn("worker {}: cannot hold body {}: {}", options.id, id, st.error().message);
            else if (orphaned)
                spdlog::info("worker {}: body {} taken over from worker {}, as it last published it",
                             options.id, id, last->second);
        }
    };
    if (full) {
        for (const auto& [key, bodies] : others.sectors())
            adopt(key, bodies);
    } else {
        for (const SectorKey& key : arrivals) {
            auto it = others.sectors().find(key);
            if (it != others.sectors().end()) adopt(key, it->second);
        }
    }
    arrivals.clear();
    leavers.clear();
}

void Worker::State::publish(bool full) {
    World& w = *world;
    std::set<SectorKey> keys(touched.begin(), touched.end());
    for (const SectorKey& k : w.stepped_sectors())
        keys.insert(k);
    for (const auto& entry : publications)
        keys.insert(entry.first);  // where bodies were: they may have left
    for (const SectorKey& k : requested) {
        if (publications.count(k)) keys.insert(k);  // a sector of this worker's that holds bodies
    }
    if (full) {
        for (const SectorKey& k : w.sectors())
            keys.insert(k);
    }
    for (const SectorKey& key : keys) {
        if (!owns(key)) {
            // A sector handed to another worker: its new owner writes it, whole first, from now on.
            publications.erase(key);
            continue;
        }
        SectorPublication& pub = publications[key];
        std::vector<BodySnapshot> bodies = w.sector_bodies(key);
        std::vector<BodyId> now;
        bool news = false;
        for (const BodySnapshot& b : bodies) {
            now.push_back(b.id);
            const wire::BodyState state = dds::to_wire(b);
            auto last = published.find(b.id);
            const bool arrived = !std::binary_search(pub.members.begin(), pub.members.end(), b.id);
            if (arrived || last == published.end() || !same_state(last->second, state)) {
                news = true;
                pub.body_changed(b.id);
                published[b.id] = state;
            }
        }
        for (BodyId id : pub.members) {
            if (std::binary_search(now.begin(), now.end(), id)) continue;
            news = true;
            pub.body_left(id);
        }
        pub.members = now;
        // Whole: when a reader may need it (the first frame, a new reader, a reader that asked, a sector new
        // to this worker or emptied), on the sector's phase, and once when it falls quiet, so that the
        // durable last sample of a quiet sector is all of it. Otherwise only what changed since the base.
        const bool on_phase = (frame + SectorKeyHash{}(key)) % kCompleteEvery == 0;
        const bool complete = full || pub.last == 0 || now.empty() || (news && on_phase) ||
                              (!news && !pub.last_complete) || requested.count(key);
        if (!news && !complete) continue;
        wire::SectorFrame sample;
        sample.sector(dds::to_wire(key));
        sample.frame(frame);
        sample.base(complete ? frame : pub.base());
        sample.worker(options.id);
        sample.epoch(current.epoch);
        sample.complete(complete);
        if (complete) {
            for (const BodySnapshot& b : bodies)
                sample.bodies().push_back(published[b.id]);
            pub.sent_complete(frame);
        } else {
            for (BodyId id : pub.changed)
                sample.bodies().push_back(published[id]);
            sample.departed().assign(pub.departed.begin(), pub.departed.end());
        }
        pub.last_complete = complete;
        frames_out->write(sample);
        stamps[key] = frame;
        if (now.empty()) {
            publications.erase(key);
            stamps.erase(key);
            frames_out->dispose(sample);  // the sector is gone: a late joiner need not see it
        }
    }
    for (auto it = published.begin(); it != published.end();) {
        it = w.contains(it->first) && !w.is_ghost(it->first) ? std::next(it) : published.erase(it);
    }
    touched.clear();
    requested.clear();
}

void Worker::State::mark(double step_ms, double wait_ms) {
    World& w = *world;
    wire::WorkerFrame m;
    m.worker(options.id);
    m.frame(frame);
    m.epoch(current.epoch);
    for (auto it = stamps.begin(); it != stamps.end();)
        it = owns(it->first) ? std::next(it) : stamps.erase(it);
    for (const auto& [key, stamp] : stamps) {
        wire::SectorStamp st;
        st.sector(dds::to_wire(key));
        st.frame(stamp);
        m.sectors().push_back(st);
    }

    // Bodies leaving this worker: crossing into a sector of another, or standing in a sector it gives up
    // with the next assignment.
    const bool reassigning = next.epoch != current.epoch && next.from_frame == frame + 1;
    const SectorAssignment& after = reassigning ? next : current;
    std::set<BodyId> leaving;
    auto hand_over = [&](BodyId id, const SectorPosition& to) {
        if (!leaving.insert(id).second) return;
        const std::uint32_t owner = after.owner_of(to.sector);
        if (owner == options.id) return;
        BodySnapshot state = *w.body(id);
        state.position = to;
        wire::Handoff h;
        h.body(id);
        h.from_worker(options.id);
        h.to_worker(owner);
        h.sector(dds::to_wire(to.sector));
        h.state(dds::to_wire(state));
        h.precise_position(dds::to_wire(to.local));
        m.leaving().push_back(h);
    };
    for (const Departure& d : w.departures())
        hand_over(d.id, d.to);
    if (reassigning) {
        for (const SectorKey& key : w.sectors()) {
            if (!owns(key) || after.owner_of(key) == options.id) continue;
            for (const BodySnapshot& b : w.sector_bodies(key)) {
                if (w.description(b.id) && w.description(b.id)->mass > 0.0) hand_over(b.id, b.position);
            }
        }
    }

    const FrameStats& s = w.last_frame_stats();
    std::uint32_t owned = 0, awake = 0, sectors = 0;
    std::map<SectorKey, float> loads;
    const bool report_loads = frame % 60 == 0;
    for (const SectorKey& key : w.sectors()) {
        if (!owns(key)) continue;
        ++sectors;
        for (const BodySnapshot& b : w.sector_bodies(key)) {
            ++owned;
            awake += b.awake ? 1 : 0;
            if (report_loads) loads[block_of(key, current.block_size)] += b.awake ? 2.0f : 1.0f;
        }
    }
    for (const auto& [block, load] : loads) {
        wire::BlockLoad l;
        l.block(dds::to_wire(block));
        l.load(load);
        m.loads().push_back(l);
    }
    m.loads_reported(report_loads);
    m.bodies(owned);
    m.planes(static_cast<std::uint32_t>(planes.size()));
    m.awake(awake);
    m.sector_count(sectors);
    m.ghosts(static_cast<std::uint32_t>(w.body_count() - owned - planes.size()));
    m.border_bodies(static_cast<std::uint32_t>(s.border_bodies));
    m.clones(static_cast<std::uint32_t>(s.clones));
    m.step_ms(static_cast<float>(step_ms));
    m.wait_ms(static_cast<float>(wait_ms));
    m.degraded(degraded);
    marks_out->write(m);
}

int Worker::run(const std::atomic<bool>& stop) {
    State& s = *state_;
    const std::uint32_t id = s.options.id;
    // Hello: frame 0 tells the coordinator this worker is up.
    wire::WorkerFrame hello;
    hello.worker(id);
    hello.frame(0);
    s.marks_out->write(hello);
    spdlog::info("worker {}: up on domain {}, waiting for the coordinator", id, s.participant->domain());

    const auto started = Clock::now();
    while (!stop.load()) {
        s.pump();
        auto go = s.gos.find(s.frame + 1);
        if (go == s.gos.end()) {
            if (!s.world && Clock::now() - started > s.options.coordinator_wait) {
                spdlog::error("worker {}: no coordinator found on domain {} within {} s", id,
                              s.participant->domain(), s.options.coordinator_wait.count() / 1000);
                return 3;
            }
            s.inbox.wait(std::chrono::milliseconds(50));
            continue;
        }
        const wire::FrameGo current = go->second;
        s.gos.erase(s.gos.begin(), std::next(go));
        if (current.stop()) {
            spdlog::info("worker {}: stopped by the coordinator after frame {}", id, s.frame);
            return 0;
        }
        if (!s.world && !s.start_world(current)) return 4;
        const auto wait_start = Clock::now();
        s.frame = current.frame();
        // The other workers' data of the previous frame, within a bounded wait.
        while (!s.border_data_ready(s.frame - 1) && !stop.load()) {
            if (Clock::now() - wait_start > s.options.border_wait) {
                ++s.degraded;
                spdlog::warn("worker {}: frame {} starts without all border data of frame {} (degraded)", id,
                             s.frame, s.frame - 1);
                break;
            }
            s.inbox.wait(std::chrono::milliseconds(5));
            s.pump();
        }
        s.apply_ghost_updates(s.frame - 1);
        s.apply_go(current);
        // The whole halo now and then, and when the assignment changed; else only where samples arrived.
        s.sync_halo(s.halo_moved || s.frame % 60 == 0);
        s.halo_moved = false;
        const double wait_ms = ms_since(wait_start);
        const auto step_start = Clock::now();
        s.world->step();
        const double step_ms = ms_since(step_start);
        // Every sector whole in the first frame, and when a reader has just matched (a late joiner): it
        // would otherwise wait for each sector's next complete sample.
        const bool full = s.frame == 1 || s.frames_out->take_new_matches() > 0;
        s.publish(full);
        s.mark(step_ms, wait_ms);
        // Forget what no longer matters: marks of frames before the previous one.
        for (auto it = s.marks.begin(); it != s.marks.end();) {
            it = it->first.second + 1 < s.frame ? s.marks.erase(it) : std::next(it);
        }
    }
    spdlog::info("worker {}: stopping", id);
    return 0;
}

}  // namespace lpss::worker
