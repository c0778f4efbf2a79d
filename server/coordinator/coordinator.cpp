#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <thread>
#include <unordered_map>
#include <utility>

#include "command_check.hpp"
#include "commands.hpp"
#include "coordinator_state.hpp"
#include "heap.hpp"
#include "lost_frame.hpp"
#include "lpss/common/border_reach.hpp"
#include "lpss/common/scene.hpp"
#include "lpss_dds/convert.hpp"
#include "lpss_dds/security.hpp"
#include "lpss_dds/topics.hpp"
#include "realtime_pacer.hpp"

namespace lpss::coordinator {
namespace {

/// A rebalance is made only if it brings the heaviest worker's load down to this share of what it is.
constexpr double kRebalanceGain = 0.85;
/// Sector samples waiting to be taken past which the coordinator takes them while it waits for marks: an
/// eighth of what its reader keeps per writer (kSectorFrameReading).
constexpr std::uint64_t kSampleBacklog = 1024;
/// How long the coordinator holds back its own work after a frame start for the standby's acknowledgement.
constexpr std::chrono::microseconds kAcknowledgementPatience{5000};

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

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
    state->status_in = std::make_unique<Reader<wire::ClusterStatus>>(
        p, p.topic<wire::ClusterStatusPubSubType>(kStatus), reader_qos(kStateDelivery), &state->inbox);
    state->marks_in =
        std::make_unique<Reader<wire::WorkerFrame>>(p, marks, reader_qos(kWorkerMarks), &state->inbox);
    state->commands_in =
        std::make_unique<Reader<wire::Command>>(p, p.topic<wire::CommandPubSubType>(kCommands),
                                                reader_qos_on_own_port(kCommandDelivery), &state->inbox);
    state->sectors_in = std::make_unique<Reader<wire::SectorFrame>>(
        p.sector_subscriber(), sectors, reader_qos(kSectorFrameReading), &state->inbox);
    if (!state->go_out->ok() || !state->assignment_out->ok() || !state->planes_out->ok() ||
        !state->results_out->ok() || !state->marks_out->ok() || !state->sectors_out->ok() ||
        (state->first_state_out && !state->first_state_out->ok()) || !state->status_out->ok() ||
        !state->status_in->ok() || !state->marks_in->ok() || !state->commands_in->ok() ||
        !state->sectors_in->ok() || !state->go_in->ok() || !state->acks_in->ok()) {
        return Error{"cannot create the coordinator's DDS readers and writers" +
                     dds::refused_endpoints_hint(options.security)};
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
    return sectors_in->take_all(each, at_most);
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
        lost_since[w] = Lapse{writer,
                              std::chrono::duration_cast<std::chrono::nanoseconds>(
                                  std::chrono::system_clock::now().time_since_epoch())
                                  .count(),
                              frame};
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
    if (std::string why = dds::implausible(f, frame); !why.empty()) return refused_samples.refuse(why);
    if (!owners.admit(f, refused_samples)) return;
    if (chain.accept(f)) samples[f.frame()].push_back(std::move(f));
}

void Coordinator::State::publish_assignment() {
    assignment_out->write(assignment_on_wire());
    for (wire::SectorFrame& f : owners.learn(next))
        take_sample(std::move(f));
}

void Coordinator::State::take_samples(std::uint64_t up_to, const std::vector<wire::SectorFrame>& also) {
    std::vector<const wire::SectorFrame*> batch;
    const auto end = samples.upper_bound(up_to);
    for (auto it = samples.begin(); it != end; ++it) {
        for (const wire::SectorFrame& f : it->second)
            batch.push_back(&f);
    }
    for (const wire::SectorFrame& f : also)
        batch.push_back(&f);
    mirror.apply(batch);
    samples.erase(samples.begin(), end);
    chain.forget_applied(up_to);
    owners.applied(up_to, refused_samples);
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

Status Coordinator::State::load_and_seed(const std::atomic<bool>& stop) {
    const auto load_start = Clock::now();
    spdlog::info("coordinator: loading {}", options.scene_path);
    Expected<Scene> loaded = load_scene(options.scene_path);
    if (!loaded) return Error{"scene refused:\n" + loaded.error().message};
    Scene scene = std::move(loaded).value();
    settings = scene.settings;
    grid = SectorGrid(settings.sector_size);
    spdlog::info("coordinator: {} bodies read and checked in {:.2f} s", scene.bodies.size(),
                 seconds_since(load_start));
    if (Status st = check_not_replaced(); !st) return st;
    status("loading", 1.0, scene.bodies.size());

    // The workers announce themselves with frame 0.
    const auto wait_start = Clock::now();
    for (;;) {
        pump();
        std::vector<std::uint32_t> missing;
        for (std::uint32_t w = 1; w <= options.workers; ++w) {
            if (!marks.count({w, 0})) missing.push_back(w);
        }
        if (missing.empty()) break;
        if (stop.load()) return Error{"stopped"};
        if (Status st = check_not_replaced(); !st) return st;
        if (Clock::now() - wait_start > options.worker_wait) {
            std::string list;
            for (std::uint32_t w : missing)
                list += (list.empty() ? "" : ", ") + std::to_string(w);
            return Error{"worker(s) " + list + " did not appear on domain " +
                         std::to_string(participant->domain()) + " within " +
                         std::to_string(options.worker_wait.count() / 1000) + " s"};
        }
        inbox.wait(std::chrono::milliseconds(50));
    }
    for (std::uint32_t w = 1; w <= options.workers; ++w)
        live.insert(w);
    if (Status st = check_not_replaced(); !st) return st;  // before the planes go out

    // The first assignment: bodies per sector, balanced along the Morton curve.
    std::unordered_map<SectorKey, std::vector<std::uint32_t>, SectorKeyHash> by_sector;
    std::vector<SectorPosition> at(scene.bodies.size());
    for (std::uint32_t n = 0; n < scene.bodies.size(); ++n) {
        const BodyDesc& b = scene.bodies[n];
        if (const auto* g = std::get_if<Eigen::Vector3d>(&b.position)) {
            at[n] = grid.from_global(*g).value();
        } else {
            at[n] = grid.canonical(std::get<SectorPosition>(b.position)).value();
        }
        statics.emplace(b.id, b.is_static());
        if (!is_plane(b.shape)) largest_radius = std::max(largest_radius, bounding_radius(b.shape));
        if (is_plane(b.shape)) {
            planes[b.id] = b;
            BodySnapshot anchor;
            anchor.id = b.id;
            anchor.position = at[n];
            anchor.orientation = b.orientation;
            wire::BodyDescription d = dds::describe(b, anchor);
            d.rank(n);
            planes_out->write(d);
            plane_descriptions[b.id] = d;
        } else {
            by_sector[at[n].sector].push_back(n);
        }
    }
    std::vector<std::pair<SectorKey, double>> loads;
    for (const auto& [key, members] : by_sector)
        loads.push_back({key, static_cast<double>(members.size())});
    current = SectorAssignment::balanced(loads, std::vector<std::uint32_t>(live.begin(), live.end()),
                                         options.block_size);
    current.epoch = 1;
    current.from_frame = 1;
    next = current;
    publish_assignment();

    if (Status st = check_not_replaced(); !st) return st;
    // The world's first state, sector by sector, to the workers that hold each (writers filter for their
    // readers' recipient filters), in the scene's order so that workers add bodies as lpss-sim does.
    // Workers that are there have matched this writer; a later one gets these samples from its history.
    const auto send_start = Clock::now();
    std::vector<SectorKey> keys;
    keys.reserve(by_sector.size());
    for (const auto& [key, members] : by_sector)
        keys.push_back(key);
    std::sort(keys.begin(), keys.end());
    wire::WorkerFrame seeded;
    seeded.worker(0);
    seeded.frame(0);
    seeded.epoch(current.epoch);
    std::size_t sent = 0;
    std::vector<double> radii;
    for (const SectorKey& key : keys) {
        wire::SectorFrame sample;
        sample.sector(dds::to_wire(key));
        sample.frame(0);
        sample.base(0);
        sample.worker(0);
        sample.slot(slot_of(key));
        sample.epoch(current.epoch);
        sample.complete(true);
        for (std::uint32_t n : by_sector[key]) {
            const BodyDesc& b = scene.bodies[n];
            BodySnapshot s;
            s.id = b.id;
            s.position = at[n];
            s.orientation = b.orientation.normalized();
            s.linear_velocity = b.linear_velocity;
            s.angular_velocity = b.angular_velocity;
            s.awake = b.mass > 0.0 && !b.asleep;
            sample.bodies().push_back(dds::to_wire(s));
            sample.offsets().push_back(dds::to_wire(at[n].local));
            sample.kinds().push_back(dds::kind_of(b));
            sample.ranks().push_back(n);
            radii.push_back(bounding_radius(b.shape));
        }
        sample.recipients(recipients(key, sample.bodies(), radii, current));
        radii.clear();
        first_state_out->write(sample);
        mirror.apply({&sample});
        chain.accept(sample);  // the base of the workers' first samples of the sector
        wire::WrittenSector entry;
        entry.sector(sample.sector());
        entry.recipients(sample.recipients());
        seeded.written().push_back(std::move(entry));
        if (++sent % 256 == 0)
            status("sending", static_cast<double>(sent) / static_cast<double>(keys.size()),
                   scene.bodies.size());
        if (stop.load()) return Error{"stopped"};
    }
    marks_out->write(seeded);
    status("sending", 1.0, scene.bodies.size());
    // A synchronization point: the clients asked for have matched every topic they read.
    auto last_word = Clock::now();
    while (ready_clients.size() < options.await_clients) {
        if (stop.load()) return Error{"stopped"};
        if (Clock::now() - last_word > std::chrono::seconds(5)) {
            last_word = Clock::now();
            spdlog::info("coordinator: frame 1 waits for {} client(s); {} ready", options.await_clients,
                         ready_clients.size());
        }
        accept_commands();
        inbox.wait(std::chrono::milliseconds(20));
    }
    // A standby, if one was asked for: from frame 1 on, every frame waits until it holds the frame's start.
    // Not for ever: a standby killed before its hello reached this coordinator is never heard (seen: the
    // world never started, lpss-cluster having said its standby had ended).
    const auto standby_wait_start = Clock::now();
    for (auto said = Clock::now(); options.await_standby && standby == 0;) {
        if (stop.load()) return Error{"stopped"};
        if (Status st = check_not_replaced(); !st) return st;
        if (Clock::now() - standby_wait_start > options.standby_wait) {
            spdlog::warn(
                "coordinator {}: no standby coordinator said it stands by within {:.0f} s: the world starts "
                "without one (no takeover should this coordinator end; a standby that comes later is too "
                "late)",
                options.id, std::chrono::duration<double>(options.standby_wait).count());
            break;
        }
        if (Clock::now() - said > std::chrono::seconds(5)) {
            said = Clock::now();
            spdlog::info("coordinator: frame 1 waits for a standby coordinator");
        }
        pump();
        inbox.wait(std::chrono::milliseconds(20));
    }
    spdlog::info("coordinator: {} sectors sent to {} worker(s) in {:.2f} s", keys.size(), live.size(),
                 seconds_since(send_start));
    // The scene is in the workers' hands now: give its memory back.
    scene = Scene{};
    by_sector.clear();
    at = {};
    runtime::give_back_free_memory();
    wrote_sectors = true;
    hold_history(0);
    return {};
}

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

void Coordinator::State::take_as_gone(std::uint32_t w, const char* why) {
    live.erase(w);
    restarted.erase(w);
    going.emplace(w, Going{why, seconds_since(frame_started)});
    // Its writers' later liveliness news is old news: a worker restarted under its id is another writer.
    forget_lapse(w);
    running_writer.erase(w);
    for (auto it = writer_of.begin(); it != writer_of.end();) {
        if (it->second != w) {
            ++it;
            continue;
        }
        lapses.forget(it->first);
        it = writer_of.erase(it);
    }
    spdlog::warn("coordinator: worker {} is taken as gone during frame {} ({}, {:.2f} s into the frame)", w,
                 frame, why, seconds_since(frame_started));
}

bool Coordinator::State::holds_samples_of(std::uint32_t w, std::uint64_t f) const {
    auto mark = marks.find({w, f});
    if (mark == marks.end()) return false;
    for (const wire::WrittenSector& written : mark->second.written()) {
        if (!chain.holds(dds::from_wire(written.sector()), f, ~std::uint64_t{0})) return false;
    }
    return true;
}

wire::SectorFrame Coordinator::State::whole_from_mirror(const SectorKey& key, std::uint64_t f) const {
    wire::SectorFrame sample;
    sample.sector(dds::to_wire(key));
    sample.frame(f);
    sample.base(f);
    sample.worker(0);
    sample.complete(true);
    auto it = mirror.sectors().find(key);
    if (it == mirror.sectors().end()) return sample;
    for (const dds::SectorMirror::Body& body : it->second) {
        sample.bodies().push_back(body.state);
        sample.kinds().push_back(mirror.kind(body));
    }
    return sample;
}

void Coordinator::State::restore_gone(std::uint64_t f) {
    // Once every live worker has ended frame f: the workers taken as gone during it, all at once (two gone
    // in one frame, restored one after the other, sent the first one's sectors to the second).
    const auto started = Clock::now();
    std::set<std::uint32_t> unfinished;
    std::string names;
    for (const auto& [w, going_why] : going) {
        names += (names.empty() ? "" : ", ") + std::to_string(w);
        bool ended = marks.count({w, f}) != 0;
        if (ended && !holds_samples_of(w, f)) {
            // Its mark came, not yet every sample it lists (other topics, other queues): those in flight
            // come within moments, or never, from a dead writer. Without them its sectors cannot be restored
            // as it left them (seen: a body that moved between two of its sectors missing from both), so the
            // frame is stepped again here, as for a worker that did not end it.
            const auto until = Clock::now() + std::chrono::milliseconds(200);
            while (!holds_samples_of(w, f) && Clock::now() < until) {
                inbox.wait(std::chrono::milliseconds(5));
                pump();
            }
            if (!holds_samples_of(w, f)) {
                ended = false;
                spdlog::warn("coordinator: worker {} ended frame {}, but not every sample it wrote came", w,
                             f);
            }
        }
        if (ended) {
            // Its samples and requests of the frame stand.
            gone_after_ending.insert(w);
            spdlog::error(
                "coordinator: worker {} is gone after ending frame {} ({}); its sectors go to the others", w,
                f, going_why.why);
        } else {
            unfinished.insert(w);
            spdlog::error(
                "coordinator: worker {} is gone during frame {} ({}, {:.2f} s into the frame); its sectors "
                "go "
                "to the others",
                w, f, going_why.why, going_why.into_frame);
        }
    }
    // The frames they did not finish, each stepped here from the world as every body was last published
    // (frame f - 1: everything received of it), with the handoffs and commands of frame f.
    take_samples(f - 1);
    std::vector<wire::SectorFrame> stepped;
    std::set<SectorKey> keys;
    std::vector<std::uint32_t> not_stepped;
    // How many sectors away a body awake can make another be stepped: two bodies are partners once their fat
    // boxes meet (each its bounding sphere widened by the border band, as the halo counts it, and by a slack
    // and a stretch along its velocity of up to L/8 each: L/2 for the two), so one sector for bodies small
    // beside a sector, more for bodies as wide as one.
    const double sector_size = settings.sector_size;
    const auto ring =
        1 + static_cast<std::int64_t>(std::floor(
                (2.0 * border_reach(settings, largest_radius, largest_radius, 0.0) + sector_size / 2.0) /
                sector_size));
    auto for_each_near = [ring](const SectorKey& key, auto&& each) {  // the sector itself included
        for (std::int64_t i = -ring; i <= ring; ++i)
            for (std::int64_t j = -ring; j <= ring; ++j)
                for (std::int64_t k = -ring; k <= ring; ++k)
                    each(key + SectorKey{i, j, k});
    };
    // Where something can change in the frame: near a sector with a body awake (a body there may wake
    // others), or one where a body is handed in. A sector with nothing of that near it is asleep throughout
    // the frame, as the engine leaves it: its state at f is its state at f - 1. Known only if every sample of
    // f - 1 is here (a sector woken then would look asleep): if not, everything may change.
    bool whole_frame_before = true;
    for (const auto& [key, mark] : marks) {
        if (key.second == f - 1)
            whole_frame_before = whole_frame_before && holds_samples_of(key.first, f - 1);
    }
    std::set<SectorKey> may_change;
    for (const auto& [key, bodies] : mirror.sectors()) {
        if (std::any_of(bodies.begin(), bodies.end(),
                        [](const dds::SectorMirror::Body& b) { return dds::is_awake(b.state); }))
            for_each_near(key, [&](const SectorKey& near) { may_change.insert(near); });
    }
    for (const wire::Handoff& h : in_flight)
        for_each_near(dds::from_wire(h.sector()), [&](const SectorKey& near) { may_change.insert(near); });
    for (std::uint32_t w : unfinished) {
        const auto step_start = Clock::now();
        // Only its sectors that may change are stepped again, with the sectors around them; the rest go to
        // their new owners as last published (building a world of every body it held took 3.6 s, the world
        // stopped meanwhile, for 252,000 bodies of a million resting ones on four workers). A command of the
        // frame may touch any sector: then all of them.
        const bool everything = !commands_in_flight.empty() || !whole_frame_before;
        std::set<SectorKey> own, to_step, around;
        for (const auto& [key, bodies] : mirror.sectors()) {
            if (current.owner_of(key) != w) continue;
            own.insert(key);
            if (everything || may_change.count(key)) to_step.insert(key);
        }
        // A sector a body is handed into may be empty so far, and in no copy.
        for (const wire::Handoff& h : in_flight) {
            if (h.to_worker() == w) to_step.insert(dds::from_wire(h.sector()));
        }
        for (const SectorKey& key : to_step) {
            for_each_near(key, [&](const SectorKey& near) {
                if (mirror.sectors().count(near)) around.insert(near);
            });
        }
        worker::LostFrameInput in;
        in.settings = settings;
        in.assignment = current;
        in.largest_radius = largest_radius;
        in.worker = w;
        in.frame = f;
        for (const SectorKey& key : around)
            in.sectors.push_back(whole_from_mirror(key, f - 1));
        for (const auto& [id, plane] : planes)
            in.planes.push_back(plane);
        in.handoffs = in_flight;
        in.commands = commands_in_flight;
        in.command_order = command_order_in_flight;
        Expected<worker::LostFrame> lost_frame = worker::step_lost_frame(in);
        in = {};
        if (!lost_frame) {
            spdlog::error(
                "coordinator: the frame worker {} did not finish cannot be stepped again ({}); its bodies "
                "are "
                "restored as last published",
                w, lost_frame.error().message);
            not_stepped.push_back(w);
            continue;
        }
        for (wire::SectorFrame& sample : lost_frame->sectors) {
            keys.insert(dds::from_wire(sample.sector()));
            stepped.push_back(std::move(sample));
        }
        // A worker that ended the frame answered its commands already.
        if (!marks.count({w, f})) {
            for (const wire::CommandResult& r : lost_frame->results)
                results_out->write(r);
        }
        stood_in.insert(stood_in.end(), lost_frame->leaving.begin(), lost_frame->leaving.end());
        // What the log says follows the decision taken above, not the conditions alone.
        std::string why;
        if (everything && !commands_in_flight.empty()) {
            why = fmt::format(" (all: the frame carries {} command(s))", commands_in_flight.size());
        } else if (everything) {
            why = " (all: a sample of the frame before has not come)";
        }
        spdlog::info(
            "coordinator: frame {} of worker {} stepped again here: {} of its {} sectors may change{}, "
            "stepped with {} sectors around them ({} bodies of its own; the rest, asleep throughout the "
            "frame, as they were), {:.3f} s",
            f, w, to_step.size(), own.size(), why, around.size(), lost_frame->bodies,
            seconds_since(step_start));
    }
    take_samples(f, stepped);
    // Not stepped: its bodies lose frame f's motion, restored as last published, and those handed to it at
    // frame f (its samples never showed them) from their grants.
    for (std::uint32_t w : not_stepped) {
        for (const wire::Handoff& h : in_flight) {
            if (h.to_worker() == w) mirror.insert(dds::from_wire(h.sector()), h.state(), h.kind());
        }
    }
    // The gone workers' ranges go to their neighbours on the curve. The live workers keep every sector they
    // have: a change from frame f + 1 is learnt at its start, too late for an owner to send a sector away
    // whole, so a sector moved between live workers here would reach its new owner empty. A change already
    // under way from f + 1 (announced with frame f, sent whole at f) goes on; one from a later frame is
    // dropped, and the workers it was to admit are admitted again later.
    SectorAssignment base = current;
    if (next.epoch != current.epoch) {
        if (next.from_frame <= f + 1) {
            base = next;
        } else {
            spdlog::warn("coordinator: the assignment of epoch {} from frame {} is dropped: a worker is gone",
                         next.epoch, next.from_frame);
            for (const auto& [w, from] : admitted) {
                joining.insert(w);
                joining_since[w] = Clock::now();
            }
            admitted.clear();
        }
    }
    std::vector<std::pair<SectorKey, double>> loads;
    for (const auto& [key, bodies] : mirror.sectors())
        loads.push_back({key, static_cast<double>(bodies.size())});
    SectorAssignment fresh = base;
    if (!held_for.empty()) {
        // No worker was left: the world goes to those that joined while it waited.
        fresh = SectorAssignment::balanced(
            loads, std::vector<std::uint32_t>(held_for.begin(), held_for.end()), options.block_size);
    } else {
        for (const auto& [w, going_why] : going)
            fresh = fresh.without(w, loads);
    }
    // Every sector a gone worker owned, or was to own from f + 1, whole at frame f to its holders under the
    // new assignment.
    for (const auto& [key, bodies] : mirror.sectors()) {
        if (going.count(current.owner_of(key)) || going.count(base.owner_of(key))) keys.insert(key);
    }
    std::vector<std::uint32_t> gone;
    for (const auto& [w, going_why] : going)
        gone.push_back(w);
    going.clear();
    send_restored(f, fresh, keys, gone, started);
    reassign(std::move(fresh), f + 1, ("worker(s) " + names + " gone").c_str());
    if (!held_for.empty()) {
        // The joiners learn their sectors from frame f's start, written again (they asked under its epoch).
        write_start_again(last_go.epoch());
        spdlog::info("coordinator: the world goes on from frame {} on worker(s) {}", f + 1,
                     fmt::join(held_for, ", "));
        held_for.clear();
    }
}

bool Coordinator::State::hold_until_a_worker_joins(std::uint64_t f, const std::atomic<bool>& stop) {
    const auto since = Clock::now();
    spdlog::error(
        "coordinator: every worker is gone during frame {}: the world ({} sectors) waits up to {} s for a "
        "worker to join",
        f, mirror.sectors().size(), options.worker_wait.count() / 1000.0);
    status("waiting for workers", 0.0, statics.size());
    // An assignment of no worker, in frame f's start written again: a worker asks to join under it without
    // first waiting to reach the workers that are gone (Worker::join). Only there, not on the assignment
    // topic: clients that read it there stopped at frame f (it names no worker to wait for, and they had
    // followed frame f under the assignment before).
    SectorAssignment none;
    none.block_size = options.block_size;
    none.epoch = next.epoch + 1;
    none.from_frame = f + 1;
    next = none;
    write_start_again(next.epoch);
    // Workers admitted from a later frame were to get their sectors from workers now gone: they read that
    // start too, and ask again (or, with a world already, join again as fresh workers).
    admitted.clear();
    for (std::uint32_t w : joining)
        joining_since[w] = Clock::now();
    // Only an ask under that assignment: it comes from a worker that has read it, whatever it did before.
    auto asked_under_it = [&](std::uint32_t w) {
        auto ask = marks.find({w, 0});
        return ask != marks.end() && ask->second.epoch() == next.epoch;
    };
    for (;;) {
        pump(sectors_in->unread() > kSampleBacklog);
        if (fenced || stop.load()) return false;
        for (auto it = joining.begin(); it != joining.end();) {
            if (!asked_under_it(*it) || !not_reaching(*it).empty()) {
                ++it;
                continue;
            }
            held_for.insert(*it);
            admitted[*it] = f + 1;
            joining_since.erase(*it);
            it = joining.erase(it);
        }
        if (!held_for.empty()) {
            spdlog::info("coordinator: worker(s) {} joined the world waiting at frame {}, after {:.2f} s",
                         fmt::join(held_for, ", "), f, seconds_since(since));
            return true;
        }
        if (Clock::now() - since > options.worker_wait) {
            spdlog::error("coordinator: every worker is gone, and none joined within {} s",
                          options.worker_wait.count() / 1000.0);
            return false;
        }
        inbox.wait(std::chrono::milliseconds(5));
    }
}

void Coordinator::State::write_start_again(std::uint32_t epoch) {
    last_go.epoch(epoch);
    last_go.next(assignment_on_wire());
    go_out->write(last_go);
}

void Coordinator::State::send_restored(std::uint64_t f, const SectorAssignment& fresh,
                                       const std::set<SectorKey>& keys,
                                       const std::vector<std::uint32_t>& gone, Clock::time_point started) {
    wire::WorkerFrame restored;
    restored.worker(0);
    restored.frame(f);
    restored.epoch(fresh.epoch);
    restored.stands_for(gone);
    std::size_t bodies = 0;
    for (const SectorKey& key : keys) {
        wire::SectorFrame sample = whole_from_mirror(key, f);
        sample.epoch(fresh.epoch);
        std::vector<double> radii;
        for (const wire::BodyKind& kind : sample.kinds())
            radii.push_back(bounding_radius(dds::from_wire(kind).shape));
        sample.recipients(recipients(key, sample.bodies(), radii, fresh));
        bodies += sample.bodies().size();
        sample.slot(slot_of(key));
        sectors_out->write(sample);
        chain.accept(sample);
        wire::WrittenSector entry;
        entry.sector(sample.sector());
        entry.recipients(sample.recipients());
        restored.written().push_back(std::move(entry));
    }
    marks_out->write(restored);
    wrote_sectors = true;
    hold_history(f);
    spdlog::info(
        "coordinator: {} bodies in {} sectors sent to their new owners, {:.3f} s after the frame ended",
        bodies, keys.size(), seconds_since(started));
}

void Coordinator::State::hold_history(std::uint64_t f) {
    if (history_from) return;
    history_from = f;
    history_written_at = Clock::now();
}

void Coordinator::State::release_history(std::uint64_t f) {
    if (!history_from || f <= *history_from) return;
    // A reader that has not acknowledged them by then is dead (Fast DDS unmatches a dead participant's
    // readers after its lease, 20 s by default) or stalled; should it come back, it asks the sectors' owners
    // for them whole, as a reader that joins late does.
    constexpr auto kKeptAtMost = std::chrono::seconds(25);
    auto acknowledged_by_all = [](dds::Writer<wire::SectorFrame>& writer) {
        return writer.raw()->wait_for_acknowledgments(eprosima::fastrtps::Duration_t(0, 0)) ==
               eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK;
    };
    const bool acknowledged =
        acknowledged_by_all(*sectors_out) && (!first_state_out || acknowledged_by_all(*first_state_out));
    if (!acknowledged && Clock::now() - history_written_at < kKeptAtMost) return;
    std::size_t removed = 0;
    sectors_out->raw()->clear_history(&removed);
    // The first state's writer goes with what it held: its history and its copy of each sector's first
    // sample. Its readers lose a writer that will write nothing more.
    const bool first_state = first_state_out != nullptr;
    first_state_out.reset();
    spdlog::info(
        "coordinator: {} written from frame {} on ({} samples) leave the writer's history after frame {}: {}",
        first_state ? "the world's first state and the sectors" : "the sectors", *history_from,
        first_state ? std::string("all") : std::to_string(removed), f,
        acknowledged ? "every reader has them" : "a reader has not acknowledged them in 25 s");
    history_from.reset();
    runtime::give_back_free_memory();
}

void Coordinator::State::collect_handoffs(std::uint64_t f) {
    // Requests of frame f become grants of frame f + 1, each body once, to the owner of the sector it enters
    // under the assignment in force then.
    const SectorAssignment then = assignment_for(f + 1);
    std::set<BodyId> granted;
    auto grant = [&](const std::vector<wire::Handoff>& requests) {
        for (wire::Handoff h : requests) {
            if (!statics.count(h.body()) || !granted.insert(h.body()).second) continue;
            const std::uint32_t to = then.owner_of(dds::from_wire(h.sector()));
            if (to == h.from_worker()) continue;
            h.to_worker(to);
            grants.push_back(h);
            ++handoffs;
        }
    };
    std::set<std::uint32_t> ended_frame = gone_after_ending;
    ended_frame.insert(live.begin(), live.end());
    for (std::uint32_t w : ended_frame) {
        auto it = marks.find({w, f});
        if (it != marks.end()) grant(it->second.leaving());
    }
    grant(stood_in);
    stood_in.clear();
    gone_after_ending.clear();
    for (auto it = marks.begin(); it != marks.end();)
        it = it->first.second < f ? marks.erase(it) : std::next(it);
}

std::vector<std::uint32_t> Coordinator::State::not_reaching(std::uint32_t joiner) const {
    std::vector<std::uint32_t> out;
    auto reader = joiner_readers.find(joiner);
    if (reader == joiner_readers.end()) return out;  // a worker that names no reader: nothing to wait for
    if (!sectors_out->reaches(reader->second)) out.push_back(0);
    for (std::uint32_t w : members()) {
        auto r = reaching.find(w);
        if (w != joiner && (r == reaching.end() || !r->second.count(joiner))) out.push_back(w);
    }
    return out;
}

void Coordinator::State::admit(std::uint64_t f) {
    std::set<std::uint32_t> workers = members();
    std::string names;
    for (auto it = joining.begin(); it != joining.end();) {
        const std::uint32_t w = *it;
        if (const std::vector<std::uint32_t> missing = not_reaching(w); !missing.empty()) {
            // Said once after a second: discovery that completes on one side only is what this waits out.
            auto since = joining_since.find(w);
            if (since != joining_since.end() && Clock::now() - since->second > std::chrono::seconds(1)) {
                std::string who;
                for (std::uint32_t m : missing)
                    who += (who.empty() ? "" : ", ") +
                           (m == 0 ? std::string("the coordinator") : std::to_string(m));
                spdlog::warn(
                    "coordinator: worker {} waits to join: not reached yet by the sector writer of {}", w,
                    who);
                joining_since.erase(since);
            }
            ++it;
            continue;
        }
        workers.insert(w);
        admitted[w] = f + 2;
        names += (names.empty() ? "" : ", ") + std::to_string(w);
        joining_since.erase(w);
        it = joining.erase(it);
    }
    if (names.empty()) return;
    reassign(balanced(workers), f + 2, ("worker(s) " + names + " joined").c_str());
}

SectorAssignment Coordinator::State::balanced(const std::set<std::uint32_t>& workers) const {
    std::vector<std::pair<SectorKey, double>> loads;
    for (const auto& [block, reported] : block_loads) {
        // A block's load stands for its first sector: balanced() groups sectors into the same blocks.
        loads.push_back(
            {SectorKey{block.i * next.block_size, block.j * next.block_size, block.k * next.block_size},
             static_cast<double>(reported.load)});
    }
    if (loads.empty()) {
        for (const auto& [key, bodies] : mirror.sectors())
            loads.push_back({key, static_cast<double>(bodies.size())});
    }
    return SectorAssignment::balanced(loads, std::vector<std::uint32_t>(workers.begin(), workers.end()),
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
            go.started_ns(static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                                         std::chrono::system_clock::now().time_since_epoch())
                                                         .count()));
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
