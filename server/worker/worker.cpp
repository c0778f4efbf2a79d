// The worker's frame loop: wait for the frame (frame_gate), bring the halo's ghosts to the other workers'
// states (halo), take over bodies and apply commands (handoff), step, publish what changed
// (SectorPublisher) and say so (WorkerFrame).
#include "worker.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <deque>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <unordered_map>

#include "commands.hpp"
#include "frame_gate.hpp"
#include "halo.hpp"
#include "handoff.hpp"
#include "heap.hpp"
#include "lpss/common/process_memory.hpp"
#include "lpss/engine/world.hpp"
#include "lpssPubSubTypes.h"
#include "lpss_dds/confirmed_lapses.hpp"
#include "lpss_dds/convert.hpp"
#include "lpss_dds/participant.hpp"
#include "lpss_dds/sample_check.hpp"
#include "lpss_dds/sample_owners.hpp"
#include "lpss_dds/sector_chain.hpp"
#include "lpss_dds/sector_publisher.hpp"
#include "lpss_dds/security.hpp"
#include "lpss_dds/topics.hpp"
#include "lpss_dds/whole_sector_asks.hpp"

namespace lpss::worker {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

/// A reader's request for an inventory of the sectors this worker owns in a region, answered with those
/// sectors whole once this worker's sector writer reaches the reader's (what a writer sends before it has
/// matched a reader never reaches it).
struct InventoryRequest {
    std::string reader;
    std::uint64_t request = 0;
    SectorKey lo, hi;
    std::optional<dds::GuidBytes> frames_reader;  ///< none: answered at once
    std::chrono::steady_clock::time_point asked;
    /// The reader holds every sector as of this frame: those not written since are listed, not sent.
    std::uint64_t held_through = 0;

    bool covers(const SectorKey& key) const {
        return key.i >= lo.i && key.i <= hi.i && key.j >= lo.j && key.j <= hi.j && key.k >= lo.k &&
               key.k <= hi.k;
    }
};

/// A request whose reader this worker's writer has not reached by then is dropped (the reader asks again
/// if it is still there).
constexpr std::chrono::seconds kInventoryPatience{10};
/// The sectors an inventory lists go whole at most this many bodies a frame: a whole-world joiner of a
/// million bodies cost a worker half a million in one frame, which starved a two-core machine long
/// enough for liveliness leases to lapse. The joiner's first frame comes once its last sector has.
constexpr std::uint32_t kJoinerBodiesPerFrame = 20000;

/// A request to join not answered by then is made again.
constexpr std::chrono::seconds kJoinPatience{5};

/// Load reports come every this many frames.
constexpr std::uint64_t kLoadReportEvery = 60;

}  // namespace

struct Worker::State {
    explicit State(const WorkerOptions& o) : options(o), gate(o.id), halo(o.id) {}

    WorkerOptions options;
    std::unique_ptr<dds::Participant> participant;
    dds::Inbox inbox;
    std::unique_ptr<dds::Writer<wire::SectorFrame>> frames_out;
    std::unique_ptr<dds::Writer<wire::WorkerFrame>> marks_out;
    std::unique_ptr<dds::Writer<wire::CommandResult>> results_out;
    std::unique_ptr<dds::Reader<wire::SectorFrame>> frames_in;
    std::unique_ptr<dds::Reader<wire::WorkerFrame>> marks_in;
    std::unique_ptr<dds::Reader<wire::FrameGo>> go_in;
    std::unique_ptr<dds::Reader<wire::FrameAck>> acks_in;  ///< a standby coordinator's
    std::unique_ptr<dds::Reader<wire::BodyDescription>> planes_in;
    std::unique_ptr<dds::Reader<wire::SectorRequest>> requests_in;
    std::unique_ptr<dds::Writer<wire::SectorRequest>> requests_out;
    std::unique_ptr<dds::LivelinessBeat> beat;  ///< keeps its marks' lease

    std::optional<World> world;
    FrameGate gate;
    Halo halo;
    std::uint64_t frame = 0;
    std::uint32_t degraded = 0;
    bool left_out = false;  ///< an assignment in force leaves it out: taken as gone
    /// A frame whose start announced a newer assignment without this worker: taken as gone (see pump).
    std::optional<std::uint64_t> announced_without_it;
    std::uint64_t frame_started_ns = 0;  ///< the FrameGo's, passed on in the mark
    double time_lost = 0.0;

    dds::WholeSectorAsks wanted_whole;  ///< other workers' sectors whose partial samples were refused
    std::uint64_t whole_requests = 0;
    void ask_for_whole_sectors();
    /// A sector sample read: checked, then queued for its frame (or refused, or held by `owners`).
    void take_sample(wire::SectorFrame f);
    /// Tells `owners` of an assignment announced; the samples it held are offered again.
    void learn(const SectorAssignment& assignment);
    // Received and not yet applied.
    std::map<std::uint64_t, std::vector<wire::SectorFrame>> samples;  ///< by frame
    dds::SectorChain chain;                                           ///< which samples are usable
    dds::SampleOwners owners;  ///< whose samples are whose to write, by the assignments announced
    std::map<std::uint64_t, std::uint64_t> received_bytes;  ///< serialized sample bytes, by frame
    std::map<BodyId, std::pair<std::uint64_t, BodyDesc>>
        early_planes;         ///< before the world exists: rank, plane
    std::set<BodyId> planes;  ///< in no sector's samples: readers count them in marks

