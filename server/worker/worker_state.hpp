// What a worker holds between frames (Worker::State), shared by the files that make up its frame loop:
// worker.cpp (the loop, and reading what comes), world_start.cpp (the world's first state), joining.cpp (a
// worker joining a running cluster), frame_start.cpp (what a frame's start changes) and publishing.cpp (the
// frame's samples and its mark). Internal to the worker.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "commands.hpp"
#include "coordinator_watch.hpp"
#include "frame_gate.hpp"
#include "halo.hpp"
#include "inventories.hpp"
#include "lpss/engine/world.hpp"
#include "lpssPubSubTypes.h"
#include "lpss_dds/participant.hpp"
#include "lpss_dds/sample_intake.hpp"
#include "lpss_dds/sector_publisher.hpp"
#include "worker.hpp"

namespace lpss::worker {

using Clock = std::chrono::steady_clock;

struct Worker::State {
    explicit State(const WorkerOptions& o)
        : options(o),
          gate(o.id),
          halo(o.id),
          intake("worker " + std::to_string(o.id), "lpss-worker-" + std::to_string(o.id), true),
          coordinators(o.id) {}

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

    /// The other writers' sector samples, checked and queued by frame until the frame after theirs starts
    /// here and applies them to the halo: a faster worker's future must not leak into a frame.
    dds::SampleIntake intake;
    /// A sector sample read. Its own are dropped: they come back only from an earlier run under its id, or
    /// from a peer that claims to be it.
    void take_sample(wire::SectorFrame f);
    std::uint64_t next_whole_request = 1;
    void ask_for_whole_sectors();
    /// The latest frame known here, and how far past it a sample may be (dds::SampleIntake::take).
    std::uint64_t known_frame() const;
    std::uint64_t frames_ahead() const;
    /// Takes note of an assignment announced (dds::SampleIntake::learn).
    void learn(const SectorAssignment& assignment);
    std::map<BodyId, std::pair<std::uint64_t, BodyDesc>>
        early_planes;         ///< before the world exists: rank, plane
    std::set<BodyId> planes;  ///< in no sector's samples: readers count them in marks

    // Published.
    dds::SectorPublisher publisher;
    std::set<SectorKey> whole_requested;  ///< sectors a reader asked to have whole
    /// Sectors taken over (the world's first state, a rebalance, a worker gone): their readers hold what
    /// another writer sent, so this worker's first sample of each is whole, empty or not.
    std::set<SectorKey> adopted;
    Inventories inventories;
    /// The largest body radius changed (a spawn): every sector's recipients are looked at again.
    bool reach_changed = false;
    std::map<SectorKey, double> block_loads;  ///< bodies, awake ones counting double, per block owned
    std::uint64_t resident_bytes = 0;

    bool coordinator_present() const { return go_in->matched() > 0; }
    CoordinatorWatch coordinators;
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

}  // namespace lpss::worker
