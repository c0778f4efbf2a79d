#include "lpss/client/client.hpp"

#include <algorithm>
#include <map>
#include <set>
#include <sstream>
#include <unordered_map>

#include "lpssPubSubTypes.h"
#include "lpss_dds/convert.hpp"
#include "lpss_dds/participant.hpp"
#include "lpss_dds/sample_check.hpp"
#include "lpss_dds/sample_intake.hpp"
#include "lpss_dds/sector_mirror.hpp"
#include "lpss_dds/topics.hpp"

namespace lpss {

// How a client holds consistent frames. A reader that starts asks every worker for an inventory of the
// sectors it owns in the region followed (the whole world: everything), with the frame of each one's latest
// sample; the answers come in the workers' WorkerFrames. From then on, each WorkerFrame lists the sectors
// written in its frame. Frame f is complete when every worker of the assignment in force has said it ended
// f, and a usable sample of each sector it lists as written at f has arrived (and, for the first frame, of
// each sector of the inventories, from the frame it names on): a sector not written since holds what it
// held. Samples are buffered by frame and applied in order, so a frame never mixes in a later frame's state
// of some sector. A partial sample is usable only on the sample it follows (SectorChain): a sector whose
// chain broke (samples lost) is asked for whole. Planes, in no sector's samples, come from their durable
// descriptions, which a frame waits for as the marks count them.
struct Client::State {
    ClientOptions options;
    std::unique_ptr<dds::Participant> participant;
    dds::Inbox inbox;
    std::unique_ptr<dds::Reader<wire::SectorFrame>> frames_in;
    std::unique_ptr<dds::Reader<wire::WorkerFrame>> marks_in;
    std::unique_ptr<dds::Reader<wire::Assignment>> assignment_in;
    std::unique_ptr<dds::Reader<wire::BodyDescription>> planes_in;
    std::unique_ptr<dds::Reader<wire::CommandResult>> results_in;
    std::unique_ptr<dds::Reader<wire::ClusterStatus>> status_in;
    std::unique_ptr<dds::Writer<wire::Command>> commands_out;
    std::unique_ptr<dds::Writer<wire::SectorRequest>> requests_out;

    std::optional<SectorGrid> grid;
    std::uint32_t term = 0;                      ///< the highest coordinator term seen
    std::optional<std::uint64_t> stopped_after;  ///< the world's last frame, once its coordinator said so
    std::optional<WorldSettings> settings;
    /// Assignments by the frame they take effect from: which workers end each frame, and own which sectors.
    std::map<std::uint64_t, std::vector<std::uint32_t>> workers_from;
    std::map<BodyId, BodyDesc> planes;
    std::map<eprosima::fastrtps::rtps::InstanceHandle_t, BodyId> plane_instances;
    /// The sector samples read: checked, judged by the assignments (which worker owns which sectors, and
    /// so writes their samples), chained, and kept by frame until shown.
    dds::SampleIntake intake{"client", "client"};  ///< named by connect()
    dds::SectorMirror mirror;                      ///< the sectors as of the last frame applied
    std::uint64_t next_sector_request = 1;

    /// What a worker said at the end of a frame: the sectors it wrote (that this client follows), how many
    /// planes the world holds, and its answer to this client's inventory request if it carries one.
    struct Mark {
        std::vector<SectorKey> written;
        std::uint32_t planes = 0;
        std::optional<std::vector<std::pair<SectorKey, std::uint64_t>>> inventory;
        std::uint64_t started_ns = 0;
        double time_lost = 0.0;
        std::vector<HandoffView> leaving;  ///< into sectors this client follows
        WorkerView report;
    };
    std::map<std::pair<std::uint32_t, std::uint64_t>, Mark> marks;
    /// The coordinator's marks of frames in which it wrote the sectors of workers gone during them: by frame,
    /// the sectors (followed) and the gone workers whose marks of that frame it stands for.
    struct Restored {
        std::vector<SectorKey> written;
        std::vector<std::uint32_t> stands_for;
    };
    std::map<std::uint64_t, Restored> restored;
    /// Whether worker `w`'s end of `frame` is known: its mark, or the coordinator's standing for it.
    bool ended(std::uint32_t w, std::uint64_t frame) const;
    /// The coordinator's mark of the world's first state (frame 0): a client there from the start follows
    /// the world from it, without asking the workers for an inventory.
    std::optional<std::vector<SectorKey>> first_state;
    /// Workers whose hello (their mark of frame 0) came: their marks writer knows this client's reader.
    std::set<std::uint32_t> hellos;
    /// The newest frame a worker has ended, as far as this client knows: samples much newer are garbage.
    static constexpr std::uint64_t kNoMarkYet = ~std::uint64_t{0} - dds::kClientFramesAhead;
    std::uint64_t newest_mark = kNoMarkYet;
    std::uint64_t inventory_request = 0;  ///< the latest asked; 0: not asked since the last (re)sync
    /// Answers to requests numbered from this on count: every request since the client began to (re)sync.
    /// A worker's answer to any of them is what it held at its frame, which sync() can start from.
    std::uint64_t inventory_since = 0;
    std::chrono::steady_clock::time_point inventory_asked;
    bool synced = false;  ///< the inventories are in: frames follow from `applied`
    /// Syncing again: the mirror holds every followed sector as of this frame, so the workers send whole
    /// only what was written after it (0: everything, a first sync).
    std::uint64_t held_through = 0;
    ClientStats stats;
    std::chrono::steady_clock::time_point synced_at;
    std::map<SectorKey, std::uint64_t> stamps;  ///< followed sectors: the frame of their latest sample
    std::set<SectorKey> unconfirmed;            ///< from inventories: not yet held at their stamp
    /// Sectors written in frames passed over since the last frame shown (a gone worker's frame skipped):
    /// a frame shown later must hold each at its stamp, or the mirror would show it as it was before.
    std::set<SectorKey> passed_over;
    std::uint64_t applied = 0;
    std::optional<WorldFrame> latest;
    std::function<void(const WorldFrame&)> callback;
    std::map<std::uint64_t, CommandOutcome> outcomes;
    std::uint64_t next_request = 1;