    // Published.
    dds::SectorPublisher publisher;
    std::set<SectorKey> whole_requested;  ///< sectors a reader asked to have whole
    /// Sectors taken over (the world's first state, a rebalance, a worker gone): their readers hold what
    /// another writer sent, so this worker's first sample of each is whole, empty or not.
    std::set<SectorKey> adopted;
    /// Asked for, not answered yet: by reader, the latest request of each.
    std::map<std::string, InventoryRequest> inventory_requests;
    /// Answered in this frame: the mark lists their sectors.
    std::vector<InventoryRequest> answering;
    /// Sectors of answered inventories still to send whole, in order, a few bodies' worth a frame.
    std::vector<SectorKey> for_joiners_due;
    std::set<SectorKey> for_joiners_queued;
    /// The largest body radius changed (a spawn): every sector's recipients are looked at again.
    bool reach_changed = false;
    std::map<SectorKey, double> block_loads;  ///< bodies, awake ones counting double, per block owned
    std::uint64_t resident_bytes = 0;

    bool coordinator_present() const { return go_in->matched() > 0; }
    /// The coordinators' frame start writers whose liveliness this worker hears (the coordinator's, a
    /// standby's): none, once it had some, means it is cut off from them (a link down), or every
    /// coordinator is gone.
    std::set<dds::fdds::InstanceHandle_t> coordinators_heard;
    /// How many of those writers the frame start reader counts alive, by its last report. A report that
    /// merged two writers' changes names one of them (Inbox::Liveliness): a standby's writer that became
    /// alive with the coordinator's was missing from the set, and the worker took itself as cut off when the
    /// coordinator died although it heard the standby take over. The count says what the set may have missed.
    std::int32_t coordinators_alive = 0;
    dds::ConfirmedLapses<dds::fdds::InstanceHandle_t> coordinator_lapses;
    bool heard_a_coordinator = false;
    /// The latest liveliness news of the coordinators' writers, for the log of a worker that takes itself as
    /// cut off (under AddressSanitizer one did so as a standby took over, and the log could not say why).
    struct LivelinessNews {
        Clock::time_point at;
        std::size_t writer;  ///< in the order first heard of: 1, 2, ...
        const char* what;
        std::int32_t alive_count;
    };
    std::deque<LivelinessNews> liveliness_news;
    std::vector<dds::fdds::InstanceHandle_t> coordinator_writers;  ///< by the numbers in liveliness_news
    void note_liveliness(const dds::fdds::InstanceHandle_t& writer, const char* what, std::int32_t alive);
    std::string liveliness_history() const;
    void follow_coordinator_liveliness();
    bool cut_off() const {
        return heard_a_coordinator && coordinators_heard.empty() && coordinators_alive == 0;
    }
    /// Out of the cluster: what its writers still hold, no one may have yet (written as the link went, or
    /// before a stop); repaired later it would be stale. Dropped from their histories.
    void forget_what_it_wrote();
    /// Cut off: forgets what it wrote, then waits until it hears a coordinator again (the link is back) to
    /// return kTakenAsGone, so that the fresh worker that joins starts on a working link (a participant
    /// created while the link was down never used that interface, and found no one when it came back); 3 if
    /// none comes within the coordinator wait, 0 if stopped.
    int sit_out(const std::atomic<bool>& stop);
    void pump();
    bool start_world(const wire::FrameGo& go, const std::atomic<bool>& stop);
    /// The engine world under the coordinator's settings; false (logged) if they are refused.
    bool create_world(const wire::Assignment& announced);
    /// A reader of the world's planes (body descriptions), made anew in place of the one there may be.
    void read_planes();
    /// The planes read before the world existed, each with its rank (its place in the scene); they count as
    /// held from now on.
    std::vector<std::pair<std::uint64_t, BodyDesc>> take_early_planes();
    // Joining a running cluster (a new worker, or one restarted under the id of one that is gone): it asks
    // with a frame-0 mark naming the assignment it saw in force; the coordinator gives it sectors from a
    // later frame, and their owners send them whole at the frame before, as in any rebalance.
    enum class Joining { waiting, joined, failed };
    Joining join(const wire::FrameGo& latest);
    bool asked_to_join = false;
    Clock::time_point asked_at;    ///< its latest request to join
    SectorAssignment joined_from;  ///< in force when it asked: its sectors' owners before it
    /// Samples of frames before it asked are history of the cluster before it joined (a restarted worker's
    /// old sectors, in the coordinator's first state): never applied.
    std::uint64_t sample_floor = 0;
    dds::RefusedSamples refused_samples{"worker " + std::to_string(options.id)};
    std::set<std::uint32_t>
        heard;  ///< workers whose marks reached it: their writers have matched its readers
    /// Each other worker's reader of sector frames, as its marks name it. A joiner asks only once its own
    /// sector writer reaches all of them; this worker's marks say which its writer reaches, and the
    /// coordinator admits a joiner only once every worker's does (a sample written before the writer matched
    /// the reader never reaches it: seen, a joiner that started without its sectors and degraded).
    std::map<std::uint32_t, dds::GuidBytes> sector_readers;
    /// A mark of this worker for `frame`, naming its sector reader and the workers' its writer reaches.
    wire::WorkerFrame mark_of(std::uint64_t frame) const;
    Clock::time_point join_noted = Clock::now();  ///< when it last said why it waits to join
    void apply_samples(std::uint64_t up_to, const std::vector<std::pair<std::uint64_t, BodyDesc>>& also = {});
    void apply_go(const wire::FrameGo& go);
    /// Takes note of the assignment the coordinator announces (it takes effect at its from_frame).
    void announce(const wire::FrameGo& go);
    void apply_command(const wire::Command& command, std::uint64_t order);
    void count_load(const SectorKey& key, const dds::SectorPublisher::Counts& before);
    /// Makes the samples of what changed (into `outgoing`, written before the mark) and says which.
    std::vector<wire::WrittenSector> publish();
    std::vector<wire::SectorFrame> outgoing;
    void mark(std::vector<wire::WrittenSector> written, double step_ms, double wait_ms, double publish_ms);
    /// Before the worker goes: waits, up to `limit` in all, until every reader has acknowledged what it
    /// wrote. Reliable delivery ends with the participant: a datagram of the last frame lost on the way
    /// (a reader under load) could not be sent again, and that reader would never see the last frame.
    void deliver_before_going(std::chrono::milliseconds limit);
};

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

