#include "lpss/client/client.hpp"

#include <algorithm>
#include <map>
#include <set>
#include <unordered_map>

#include "lpssPubSubTypes.h"
#include "lpss_dds/convert.hpp"
#include "lpss_dds/participant.hpp"
#include "lpss_dds/sector_chain.hpp"
#include "lpss_dds/sector_mirror.hpp"
#include "lpss_dds/topics.hpp"

namespace lpss {

// A frame is complete when every worker of the current assignment has said it ended it, and for every
// sector it owns (that this client follows) a usable sample from between the worker's stamp and this frame
// arrived: the sector as it was at this frame; and the descriptions of the world's planes, which are in no
// sector's samples. Samples are buffered by frame and applied in order, so a frame never shows a later
// frame's state of some sector. A partial sample is usable only on the complete sample it adds to
// (SectorChain): a late joiner shows its first frame once every sector has come whole.
struct Client::State {
    ClientOptions options;
    std::unique_ptr<dds::Participant> participant;
    dds::Inbox inbox;
    std::unique_ptr<dds::Reader<wire::SectorFrame>> frames_in;
    std::unique_ptr<dds::Reader<wire::WorkerFrame>> marks_in;
    std::unique_ptr<dds::Reader<wire::Assignment>> assignment_in;
    std::unique_ptr<dds::Reader<wire::BodyDescription>> descriptions_in;
    std::unique_ptr<dds::Reader<wire::CommandResult>> results_in;
    std::unique_ptr<dds::Writer<wire::Command>> commands_out;
    std::unique_ptr<dds::Writer<wire::SectorRequest>> requests_out;

    std::optional<SectorGrid> grid;
    std::vector<std::uint32_t> workers;
    std::unordered_map<BodyId, BodyDesc> descriptions;
    std::map<std::uint64_t, std::vector<wire::SectorFrame>> pending;  ///< samples by frame
    dds::SectorChain chain;                                           ///< which samples are usable
    dds::SectorMirror mirror;  ///< the sectors as of the last frame applied
    /// Sectors whose partial samples were refused, and when each was last asked for whole.
    std::set<SectorKey> wanted_whole;
    std::unordered_map<SectorKey, std::chrono::steady_clock::time_point, SectorKeyHash> asked;
    std::uint64_t next_sector_request = 1;
    /// What a worker said at the end of a frame: the sectors it owns (that this client follows), each with
    /// the frame of its latest sample, and how many planes the world holds.
    struct Mark {
        std::vector<std::pair<SectorKey, std::uint64_t>> stamps;
        std::uint32_t planes = 0;
    };
    std::map<std::pair<std::uint32_t, std::uint64_t>, Mark> marks;
    std::set<BodyId> plane_descriptions;
    std::map<eprosima::fastrtps::rtps::InstanceHandle_t, BodyId> description_instances;
    std::set<std::uint64_t> marked_frames;
    std::uint64_t applied = 0;
    std::optional<WorldFrame> latest;
    std::function<void(const WorldFrame&)> callback;
    std::map<std::uint64_t, CommandOutcome> outcomes;
    std::uint64_t next_request = 1;

