// The coordinator: its DDS entities, reading what comes (pump), and the frame loop (run): each frame started
// once every live worker has ended the one before. coordinator_state.hpp lists the files of the rest.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <map>
#include <set>
#include <unordered_map>
#include <utility>

#include "coordinator_state.hpp"
#include "heap.hpp"
#include "lpss/common/border_reach.hpp"
#include "lpss_dds/convert.hpp"
#include "lpss_dds/security.hpp"
#include "lpss_dds/topics.hpp"
#include "lpss_dds/wall_clock.hpp"
#include "realtime_pacer.hpp"

namespace lpss::coordinator {
namespace {

/// A rebalance is made only if it brings the heaviest worker's load down to this share of what it is.
constexpr double kRebalanceGain = 0.85;
/// How long the coordinator holds back its own work after a frame start for the standby's acknowledgement.
constexpr std::chrono::microseconds kAcknowledgementPatience{5000};

}  // namespace

Coordinator::Coordinator(std::unique_ptr<State> state) : state_(std::move(state)) {}

Coordinator::~Coordinator() {
    if (!state_) return;
    // The beats first: each asserts a writer's liveliness from its own thread (seen under AddressSanitizer:
    // a beat asserting a writer deleted before it).
    state_->go_beat.reset();
    state_->marks_beat.reset();
    state_->acks_beat.reset();
    state_->go_out.reset();
    state_->assignment_out.reset();
    state_->planes_out.reset();
    state_->results_out.reset();
    state_->marks_out.reset();
    state_->sectors_out.reset();
    state_->first_state_out.reset();
    state_->status_out.reset();
    state_->requests_out.reset();
    state_->marks_in.reset();
    state_->commands_in.reset();
    state_->sectors_in.reset();
    state_->go_in.reset();
    state_->acks_out.reset();
    state_->acks_in.reset();
    state_->assignment_in.reset();
    state_->planes_in.reset();
    state_->results_in.reset();
    state_->status_in.reset();
}

Expected<std::unique_ptr<Coordinator>> Coordinator::create(const CoordinatorOptions& options) {
    if (options.workers < 1) return Error{"a cluster needs at least one worker"};
    if (options.block_size < 1) return Error{"block size must be at least 1"};
    auto state = std::make_unique<State>();
    state->options = options;
    state->intake = dds::SampleIntake("coordinator", "lpss-coordinator-" + std::to_string(options.id));
    state->command_rate = CommandRate(options.command_rate);
    Expected<std::unique_ptr<dds::Participant>> participant =
        dds::Participant::create(options.domain, options.profile, "lpss-coordinator", {}, options.security);
    if (!participant) return participant.error();
    state->participant = std::move(participant).value();
    dds::Participant& p = *state->participant;
    using namespace dds;
    if (options.id == 0)
        return Error{"coordinator id 0 is the coordinator's as a sector writer: take 1 or more"};
    fdds::Topic* go = p.topic<wire::FrameGoPubSubType>(kFrameGo);
    state->go_out = std::make_unique<Writer<wire::FrameGo>>(p, go, writer_qos(kCoordinatorWords));
    state->go_in =
        std::make_unique<Reader<wire::FrameGo>>(p, go, reader_qos(kCoordinatorWords), &state->start_acks);
    fdds::Topic* acks = p.topic<wire::FrameAckPubSubType>(kFrameAcks);
    state->acks_in =
        std::make_unique<Reader<wire::FrameAck>>(p, acks, reader_qos(kCoordinatorWords), &state->inbox);
    if (options.standby) {
        state->acks_out = std::make_unique<Writer<wire::FrameAck>>(p, acks, writer_qos(kCoordinatorWords));
        state->assignment_in =
            std::make_unique<Reader<wire::Assignment>>(p, p.topic<wire::AssignmentPubSubType>(kSectorOwners),
                                                       reader_qos(kAssignmentDelivery), &state->inbox);
        state->planes_in = std::make_unique<Reader<wire::BodyDescription>>(
            p, p.topic<wire::BodyDescriptionPubSubType>(kBodyDescriptions), reader_qos(kDescriptionReading),
            &state->inbox);
        state->results_in = std::make_unique<Reader<wire::CommandResult>>(
            p, p.topic<wire::CommandResultPubSubType>(kCommandResults), reader_qos(kResultDelivery),
            &state->inbox);
        if (!state->acks_out->ok() || !state->assignment_in->ok() || !state->planes_in->ok() ||
            !state->results_in->ok())
            return Error{"cannot create the standby coordinator's DDS readers and writers" +
                         dds::refused_endpoints_hint(options.security)};
    }
    state->assignment_out = std::make_unique<Writer<wire::Assignment>>(
        p, p.topic<wire::AssignmentPubSubType>(kSectorOwners), writer_qos(kAssignmentDelivery));
    state->planes_out = std::make_unique<Writer<wire::BodyDescription>>(
        p, p.topic<wire::BodyDescriptionPubSubType>(kBodyDescriptions), writer_qos(kStateDelivery));
    state->results_out = std::make_unique<Writer<wire::CommandResult>>(
        p, p.topic<wire::CommandResultPubSubType>(kCommandResults), writer_qos(kResultDelivery));
    fdds::Topic* marks = p.topic<wire::WorkerFramePubSubType>(kWorkerFrames);
    // With the workers' lease, which readers of marks ask for (a standby among them, for the first state).
    state->marks_out = std::make_unique<Writer<wire::WorkerFrame>>(p, marks, writer_qos(kWorkerMarks));
    fdds::Topic* sectors = p.topic<wire::SectorFramePubSubType>(kSectorFrames);
    // Its own samples do not come back to its own reader (own_partition.hpp): the first state is the world.
    state->sectors_out = std::make_unique<Writer<wire::SectorFrame>>(p.sector_publisher(), sectors,
                                                                     writer_qos(kFirstStateDelivery));
    // Made with the others, so that the workers there have matched it by the time the scene is read.
    if (!options.standby)
        state->first_state_out = std::make_unique<Writer<wire::SectorFrame>>(p.sector_publisher(), sectors,
                                                                             writer_qos(kFirstStateDelivery));
    state->status_out = std::make_unique<Writer<wire::ClusterStatus>>(
        p, p.topic<wire::ClusterStatusPubSubType>(kStatus), writer_qos(kStateDelivery));
    state->requests_out = std::make_unique<Writer<wire::SectorRequest>>(
        p, p.topic<wire::SectorRequestPubSubType>(kSectorRequests), writer_qos(kCommandDelivery));
    state->status_in = std::make_unique<Reader<wire::ClusterStatus>>(
        p, p.topic<wire::ClusterStatusPubSubType>(kStatus), reader_qos(kStateDelivery), &state->inbox);
    // A standby's loop needs no wake for each worker's mark either (it takes them with the start that
    // follows them): only once it leads (Coordinator::State::lead).
    state->marks_in = std::make_unique<Reader<wire::WorkerFrame>>(
        p, marks, reader_qos(kWorkerMarks), &state->inbox, options.standby ? Wake::on_news : Wake::on_data);
    state->commands_in =
        std::make_unique<Reader<wire::Command>>(p, p.topic<wire::CommandPubSubType>(kCommands),
                                                reader_qos_on_own_port(kCommandDelivery), &state->inbox);
    // Sector samples do not wake the loop: it takes them when a mark, a start or an acknowledgement does
    // (a worker writes its samples before its mark), or within its 5 ms waits. Woken by each (and a standby
    // by each mark), the coordinator's loop woke some 13 times a frame at 10,000 bodies on two workers, and
    // the standby's 12, mostly for nothing (while the coordinator waits for the standby's acknowledgement,
    // it takes no sample); now 3.5 and 2.5 (docs/protocol.md, "A standby coordinator").
    state->sectors_in = std::make_unique<Reader<wire::SectorFrame>>(
        p.sector_subscriber(), sectors, reader_qos(kSectorFrameReading), &state->inbox, Wake::on_news);
    if (!state->go_out->ok() || !state->assignment_out->ok() || !state->planes_out->ok() ||
        !state->results_out->ok() || !state->marks_out->ok() || !state->sectors_out->ok() ||
        (state->first_state_out && !state->first_state_out->ok()) || !state->status_out->ok() ||
        !state->status_in->ok() || !state->marks_in->ok() || !state->commands_in->ok() ||
        !state->sectors_in->ok() || !state->go_in->ok() || !state->acks_in->ok()) {
        return Error{"cannot create the coordinator's DDS readers and writers" +
                     dds::refused_endpoints_hint(options.security)};
    }
    if (!state->requests_out->ok()) {
        // Not fatal: the copy of the world then mends a sector that lost its base only when its owner next
        // sends it whole.
        spdlog::warn(
            "coordinator {}: cannot write on lpss/sector_requests (an identity made before 2026-12-06 "
            "does not grant it: make it again with deploy/security/identities.sh); sectors whose "
            "samples lose their base are not asked for whole",
            options.id);
        state->requests_out.reset();
    }
    // Beats within the lease, as workers' marks: a standby takes over when the coordinator's lapse.
    state->marks_beat = std::make_unique<LivelinessBeat>(state->marks_out->raw(), beat_period(kWorkerMarks));
    state->go_beat = std::make_unique<LivelinessBeat>(state->go_out->raw(), beat_period(kCoordinatorWords));
    if (options.standby) {
        state->acks_beat =
            std::make_unique<LivelinessBeat>(state->acks_out->raw(), beat_period(kCoordinatorWords));
    } else {
        state->status("loading", 0.0, 0);
    }
    return std::unique_ptr<Coordinator>(new Coordinator(std::move(state)));
}

void Coordinator::State::status(const std::string& phase, double progress, std::uint64_t bodies) {
    wire::ClusterStatus s;
    s.coordinator(options.id);
    s.phase(phase);
    s.progress(progress);
    s.bodies(bodies);
    s.frame(frame);
    status_out->write(s);
}

std::vector<std::uint32_t> Coordinator::State::recipients(const SectorKey& key,
                                                          const std::vector<wire::BodyState>& bodies,
                                                          const std::vector<double>& radii,
                                                          const SectorAssignment& assignment) const {
    std::vector<std::uint32_t> out;
    for (std::size_t n = 0; n < bodies.size(); ++n) {
        const wire::BodyState& b = bodies[n];
        const Eigen::Vector3d local(b.position().x(), b.position().y(), b.position().z());
        const Eigen::Vector3d v(b.linear_velocity().x(), b.linear_velocity().y(), b.linear_velocity().z());
        const double reach = border_reach(settings, radii[n], largest_radius, v.norm());
        neighbours_within(local, settings.sector_size, reach, [&](const SectorKey& d) {
            const SectorKey neighbour = key + d;
            if (!in_range(neighbour)) return;
            const std::uint32_t owner = assignment.owner_of(neighbour);
            if (owner != 0 && std::find(out.begin(), out.end(), owner) == out.end()) out.push_back(owner);
        });
    }
    const std::uint32_t owner = assignment.owner_of(key);
    if (std::find(out.begin(), out.end(), owner) == out.end()) out.push_back(owner);
    std::sort(out.begin(), out.end());
    return out;
}

int Coordinator::State::take_sector_samples(std::uint64_t at_most) {
    auto each = [&](wire::SectorFrame& f, const dds::fdds::SampleInfo& info) {
        if (!info.valid_data) return;
        if (f.worker() == 0) {
            // Its own samples are in the mirror already. Another coordinator's (the world's first state, the
            // sectors of a worker that is gone) are the world's to a standby, the first state with what each
            // body is.
            if (!standing_by || info.publication_handle == sectors_out->raw()->get_instance_handle()) return;
            if (f.frame() == 0) {
                first_state_begun = true;
                for (const wire::BodyKind& kind : f.kinds())
                    statics.emplace(kind.id(), kind.mass() == 0.0);
            }
        }
        take_sample(std::move(f));
    };
    const int taken = sectors_in->take_all(each, at_most);
    ask_for_whole_sectors();
    return taken;
}

void Coordinator::State::pump(bool with_samples) {
    marks_in->take_all([&](const wire::WorkerFrame& m, const dds::fdds::SampleInfo& info) {
        if (!info.valid_data) return;
        lapses.heard(info.publication_handle, info.source_timestamp.to_ns());
        if (m.worker() == 0) {
            // Another coordinator's, which a standby follows: the sectors of the world's first state, and the
            // frames it wrote sector samples for.
            if (!standing_by || info.publication_handle == marks_out->raw()->get_instance_handle()) return;
            if (m.frame() == 0) {
                first_state_begun = true;
                first_state.emplace();
                for (const wire::WrittenSector& w : m.written())
                    first_state->push_back(dds::from_wire(w.sector()));
            } else {
                primary_wrote.insert(m.frame());
            }
            return;
        }
        // A hello or an ask to join under the id of a live worker, from another writer: that worker started
        // again, and its old self is dead or cut off. Not word from the old one, whose silence goes on. The
        // hello counts too: a worker started again may not be able to ask for a long time (it asks once it
        // reaches every worker the assignment names, and those may be dead with it: every worker killed at
        // once waited out the last one's silence, 5 s, before this).
        const bool restarted_ask = [&] {
            if (m.frame() != 0 || frame < 1 || !live.count(m.worker())) return false;
            auto running = running_writer.find(m.worker());
            return running != running_writer.end() && running->second != info.publication_handle;
        }();
        if (restarted_ask) {
            if (restarted.insert(m.worker()).second)
                spdlog::info(
                    "coordinator: worker {} started again (a new writer says hello or asks to join) while "
                    "its old self is live",
                    m.worker());
        } else {
            last_heard[m.worker()] = Clock::now();
        }
        writer_of[info.publication_handle] = m.worker();
        newest_writer[m.worker()] = info.publication_handle;
        // Its hello before the world runs, or a mark of a frame: not a newcomer's hello or ask to join.
        if (m.frame() > 0 || frame == 0) {
            running_writer[m.worker()] = info.publication_handle;
            // Running under the id of one whose lease lapsed: started again, and the lapse was its old
            // self's. (A coordinator has taken that one as gone by now; a standby, which leaves deaths to
            // the coordinator, kept it, and took every worker ever restarted as gone at its takeover.)
            forget_lapse_of_another(m.worker(), info.publication_handle);
        }
        if (auto since = lost_since.find(m.worker()); since != lost_since.end() &&
                                                      since->second.writer == info.publication_handle &&
                                                      info.source_timestamp.to_ns() > since->second.at_ns) {
            spdlog::warn("coordinator: worker {} wrote a mark after its lease lapsed: alive", m.worker());
            forget_lapse(m.worker());
        }
        reaching[m.worker()] = std::set<std::uint32_t>(m.reaching().begin(), m.reaching().end());
        if (m.frame() == 0 && m.epoch() != 0 && m.sector_reader().size() == 16) {
            dds::GuidBytes reader{};
            std::copy(m.sector_reader().begin(), m.sector_reader().end(), reader.begin());
            joiner_readers[m.worker()] = reader;
        }
        // A frame-0 mark naming an epoch, once the world runs: a worker asking to join (see Worker::join).
        // An ask under the id of a worker that is not live comes from a new writer: a lapse noted under that
        // id was its old self's (taken as gone by now), not this one's. (Kept, a standby that took over
        // took the worker as gone the moment it let it in: "0.00 s into the frame", seen under
        // AddressSanitizer.)
        const bool asks_to_join = m.frame() == 0 && m.epoch() != 0 && frame >= 1 && !live.count(m.worker());
        if (asks_to_join && !standing_by) forget_lapse_of_another(m.worker(), info.publication_handle);
        if (asks_to_join && !admitted.count(m.worker()) && joining.insert(m.worker()).second) {
            spdlog::info("coordinator: worker {} asks to join at frame {}", m.worker(), frame);
            joining_since[m.worker()] = Clock::now();
        }
        if (m.loads_reported()) {
            for (auto it = block_loads.begin(); it != block_loads.end();)
                it = it->second.worker == m.worker() ? block_loads.erase(it) : std::next(it);
            for (const wire::BlockLoad& l : m.loads())
                block_loads[dds::from_wire(l.block())] = ReportedLoad{l.load(), m.worker()};
        }
        marks[{m.worker(), m.frame()}] = m;
    });
    if (with_samples) take_sector_samples();
    if (!standing_by) watch_coordinators();

    // A worker whose lease expired and that came back before it was taken as gone (a late beat on a loaded
    // machine) stays.
    const auto now = Clock::now();
    for (const dds::Inbox::Liveliness& change : inbox.take_liveliness()) {
        // Every writer's report counts, known or not: a false one comes right after a real one.
        lapses.reported(change.writer, change.alive, now);
        // Before frame 1 a standby knows the coordinator by its participant, which it may learn later.
        if (standing_by && !primary_writer && change.alive)
            heard_alive_before_frame_1.insert(dds::participant_of(change.writer));
        if (change.merged)
            spdlog::warn(
                "coordinator {}: one liveliness report merged several writers' changes; it names one",
                options.id);
        if (!change.alive) continue;
        if (standby_writer && change.writer == *standby_writer) {
            standby_lost = false;
            if (dropped_standby != 0) {
                standby = std::exchange(dropped_standby, 0);
                spdlog::warn("coordinator {}: standby coordinator {} is back: frames wait for it again",
                             options.id, standby);
            }
        } else if (is_primary(change.writer)) {
            primary_lost = false;
        } else if (auto worker = writer_of.find(change.writer); worker != writer_of.end()) {
            if (auto since = lost_since.find(worker->second);
                since != lost_since.end() && since->second.writer == change.writer) {
                forget_lapse(worker->second);
            }
        }
    }
    for (const dds::fdds::InstanceHandle_t& writer : lapses.confirmed(now)) {
        if (standby_writer && writer == *standby_writer) {
            standby_lost = true;
            continue;
        }
        if (is_primary(writer)) {
            primary_lost = true;
            continue;
        }
        auto worker = writer_of.find(writer);
        if (worker == writer_of.end()) continue;
        const std::uint32_t w = worker->second;
        auto running = running_writer.find(w);
        if (running != running_writer.end() && running->second != writer) continue;  // not the one running
        lost.insert(w);
        lost_since[w] = Lapse{writer, dds::wall_clock_ns(), frame};
        spdlog::warn("coordinator: worker {} missed its liveliness lease", w);
    }
}

void Coordinator::State::watch_coordinators() {
    go_in->take_all([&](const wire::FrameGo& go, const dds::fdds::SampleInfo& info) {
        if (!info.valid_data || go.coordinator() == options.id || go.term() <= term || fenced) return;
        fenced = true;
        spdlog::error(
            "coordinator {}: coordinator {} started frame {} under term {} (this one's is {}): it took over, "
            "and this one stops without starting another frame",
            options.id, go.coordinator(), go.frame(), go.term(), term);
    });
    acks_in->take_all([&](const wire::FrameAck& ack, const dds::fdds::SampleInfo& info) {
        if (info.valid_data) lapses.heard(info.publication_handle, info.source_timestamp.to_ns());
        if (info.valid_data && standby_writer && info.publication_handle == *standby_writer)
            standby_acked = std::max(standby_acked, ack.frame());
        // A standby's hello (frame 0): named in every frame start from now on, until it is gone.
        if (!info.valid_data || ack.frame() != 0 || ack.coordinator() == options.id || standby != 0 ||
            dropped_standby != 0)
            return;
        if (frame > 0) {
            // It would not hold the world's first state nor the frames before: it says so and stops.
            spdlog::warn(
                "coordinator {}: coordinator {} offers to stand by at frame {}: too late (a standby "
                "must be there before frame 1)",
                options.id, ack.coordinator(), frame);
            return;
        }
        standby = ack.coordinator();
        standby_writer = info.publication_handle;
        spdlog::info("coordinator {}: coordinator {} stands by; frames wait until it holds their start",
                     options.id, standby);
    });
}

void Coordinator::State::await_acknowledgement(std::uint64_t f, std::chrono::microseconds patience) {
    const auto until = Clock::now() + patience;
    while (standby != 0 && standby_acked < f && !standby_lost && !fenced) {
        const auto now = Clock::now();
        if (now >= until) return;
        inbox.wait(std::chrono::duration_cast<std::chrono::milliseconds>(until - now) +
                   std::chrono::milliseconds(1));
        pump(false);
    }
}

void Coordinator::State::take_sample(wire::SectorFrame f) {
    intake.take(std::move(f), frame, dds::kFramesAhead);
}

void Coordinator::State::ask_for_whole_sectors() {
    if (!requests_out) return;
    if (auto request = intake.whole_request(next_whole_request)) {
        // Each sector at most every 100 ms (whole_due): a line per request does not flood the log.
        spdlog::warn("coordinator {}: asks for {} sector(s) whole: their samples came without their base",
                     options.id, request->sectors().size());
        requests_out->write(*request);
    }
}

void Coordinator::State::publish_assignment() {
    assignment_out->write(assignment_on_wire());
    for (wire::SectorFrame& f : intake.learn(next))
        take_sample(std::move(f));
}

void Coordinator::State::take_samples(std::uint64_t up_to, const std::vector<wire::SectorFrame>& also) {
    std::vector<const wire::SectorFrame*> batch = intake.through(up_to);
    for (const wire::SectorFrame& f : also)
        batch.push_back(&f);
    mirror.apply(batch);
    intake.applied(up_to);
}

Status Coordinator::State::check_not_replaced() {
    // Only the coordinator started as one: a standby that starts the world does so because this one's
    // lease lapsed, and must not yield to it in turn.
    if (options.standby) return {};
    // A standby writes no status while it stands by: any word of another coordinator's is that it leads. (Or
    // a start under a higher term, which pump() reads: the standby may be past frame 1 already.)
    std::optional<std::uint32_t> other;
    status_in->take_all([&](const wire::ClusterStatus& st, const dds::fdds::SampleInfo& info) {
        if (info.valid_data && st.coordinator() != options.id) other = st.coordinator();
    });
    if (!other && !fenced) return {};
    fenced = true;
    return Error{"coordinator " + (other ? std::to_string(*other) : std::string("of a higher term")) +
                 " started the world while this one read the scene (this one's lease lapsed: it was stopped "
                 "or cut off): stopping"};
}

void Coordinator::State::drop_standby() {
    spdlog::warn(
        "coordinator {}: standby coordinator {} missed its liveliness lease: frames go on without it, and it "
        "cannot take over unless it comes back",
        options.id, standby);
    dropped_standby = std::exchange(standby, 0);
    if (last_go.standby() != 0) {
        last_go.standby(0);
        go_out->write(last_go);
    }
}

bool Coordinator::State::wait_for_frame(std::uint64_t f, const std::atomic<bool>& stop) {
    // Every live worker's end of frame f. A worker whose liveliness lease expired (killed, or cut off), or
    // that is silent for too long (alive but stuck), is taken as gone; once the others have ended the frame,
    // the frame it did not finish is stepped here and its sectors go to the others (restore_gone).
    for (;;) {
        // Marks only: the frame's samples come just before its marks, and taking them here (deserialized,
        // checked, copied) put them between the last mark and the next frame start (from a worker writing
        // its mark to the coordinator holding every mark: 0.74-0.84 ms at the median, 0.37-0.43 ms without,
        // 100,000 resting bodies and 1,000 balls on one worker). They are taken once the next frame has
        // started, while the workers step; here only when many wait, so that a burst (a rebalance sends
        // sectors whole) never outgrows what the reader keeps (kSectorFrameReading) before it is taken.
        pump(sectors_in->unread() > kSampleBacklog);
        if (fenced) return false;
        if (standby != 0 && standby_lost) drop_standby();
        for (std::uint32_t w : std::set<std::uint32_t>(live)) {
            if (!lost.count(w)) continue;
            // Not the last one: every worker's lease lapsing is a machine starved (seen, with three
            // clusters on two cores, both workers and the standby within 80 ms, all alive), and taken as
            // gone they would all have to join again while the world waits for them
            // (hold_until_a_worker_joins). The last waits for silence (worker_timeout) instead, unless a
            // worker started again under its id asks to join: it is dead, not starved.
            if (live.size() == 1 && !restarted.count(w)) {
                if (!last_lapse_noted) {
                    last_lapse_noted = true;
                    spdlog::warn(
                        "coordinator: worker {}, the last live one, missed its liveliness lease: taken as "
                        "gone "
                        "only after {} s of silence",
                        w, options.worker_timeout.count() / 1000.0);
                }
                continue;
            }
            take_as_gone(w, "its liveliness lease expired");
        }
        if (live.empty() && held_for.empty() && !hold_until_a_worker_joins(f, stop)) return false;
        bool all = true;
        for (std::uint32_t w : live)
            all = all && marks.count({w, f});
        if (all) {
            if (!going.empty()) {
                take_sector_samples();
                restore_gone(f);
            }
            return true;
        }
        if (stop.load()) return false;
        for (std::uint32_t w : std::set<std::uint32_t>(live)) {
            if (marks.count({w, f})) continue;
            // Silence counts from the frame's start (or the last word, if later); the first frame may take
            // as long as the workers take to build the world.
            const auto since = std::max(last_heard[w], frame_started);
            if (Clock::now() - since > (f == 1 ? options.worker_wait : options.worker_timeout))
                take_as_gone(w, "it stopped answering");
        }
        if (live.empty() && held_for.empty() && !hold_until_a_worker_joins(f, stop)) return false;
        inbox.wait(std::chrono::milliseconds(5));
    }
}

int Coordinator::run(const std::atomic<bool>& stop) {
    State& s = *state_;
    const CoordinatorOptions& o = s.options;
    // A standby goes on from the last frame start of the coordinator it took over from: that frame runs,
    // and this coordinator waits for its end.
    std::uint64_t first = 1;
    bool resumes = false;  // a standby that took over, from the coordinator's last start
    bool anew = false;     // a standby that starts the world, the coordinator gone before frame 1
    if (o.standby) {
        Expected<std::uint64_t> from = s.follow(stop);
        if (!from) {
            spdlog::error("coordinator {}: {}", o.id, from.error().message);
            return 3;
        }
        if (*from == 0) return 0;  // stopped, or the cluster ended
        if (*from == State::kStartTheWorld) {
            s.start_instead();
            anew = true;
        } else {
            first = *from;
            resumes = true;
        }
    }
    if (!resumes) {
        if (Status st = s.load_and_seed(stop); !st) {
            if (stop.load()) return 0;
            if (s.fenced) {
                spdlog::warn("coordinator {}: {}", o.id, st.error().message);
                return 6;
            }
            spdlog::error("coordinator: {}", st.error().message);
            return 3;
        }
    }
    if (anew) s.decide_standing_commands();  // as at a takeover

    const auto start = Clock::now();
    auto last_log = start;
    RealtimePacer pacer(start, s.settings.dt, resumes ? first + 1 : 1, resumes ? s.last_go.time_lost() : 0.0);
    for (std::uint64_t f = first;; ++f) {
        if (s.fenced) return 6;
        const bool taken_over = resumes && f == first;  // its start was the coordinator's
        if (!taken_over) {
            s.frame = f - 1;
            const bool finished = (o.frames > 0 && f > o.frames) || stop.load();
            s.accept_commands();
            wire::FrameGo go;
            go.coordinator(o.id);
            go.term(s.term);
            go.standby(s.standby);
            go.frame(f);
            if (s.next.from_frame <= f) s.current = s.next;
            for (auto it = s.admitted.begin(); it != s.admitted.end();) {
                if (it->second > f) {
                    ++it;
                    continue;
                }
                s.live.insert(it->first);
                s.last_heard[it->first] = Clock::now();
                it = s.admitted.erase(it);
            }
            go.epoch(s.current.epoch);
            go.next(s.assignment_on_wire());
            go.planes(static_cast<std::uint32_t>(s.planes.size()));
            go.ended(s.ended);
            go.coordinator_wrote(s.wrote_sectors);
            go.stop(finished);
            go.handoffs(s.grants);
            go.commands(s.commands);
            go.command_sequence(s.command_order);
            // The world's first start, unless the standby started the world instead meanwhile.
            if (f == 1 && !o.standby) {
                s.pump(false);
                if (Status st = s.check_not_replaced(); !st) {
                    spdlog::warn("coordinator {}: {}", o.id, st.error().message);
                    return 6;
                }
            }
            if (o.realtime) pacer.pace(f);
            go.started_ns(static_cast<std::uint64_t>(dds::wall_clock_ns()));
            go.time_lost(pacer.lost());
            s.go_out->write(go);
            s.last_go = go;
            // While the workers step: the frame's samples are taken and the copy of the world catches up
            // with the frame before, off the path from one frame's end to the next one's start. Only once the
            // standby has acknowledged the start, which the workers wait for: on two cores this work, begun
            // at once, competes with the standby for a core.
            s.await_acknowledgement(f, kAcknowledgementPatience);
            s.take_sector_samples();
            if (f > 1) s.take_samples(f - 1);
            s.frame_started = Clock::now();
            if (f == 1 || f % 60 == 0) s.status("running", 0.0, s.statics.size());
            if (finished) {
                spdlog::info("coordinator: stopping after frame {} ({} handoffs)", f - 1, s.handoffs);
                s.status("stopped", 0.0, s.statics.size());
                // The workers must read the stop before this participant goes (a fixed 0.3 s was too short on
                // a loaded machine: workers that never read it waited for a coordinator that was gone). A
                // reader killed earlier stays matched until its participant's lease runs out, and never
                // acknowledges: the wait is bounded.
                if (!s.go_out->delivered(std::chrono::seconds(1)))
                    spdlog::info(
                        "coordinator: not every reader of frame starts acknowledged the stop within 1 s "
                        "(one killed earlier stays matched for a while)");
                return 0;
            }
            s.in_flight = std::move(s.grants);
            s.grants.clear();
            s.commands_in_flight = std::move(s.commands);
            s.command_order_in_flight = std::move(s.command_order);
            s.commands.clear();
            s.command_order.clear();
            s.wrote_sectors = false;
        }
        s.frame = f;
        if (!s.wait_for_frame(f, stop)) {
            if (s.fenced) return 6;
            if (s.live.empty() && !stop.load()) {
                spdlog::error("coordinator: every worker is gone");
                return 5;
            }
            continue;  // stopping: the next round sends the stop
        }
        s.ended.assign(s.live.begin(), s.live.end());
        // The world's first state, or sectors restored after a death, leave the history once every reader
        // has them. A reader that comes later asks for an inventory and gets its sectors whole from their
        // owners. (Cleared at frame 2 before, whether read or not: under load a reader there before frame 1
        // lost the first state and showed 30 frames with bodies missing.)
        if (f == 3) runtime::give_back_free_memory();
        s.release_history(f);
        s.collect_handoffs(f);
        if (!s.joining.empty() && s.next.epoch == s.current.epoch) s.admit(f);
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
                // Moving sectors costs complete samples: only for a clear gain, else a load that shifts back
                // and forth would move the same sectors back and forth.
                SectorAssignment fresh = s.balanced(s.members());
                const double after = heaviest(s.worker_loads(fresh));
                if (after <= kRebalanceGain * most) {
                    spdlog::info(
                        "coordinator: frame {}: the busiest worker carries {:.0f} against a mean of "
                        "{:.0f}; a new assignment brings it to {:.0f}",
                        f, most, mean, after);
                    s.reassign(std::move(fresh), f + 2, "load shifted");
                } else {
                    spdlog::info(
                        "coordinator: frame {}: load uneven ({:.0f} against a mean of {:.0f}), but a "
                        "new assignment would carry {:.0f} at most: kept",
                        f, most, mean, after);
                }
            }
        }
        if (Clock::now() - last_log > std::chrono::seconds(5)) {
            last_log = Clock::now();
            spdlog::info("coordinator: frame {}, {:.1f} frames/s, {} handoffs so far", f,
                         static_cast<double>(f - first + 1) / seconds_since(start), s.handoffs);
        }
    }
}

}  // namespace lpss::coordinator