void Worker::State::note_liveliness(const dds::fdds::InstanceHandle_t& writer, const char* what,
                                    std::int32_t alive) {
    auto known = std::find(coordinator_writers.begin(), coordinator_writers.end(), writer);
    if (known == coordinator_writers.end()) known = coordinator_writers.insert(known, writer);
    const auto number = static_cast<std::size_t>(known - coordinator_writers.begin()) + 1;
    liveliness_news.push_back({Clock::now(), number, what, alive});
    if (liveliness_news.size() > 12) liveliness_news.pop_front();
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

std::string Worker::State::liveliness_history() const {
    std::string out;
    const auto now = Clock::now();
    for (const LivelinessNews& n : liveliness_news) {
        out +=
            fmt::format("{}{:.3f} s ago, coordinators' writer {} {} ({} alive)", out.empty() ? "" : "; ",
                        std::chrono::duration<double>(now - n.at).count(), n.writer, n.what, n.alive_count);
    }
    return out.empty() ? "none" : out;
}

void Worker::State::follow_coordinator_liveliness() {
    const auto now = Clock::now();
    for (const dds::Inbox::Liveliness& change : inbox.take_liveliness()) {
        note_liveliness(change.writer,
                        change.alive ? "alive" : (change.merged ? "lapsed (merged)" : "lapsed"),
                        change.alive_count);
        coordinator_lapses.reported(change.writer, change.alive, now);
        if (change.merged)
            spdlog::info("worker {}: one liveliness report of two coordinators' writers ({} alive now)",
                         options.id, change.alive_count);
        if (change.alive || change.alive_count > 0) heard_a_coordinator = true;
        // A writer that lapsed while its coming alive went unreported was alive all the same: in the set, it
        // gets the grace of any lapse (ConfirmedLapses) before the worker can count itself cut off.
        if (change.alive || change.alive_count < coordinators_alive) coordinators_heard.insert(change.writer);
        coordinators_alive = change.alive_count;
    }
    for (const dds::fdds::InstanceHandle_t& writer : coordinator_lapses.confirmed(now)) {
        note_liveliness(writer, "lapse confirmed", coordinators_alive);
        coordinators_heard.erase(writer);
    }
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
    while (!stop.load() && cut_off()) {
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
    follow_coordinator_liveliness();
    go_in->take_all([&](const wire::FrameGo& go, const dds::fdds::SampleInfo& info) {
        if (!info.valid_data) return;
        coordinator_lapses.heard(info.publication_handle, info.source_timestamp.to_ns());
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
        if (r.inventory()) {
            InventoryRequest asked{r.reader(),   r.request(),  dds::from_wire(r.lo()), dds::from_wire(r.hi()),
                                   std::nullopt, Clock::now(), r.held_through()};
            if (r.frames_reader().size() == 16) {
                asked.frames_reader.emplace();
                std::copy(r.frames_reader().begin(), r.frames_reader().end(), asked.frames_reader->begin());
            }
            inventory_requests[r.reader()] = std::move(asked);
        }
    });
    marks_in->take_all([&](const wire::WorkerFrame& m, const dds::fdds::SampleInfo& info) {
        if (!info.valid_data) return;
        if (m.sector_reader().size() == 16 && m.worker() != options.id && m.worker() != 0) {
            dds::GuidBytes reader{};
            std::copy(m.sector_reader().begin(), m.sector_reader().end(), reader.begin());
            sector_readers[m.worker()] = reader;
        }
        gate.take_mark(m);
        if (!world && m.frame() > 0) heard.insert(m.worker());
    });
    frames_in->take_all([&](wire::SectorFrame& f, const dds::fdds::SampleInfo& info) {
        if (info.valid_data) take_sample(std::move(f));
    });
    ask_for_whole_sectors();
}

void Worker::State::take_sample(wire::SectorFrame f) {
    if (f.worker() == options.id || f.frame() < sample_floor) return;
    const wire::FrameGo* latest = gate.latest();
    // A worker not yet in the world reads the coordinator's frame starts from its writer's history, which
    // can come in a burst after newer samples (seen in the soak: 111 frames behind, and the sector sample
    // that a joiner was waiting for refused; its first frame then waited 2 s and started degraded).
    const std::uint64_t ahead = world ? dds::kFramesAhead : dds::kClientFramesAhead;
    if (std::string why = dds::implausible(f, std::max(frame, latest ? latest->frame() : 0), ahead);
        !why.empty())
        return refused_samples.refuse(why);
    if (!owners.admit(f, refused_samples)) return;
    received_bytes[f.frame()] += wire::SectorFrame::getCdrSerializedSize(f);
    if (chain.stale(f)) return;
    // A refused sample (its base missing: lost to newer ones on a loaded machine) is not applied; the
    // sector is asked for whole, as clients do, or it would stay broken until its owner sent it whole
    // for some other reason (seen: a worker degraded 2 s a frame for minutes).
    if (!chain.accept(f)) {
        spdlog::warn("worker {}: sector sample of frame {} without its base", options.id, f.frame());
        wanted_whole.want(dds::from_wire(f.sector()));
        return;
    }
    wanted_whole.got(dds::from_wire(f.sector()));
    samples[f.frame()].push_back(std::move(f));
}

void Worker::State::learn(const SectorAssignment& assignment) {
    for (wire::SectorFrame& f : owners.learn(assignment))
        take_sample(std::move(f));
}

void Worker::State::ask_for_whole_sectors() {
    wire::SectorRequest request;
    request.sectors(wanted_whole.due(Clock::now()));
    if (request.sectors().empty()) return;
    request.reader("lpss-worker-" + std::to_string(options.id));
    request.request(++whole_requests);
    requests_out->write(request);
}

void Worker::State::apply_samples(std::uint64_t up_to,
                                  const std::vector<std::pair<std::uint64_t, BodyDesc>>& also) {
    // Samples of later frames stay queued: a faster worker's future must not leak into this frame.
    std::vector<const wire::SectorFrame*> batch;
    const auto end = samples.upper_bound(up_to);
    for (auto it = samples.begin(); it != end; ++it) {
        for (const wire::SectorFrame& f : it->second)
            batch.push_back(&f);
    }
    halo.apply(*world, batch, also);
    samples.erase(samples.begin(), end);
    chain.forget_applied(up_to);
    owners.applied(up_to, refused_samples);
}

bool Worker::State::start_world(const wire::FrameGo& go, const std::atomic<bool>& stop) {
    const SectorAssignment current = dds::from_wire(go.next());
    halo.follow(current, current, go.next().largest_radius());
    learn(current);
    if (!create_world(go.next())) return false;
    // The world's first state: the coordinator's samples of the sectors this worker holds, and the planes.
    // Waits as long as the coordinator is there: a large world takes a while to send.
    const auto started = Clock::now();
    auto last_word = started;
    constexpr auto kNotYet = Clock::time_point::max();
    auto planes_matched_at = kNotYet;  // when this planes reader first had a writer
    auto planes_patience = std::chrono::seconds(5);
    while (!stop.load() && (!gate.whole(0, {}, true, chain) || early_planes.size() < go.planes())) {
        if (!coordinator_present()) {
            spdlog::error("worker {}: the coordinator went away while sending the world", options.id);
            return false;
        }
        inbox.wait(std::chrono::milliseconds(50));
        pump();
        // The planes are durable samples the coordinator wrote before this start: a reader matched to their
        // writer has them within moments. Twice a secured cluster's worker waited 30 s for "0 of 1 planes"
        // (2026-12-05; whether its reader had matched was not logged then). A new reader is a new match,
        // to which the writer sends its history again. Its patience doubles each time: a new reader starts
        // its matching over, and one matched only to the standby's writer (which writes no plane) must
        // not be made anew faster than a loaded machine matches the coordinator's.
        if (early_planes.size() < go.planes() && planes_in->matched() > 0) {
            if (planes_matched_at == kNotYet) {
                planes_matched_at = Clock::now();
            } else if (Clock::now() - planes_matched_at > planes_patience) {
                spdlog::warn(
                    "worker {}: {} of {} planes after {:.0f} s from {} matched writer(s): reading them anew",
                    options.id, early_planes.size(), go.planes(),
                    std::chrono::duration<double>(Clock::now() - started).count(), planes_in->matched());
                read_planes();
                if (!planes_in->ok()) {
                    spdlog::error("worker {}: cannot make its reader of the world's planes anew", options.id);
                    return false;
                }
                planes_matched_at = kNotYet;
                planes_patience *= 2;
            }
        }
        if (Clock::now() - last_word > std::chrono::seconds(5)) {
            last_word = Clock::now();
            spdlog::warn(
                "worker {}: still waiting for the world's first state after {:.0f} s: the coordinator's "
                "mark of it {}, {} of {} planes ({} writers of planes matched), {} sector samples of "
                "frame 0, {} writers of sector frames matched",
                options.id, std::chrono::duration<double>(Clock::now() - started).count(),
                gate.has_mark(0, 0) ? "here" : "missing", early_planes.size(), go.planes(),
                planes_in->matched(), samples.count(0) ? samples.at(0).size() : 0, frames_in->matched());
        }
    }
    if (stop.load()) return false;
    const std::vector<std::pair<std::uint64_t, BodyDesc>> ranked_planes = take_early_planes();
    // Readers hold this worker's sectors as the coordinator sent them, from the coordinator's history:
    // publishing them again would send the whole world at frame 1 (200 MB for a million bodies) and stall
    // the first frames. Their first samples are partial, on the coordinator's.
    std::unordered_map<SectorKey, std::vector<std::uint32_t>, SectorKeyHash> seed_recipients;
    if (auto first = samples.find(0); first != samples.end()) {
        for (const wire::SectorFrame& f : first->second) {
            const SectorKey key = dds::from_wire(f.sector());
            if (f.worker() == 0 && halo.owns(key)) seed_recipients[key] = f.recipients();
        }
    }
    apply_samples(0, ranked_planes);
    for (const SectorKey& key : world->sectors()) {
        if (!halo.owns(key)) continue;
        auto seeded = seed_recipients.find(key);
        if (seeded == seed_recipients.end()) {
            adopted.insert(key);  // not from the coordinator's first state: published whole at frame 1
            continue;
        }
        const std::vector<BodySnapshot> all = world->sector_bodies(key);
        const dds::SectorPublisher::Counts before = publisher.counts(key);
        publisher.adopt(key, all, halo.near(*world, all, radii_of(*world, all)), 0);
        count_load(key, before);  // its load counts from now, though it may never change
        halo.addressed(key, seeded->second, 0);
    }
    // Building the world left the heap full of the freed samples that carried it: given back here, before
    // frame 1 is stepped, rather than after it, where it stalled the running world (0.37-0.41 s at a million
    // bodies, the whole cluster waiting on frame 2).
    runtime::give_back_free_memory();
    // A neighbour's sector comes here whole once one of its bodies comes near; only the bodies that come
    // near are ghosts in the engine, the rest wait as records (Halo::dormant).
    const double built_s = std::chrono::duration<double>(Clock::now() - started).count();
    std::size_t own_sectors = 0, ghosts = 0;
    for (const SectorKey& key : world->sectors()) {
        if (halo.owns(key)) {
            ++own_sectors;
            continue;
        }
        ghosts += world->sector_bodies(key).size();
    }
    spdlog::info(
        "worker {}: holds {} bodies in {} sectors ({} of its own) after {:.2f} s; {} of them ghosts near its "
        "own sectors; {} bodies of the sectors around kept out of the engine",
        options.id, world->body_count(), world->sectors().size(), own_sectors, built_s, ghosts,
        halo.dormant());
    return true;
}

bool Worker::State::create_world(const wire::Assignment& announced) {
    EngineOptions engine;
    engine.threads = options.threads;
    engine.owns = [this](const SectorKey& key) { return halo.owns(key); };
    Expected<World> created = World::create(dds::from_wire(announced.settings()), engine);
    if (!created) {
        spdlog::error("worker {}: the coordinator's settings are refused: {}", options.id,
                      created.error().message);
        return false;
    }
    world.emplace(std::move(created).value());
    return true;
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

void Worker::State::read_planes() {
    planes_in.reset();  // its endpoint goes before the new one is made
    dds::Participant& p = *participant;
    planes_in = std::make_unique<dds::Reader<wire::BodyDescription>>(
        p, p.topic<wire::BodyDescriptionPubSubType>(dds::kBodyDescriptions),
        dds::reader_qos(dds::kDescriptionReading), &inbox);
}

std::vector<std::pair<std::uint64_t, BodyDesc>> Worker::State::take_early_planes() {
    std::vector<std::pair<std::uint64_t, BodyDesc>> ranked;
    for (auto& [id, plane] : early_planes) {
        ranked.push_back(std::move(plane));
        planes.insert(id);
    }
    early_planes.clear();
    return ranked;
}

Worker::State::Joining Worker::State::join(const wire::FrameGo& latest) {
    const SectorAssignment announced = dds::from_wire(latest.next());
    const bool given =
        asked_to_join && announced.epoch != joined_from.epoch &&
        std::find(announced.workers.begin(), announced.workers.end(), options.id) != announced.workers.end();
    if (announced.epoch == latest.epoch() && !given) {
        // No change under way: ask, once for each assignment seen in force (an answer may be a change made
        // for another reason, such as a worker gone, that leaves this one out).
        // Once for each, and again if no answer comes (a request the coordinator never read: written before
        // its reader matched this writer, or lost with a coordinator that went).
        if (asked_to_join && joined_from.epoch == announced.epoch && Clock::now() - asked_at < kJoinPatience)
            return Joining::waiting;
        // Not before every worker and the coordinator can reach it and it them: its first frame needs their
        // samples at once, and discovery that matched one side only took seconds at times (seen: a joiner
        // that started its first frame without its sectors, 2 s later, and showed bodies twice).
        const int peers = static_cast<int>(announced.workers.size()) + 1;
        bool reachable = frames_in->matched() >= peers && marks_in->matched() >= peers &&
                         frames_out->matched() >= peers && marks_out->matched() >= peers;
        for (std::uint32_t w : announced.workers) {
            auto reader = sector_readers.find(w);
            reachable = reachable && (w == options.id || (heard.count(w) && reader != sector_readers.end() &&
                                                          frames_out->reaches(reader->second)));
        }
        if (!reachable) {
            if (Clock::now() - join_noted > std::chrono::seconds(5)) {
                join_noted = Clock::now();
                std::string heard_from;
                for (std::uint32_t w : heard)
                    heard_from += " " + std::to_string(w);
                spdlog::info(
                    "worker {}: waiting to reach the cluster's {} workers and coordinator before joining: "
                    "matched {} sector writers, {} mark writers, {} readers of its sectors, {} of its marks; "
                    "marks heard from workers{}",
                    options.id, announced.workers.size(), frames_in->matched(), marks_in->matched(),
                    frames_out->matched(), marks_out->matched(), heard_from);
            }
            return Joining::waiting;
        }
        if (!asked_to_join) {
            spdlog::info("worker {}: the cluster is running (frame {}): asking to join", options.id,
                         latest.frame());
        } else if (joined_from.epoch == announced.epoch) {
            spdlog::warn("worker {}: no answer to its request to join after {} s: asking again", options.id,
                         kJoinPatience.count());
        }
        asked_to_join = true;
        asked_at = Clock::now();
        joined_from = announced;
        // What came before is history: the coordinator's first state and restored sectors, addressed to a
        // worker of this id that is gone (seen: a restarted worker showed a body where it was at frame 0).
        sample_floor = latest.frame();
        samples.clear();
        chain = dds::SectorChain();
        owners = dds::SampleOwners();
        wanted_whole = dds::WholeSectorAsks();
        wire::WorkerFrame ask = mark_of(0);
        ask.epoch(announced.epoch);
        marks_out->write(ask);
        return Joining::waiting;
    }
    if (!given) return Joining::waiting;
    // Given sectors from a later frame, whose owners send them whole at the frame before; or from the latest
    // frame, whose start came before this worker read the one that announced it (two starts in one read):
    // it has not started here yet, and the whole samples of the frame before are on their way.
    if (announced.from_frame < latest.frame()) {
        spdlog::error("worker {}: given sectors from frame {}, but frame {} has started already", options.id,
                      announced.from_frame, latest.frame());
        return Joining::failed;
    }
    if (early_planes.size() < latest.planes()) return Joining::waiting;
    if (!create_world(latest.next())) return Joining::failed;
    halo.follow(joined_from, announced, latest.next().largest_radius());
    // Not joined_from: assignments may have come between (its sectors' whole samples of the frame before
    // are under the epoch then in force, unknown here, and so let through).
    learn(announced);
    halo.apply(*world, {}, take_early_planes());
    // It is as if it had ended the frame before its sectors become its own: that frame's samples (its
    // sectors whole, and its halo) are the ones it starts from.
    frame = announced.from_frame - 1;
    gate.started(frame);
    spdlog::info("worker {}: joins the cluster with sectors of epoch {} from frame {}", options.id,
                 announced.epoch, announced.from_frame);
    return Joining::joined;
}

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

void Worker::State::count_load(const SectorKey& key, const dds::SectorPublisher::Counts& before) {
    const dds::SectorPublisher::Counts after = publisher.counts(key);
    const double change =
        (double(after.bodies) + double(after.awake)) - (double(before.bodies) + double(before.awake));
    if (change == 0.0) return;
    const SectorKey block = block_of(key, halo.current().block_size);
    double& load = block_loads[block];
    load += change;
    if (load <= 0.0) block_loads.erase(block);
}

std::vector<wire::WrittenSector> Worker::State::publish() {
    World& w = *world;
    // Where something happened, and what readers asked for whole; at the frame before an assignment
    // change, every sector that changes owner or gains holders, whole (its new holders build it from that
    // sample, exactly: complete samples carry offsets in double).
    std::set<SectorKey> keys;
    for (const SectorKey& key : w.changed_sectors())
        keys.insert(key);
    // An owned sector asked for that holds nothing is answered too, with an empty sample: a reader that lost
    // the sample that emptied it waits for that.
    for (const SectorKey& key : whole_requested) {
        if (publisher.publishes(key) || halo.owns(key)) keys.insert(key);
    }
    keys.insert(adopted.begin(), adopted.end());
    // Readers that asked for an inventory and that this worker's sector writer reaches: every sector of
    // their region, whole (DDS's history holds a worker's last samples, not every sector's: see SectorFrame
    // in idl/lpss.idl).
    for (auto it = inventory_requests.begin(); it != inventory_requests.end();) {
        const InventoryRequest& r = it->second;
        if (r.frames_reader && !frames_out->reaches(*r.frames_reader)) {
            it = Clock::now() - r.asked > kInventoryPatience ? inventory_requests.erase(it) : std::next(it);
            continue;
        }
        answering.push_back(r);
        it = inventory_requests.erase(it);
    }
    if (!answering.empty()) {
        // A sector whose latest sample is no newer than what the reader holds is listed with that frame and
        // not sent: the reader has it (a whole-world client of a million resting bodies, which falls behind
        // while it builds its first frame, was sent every body again, 20,000 a frame from each worker).
        publisher.for_each(
            [&](const SectorKey& key, std::uint64_t stamp, const dds::SectorPublisher::Counts&) {
                for (const InventoryRequest& r : answering) {
                    const bool held = r.held_through != 0 && stamp <= r.held_through;
                    if (r.covers(key) && !held && for_joiners_queued.insert(key).second) {
                        for_joiners_due.push_back(key);
                        break;
                    }
                }
            });
    }
    std::set<SectorKey> for_joiners;
    std::size_t taken = 0;
    for (std::uint32_t bodies = 0; taken < for_joiners_due.size() && bodies < kJoinerBodiesPerFrame;
         ++taken) {
        const SectorKey& key = for_joiners_due[taken];
        for_joiners_queued.erase(key);
        if (!publisher.publishes(key)) continue;  // given away or emptied since: its new sample says so
        bodies += publisher.counts(key).bodies;
        for_joiners.insert(key);
    }
    for_joiners_due.erase(for_joiners_due.begin(),
                          for_joiners_due.begin() + static_cast<std::ptrdiff_t>(taken));
    keys.insert(for_joiners.begin(), for_joiners.end());
    // At the frame before an assignment change, and when bodies may reach farther, every sector's
    // recipients are looked at again (neighbours change owners); those that change owner go whole.
    std::set<SectorKey> handed;
    const bool reach_changed_now = reach_changed;
    if (halo.switching_after(frame) || reach_changed) {
        publisher.for_each([&](const SectorKey& key, std::uint64_t, const dds::SectorPublisher::Counts&) {
            keys.insert(key);
            if (halo.switching_after(frame) && halo.next().owner_of(key) != options.id) handed.insert(key);
        });
        reach_changed = false;
    }
    if (reach_changed_now) {
        // Bodies reach farther: every body's near mask again (rare: a spawn of a larger body).
        for (const SectorKey& key : keys) {
            if (!publisher.publishes(key)) continue;
            std::vector<BodySnapshot> all = w.sector_bodies(key);
            publisher.set_near(key, all, halo.near(w, all, radii_of(w, all)));
        }
    }
    auto describe = [&w](BodyId id) { return dds::kind_of(*w.description(id)); };
    std::vector<wire::WrittenSector> written;
    for (const SectorKey& key : keys) {
        if (!halo.owns(key)) continue;  // a sector of ghosts
        // What changed; or everything, for a sector readers must get whole.
        const bool asked = whole_requested.count(key) || handed.count(key) || adopted.count(key) ||
                           for_joiners.count(key) || !publisher.publishes(key);
        const dds::SectorPublisher::Counts before = publisher.counts(key);
        std::optional<wire::SectorFrame> sample;
        auto send_whole = [&] {
            const std::vector<BodySnapshot> all = w.sector_bodies(key);
            if (all.empty() && !publisher.publishes(key) && !adopted.count(key) &&
                !whole_requested.count(key))
                return;  // nothing, never sent
            sample = publisher.whole(key, all, halo.near(w, all, radii_of(w, all)), frame, describe);
        };
        if (asked) {
            send_whole();
        } else {
            const SectorChanges changes = w.sector_changes(key);
            sample = publisher.update(key, changes.bodies, halo.near(w, changes.bodies, changes.radii),
                                      changes.left, frame, describe);
        }
        Halo::Addressing to = halo.address(key, publisher.near(key), !publisher.publishes(key), frame);
        // A worker that gains the sector builds its ghosts from a complete sample; one released learns it
        // from whatever sample comes, an empty one if nothing changed.
        if (to.gained && !(sample && sample->complete())) send_whole();
        if (!sample && to.changed() && publisher.publishes(key)) sample = publisher.nothing_new(key, frame);
        count_load(key, before);
        if (!sample) continue;
        sample->recipients(to.recipients);
        sample->released(std::move(to.released));
        sample->worker(options.id);
        sample->slot(0);  // one instance: see SectorFrame
        sample->epoch(halo.current().epoch);
        outgoing.push_back(std::move(*sample));
        wire::WrittenSector entry;
        entry.sector(sample->sector());
        entry.recipients(std::move(to.recipients));
        written.push_back(std::move(entry));
    }
    whole_requested.clear();
    adopted.clear();
    return written;
}

void Worker::State::mark(std::vector<wire::WrittenSector> written, double step_ms, double wait_ms,
                         double publish_ms) {
    World& w = *world;
    wire::WorkerFrame m = mark_of(frame);
    m.epoch(halo.current().epoch);
    m.written(std::move(written));
    // Inventories: what a reader that starts needs to know which sectors exist (their samples of this
    // frame, whole, follow the mark).
    for (const InventoryRequest& r : answering) {
        wire::SectorInventory inventory;
        inventory.reader(r.reader);
        inventory.request(r.request);
        publisher.for_each(
            [&](const SectorKey& key, std::uint64_t stamp, const dds::SectorPublisher::Counts&) {
                if (!r.covers(key)) return;
                wire::SectorStamp s;
                s.sector(dds::to_wire(key));
                s.frame(stamp);
                inventory.sectors().push_back(s);
            });
        m.inventories().push_back(std::move(inventory));
    }
    answering.clear();

    const SectorAssignment& after = halo.switching_after(frame) ? halo.next() : halo.current();
    m.leaving(handoff_requests(w, options.id, after));

    const bool report_loads = frame % kLoadReportEvery == 0;
    if (report_loads) {
        for (const auto& [block, load] : block_loads) {
            wire::BlockLoad l;
            l.block(dds::to_wire(block));
            l.load(static_cast<float>(load));
            m.loads().push_back(l);
        }
        if (const std::optional<MemoryUse> memory = memory_use()) resident_bytes = memory->resident_bytes;
    }
    const FrameStats& s = w.last_frame_stats();
    const dds::SectorPublisher::Counts owned = publisher.totals();
    m.loads_reported(report_loads);
    m.bodies(owned.bodies);
    m.planes(static_cast<std::uint32_t>(planes.size()));
    m.awake(owned.awake);
    m.sector_count(static_cast<std::uint32_t>(publisher.sector_count()));
    m.ghosts(static_cast<std::uint32_t>(w.body_count() - owned.bodies - planes.size()));
    m.dormant(static_cast<std::uint32_t>(halo.dormant()));
    m.border_bodies(static_cast<std::uint32_t>(s.border_bodies));
    m.clones(static_cast<std::uint32_t>(s.clones));
    m.step_ms(static_cast<float>(step_ms));
    m.wait_ms(static_cast<float>(wait_ms));
    m.publish_ms(static_cast<float>(publish_ms));
    auto bytes = received_bytes.find(frame - 1);
    m.received_bytes(bytes == received_bytes.end() ? 0 : bytes->second);
    received_bytes.erase(received_bytes.begin(), received_bytes.upper_bound(frame - 1));
    m.resident_bytes(resident_bytes);
    m.degraded(degraded);
    m.started_ns(frame_started_ns);
    m.time_lost(time_lost);
    marks_out->write(m);
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
        if (s.world && s.cut_off()) {
            // No coordinator's beat for its lease: this worker is cut off (or every coordinator is gone).
            // The others are taking its sectors over; whatever it published from now on would be stale.
            spdlog::error(
                "worker {}: no coordinator heard for its lease (cut off, or every coordinator gone) after "
                "frame {}: stopping without publishing; it is taken as gone (liveliness news: {})",
                id, s.frame, s.liveliness_history());
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
        while (!s.gate.whole(s.frame - 1, go.ended(), go.coordinator_wrote(), s.chain) && !stop.load()) {
            if (s.cut_off()) {
                // Cut off while waiting for the others' data (the wait would end degraded, then publish).
                spdlog::error(
                    "worker {}: no coordinator heard for its lease (cut off, or every coordinator gone) "
                    "during frame {}: stopping without publishing; it is taken as gone (liveliness news: {})",
                    id, s.frame, s.liveliness_history());
                return s.sit_out(stop);
            }
            if (Clock::now() - wait_start > s.options.border_wait) {
                ++s.degraded;
                spdlog::warn("worker {}: frame {} starts without all border data of frame {} (degraded): {}",
                             id, s.frame, s.frame - 1,
                             s.gate.missing(s.frame - 1, go.ended(), go.coordinator_wrote(), s.chain));
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