    bool follows(const SectorKey& key) const { return !options.region || options.region->contains(key); }
    void take();
    bool complete(std::uint64_t frame) const;
    void apply_until(std::uint64_t frame);
    WorldFrame frame_view(std::uint64_t frame) const;
    std::uint64_t send(wire::Command command);
    void ask_for_whole_sectors();
};

Client::Client(std::unique_ptr<State> state) : state_(std::move(state)) {}

Client::~Client() {
    if (!state_) return;
    state_->frames_in.reset();
    state_->marks_in.reset();
    state_->assignment_in.reset();
    state_->descriptions_in.reset();
    state_->results_in.reset();
    state_->commands_out.reset();
    state_->requests_out.reset();
}

Expected<std::unique_ptr<Client>> Client::connect(const ClientOptions& options) {
    if (options.name.empty()) return Error{"a client needs a name (its commands carry it)"};
    auto state = std::make_unique<State>();
    state->options = options;
    Expected<std::unique_ptr<dds::Participant>> participant =
        dds::Participant::create(options.domain, options.profile, "lpss-client-" + options.name);
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
        p, p.topic<wire::WorkerFramePubSubType>(kWorkerFrames), reader_qos(kFrameDelivery), &state->inbox);
    state->assignment_in = std::make_unique<Reader<wire::Assignment>>(
        p, p.topic<wire::AssignmentPubSubType>(kSectorOwners), reader_qos(kStateDelivery), &state->inbox);
    state->descriptions_in = std::make_unique<Reader<wire::BodyDescription>>(
        p, p.topic<wire::BodyDescriptionPubSubType>(kBodyDescriptions), reader_qos(kDescriptionReading),
        &state->inbox);
    state->results_in = std::make_unique<Reader<wire::CommandResult>>(
        p, p.topic<wire::CommandResultPubSubType>(kCommandResults), reader_qos(kCommandDelivery),
        &state->inbox);
    state->commands_out = std::make_unique<Writer<wire::Command>>(
        p, p.topic<wire::CommandPubSubType>(kCommands), writer_qos(kCommandDelivery));
    state->requests_out = std::make_unique<Writer<wire::SectorRequest>>(
        p, p.topic<wire::SectorRequestPubSubType>(kSectorRequests), writer_qos(kCommandDelivery));
    if (!state->frames_in->ok() || !state->marks_in->ok() || !state->assignment_in->ok() ||
        !state->descriptions_in->ok() || !state->results_in->ok() || !state->commands_out->ok() ||
        !state->requests_out->ok()) {
        return Error{"cannot create the client's DDS readers and writers"};
    }
    return std::unique_ptr<Client>(new Client(std::move(state)));
}

void Client::State::take() {
    assignment_in->take_all([&](const wire::Assignment& a, const dds::fdds::SampleInfo& info) {
        if (!info.valid_data) return;
        grid = SectorGrid(a.settings().sector_size());
        workers = a.workers();
    });
    descriptions_in->take_all([&](const wire::BodyDescription& d, const dds::fdds::SampleInfo& info) {
        if (info.valid_data) {
            BodyDesc body = dds::from_wire(d);
            if (is_plane(body.shape)) plane_descriptions.insert(body.id);
            description_instances[info.instance_handle] = body.id;
            descriptions[d.id()] = std::move(body);
            return;
        }
        // Disposed: the body was removed. The sample holds no data, and the reader may have forgotten the
        // instance's key by now: the id comes from the instance's earlier samples.
        auto instance = description_instances.find(info.instance_handle);
        if (instance == description_instances.end()) return;
        const BodyId id = instance->second;
        description_instances.erase(instance);
        descriptions.erase(id);
        plane_descriptions.erase(id);
    });
    marks_in->take_all([&](const wire::WorkerFrame& m, const dds::fdds::SampleInfo& info) {
        if (!info.valid_data || m.frame() == 0) return;
        Mark mark;
        for (const wire::SectorStamp& st : m.sectors()) {
            const SectorKey key = dds::from_wire(st.sector());
            if (follows(key)) mark.stamps.emplace_back(key, st.frame());
        }
        mark.planes = m.planes();
        marks[{m.worker(), m.frame()}] = std::move(mark);
        marked_frames.insert(m.frame());
    });
    frames_in->take_all([&](const wire::SectorFrame& f, const dds::fdds::SampleInfo& info) {
        if (!info.valid_data) return;
        if (!chain.accept(f)) {
            wanted_whole.insert(dds::from_wire(f.sector()));
            return;
        }
        wanted_whole.erase(dds::from_wire(f.sector()));
        pending[f.frame()].push_back(f);
    });
    results_in->take_all([&](const wire::CommandResult& r, const dds::fdds::SampleInfo& info) {
        if (!info.valid_data || r.client() != options.name) return;
        outcomes[r.request()] = CommandOutcome{r.applied(), r.order(), r.frame(), r.reason()};
    });
    ask_for_whole_sectors();
}

void Client::State::ask_for_whole_sectors() {
    // Without a request the owner sends the sector whole within 30 frames anyway; asking makes it the next
    // frame. Asked again while refused, not more than every 100 ms (a request can be lost to discovery).
    const auto now = std::chrono::steady_clock::now();
    wire::SectorRequest request;
    for (const SectorKey& key : wanted_whole) {
        auto last = asked.find(key);
        if (last != asked.end() && now - last->second < std::chrono::milliseconds(100)) continue;
        asked[key] = now;
        request.sectors().push_back(dds::to_wire(key));
    }
    if (request.sectors().empty()) return;
    request.reader(options.name);
    request.request(next_sector_request++);
    requests_out->write(request);
}