    bool follows(const SectorKey& key) const { return !options.region || options.region->contains(key); }
    const std::vector<std::uint32_t>* workers_of(std::uint64_t frame) const;
    void take();
    void ask_for_inventory();
    /// Tells the coordinator once that this client reads every topic from every writer there is (a
    /// coordinator started with --await-clients starts frame 1 then).
    void say_ready();
    std::uint64_t ready_request = 0;  ///< the request saying so; 0: not said yet
    std::chrono::steady_clock::time_point ready_said;
    bool sync();
    /// Drops the sync: the inventories are asked for again and frames follow from their answers.
    void resync();
    /// Just synced: drops what is held or pending of sectors no inventory lists.
    void forget_unlisted();
    /// Whether a worker's mark of `frame` will never come: a later mark of that worker is here.
    bool mark_lost(std::uint64_t frame) const;
    /// Whether `frame` can be shown: every sector written in it, every sector of `passed` (written in frames
    /// since the last one shown) and every unconfirmed one is held at its stamp.
    /// If not, and `missing` is given, the sectors it waits for are added to it.
    bool complete(std::uint64_t frame, const std::map<SectorKey, std::uint64_t>& stamps,
                  const std::set<SectorKey>& passed, std::set<SectorKey>* missing = nullptr) const;
    /// When no frame was shown since: a frame that waits this long for sectors has lost their samples (a
    /// reader that fell behind loses samples its writer's history no longer holds), and asks for them whole.
    std::chrono::steady_clock::time_point last_progress;
    /// Brings stamps as of frame - 1 to `frame`, from the marks of `frame`; false if a mark is missing.
    /// The sectors written in `frame` are added to `written` if given.
    bool stamp_frame(std::uint64_t frame, std::map<SectorKey, std::uint64_t>& stamps,
                     std::set<SectorKey>* written = nullptr) const;
    /// Whether every sector of the inventories has come at its stamp or later, so that some frame can be
    /// complete: without it, no frame is, and looking for one is wasted.
    bool inventories_held() const;
    void apply_until(std::uint64_t frame);
    WorldFrame frame_view(std::uint64_t frame) const;
    WorldFrame changes_view(std::uint64_t frame);
    BodyView view_of(const SectorKey& key, const dds::PackedBodyState& state) const;
    BodyView view_of(BodyId id, const BodyDesc& plane) const;
    /// Of the samples applied since the last frame returned: the bodies they carry, with their sectors,
    /// and those that left what this client holds (FrameContent::changes).
    std::vector<std::pair<BodyId, SectorKey>> touched;
    std::vector<BodyId> left;
    std::set<BodyId> planes_shown;  ///< the planes of the last frame returned (FrameContent::changes)
    bool shown_whole = false;       ///< a frame with every body was returned (FrameContent::changes)
    /// The outcomes kept, the newest by request number: a client that never asks for them does not grow.
    static constexpr std::size_t kMostOutcomes = 4096;
    std::uint64_t send(wire::Command command);
    void ask_for_whole_sectors();
    /// A sector sample read: checked, then kept for its frame (or refused, or held until its epoch is known,
    /// or its sector wanted whole: dds::SampleIntake).
    void take_sample(wire::SectorFrame f);
    /// Sectors a frame has waited for since kLostAfter without a frame shown: their samples are asked for
    /// whole (their owners answer in their next frame, an emptied sector with an empty sample).
    void ask_for_lost(const std::set<SectorKey>& missing);
    /// Fills in what the marks of frames [from, shown] tell beyond the bodies: each body's worker, the
    /// handoffs, the workers' reports.
    void describe_cluster(WorldFrame& frame, std::uint64_t from, std::uint64_t shown) const;
};

void Client::State::describe_cluster(WorldFrame& out, std::uint64_t from, std::uint64_t shown) const {
    if (const SectorAssignment* assignment = intake.owners().in_force(shown)) {
        // Once per sector: the owner's lookup (a Morton code, a search) was a tenth of what a whole-world
        // client of a million bodies spent a frame, with the same few sectors asked for over and over.
        std::unordered_map<SectorKey, std::uint32_t, SectorKeyHash> owner;
        for (BodyView& b : out.bodies) {
            if (planes.count(b.id) != 0) continue;
            auto [at, fresh] = owner.try_emplace(b.position.sector, 0);
            if (fresh) at->second = assignment->owner_of(b.position.sector);
            b.worker = at->second;
        }
    }
    for (std::uint64_t g = from; g <= shown; ++g) {
        const std::vector<std::uint32_t>* workers = workers_of(g);
        if (workers == nullptr) continue;
        for (std::uint32_t w : *workers) {
            auto it = marks.find({w, g});
            if (it == marks.end()) continue;
            out.handoffs.insert(out.handoffs.end(), it->second.leaving.begin(), it->second.leaving.end());
            if (g == shown) out.workers.push_back(it->second.report);
        }
    }
}

Client::Client(std::unique_ptr<State> state) : state_(std::move(state)) {}

Client::~Client() {
    if (!state_) return;
    state_->frames_in.reset();
    state_->marks_in.reset();
    state_->assignment_in.reset();
    state_->planes_in.reset();
    state_->results_in.reset();
    state_->status_in.reset();
    state_->commands_out.reset();
    state_->requests_out.reset();
}

Expected<std::unique_ptr<Client>> Client::connect(const ClientOptions& options) {
    if (options.name.empty()) return Error{"a client needs a name (its commands carry it)"};
    auto state = std::make_unique<State>();
    state->options = options;
    state->intake = dds::SampleIntake("client", options.name);
    Expected<std::unique_ptr<dds::Participant>> participant = dds::Participant::create(
        options.domain, options.profile, "lpss-client-" + options.name, {}, options.security);
    if (!participant) return participant.error();
    state->participant = std::move(participant).value();
    dds::Participant& p = *state->participant;
    using namespace dds;
    fdds::TopicDescription* frames = p.topic<wire::SectorFramePubSubType>(kSectorFrames);
    if (options.region) {
        const std::int64_t lo[3] = {options.region->lo.i, options.region->lo.j, options.region->lo.k};
        const std::int64_t hi[3] = {options.region->hi.i, options.region->hi.j, options.region->hi.k};
        frames = p.sector_region(kSectorFrames, lo, hi);
        if (frames == nullptr) return Error{"cannot create the region filter"};
    }
    state->frames_in = std::make_unique<Reader<wire::SectorFrame>>(p, frames, reader_qos(kSectorFrameReading),
                                                                   &state->inbox);
    state->marks_in = std::make_unique<Reader<wire::WorkerFrame>>(
        p, p.topic<wire::WorkerFramePubSubType>(kWorkerFrames), reader_qos(kMarksReading), &state->inbox);
    state->assignment_in =
        std::make_unique<Reader<wire::Assignment>>(p, p.topic<wire::AssignmentPubSubType>(kSectorOwners),
                                                   reader_qos(kAssignmentDelivery), &state->inbox);
    state->planes_in = std::make_unique<Reader<wire::BodyDescription>>(
        p, p.topic<wire::BodyDescriptionPubSubType>(kBodyDescriptions), reader_qos(kDescriptionReading),
        &state->inbox);
    state->results_in = std::make_unique<Reader<wire::CommandResult>>(
        p, p.topic<wire::CommandResultPubSubType>(kCommandResults), reader_qos(kResultDelivery),
        &state->inbox);
    state->status_in = std::make_unique<Reader<wire::ClusterStatus>>(
        p, p.topic<wire::ClusterStatusPubSubType>(kStatus), reader_qos(kStateDelivery), &state->inbox);
    state->commands_out = std::make_unique<Writer<wire::Command>>(
        p, p.topic<wire::CommandPubSubType>(kCommands), writer_qos(kCommandDelivery));
    state->requests_out = std::make_unique<Writer<wire::SectorRequest>>(
        p, p.topic<wire::SectorRequestPubSubType>(kSectorRequests), writer_qos(kCommandDelivery));
    // Under DDS Security an observer's identity may not write commands: access control refuses the writer,
    // and the client goes on without one (its commands are refused, with that reason).
    if (!state->commands_out->ok() && !options.security.empty()) state->commands_out.reset();
    if (!state->frames_in->ok() || !state->marks_in->ok() || !state->assignment_in->ok() ||
        !state->planes_in->ok() || !state->results_in->ok() || !state->status_in->ok() ||
        (state->commands_out && !state->commands_out->ok()) || !state->requests_out->ok()) {
        return Error{"cannot create the client's DDS readers and writers" +
                     std::string(options.security.empty() ? ""
                                                          : " (does the identity in " + options.security +
                                                                " permit reading lpss's topics?)")};
    }
    return std::unique_ptr<Client>(new Client(std::move(state)));
}

void Client::State::take() {
    // The coordinator that runs the world says "stopped" once its last frame has ended (its --frames ran
    // out, or it was stopped); a coordinator killed says nothing, and a standby that took over says it in
    // its turn. A coordinator loading a world is another world beginning on the domain.
    status_in->take_all([&](const wire::ClusterStatus& st, const dds::fdds::SampleInfo& info) {
        if (!info.valid_data) return;
        if (st.phase() == "stopped") stopped_after = st.frame();
        if (st.phase() == "loading" || st.phase() == "sending") stopped_after.reset();
    });
    assignment_in->take_all([&](const wire::Assignment& a, const dds::fdds::SampleInfo& info) {
        // A coordinator replaced by its standby (a lower term) may still be about: its word no longer counts.
        if (!info.valid_data || a.term() < term) return;
        term = a.term();
        grid = SectorGrid(a.settings().sector_size());
        settings = dds::from_wire(a.settings());
        workers_from[a.from_frame()] = a.workers();
        for (wire::SectorFrame& f : intake.learn(dds::from_wire(a)))
            take_sample(std::move(f));
    });
    planes_in->take_all([&](const wire::BodyDescription& d, const dds::fdds::SampleInfo& info) {
        if (info.valid_data) {
            plane_instances[info.instance_handle] = d.id();
            planes[d.id()] = dds::from_wire(d);
            return;
        }
        // Disposed: the plane was removed. The sample holds no data, and the reader may have forgotten the
        // instance's key by now: the id comes from the instance's earlier samples.
        auto instance = plane_instances.find(info.instance_handle);
        if (instance == plane_instances.end()) return;
        planes.erase(instance->second);
        plane_instances.erase(instance);
    });
    marks_in->take_all([&](const wire::WorkerFrame& m, const dds::fdds::SampleInfo& info) {
        if (info.valid_data && m.frame() == 0 && m.worker() == 0) {
            first_state.emplace();
            for (const wire::WrittenSector& w : m.written()) {
                const SectorKey key = dds::from_wire(w.sector());
                if (follows(key)) first_state->push_back(key);
            }
            return;
        }
        if (info.valid_data && m.frame() == 0) hellos.insert(m.worker());
        if (info.valid_data && m.frame() > applied && m.worker() == 0) {
            // A worker gone during this frame: the coordinator wrote its sectors whole and ends the frame for
            // it (a gone worker's own mark may never come, or come without its samples).
            Restored& r = restored[m.frame()];
            for (const wire::WrittenSector& w : m.written()) {
                const SectorKey key = dds::from_wire(w.sector());
                if (follows(key)) r.written.push_back(key);
            }
            r.stands_for.insert(r.stands_for.end(), m.stands_for().begin(), m.stands_for().end());
            return;
        }
        if (!info.valid_data || m.frame() == 0 || m.worker() == 0) return;
        Mark mark;
        for (const wire::WrittenSector& w : m.written()) {
            const SectorKey key = dds::from_wire(w.sector());
            if (follows(key)) mark.written.push_back(key);
        }
        mark.planes = m.planes();
        for (const wire::Handoff& h : m.leaving()) {
            const SectorKey key = dds::from_wire(h.sector());
            if (follows(key))
                mark.leaving.push_back({h.body(), h.from_worker(), h.to_worker(), key, m.frame()});
        }
        mark.report = WorkerView{m.worker(), m.sector_count(), m.bodies(), m.awake(),
                                 m.ghosts(), m.clones(),       m.step_ms()};
        mark.started_ns = m.started_ns();
        mark.time_lost = m.time_lost();
        for (const wire::SectorInventory& inventory : m.inventories()) {
            // Answers to this client's requests since it began to sync. Not only the latest: a client slow
            // to take its samples asked again every second and dropped every answer to an earlier request,
            // and every answer came later than that (seen in a soak with a worker killed every 3 s: never
            // synced).
            if (inventory.reader() != options.name || inventory_since == 0 ||
                inventory.request() < inventory_since)
                continue;
            mark.inventory.emplace();
            for (const wire::SectorStamp& st : inventory.sectors()) {
                const SectorKey key = dds::from_wire(st.sector());
                if (follows(key)) mark.inventory->emplace_back(key, st.frame());
            }
        }
        newest_mark = newest_mark == kNoMarkYet ? m.frame() : std::max(newest_mark, m.frame());
        marks[{m.worker(), m.frame()}] = std::move(mark);
    });
    frames_in->take_all([&](wire::SectorFrame& f, const dds::fdds::SampleInfo& info) {
        if (!info.valid_data) return;
        if (f.complete()) stats.bodies_in_complete_samples += f.bodies().size();
        take_sample(std::move(f));
    });
    results_in->take_all([&](const wire::CommandResult& r, const dds::fdds::SampleInfo& info) {
        if (!info.valid_data || r.client() != options.name) return;
        const CommandOutcome outcome{r.applied(), r.order(), r.frame(), r.reason()};
        // An answer for a run of requests: only the newest kMostOutcomes can be asked for anyway.
        const std::uint64_t most = kMostOutcomes;
        std::uint64_t from =
            r.first_request() != 0 && r.first_request() < r.request() ? r.first_request() : r.request();
        if (r.request() - from >= most) from = r.request() - most + 1;
        for (std::uint64_t q = from; q <= r.request(); ++q)
            outcomes[q] = outcome;
        while (outcomes.size() > most)
            outcomes.erase(outcomes.begin());
    });
    ask_for_inventory();
    ask_for_whole_sectors();
    say_ready();
}

void Client::State::take_sample(wire::SectorFrame f) {
    // The coordinator's samples hold the world's first state, of sectors not written since (and the
    // state of a dead worker's sectors, for their next owner).
    if (intake.chain().stale(f)) return;
    // A sector no inventory and no mark names, at a frame already applied: it was empty then, and this
    // is an older sample of it from a history that still holds one (see forget_unlisted).
    if (synced && f.frame() <= applied && !stamps.count(dds::from_wire(f.sector()))) return;
    intake.take(std::move(f), newest_mark, dds::kClientFramesAhead);
}

void Client::State::say_ready() {
    // Matched is not enough: a durable writer's history (the world's first state) may still be on its way,
    // and a frame's partial samples would then arrive before their base.
    if (ready_request != 0) {
        // Said: the coordinator answers. A command written just after matching can be lost (the
        // coordinator's reader may not have matched this writer yet, and a volatile reader takes nothing
        // from before): said again until answered.
        if (outcomes.count(ready_request) ||
            std::chrono::steady_clock::now() - ready_said < std::chrono::milliseconds(500))
            return;
    }
    if (!grid || workers_from.empty() || !first_state) return;
    for (const SectorKey& key : *first_state) {
        if (!intake.chain().holds(key, 0, ~std::uint64_t{0})) return;
    }
    // Matched here is not matched there either: a writer that has not matched this reader yet sends it
    // nothing, and its history keeps eight frames. A worker's hello, in its writer's history, shows that
    // its marks writer has matched this client (seen: a worker's mark of frame 1 lost to a client that
    // said it was ready).
    for (std::uint32_t w : workers_from.rbegin()->second) {
        if (!hellos.count(w)) return;
    }
    const int writers = static_cast<int>(workers_from.rbegin()->second.size()) + 1;  // workers, coordinator
    // A client that may not write commands cannot say it is ready: a cluster cannot await it.
    if (!commands_out) return;
    if (commands_out->matched() < 1 || assignment_in->matched() < 1 || planes_in->matched() < 1 ||
        marks_in->matched() < writers || frames_in->matched() < writers || results_in->matched() < writers ||
        requests_out->matched() < writers - 1)
        return;
    if (ready_request == 0) ready_request = next_request++;
    wire::Command ready;
    ready.client(options.name);
    ready.request(ready_request);
    ready.kind(wire::kCommandReady);
    commands_out->write(ready);
    ready_said = std::chrono::steady_clock::now();
}

const std::vector<std::uint32_t>* Client::State::workers_of(std::uint64_t frame) const {
    auto it = workers_from.upper_bound(frame);
    if (it == workers_from.begin()) return nullptr;
    return &std::prev(it)->second;
}

void Client::State::ask_for_inventory() {
    // Once every worker's request reader and sector writer are matched, so that the answer finds this client
    // reading (the samples it names are in the workers' histories, which a matched reader receives).
    // Asked again after a second without the answers: a request written just after matching can be lost
    // (a worker's reader not yet matched with this writer takes nothing from before), and so can the
    // inventory a worker gives for a reader that joins (its writer's history keeps eight frames, and this
    // reader may match it later than that under load). Seen: a late joiner that never showed a frame.
    if (synced || !grid || workers_from.empty()) return;
    // Not before the world runs, nor while a client that holds the world's first state can still follow it
    // from frame 1 (each worker's mark of frame 1 stays in its writer's history for its first eight
    // frames): the answer costs the workers the client's sectors whole.
    if (newest_mark == kNoMarkYet ||
        (first_state && newest_mark <= static_cast<std::uint64_t>(dds::kFrameDelivery.depth)))
        return;
    if (inventory_request != 0 &&
        std::chrono::steady_clock::now() - inventory_asked < std::chrono::seconds(1))
        return;
    const int workers = static_cast<int>(workers_from.rbegin()->second.size());
    if (requests_out->matched() < workers || marks_in->matched() < workers) return;
    wire::SectorRequest request;
    request.reader(options.name);
    if (inventory_request == 0) {
        inventory_since = next_sector_request;
        for (auto& [at, mark] : marks)
            mark.inventory.reset();  // answers to the requests of a sync before
    }
    inventory_request = next_sector_request++;
    inventory_asked = std::chrono::steady_clock::now();
    request.request(inventory_request);
    request.inventory(true);
    request.held_through(held_through);
    const SectorKey lo = options.region ? options.region->lo : SectorKey{INT64_MIN, INT64_MIN, INT64_MIN};
    const SectorKey hi = options.region ? options.region->hi : SectorKey{INT64_MAX, INT64_MAX, INT64_MAX};
    request.lo(dds::to_wire(lo));
    request.hi(dds::to_wire(hi));
    // The answer comes with the sectors whole, in the frame the workers' sector writers reach this reader.
    const dds::GuidBytes reader = frames_in->guid();
    request.frames_reader(std::vector<std::uint8_t>(reader.begin(), reader.end()));
    requests_out->write(request);
}

void Client::State::ask_for_whole_sectors() {
    // Without a request a refused sector would wait for the next complete sample, which may never come;
    // asking makes it the next frame. Asked again while refused, not more than every 100 ms (a request can
    // be lost to discovery). Not before the inventories are in: a reader that joins gets the workers' last
    // samples from DDS's history, most of them partial, and the answers bring its sectors whole anyway.
    // Once synced, a sector of the inventories that has not come at its stamp within a second (its whole
    // sample lost to a reader that fell behind) is asked for too.
    if (!synced) return;
    if (!unconfirmed.empty() && std::chrono::steady_clock::now() - synced_at > std::chrono::seconds(1)) {
        for (const SectorKey& key : unconfirmed) {
            if (!intake.chain().holds(key, stamps.at(key), ~std::uint64_t{0})) intake.want_whole(key);
        }
    }
    if (auto request = intake.whole_request(next_sector_request)) requests_out->write(*request);
}

void Client::State::ask_for_lost(const std::set<SectorKey>& missing) {
    // Samples in flight come within a few frames; a sample that has not come in a quarter of a second was
    // lost: its writer's history moved past it before this reader took it (seen in the soak: a sector
    // emptied in a frame whose samples a busy client lost, and every frame after waited on it for good,
    // since an empty sector is not written again and only a refused partial sample asked for it).
    constexpr std::chrono::milliseconds kLostAfter{250};
    if (!synced || std::chrono::steady_clock::now() - std::max(last_progress, synced_at) < kLostAfter) return;
    for (const SectorKey& key : missing)
        intake.want_whole(key);
}

bool Client::State::sync() {
    // Every worker of the newest assignment has answered: the sectors it owns, each as of its stamp. Frames
    // start from the latest answer; the workers that answered earlier list what they wrote since.
    if (workers_from.empty()) return false;
    if (const std::vector<std::uint32_t>* first = workers_of(1); first_state && first) {
        // There from the start: every worker's mark of frame 1 is here, so nothing was written before this
        // client read it. The world is the first state, and frames follow from frame 1.
        bool from_start = true;
        for (std::uint32_t w : *first)
            from_start = from_start && marks.count({w, 1});
        if (from_start) {
            stamps.clear();
            unconfirmed.clear();
            passed_over.clear();
            for (const SectorKey& key : *first_state) {
                stamps[key] = 0;
                unconfirmed.insert(key);
            }
            applied = 0;
            synced = true;
            ++stats.syncs;
            synced_at = std::chrono::steady_clock::now();
            forget_unlisted();
            return true;
        }
    }
    const std::vector<std::uint32_t>& workers = workers_from.rbegin()->second;
    std::map<std::uint32_t, std::uint64_t> answered;
    for (const auto& [at, mark] : marks) {
        if (mark.inventory && std::find(workers.begin(), workers.end(), at.first) != workers.end())
            answered[at.first] = at.second;
    }
    if (answered.size() < workers.size()) return false;
    std::uint64_t start = 0;
    for (const auto& [w, f] : answered)
        start = std::max(start, f);
    stamps.clear();
    unconfirmed.clear();
    passed_over.clear();  // the inventories say where every sector stands
    for (const auto& [w, f] : answered) {
        for (const auto& [key, stamp] : *marks.at({w, f}).inventory) {
            stamps[key] = std::max(stamps[key], stamp);
            unconfirmed.insert(key);
        }
        for (std::uint64_t g = f + 1; g <= start; ++g) {
            auto it = marks.find({w, g});
            if (it == marks.end()) {
                // Not here yet (it answered a frame or two before another worker did, and its later marks
                // are on their way): wait. A gap (a later mark of it is here): what it wrote then is
                // unknown; ask again. Taken for a gap, a mark still on its way made a client ask again and
                // drop the answers it had, for seconds after a worker was killed.
                auto later = marks.lower_bound({w, g});
                if (later != marks.end() && later->first.first == w) inventory_request = 0;
                return false;
            }
            for (const SectorKey& key : it->second.written)
                stamps[key] = g;
        }
    }
    applied = start - 1;
    synced = true;
    ++stats.syncs;
    synced_at = std::chrono::steady_clock::now();
    forget_unlisted();
    return true;
}

void Client::State::forget_unlisted() {
    // The inventories list every sector that holds bodies (in the region followed): one they do not list,
    // and no mark since names, is empty. Its samples may still come: a sector's samples are carried by a
    // slot of their writer (SectorSlots), which carries another sector's once the sector empties, so the
    // sample that emptied it can be gone from DDS's history while older ones of it (the coordinator's first
    // state, a previous owner's last) are still there. Those, and whatever the mirror holds of such a sector
    // from before a resync, are dropped.
    intake.drop_queued(applied,
                       [&](const wire::SectorFrame& f) { return !stamps.count(dds::from_wire(f.sector())); });
    std::vector<SectorKey> empty;
    for (const auto& [key, bodies] : mirror.sectors()) {
        if (!stamps.count(key)) empty.push_back(key);
    }
    mirror.drop(empty, options.content == FrameContent::changes ? &left : nullptr);
}

void Client::State::resync() {
    // What the mirror shows is every followed sector as of `applied`, unless frames were passed over (a
    // gone worker's: those sectors may be older there) or no frame has been shown since the last sync
    // (`applied` is then where the sync starts, and sectors of the inventories may not have come): then
    // everything comes again.
    held_through = synced && passed_over.empty() && unconfirmed.empty() ? applied : 0;
    synced = false;
    inventory_request = 0;
    for (auto& [at, mark] : marks)
        mark.inventory.reset();  // answers to the request before
}

bool Client::State::mark_lost(std::uint64_t frame) const {
    const std::vector<std::uint32_t>* workers = workers_of(frame);
    if (workers == nullptr) return false;
    for (std::uint32_t w : *workers) {
        if (ended(w, frame)) continue;
        auto later = marks.lower_bound({w, frame});
        if (later != marks.end() && later->first.first == w) return true;
    }
    return false;
}

bool Client::State::ended(std::uint32_t w, std::uint64_t frame) const {
    if (marks.count({w, frame})) return true;
    auto r = restored.find(frame);
    return r != restored.end() && std::find(r->second.stands_for.begin(), r->second.stands_for.end(), w) !=
                                      r->second.stands_for.end();
}

bool Client::State::stamp_frame(std::uint64_t frame, std::map<SectorKey, std::uint64_t>& out,
                                std::set<SectorKey>* written) const {
    const std::vector<std::uint32_t>* workers = workers_of(frame);
    if (workers == nullptr) return false;
    for (std::uint32_t w : *workers) {
        if (!ended(w, frame)) return false;
    }
    for (std::uint32_t w : *workers) {
        auto it = marks.find({w, frame});
        if (it == marks.end()) continue;  // the coordinator's stands for it
        for (const SectorKey& key : it->second.written) {
            out[key] = frame;
            if (written) written->insert(key);
        }
    }
    if (auto r = restored.find(frame); r != restored.end()) {
        for (const SectorKey& key : r->second.written) {
            out[key] = frame;
            if (written) written->insert(key);
        }
    }
    return true;
}

bool Client::State::inventories_held() const {
    for (const SectorKey& key : unconfirmed) {
        if (!intake.chain().holds(key, stamps.at(key), ~std::uint64_t{0})) return false;
    }
    return true;
}

bool Client::State::complete(std::uint64_t frame, const std::map<SectorKey, std::uint64_t>& stamps,
                             const std::set<SectorKey>& passed, std::set<SectorKey>* missing) const {
    const std::vector<std::uint32_t>* workers = workers_of(frame);
    if (workers == nullptr || !grid) return false;
    bool held = true;
    // Whether the sector is held as of `from` at `frame`; noted as missing if not.
    auto holds = [&](const SectorKey& key, std::uint64_t from) {
        if (intake.chain().holds(key, from, frame)) return true;
        held = false;
        if (missing) missing->insert(key);
        return missing != nullptr;  // go on only to collect
    };
    for (std::uint32_t w : *workers) {
        if (!ended(w, frame)) return false;
        auto it = marks.find({w, frame});
        if (it == marks.end()) continue;  // the coordinator's stands for it
        // Planes are shown from their descriptions, which travel apart from the frames: a frame waits
        // until those it counts (spawned or removed) have come.
        if (planes.size() != it->second.planes) return false;
        for (const SectorKey& key : it->second.written) {
            if (!holds(key, frame)) return false;
        }
    }
    if (auto r = restored.find(frame); r != restored.end()) {
        for (const SectorKey& key : r->second.written) {
            if (!holds(key, frame)) return false;
        }
    }
    for (const SectorKey& key : unconfirmed) {
        if (!holds(key, stamps.at(key))) return false;
    }
    // A sector written in a frame passed over and not since: its sample there must be held, or what the
    // mirror shows of it is older (seen in the soak: a partial sample refused for a missing base, the frames
    // after it skipped, and the bodies that had left the sector shown in it and in the sector they went to).
    for (const SectorKey& key : passed) {
        if (!holds(key, stamps.at(key))) return false;
    }
    return held;
}

void Client::State::apply_until(std::uint64_t frame) {
    const std::vector<const wire::SectorFrame*> batch = intake.through(frame);
    if (options.content == FrameContent::changes) {
        for (const wire::SectorFrame* sample : batch) {
            const SectorKey key = dds::from_wire(sample->sector());
            for (const wire::BodyState& b : sample->bodies())
                touched.emplace_back(b.id(), key);
        }
    }
    mirror.apply(batch, options.content == FrameContent::changes ? &left : nullptr);
    intake.applied(frame);
}

BodyView Client::State::view_of(const SectorKey& key, const dds::PackedBodyState& state) const {
    const BodySnapshot s = dds::unpack(state, key);
    BodyView b;
    b.id = s.id;
    b.position = s.position;
    b.orientation = s.orientation;
    b.linear_velocity = s.linear_velocity;
    b.angular_velocity = s.angular_velocity;
    b.awake = s.awake;
    b.global = grid->to_global(b.position);
    return b;
}

BodyView Client::State::view_of(BodyId id, const BodyDesc& plane) const {
    BodyView b;
    b.id = id;
    b.position = std::get<SectorPosition>(plane.position);
    b.orientation = plane.orientation;
    b.global = grid->to_global(b.position);
    return b;
}

WorldFrame Client::State::changes_view(std::uint64_t frame) {
    WorldFrame out;
    if (!shown_whole) {
        out = frame_view(frame);
        shown_whole = true;
        for (const auto& [id, plane] : planes) {
            if (follows(std::get<SectorPosition>(plane.position).sector)) planes_shown.insert(id);
        }
    } else {
        out.frame = frame;
        out.every_body = false;
        // Where each body the samples carried is now: the last of its sectors that holds it (a body that
        // crossed a border comes in two samples).
        std::sort(touched.begin(), touched.end(),
                  [](const auto& a, const auto& b) { return a.first < b.first; });
        for (std::size_t n = 0; n < touched.size();) {
            const BodyId id = touched[n].first;
            std::optional<BodyView> found;
            for (; n < touched.size() && touched[n].first == id; ++n) {
                const SectorKey& key = touched[n].second;
                if (found || !follows(key)) continue;
                if (const dds::SectorMirror::Body* body = mirror.find(key, id))
                    found = view_of(key, body->state);
            }
            if (found) out.bodies.push_back(*found);
        }
        out.departed = std::move(left);
        std::set<BodyId> now;
        for (const auto& [id, plane] : planes) {
            if (!follows(std::get<SectorPosition>(plane.position).sector)) continue;
            now.insert(id);
            if (!planes_shown.count(id)) out.bodies.push_back(view_of(id, plane));
        }
        for (BodyId id : planes_shown) {
            if (!now.count(id)) out.departed.push_back(id);
        }
        planes_shown = std::move(now);
        std::sort(out.bodies.begin(), out.bodies.end(),
                  [](const BodyView& a, const BodyView& b) { return a.id < b.id; });
        std::sort(out.departed.begin(), out.departed.end());
        out.departed.erase(std::unique(out.departed.begin(), out.departed.end()), out.departed.end());
    }
    touched.clear();
    left.clear();
    return out;
}

WorldFrame Client::State::frame_view(std::uint64_t frame) const {
    // Each body's place in id order first, then its view made there: sorting the views themselves (176
    // bytes each) in a vector grown as it went took 1.6-1.7 s of the 3.3 s a whole-world client waited for
    // its first frame at a million bodies, and is every frame's cost for a client of every body.
    struct Place {
        BodyId id;
        const SectorKey* sector;            // null for a plane
        const dds::PackedBodyState* state;  // the body's, or null for a plane
        const BodyDesc* plane;
    };
    std::vector<Place> places;
    std::size_t count = planes.size();
    for (const auto& [key, bodies] : mirror.sectors())
        count += follows(key) ? bodies.size() : 0;
    places.reserve(count);
    for (const auto& [key, bodies] : mirror.sectors()) {
        if (!follows(key)) continue;
        for (const dds::SectorMirror::Body& body : bodies)
            places.push_back({body.state.id, &key, &body.state, nullptr});
    }
    // Planes are not in any sector's frames (each worker holds its own instances): from descriptions.
    for (const auto& [id, d] : planes) {
        if (follows(std::get<SectorPosition>(d.position).sector))
            places.push_back({id, nullptr, nullptr, &d});
    }
    std::sort(places.begin(), places.end(), [](const Place& a, const Place& b) { return a.id < b.id; });
    WorldFrame out;
    out.frame = frame;
    out.bodies.reserve(places.size());
    for (const Place& p : places)
        out.bodies.push_back(p.plane ? view_of(p.id, *p.plane) : view_of(*p.sector, *p.state));
    return out;
}

std::vector<WorldFrame> Client::poll(std::chrono::milliseconds wait) {
    State& s = *state_;
    if (wait.count() > 0) s.inbox.wait(wait);
    s.take();
    std::vector<WorldFrame> out;
    if (!s.synced && !s.sync()) return out;
    for (;;) {
        const std::uint64_t f = s.applied + 1;
        const std::vector<std::uint32_t>* workers = s.workers_of(f);
        if (workers == nullptr) break;
        // What the workers wrote at f: sectors not written since hold what they held.
        bool marked = true;
        for (std::uint32_t w : *workers)
            marked = marked && s.ended(w, f);
        if (!marked) {
            // A worker whose end of f is missing while a later one is here: the marks of frames this client
            // did not read in time were replaced by newer ones (a client not polled for a while), and what
            // was written then is unknown. Ask for the inventories again and go on from their answers.
            if (s.mark_lost(f)) {
                s.resync();
                break;
            }
            // A worker that never ends f (for this client) is gone if a later assignment leaves it out and
            // every worker of that assignment has ended its first frame: the sectors it had come whole from
            // their new owners. Skip f. (It may have ended f and more: killed right after writing its end
            // of f, that reached the coordinator and not this client, which waited on f for ever.)
            std::vector<std::uint32_t> missing;
            for (std::uint32_t w : *workers) {
                if (!s.ended(w, f)) missing.push_back(w);
            }
            bool skip = false;
            for (auto later = s.workers_from.upper_bound(f); later != s.workers_from.end() && !skip;
                 ++later) {
                const std::vector<std::uint32_t>& then = later->second;
                bool leaves_out = true, ended = true;
                for (std::uint32_t w : missing)
                    leaves_out = leaves_out && std::find(then.begin(), then.end(), w) == then.end();
                for (std::uint32_t w : then)
                    ended = ended && s.marks.count({w, later->first});
                skip = leaves_out && ended;
            }
            if (!skip) break;
            for (std::uint32_t w : *workers) {
                if (auto it = s.marks.find({w, f}); it != s.marks.end()) {
                    for (const SectorKey& key : it->second.written) {
                        s.stamps[key] = f;
                        s.passed_over.insert(key);
                    }
                }
            }
            s.applied = f;
            continue;
        }
        // Frame f, or if it never will be complete (samples it needs were replaced by newer ones before
        // this client read them, or a sector of an inventory came whole only later), the first marked frame
        // after it that is: frames in between are skipped.
        // The stamps are brought forward frame by frame (a client behind by hundreds of frames looked for a
        // complete one by working out each frame's stamps from the start, and never caught up).
        std::map<SectorKey, std::uint64_t> at = s.stamps;
        std::set<SectorKey> passed = s.passed_over;
        std::uint64_t show = 0, g = f;
        // What the newest frame looked at waits for: asked for whole if nothing is shown for a while.
        std::set<SectorKey> missing;
        if (s.inventories_held()) {
            for (std::set<SectorKey> written; show == 0 && s.stamp_frame(g, at, &written); ++g) {
                missing.clear();
                if (s.complete(g, at, passed, &missing)) {
                    show = g;
                } else {
                    passed.insert(written.begin(), written.end());
                    written.clear();
                }
            }
        } else {
            while (s.stamp_frame(g, at))
                ++g;  // where the marks stop, for mark_lost below
        }
        if (show == 0) {
            s.ask_for_lost(missing);
            // Stopped at a frame whose marks are not all here. One that a later mark of its worker has
            // overtaken is lost for good (a worker's marks come in order; its writer keeps eight, and a
            // joiner flooded by the world's samples can fall that far behind): what was written then is
            // unknown, and every later frame would wait on it. Start again from fresh inventories.
            if (s.mark_lost(g)) s.resync();
            break;
        }
        s.stamps = std::move(at);
        s.apply_until(show);
        s.applied = show;
        s.unconfirmed.clear();  // complete() found each of them held
        s.passed_over.clear();
        s.last_progress = std::chrono::steady_clock::now();
        out.push_back(s.options.content == FrameContent::changes ? s.changes_view(show) : s.frame_view(show));
        s.describe_cluster(out.back(), f, show);
        // Every worker's mark of a frame carries the coordinator's start of it.
        for (std::uint32_t w : *s.workers_of(show)) {
            auto it = s.marks.find({w, show});
            if (it == s.marks.end()) continue;
            out.back().started = std::chrono::system_clock::time_point(
                std::chrono::duration_cast<std::chrono::system_clock::duration>(
                    std::chrono::nanoseconds(it->second.started_ns)));
            out.back().time_lost_s = it->second.time_lost;
            break;
        }
    }
    for (auto it = s.marks.begin(); it != s.marks.end();)
        it = it->first.second <= s.applied ? s.marks.erase(it) : std::next(it);
    s.restored.erase(s.restored.begin(), s.restored.upper_bound(s.applied));
    for (const WorldFrame& f : out) {
        if (s.callback) s.callback(f);
    }
    if (!out.empty()) s.latest = out.back();
    return out;
}

bool Client::reaches_cluster() const {
    const State& s = *state_;
    const int workers = s.workers_from.empty() ? 0 : static_cast<int>(s.workers_from.rbegin()->second.size());
    return s.grid && (!s.commands_out || s.commands_out->matched() > 0) &&
           s.results_in->matched() >= workers + 1;  // coordinator, workers
}

bool Client::wait_for_cluster(std::chrono::milliseconds limit) {
    State& s = *state_;
    const auto end = std::chrono::steady_clock::now() + limit;
    while (!reaches_cluster() && std::chrono::steady_clock::now() < end) {
        s.inbox.wait(std::chrono::milliseconds(20));
        s.take();
    }
    return s.grid.has_value();
}

void Client::on_frame(std::function<void(const WorldFrame&)> callback) {
    state_->callback = std::move(callback);
}
const std::optional<WorldFrame>& Client::latest() const { return state_->latest; }
std::optional<SectorGrid> Client::grid() const { return state_->grid; }
std::optional<WorldSettings> Client::settings() const { return state_->settings; }
const std::optional<Region>& Client::region() const { return state_->options.region; }

ClientStats Client::stats() const { return state_->stats; }

std::optional<std::uint64_t> Client::stopped_after() const { return state_->stopped_after; }

Expected<Region> parse_region(const std::string& text) {
    const std::string usage =
        "--region wants six sector indices: i_lo,i_hi,j_lo,j_hi,k_lo,k_hi; got '" + text + "'";
    std::istringstream in(text);
    std::int64_t v[6];
    char comma = 0;
    for (int n = 0; n < 6; ++n) {
        if (!(in >> v[n]) || (n < 5 && (!(in >> comma) || comma != ','))) return Error{usage};
    }
    if (!(in >> std::ws).eof()) return Error{usage};  // something after the sixth
    if (v[0] > v[1] || v[2] > v[3] || v[4] > v[5])
        return Error{"--region: each low index must be <= its high; got '" + text + "'"};
    return Region{{v[0], v[2], v[4]}, {v[1], v[3], v[5]}};
}

std::optional<BodyDesc> Client::description(BodyId id) const {
    if (auto plane = state_->planes.find(id); plane != state_->planes.end()) return plane->second;
    if (const std::optional<wire::BodyKind> kind = state_->mirror.kind(id)) return dds::from_wire(*kind);
    return std::nullopt;
}

std::optional<BodyDesc> Client::description(const BodyView& body) const {
    if (auto plane = state_->planes.find(body.id); plane != state_->planes.end()) return plane->second;
    if (const std::optional<wire::BodyKind> kind = state_->mirror.kind(body.position.sector, body.id))
        return dds::from_wire(*kind);
    return description(body.id);
}

std::uint64_t Client::State::send(wire::Command command) {
    const std::uint64_t request = next_request++;
    command.client(options.name);
    command.request(request);
    if (!commands_out) {
        outcomes[request] = CommandOutcome{false, 0, 0,
                                           "this client's identity (" + options.security +
                                               ") may not send commands: DDS access control refused its "
                                               "commands writer (an operator identity may)"};
        return request;
    }
    commands_out->write(command);
    return request;
}

std::uint64_t Client::spawn(const BodyDesc& body) {
    wire::Command c;
    c.kind(wire::kCommandSpawn);
    c.body(body.id);
    BodySnapshot at;
    at.orientation = body.orientation;
    at.linear_velocity = body.linear_velocity;
    at.angular_velocity = body.angular_velocity;
    if (const auto* g = std::get_if<Eigen::Vector3d>(&body.position)) {
        at.position.local = *g;  // a global position travels in the offset field, flagged as such
        c.spawn_global(true);
    } else {
        at.position = std::get<SectorPosition>(body.position);
    }
    c.spawn(dds::describe(body, at));
    return state_->send(c);
}

std::uint64_t Client::remove(BodyId id) {
    wire::Command c;
    c.kind(wire::kCommandRemove);
    c.body(id);
    return state_->send(c);
}

std::uint64_t Client::apply_impulse(BodyId id, const Eigen::Vector3d& impulse,
                                    const Eigen::Vector3d& offset) {
    wire::Command c;
    c.kind(wire::kCommandImpulse);
    c.body(id);
    c.vector1(dds::to_wire(impulse));
    c.vector2(dds::to_wire(offset));
    return state_->send(c);
}

std::uint64_t Client::set_velocity(BodyId id, const Eigen::Vector3d& linear, const Eigen::Vector3d& angular) {
    wire::Command c;
    c.kind(wire::kCommandSetVelocity);
    c.body(id);
    c.vector1(dds::to_wire(linear));
    c.vector2(dds::to_wire(angular));
    return state_->send(c);
}

std::optional<CommandOutcome> Client::outcome(std::uint64_t request) const {
    auto it = state_->outcomes.find(request);
    if (it == state_->outcomes.end()) return std::nullopt;
    return it->second;
}

std::optional<CommandOutcome> Client::wait_outcome(std::uint64_t request, std::chrono::milliseconds limit) {
    const auto end = std::chrono::steady_clock::now() + limit;
    while (!outcome(request) && std::chrono::steady_clock::now() < end)
        poll(std::chrono::milliseconds(10));
    return outcome(request);
}

}  // namespace lpss
