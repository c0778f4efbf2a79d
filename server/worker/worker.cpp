// The worker's frame loop: wait for the frame (frame_gate), bring the halo's ghosts to the other workers'
// states (halo), take over bodies and apply commands (frame_start, handoff), step, publish what changed
// and say so (publishing). Here too: making the worker's DDS entities and reading what comes (pump).
// worker_state.hpp lists the other files of the loop.
#include "worker.hpp"

#include <spdlog/spdlog.h>

#include "heap.hpp"
#include "lpss_dds/convert.hpp"
#include "lpss_dds/sample_check.hpp"
#include "lpss_dds/security.hpp"
#include "lpss_dds/topics.hpp"
#include "worker_state.hpp"

namespace lpss::worker {
namespace {

/// How long after a mark came a sample it lists is taken as lost, and its sector asked for whole: past the
/// time its writer keeps it for repair (it was written before the mark), with a heartbeat's room (100 ms).
constexpr std::chrono::milliseconds kLostAfter{dds::kSectorFrameDelivery.lifespan_ms + 100};

double ms_since(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

}  // namespace

Worker::Worker(std::unique_ptr<State> state) : state_(std::move(state)) {}

Worker::~Worker() {
    // Endpoints go before the participant that made them.
    if (!state_) return;
    state_->beat.reset();
    state_->frames_out.reset();
    state_->marks_out.reset();
    state_->results_out.reset();
    state_->frames_in.reset();
    state_->marks_in.reset();
    state_->go_in.reset();
    state_->acks_in.reset();
    state_->planes_in.reset();
    state_->requests_in.reset();
    state_->requests_out.reset();
}

Expected<std::unique_ptr<Worker>> Worker::create(const WorkerOptions& options) {
    if (options.id == 0) return Error{"worker ids start at 1"};
    auto state = std::make_unique<State>(options);
    Expected<std::unique_ptr<dds::Participant>> participant =
        dds::Participant::create(options.domain, options.profile, "lpss-worker-" + std::to_string(options.id),
                                 options.avoid_participant_ids, options.security);
    if (!participant) return participant.error();
    state->participant = std::move(participant).value();
    dds::Participant& p = *state->participant;
    using namespace dds;
    fdds::Topic* frames = p.topic<wire::SectorFramePubSubType>(kSectorFrames);
    // Its own samples do not come back to its own reader (own_partition.hpp).
    state->frames_out = std::make_unique<Writer<wire::SectorFrame>>(p.sector_publisher(), frames,
                                                                    writer_qos(kSectorFrameDelivery));
    state->marks_out = std::make_unique<Writer<wire::WorkerFrame>>(
        p, p.topic<wire::WorkerFramePubSubType>(kWorkerFrames), writer_qos(kWorkerMarks));
    state->results_out = std::make_unique<Writer<wire::CommandResult>>(
        p, p.topic<wire::CommandResultPubSubType>(kCommandResults), writer_qos(kResultDelivery));
    // Only the samples addressed to this worker: its sectors and its halo's.
    state->frames_in = std::make_unique<Reader<wire::SectorFrame>>(
        p.sector_subscriber(), p.sector_recipient(kSectorFrames, options.id), reader_qos(kSectorFrameReading),
        &state->inbox);
    state->marks_in = std::make_unique<Reader<wire::WorkerFrame>>(
        p, p.topic<wire::WorkerFramePubSubType>(kWorkerFrames), reader_qos(kFrameDelivery), &state->inbox);
    // With the frame starts' lease: a worker that hears no coordinator beat knows it is cut off.
    state->go_in = std::make_unique<Reader<wire::FrameGo>>(p, p.topic<wire::FrameGoPubSubType>(kFrameGo),
                                                           reader_qos(kCoordinatorWords), &state->inbox);
    state->acks_in = std::make_unique<Reader<wire::FrameAck>>(
        p, p.topic<wire::FrameAckPubSubType>(kFrameAcks), reader_qos(kFrameDelivery), &state->inbox);
    state->read_planes();
    state->requests_out = std::make_unique<Writer<wire::SectorRequest>>(
        p, p.topic<wire::SectorRequestPubSubType>(kSectorRequests), writer_qos(kCommandDelivery));
    state->requests_in = std::make_unique<Reader<wire::SectorRequest>>(
        p, p.topic<wire::SectorRequestPubSubType>(kSectorRequests), reader_qos(kCommandDelivery),
        &state->inbox);
    if (!state->frames_out->ok() || !state->marks_out->ok() || !state->results_out->ok() ||
        !state->frames_in->ok() || !state->marks_in->ok() || !state->go_in->ok() || !state->acks_in->ok() ||
        !state->planes_in->ok() || !state->requests_in->ok() || !state->requests_out->ok()) {
        return Error{"cannot create the worker's DDS readers and writers" +
                     dds::refused_endpoints_hint(options.security)};
    }
    // Several beats a lease: a late beat or two does not make a worker look gone.
    state->beat = std::make_unique<LivelinessBeat>(state->marks_out->raw(), beat_period(kWorkerMarks));
    return std::unique_ptr<Worker>(new Worker(std::move(state)));
}

void Worker::State::deliver_before_going(std::chrono::milliseconds limit) {
    const auto deadline = Clock::now() + limit;
    bool all = true;
    auto left = [&] {
        return std::max(std::chrono::milliseconds(1),
                        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()));
    };
    all = frames_out->delivered(left()) && all;
    all = marks_out->delivered(left()) && all;
    all = results_out->delivered(left()) && all;
    if (!all)
        spdlog::info(
            "worker {}: not every reader acknowledged what this worker wrote within {} ms (a reader killed "
            "earlier stays matched for a while)",
            options.id, limit.count());
}

void Worker::State::forget_what_it_wrote() {
    std::size_t removed = 0;
    frames_out->raw()->clear_history(&removed);
    marks_out->raw()->clear_history(&removed);
    results_out->raw()->clear_history(&removed);
}

int Worker::State::sit_out(const std::atomic<bool>& stop) {
    forget_what_it_wrote();
    const auto since = Clock::now();
    while (!stop.load() && coordinators.cut_off()) {
        if (Clock::now() - since > options.coordinator_wait) {
            spdlog::error("worker {}: no coordinator came back within {} s; stopping", options.id,
                          options.coordinator_wait.count() / 1000);
            return 3;
        }
        inbox.wait(std::chrono::milliseconds(50));
        pump();
    }
    if (stop.load()) return 0;
    spdlog::info("worker {}: a coordinator is heard again", options.id);
    return kTakenAsGone;
}

void Worker::State::pump() {
    coordinators.follow(inbox.take_liveliness());
    go_in->take_all([&](const wire::FrameGo& go, const dds::fdds::SampleInfo& info) {
        if (!info.valid_data) return;
        coordinators.heard(info.publication_handle, info.source_timestamp.to_ns());
        if (go.frame() > frame) gate.take_go(go);
        // A start, one of a frame begun here written again included, announcing an assignment newer than
        // any known here that leaves this worker out: the coordinator took it as gone (every worker gone,
        // it waits for one to join and names none). Older ones (history a joiner reads) say nothing.
        const auto& named = go.next().workers();
        if (world && !go.stop() && go.next().epoch() > halo.next().epoch &&
            std::find(named.begin(), named.end(), options.id) == named.end())
            announced_without_it = go.frame();
    });
    acks_in->take_all([&](const wire::FrameAck& ack, const dds::fdds::SampleInfo& info) {
        if (info.valid_data) gate.take_ack(ack);
    });
    planes_in->take_all([&](const wire::BodyDescription& d, const dds::fdds::SampleInfo& info) {
        // The world's planes at the start; later ones arrive as commands, in order, and removals too.
        if (!info.valid_data || world) return;
        early_planes[d.id()] = {d.rank(), dds::from_wire(d)};
    });
    requests_in->take_all([&](const wire::SectorRequest& r, const dds::fdds::SampleInfo& info) {
        if (!info.valid_data) return;
        for (const wire::SectorKey& key : r.sectors())
            whole_requested.insert(dds::from_wire(key));  // publish() keeps those it owns
        if (r.inventory()) inventories.ask(r);
    });
    marks_in->take_all([&](const wire::WorkerFrame& m, const dds::fdds::SampleInfo& info) {
        if (!info.valid_data) return;
        if (m.sector_reader().size() == 16 && m.worker() != options.id && m.worker() != 0) {
            dds::GuidBytes reader{};
            std::copy(m.sector_reader().begin(), m.sector_reader().end(), reader.begin());
            sector_readers[m.worker()] = reader;
        }
        gate.take_mark(m, Clock::now());
        if (!world && m.frame() > 0) heard.insert(m.worker());
    });
    frames_in->take_all([&](wire::SectorFrame& f, const dds::fdds::SampleInfo& info) {
        if (info.valid_data) take_sample(std::move(f));
    });
    ask_for_whole_sectors();
}

std::uint64_t Worker::State::known_frame() const {
    const wire::FrameGo* latest = gate.latest();
    return std::max(frame, latest ? latest->frame() : 0);
}

std::uint64_t Worker::State::frames_ahead() const {
    // A worker not yet in the world reads the coordinator's frame starts from its writer's history, which
    // can come in a burst after newer samples (seen in the soak: 111 frames behind, and the sector sample
    // that a joiner was waiting for refused; its first frame then waited 2 s and started degraded).
    return world ? dds::kFramesAhead : dds::kClientFramesAhead;
}

void Worker::State::take_sample(wire::SectorFrame f) {
    if (f.worker() == options.id) return;
    const std::uint64_t frame_of = f.frame();
    // Not applied: the sector is asked for whole (ask_for_whole_sectors), as clients and the coordinators
    // do, or it would stay broken until its owner sent it whole for some other reason.
    if (intake.take(std::move(f), known_frame(), frames_ahead()) == dds::SampleIntake::Taken::without_base)
        spdlog::warn("worker {}: sector sample of frame {} without its base", options.id, frame_of);
}

void Worker::State::learn(const SectorAssignment& assignment) {
    for (wire::SectorFrame& f : intake.learn(assignment))
        take_sample(std::move(f));
}

void Worker::State::ask_for_whole_sectors() {
    if (auto request = intake.whole_request(next_whole_request)) requests_out->write(*request);
}

void Worker::State::apply_samples(std::uint64_t up_to,
                                  const std::vector<std::pair<std::uint64_t, BodyDesc>>& also) {
    halo.apply(*world, intake.through(up_to), also);
    intake.applied(up_to);
}

wire::WorkerFrame Worker::State::mark_of(std::uint64_t f) const {
    wire::WorkerFrame m;
    m.worker(options.id);
    m.frame(f);
    const dds::GuidBytes reader = frames_in->guid();
    m.sector_reader(std::vector<std::uint8_t>(reader.begin(), reader.end()));
    for (const auto& [w, reader] : sector_readers) {
        if (frames_out->reaches(reader)) m.reaching().push_back(w);
    }
    return m;
}

int Worker::participant_id() const { return state_->participant->participant_id(); }

int Worker::run(const std::atomic<bool>& stop) {
    State& s = *state_;
    const std::uint32_t id = s.options.id;
    // Hello: frame 0 tells the coordinator this worker is up.
    s.marks_out->write(s.mark_of(0));
    spdlog::info("worker {}: up on domain {}, waiting for the coordinator", id, s.participant->domain());

    const auto started = Clock::now();
    bool coordinator_seen = false;
    bool coordinator_lost = false;          ///< a running world has no coordinator
    Clock::time_point coordinator_lost_at;  ///< since when
    while (!stop.load()) {
        s.pump();
        if (s.world && s.coordinators.cut_off()) {
            // No coordinator's beat for its lease: this worker is cut off (or every coordinator is gone).
            // The others are taking its sectors over; whatever it published from now on would be stale.
            spdlog::error(
                "worker {}: no coordinator heard for its lease (cut off, or every coordinator gone) after "
                "frame {}: stopping without publishing; it is taken as gone (liveliness news: {})",
                id, s.frame, s.coordinators.history());
            return s.sit_out(stop);
        }
        if (s.announced_without_it) {
            spdlog::error(
                "worker {}: the coordinator took this worker as gone (frame {}'s start announces an "
                "assignment without it) after its frame {}: stopping without publishing",
                id, *s.announced_without_it, s.frame);
            s.forget_what_it_wrote();
            return kTakenAsGone;
        }
        const wire::FrameGo* next = s.gate.go(s.frame + 1);
        if (next == nullptr) {
            // A frame after the next started without this worker: the coordinator took it as gone (it was
            // stopped, or cut off, longer than its lease) and will not start its next frame again. (Not a
            // stop: it does not wait for the standby as the start before it does, and may come first.)
            if (const wire::FrameGo* latest = s.gate.latest();
                s.world && latest != nullptr && latest->frame() >= s.frame + 2 && !latest->stop()) {
                spdlog::error(
                    "worker {}: the coordinator took this worker as gone (frame {} started without it after "
                    "its frame {}): stopping without publishing",
                    id, latest->frame(), s.frame);
                s.forget_what_it_wrote();
                return kTakenAsGone;
            }
            // A cluster already running when this worker came (it sees no frame 1 but later ones): it joins.
            if (const wire::FrameGo* latest = s.gate.latest();
                !s.world && latest != nullptr && latest->frame() > 1) {
                if (latest->stop()) {
                    spdlog::info("worker {}: the cluster stopped before this worker joined it", id);
                    return 0;
                }
                if (!s.coordinator_present()) {
                    // Joining a world whose coordinator went: not for ever.
                    if (!coordinator_lost) {
                        coordinator_lost = true;
                        coordinator_lost_at = Clock::now();
                    } else if (Clock::now() - coordinator_lost_at > s.options.coordinator_wait) {
                        spdlog::error("worker {}: the coordinator went before this worker joined; stopping",
                                      id);
                        return 3;
                    }
                } else {
                    coordinator_lost = false;
                }
                const State::Joining joining = s.join(*latest);
                if (joining == State::Joining::failed) return 4;
                if (joining == State::Joining::waiting) {
                    s.gate.started(latest->frame() - 1);  // keeps only the latest word
                    s.inbox.wait(std::chrono::milliseconds(20));
                }
                continue;
            }
            if (!s.world) {
                // A coordinator loading a large world says nothing for a while: wait as long as it is there.
                if (s.coordinator_present()) {
                    if (!coordinator_seen) spdlog::info("worker {}: a coordinator is there, loading", id);
                    coordinator_seen = true;
                    if (!s.heard.empty() && Clock::now() - s.join_noted > std::chrono::seconds(5)) {
                        // Workers run frames, yet no start of one has come: say what is matched.
                        s.join_noted = Clock::now();
                        spdlog::warn(
                            "worker {}: other workers run frames, but no frame start has come from a "
                            "coordinator yet ({} frame start writers matched, {} acknowledgement writers)",
                            id, s.go_in->matched(), s.acks_in->matched());
                    }
                } else if (coordinator_seen) {
                    spdlog::error("worker {}: the coordinator went away before the first frame", id);
                    return 3;
                } else if (Clock::now() - started > s.options.coordinator_wait) {
                    spdlog::error("worker {}: no coordinator found on domain {} within {} s", id,
                                  s.participant->domain(), s.options.coordinator_wait.count() / 1000);
                    return 3;
                }
            } else if (!s.coordinator_present()) {
                // Gone mid-run (DDS drops a killed participant when its lease of 20 s runs out). No other
                // coordinator takes over yet: say so, and stop after the coordinator wait rather than wait
                // for ever in silence.
                if (!coordinator_lost) {
                    coordinator_lost = true;
                    coordinator_lost_at = Clock::now();
                    spdlog::error(
                        "worker {}: the coordinator is gone after frame {}; stopping unless one "
                        "comes within {} s",
                        id, s.frame, s.options.coordinator_wait.count() / 1000);
                } else if (Clock::now() - coordinator_lost_at > s.options.coordinator_wait) {
                    spdlog::error("worker {}: no coordinator came back; stopping after frame {}", id,
                                  s.frame);
                    return 3;
                }
            } else {
                coordinator_lost = false;
            }
            s.inbox.wait(std::chrono::milliseconds(50));
            continue;
        }
        const wire::FrameGo go = *next;
        s.gate.started(go.frame());
        s.coordinators.standby_follows(go.standby() != 0 && !go.stop());
        if (go.stop()) {
            spdlog::info("worker {}: stopped by the coordinator after frame {}", id, s.frame);
            s.deliver_before_going(std::chrono::seconds(1));
            return 0;
        }
        if (!s.world && !s.start_world(go, stop)) return 4;
        const auto wait_start = Clock::now();
        s.frame = go.frame();
        s.frame_started_ns = go.started_ns();
        s.time_lost = go.time_lost();
        // The other workers' data of the previous frame, within a bounded wait.
        s.announce(go);
        bool asked_whole = false;  // said once a frame
        while (!s.gate.whole(s.frame - 1, go.ended(), go.coordinator_wrote(), s.intake.chain()) &&
               !stop.load()) {
            if (s.coordinators.cut_off()) {
                // Cut off while waiting for the others' data (the wait would end degraded, then publish).
                spdlog::error(
                    "worker {}: no coordinator heard for its lease (cut off, or every coordinator gone) "
                    "during frame {}: stopping without publishing; it is taken as gone (liveliness news: {})",
                    id, s.frame, s.coordinators.history());
                return s.sit_out(stop);
            }
            // A sample a mark lists that has not come once its writer's history has let it go (the
            // lifespan, topics.hpp) will not be repaired: its sector is asked for whole, as a client does
            // (the owner answers at the end of its frame, and a sample of that frame or later is what the
            // gate takes). Asked sooner, it would only double what repair still brings.
            const std::vector<SectorKey> lost = s.gate.samples_not_come(
                s.frame - 1, go.ended(), go.coordinator_wrote(), s.intake.chain(), Clock::now() - kLostAfter);
            for (const SectorKey& key : lost)
                s.intake.want_whole(key);
            if (!lost.empty() && !asked_whole) {
                asked_whole = true;
                spdlog::warn(
                    "worker {}: frame {} waits on {} sample(s) of frame {} still missing {} ms after "
                    "their marks came: asked for whole",
                    id, s.frame, lost.size(), s.frame - 1, kLostAfter.count());
            }
            // Not while no coordinator is heard: a frame published degraded then would be stale should this
            // worker be cut off (it is taken as gone once the standby's time to take over has passed).
            if (Clock::now() - wait_start > s.options.border_wait && !s.coordinators.none_alive()) {
                ++s.degraded;
                spdlog::warn(
                    "worker {}: frame {} starts without all border data of frame {} (degraded): {}", id,
                    s.frame, s.frame - 1,
                    s.gate.missing(s.frame - 1, go.ended(), go.coordinator_wrote(), s.intake.chain()));
                break;
            }
            s.inbox.wait(std::chrono::milliseconds(5));
            s.pump();
        }
        s.apply_samples(s.frame - 1);
        s.apply_go(go);
        if (s.left_out || s.announced_without_it) {
            spdlog::error(
                "worker {}: the coordinator took this worker as gone (the assignment in force from frame {} "
                "leaves it out): stopping without publishing",
                id, s.frame);
            s.forget_what_it_wrote();
            return kTakenAsGone;
        }
        const double wait_ms = ms_since(wait_start);
        const auto step_start = Clock::now();
        s.world->step();
        const double step_ms = ms_since(step_start);
        const auto publish_start = Clock::now();
        std::vector<wire::WrittenSector> written = s.publish();
        // The samples before the mark: a worker killed between the two must not leave a mark whose samples
        // never come (seen, with the mark first: readers waited for them, a client for ever, and the frame
        // stepped again for it started from the frame before it, a frame of motion lost).
        for (const wire::SectorFrame& sample : s.outgoing)
            s.frames_out->write(sample);
        s.outgoing.clear();
        s.mark(std::move(written), step_ms, wait_ms, ms_since(publish_start));
        // Freed buffers of handoffs and halo changes (the world's build gave back its own before frame 1).
        if (s.frame % 600 == 0) runtime::give_back_free_memory();
        s.gate.forget_before(s.frame - 1);
    }
    spdlog::info("worker {}: stopping", id);
    return 0;
}

}  // namespace lpss::worker