bool Client::State::complete(std::uint64_t frame) const {
    if (workers.empty() || !grid) return false;
    for (std::uint32_t w : workers) {
        auto it = marks.find({w, frame});
        if (it == marks.end()) return false;
        // Planes are shown from their descriptions, which travel apart from the frames.
        if (plane_descriptions.size() < it->second.planes) return false;
        // A sample of each sector from between its stamp and this frame: that sector's state at this frame.
        for (const auto& [key, stamp] : it->second.stamps) {
            if (!chain.holds(key, stamp, frame)) return false;
        }
    }
    return true;
}

void Client::State::apply_until(std::uint64_t frame) {
    while (!pending.empty() && pending.begin()->first <= frame) {
        for (const wire::SectorFrame& f : pending.begin()->second)
            mirror.apply(f);
        pending.erase(pending.begin());
    }
    chain.forget_applied(frame);
}

WorldFrame Client::State::frame_view(std::uint64_t frame) const {
    WorldFrame out;
    out.frame = frame;
    for (const auto& [key, bodies] : mirror.sectors()) {
        if (!follows(key)) continue;
        for (const auto& [id, state] : bodies) {
            const BodySnapshot s = dds::from_wire(state, key);
            BodyView b;
            b.id = s.id;
            b.position = s.position;
            b.orientation = s.orientation;
            b.linear_velocity = s.linear_velocity;
            b.angular_velocity = s.angular_velocity;
            b.awake = s.awake;
            b.global = grid->to_global(b.position);
            out.bodies.push_back(b);
        }
    }
    // Planes are not in any sector's frames (each worker holds its own instances): from descriptions.
    for (const auto& [id, d] : descriptions) {
        if (!is_plane(d.shape)) continue;
        BodyView b;
        b.id = id;
        b.position = std::get<SectorPosition>(d.position);
        if (!follows(b.position.sector)) continue;
        b.orientation = d.orientation;
        b.global = grid->to_global(b.position);
        out.bodies.push_back(b);
    }
    std::sort(out.bodies.begin(), out.bodies.end(),
              [](const BodyView& a, const BodyView& b) { return a.id < b.id; });
    return out;
}

std::vector<WorldFrame> Client::poll(std::chrono::milliseconds wait) {
    State& s = *state_;
    if (wait.count() > 0) s.inbox.wait(wait);
    s.take();
    std::vector<WorldFrame> out;
    // Frames complete in order; an older frame still incomplete when a newer one is complete never will
    // be (a late joiner finds only the last few frames' marks of each worker): it is skipped.
    std::uint64_t newest_complete = 0;
    for (std::uint64_t f : s.marked_frames) {
        if (f > s.applied && s.complete(f)) newest_complete = f;
    }
    for (auto it = s.marked_frames.begin(); it != s.marked_frames.end() && *it <= newest_complete;) {
        const std::uint64_t f = *it;
        it = s.marked_frames.erase(it);
        if (f <= s.applied || !s.complete(f)) continue;
        s.apply_until(f);
        s.applied = f;
        out.push_back(s.frame_view(f));
    }
    for (auto it = s.marks.begin(); it != s.marks.end();)
        it = it->first.second <= s.applied ? s.marks.erase(it) : std::next(it);
    for (const WorldFrame& f : out) {
        if (s.callback) s.callback(f);
    }
    if (!out.empty()) s.latest = out.back();
    return out;
}

bool Client::wait_for_cluster(std::chrono::milliseconds limit) {
    State& s = *state_;
    auto connected = [&] {
        return s.grid && s.commands_out->matched() > 0 &&
               s.results_in->matched() >= static_cast<int>(s.workers.size()) + 1;  // coordinator, workers
    };
    const auto end = std::chrono::steady_clock::now() + limit;
    while (!connected() && std::chrono::steady_clock::now() < end) {
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

std::optional<BodyDesc> Client::description(BodyId id) const {
    auto it = state_->descriptions.find(id);
    if (it == state_->descriptions.end()) return std::nullopt;
    return it->second;
}

std::uint64_t Client::State::send(wire::Command command) {
    const std::uint64_t request = next_request++;
    command.client(options.name);
    command.request(request);
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
    c.spawn(dds::describe(body, at, 0));
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
