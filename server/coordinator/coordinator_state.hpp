// What a coordinator holds and does, shared by its files: coordinator.cpp (its DDS entities, reading what
// comes, the frame loop), world_load.cpp (the scene and the world's first state), command_decisions.cpp
// (clients' commands), assignment_changes.cpp (handoffs, joiners, rebalancing), gone_workers.cpp (a gone
// worker's frame stepped here, its sectors given to the others) and standby.cpp (following another
// coordinator and taking over from it).
#pragma once

#include <chrono>
#include <map>
#include <optional>
#include <set>
#include <unordered_map>
#include <vector>

#include "command_rate.hpp"
#include "coordinator.hpp"
#include "lpss/common/assignment.hpp"
#include "lpss/common/body_desc.hpp"
#include "lpss/common/sector_grid.hpp"
#include "lpss/common/world_settings.hpp"
#include "lpssPubSubTypes.h"
#include "lpss_dds/confirmed_lapses.hpp"
#include "lpss_dds/convert.hpp"
#include "lpss_dds/participant.hpp"
#include "lpss_dds/sample_check.hpp"
#include "lpss_dds/sample_intake.hpp"
#include "lpss_dds/sector_mirror.hpp"
#include "standing_commands.hpp"
#include "start_acknowledger.hpp"

namespace lpss::coordinator {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

/// Sector samples waiting to be taken past which the coordinator takes them while it waits for marks (or
/// for a worker to join): an eighth of what its reader keeps per writer (kSectorFrameReading).
inline constexpr std::uint64_t kSampleBacklog = 1024;

struct Coordinator::State {
    CoordinatorOptions options;
    WorldSettings settings;
    SectorGrid grid{1.0};
    std::unique_ptr<dds::Participant> participant;
    dds::Inbox inbox;
    /// Takes the coordinator's frame starts as they come while this one stands by (before go_in: its
    /// listener), and acknowledges those it may on sight.
    StartAcknowledger start_acks{inbox};
    std::unique_ptr<dds::Writer<wire::FrameGo>> go_out;
    std::unique_ptr<dds::Writer<wire::Assignment>> assignment_out;
    std::unique_ptr<dds::Writer<wire::BodyDescription>> planes_out;
    std::unique_ptr<dds::Writer<wire::CommandResult>> results_out;
    std::unique_ptr<dds::Writer<wire::WorkerFrame>>
        marks_out;  ///< as worker 0, when it writes sectors itself
    /// The sectors of a worker that is gone (and whole sectors asked for). Its history serves them to readers
    /// that join or fall behind until every reader has them (see release_history).
    std::unique_ptr<dds::Writer<wire::SectorFrame>> sectors_out;
    /// The world's first state, through a writer of its own that goes once every reader has it: Fast DDS 2.9
    /// keeps a copy of the first sample of each instance a writer writes for as long as the writer lives
    /// (DataWriterHistory::find_or_add_key), and a sector's first sample here is the whole sector: 21 MB
    /// at 100,000 bodies (heaptrack), most of what the coordinator held beyond its standby. None as a
    /// standby, and none once released.
    std::unique_ptr<dds::Writer<wire::SectorFrame>> first_state_out;
    /// The frame of the oldest samples in sectors_out's (or first_state_out's) history still to be released
    /// (none: all released), and when they were written. The first state is 380 bytes a body (537 MiB at a
    /// million bodies); the sectors restored after a death are as much per body restored, eight samples deep
    /// per sector: kept, they held up to eight copies of the restored part of the world after a few deaths
    /// (measured: 0.8 MB after one restore in a world of 2,512 bodies).
    std::optional<std::uint64_t> history_from;
    Clock::time_point history_written_at;
    /// The samples just written to sectors_out (at frame `f`) wait in its history for release_history.
    void hold_history(std::uint64_t f);
    /// Once every reader has acknowledged what sectors_out holds (or 25 s have passed), after `frame` has
    /// ended: it leaves the history, and the heap gives back what writing it took.
    void release_history(std::uint64_t frame);
    /// The instance of each sector it wrote (idl/lpss.idl: one per sector, never reused): the world's first
    /// state stays in its history until every reader there before frame 1 has it.
    std::unordered_map<SectorKey, std::uint32_t, SectorKeyHash> slots;
    std::uint32_t slot_of(const SectorKey& key) {
        return slots.try_emplace(key, static_cast<std::uint32_t>(slots.size())).first->second;
    }
    std::unique_ptr<dds::Writer<wire::ClusterStatus>> status_out;
    std::unique_ptr<dds::Writer<wire::SectorRequest>> requests_out;  ///< sectors it wants whole
    std::unique_ptr<dds::Reader<wire::WorkerFrame>> marks_in;
    std::unique_ptr<dds::Reader<wire::Command>> commands_in;
    std::unique_ptr<dds::Reader<wire::SectorFrame>> sectors_in;
    /// The other coordinator's frame starts: a standby follows the coordinator's; a coordinator learns
    /// from a higher term that a standby took over from it.
    std::unique_ptr<dds::Reader<wire::FrameGo>> go_in;
    std::unique_ptr<dds::Writer<wire::FrameAck>> acks_out;          ///< as a standby
    std::unique_ptr<dds::Reader<wire::FrameAck>> acks_in;           ///< its standby's
    std::unique_ptr<dds::Reader<wire::Assignment>> assignment_in;   ///< as a standby
    std::unique_ptr<dds::Reader<wire::BodyDescription>> planes_in;  ///< as a standby
    std::unique_ptr<dds::Reader<wire::CommandResult>> results_in;   ///< as a standby: refusals given
    /// The other coordinator's status. A standby learns from the coordinator's first word which participant
    /// it follows; a coordinator that reads the scene learns from any word of its standby's (which writes
    /// none while it stands by) that the standby started the world instead of it (check_not_replaced).
    std::unique_ptr<dds::Reader<wire::ClusterStatus>> status_in;
    std::unique_ptr<dds::LivelinessBeat> go_beat;     ///< keeps its frame starts' lease
    std::unique_ptr<dds::LivelinessBeat> acks_beat;   ///< keeps its acknowledgements' lease, as a standby
    std::unique_ptr<dds::LivelinessBeat> marks_beat;  ///< keeps its marks' lease (as worker 0)

    std::uint32_t term = 1;
    /// Following another coordinator (options.standby, until it takes over).
    bool standing_by = false;
    std::optional<dds::fdds::InstanceHandle_t> primary_writer;  ///< the followed coordinator's frame starts
    bool primary_lost = false;                                  ///< their liveliness lapsed (confirmed)
    /// The followed coordinator's participant (its writers' GUID prefix), from its status: before frame 1
    /// no frame start has named its writer, and the lapse of any of its leased writers is its end.
    std::optional<dds::ParticipantPrefix> primary_participant;
    /// Whether a lapse (or a return) reported for `writer` is the followed coordinator's.
    bool is_primary(const dds::fdds::InstanceHandle_t& writer) const {
        if (primary_writer) return writer == *primary_writer;
        return standing_by && primary_participant && dds::participant_of(writer) == *primary_participant;
    }
    /// Status writers matched when the coordinator's status came: fewer, and its participant is gone.
    int status_writers = 0;
    /// As a standby before frame 1: the participants whose leased writers were heard alive. Only a writer
    /// heard alive is heard to lapse: the standby says once that it would notice the coordinator's end.
    std::set<dds::ParticipantPrefix> heard_alive_before_frame_1;
    bool said_it_follows = false;
    /// As a standby: said that the coordinator's lease lapsed while it sent the first state (and not yet
    /// that it came back).
    bool said_lapse_in_first_state = false;
    /// As a standby: some of the world's first state came (a sample of it, or the mark that lists it).
    bool first_state_begun = false;
    bool standby_lost = false;  ///< the standby's acknowledgements' lapsed
    /// The sectors of the world's first state, from the coordinator's mark of frame 0 (as a standby).
    std::optional<std::vector<SectorKey>> first_state;
    /// Another coordinator started frames under a higher term: this one was taken over from.
    bool fenced = false;
    /// The standby the frames wait for (named in FrameGo); 0: none. Dropped when its lease runs out, and
    /// named again if the same writer comes back (a late beat on a loaded machine): it reads every start,
    /// and one that lost some while no frame waited for it says so and stops, never acknowledging again.
    std::uint32_t standby = 0;
    std::uint32_t dropped_standby = 0;                          ///< the one dropped, until it comes back
    std::optional<dds::fdds::InstanceHandle_t> standby_writer;  ///< its acknowledgements' writer
    std::uint64_t standby_acked = 0;                            ///< the latest frame it acknowledged
    wire::FrameGo last_go;  ///< the latest written: written again without a standby that is gone
    /// Marks of frames a coordinator wrote sector samples for (worker 0's), as a standby learns them.
    std::set<std::uint64_t> primary_wrote;
    /// Commands read while standing by, in the order read, until the coordinator applies (FrameGo) or
    /// refuses (its answer) them: those left when it takes over are its to accept or refuse.
    StandingCommands standing_commands;
    std::uint64_t followed_order = 0;  ///< the highest command sequence number a followed start carried

    /// Every body's id, and whether it is static: what commands are checked against. Bodies come and go
    /// through the coordinator only (the scene, spawns, removals), so this is always exact.
    std::unordered_map<BodyId, bool> statics;
    std::map<BodyId, BodyDesc> planes;
    /// Each plane's description as the coordinator wrote it (or its standby read it). Durable samples live in
    /// their writer: a standby that takes over writes them again, or a worker joining later waits for ever
    /// for the planes the starts count (seen: tests/tools/takeover_during_hold.sh).
    std::map<BodyId, wire::BodyDescription> plane_descriptions;
    /// The world as the workers last published it (plus in-flight handoffs): what a worker that is gone
    /// leaves behind, restored to the workers that take its sectors over.
    dds::SectorMirror mirror;
    /// The sector samples read, checked and queued by frame until take_samples applies them to the mirror.
    dds::SampleIntake intake{"coordinator", "lpss-coordinator"};  ///< named with its id by create()
    std::uint64_t next_whole_request = 1;
    /// Asks the sectors' owners for the sectors whose partial samples came without their base (lost on a
    /// loaded machine): until a whole sample comes the mirror holds them stale, and a worker gone meanwhile
    /// would be restored from them.
    void ask_for_whole_sectors();

    SectorAssignment current;
    SectorAssignment next;
    double largest_radius = 0.0;  ///< of any body the world has held: how far bodies reach (border_reach)
    std::set<std::uint32_t> live;
    std::map<std::pair<std::uint32_t, std::uint64_t>, wire::WorkerFrame> marks;
    std::map<std::uint32_t, Clock::time_point> last_heard;
    std::map<dds::fdds::InstanceHandle_t, std::uint32_t> writer_of;  ///< marks writer -> its worker
    /// Each worker id's marks writer heard from last (a worker restarted under an id writes with another).
    std::map<std::uint32_t, dds::fdds::InstanceHandle_t> newest_writer;
    /// Each worker's marks writer that runs its frames (its hello at the start, then its marks of frames):
    /// a worker restarted under the id of one that is gone writes with another, whose ask to join must not
    /// be taken for the old one's liveliness, nor the old one's lapse for the new one's.
    std::map<std::uint32_t, dds::fdds::InstanceHandle_t> running_writer;
    std::set<std::uint32_t> lost;  ///< workers whose running writer's liveliness lease expired (confirmed)
    /// Lapses reported and not yet confirmed, by writer: workers' marks, the followed coordinator's frame
    /// starts (primary_writer), the standby's acknowledgements (standby_writer).
    dds::ConfirmedLapses<dds::fdds::InstanceHandle_t> lapses;
    /// When each was found lost (system clock, ns, as DDS source timestamps), and its marks' writer then: a
    /// mark that writer wrote later shows it alive, should DDS not say so (seen: a standby stopped past the
    /// leases found a worker lost on waking, and never heard it was back, though its marks kept coming; at
    /// takeover it took that worker as gone). Another writer of the same id is a worker restarted under it:
    /// its hello says nothing of the one that was lost.
    struct Lapse {
        dds::fdds::InstanceHandle_t writer;
        std::int64_t at_ns = 0;
        /// The frame this coordinator was at (a standby: the last start it followed).
        std::uint64_t frame = 0;
    };
    std::map<std::uint32_t, Lapse> lost_since;
    /// The worker is not (or no longer) taken as lost: its lapse is over, or was another writer's.
    void forget_lapse(std::uint32_t w) {
        lost.erase(w);
        lost_since.erase(w);
    }
    /// A lapse under w's id of another writer than `writer` was its old self's: w was started again.
    void forget_lapse_of_another(std::uint32_t w, const dds::fdds::InstanceHandle_t& writer) {
        if (auto since = lost_since.find(w); since != lost_since.end() && since->second.writer != writer)
            forget_lapse(w);
    }
    std::uint64_t started_without_standby = 0;  ///< a standby: the last frame started without waiting for it
    /// Workers that came to the running cluster (new, or restarted under the id of one gone) and asked to
    /// join; then, once given sectors, the frame from which they are live.
    std::set<std::uint32_t> joining;
    /// Each joiner's reader of sector frames; and, from each worker's latest mark, the joiners whose reader
    /// its sector writer has matched. A joiner is admitted once every worker and this coordinator reach it:
    /// what is written before a writer matches a reader never reaches it.
    std::map<std::uint32_t, dds::GuidBytes> joiner_readers;
    std::map<std::uint32_t, std::set<std::uint32_t>> reaching;
    std::map<std::uint32_t, Clock::time_point> joining_since;
    /// The workers that do not reach this joiner yet (0 stands for the coordinator); empty once all do.
    std::vector<std::uint32_t> not_reaching(std::uint32_t joiner) const;
    std::map<std::uint32_t, std::uint64_t> admitted;
    /// Live workers whose id a newly started worker asks to join under: their old selves are gone.
    std::set<std::uint32_t> restarted;
    /// The workers sectors can go to: the live ones and those admitted.
    std::set<std::uint32_t> members() const {
        std::set<std::uint32_t> out = live;
        for (const auto& [w, from] : admitted)
            out.insert(w);
        return out;
    }
    /// Gives the workers that asked to join sectors from frame f + 2 (their owners send them whole at f + 1).
    void admit(std::uint64_t f);
    /// The load of each block with bodies, as its owner last reported it. A worker's report replaces what
    /// it reported before: a block it no longer reports has emptied, or another worker reports it.
    struct ReportedLoad {
        float load = 0.0f;
        std::uint32_t worker = 0;
    };
    std::map<SectorKey, ReportedLoad> block_loads;
    std::vector<wire::Handoff> grants;          ///< for the next frame
    std::vector<wire::Handoff> in_flight;       ///< granted with the last frame started
    std::vector<wire::Handoff> stood_in;        ///< requests of a gone worker's lost frame, stepped here
    std::set<std::uint32_t> gone_after_ending;  ///< gone after ending the frame: its requests stand
    std::vector<wire::Command> commands;        ///< accepted, for the next frame
    std::vector<std::uint64_t> command_order;
    std::vector<wire::Command> commands_in_flight;  ///< sent with the last frame started
    std::vector<std::uint64_t> command_order_in_flight;
    std::set<std::string> ready_clients;  ///< clients that matched every topic they read
    CommandRate command_rate{0.0};
    std::uint64_t next_order = 1;
    std::uint64_t frame = 0;
    std::uint64_t handoffs = 0;
    bool wrote_sectors = false;  ///< for the frame before the next: its FrameGo says so
    std::vector<std::uint32_t> ended;
    Clock::time_point frame_started;

    void status(const std::string& phase, double progress, std::uint64_t bodies);
    Status load_and_seed(const std::atomic<bool>& stop);
    /// While it loads, as the coordinator started as one: an error (and `fenced`) once its standby has
    /// started the world instead (its lease lapsed while it read the scene: it was stopped or cut off).
    Status check_not_replaced();
    /// Takes what has come: the workers' marks, liveliness changes, other coordinators' words and, unless
    /// `with_samples` is false, sector samples (take_sector_samples).
    void pump(bool with_samples = true);
    /// Takes the sector samples that have come (at most `at_most`), each checked and queued for its frame
    /// (take_sample), and asks for the sectors wanted whole. Returns how many were taken.
    int take_sector_samples(std::uint64_t at_most = ~std::uint64_t{0});
    /// Waits, at most `patience`, until the standby (if one is named) acknowledges frame f's start.
    void await_acknowledgement(std::uint64_t f, std::chrono::microseconds patience);
    /// A sector sample read: checked, then queued for its frame (or refused, or held until its epoch is
    /// known, or its sector wanted whole: dds::SampleIntake).
    void take_sample(wire::SectorFrame f);
    /// Applies the samples received up to a frame (and `also`, of that frame) to the copy of the world.
    void take_samples(std::uint64_t up_to, const std::vector<wire::SectorFrame>& also = {});
    /// A complete sample of a sector as the copy of the world holds it, as worker 0.
    wire::SectorFrame whole_from_mirror(const SectorKey& key, std::uint64_t f) const;
    /// Takes a worker as gone now; what it leaves is restored once the frame has ended (restore_gone).
    void take_as_gone(std::uint32_t w, const char* why);
    /// Workers taken as gone during the frame being waited for: why, and how far into the frame.
    struct Going {
        const char* why = "";
        double into_frame = 0.0;
    };
    std::map<std::uint32_t, Going> going;
    bool last_lapse_noted = false;  ///< the last live worker's lapse was logged (once)
    /// Sends sectors as of frame f, whole, to their holders under `fresh`, with a mark that stands for the
    /// `gone` workers' marks of f.
    void send_restored(std::uint64_t f, const SectorAssignment& fresh, const std::set<SectorKey>& keys,
                       const std::vector<std::uint32_t>& gone, Clock::time_point started);
    void accept_commands();
    /// A command read from a client: the commands lost before it are refused (refuse_lost), then it is
    /// decided.
    void accept(const wire::Command& c);
    /// Accepts one command for the next frame, or refuses it with the reason.
    void decide(const wire::Command& c);
    /// The body set as a command another coordinator applied changes it (spawn, removal), for a standby.
    void follow_bodies(const wire::Command& c);
    /// Standing by: follows the coordinator until it is gone, then takes over. The frame of the coordinator's
    /// last start it holds (run() goes on from its end); 0: the cluster stopped or `stop` was set;
    /// kStartTheWorld: the coordinator went before it sent any of the world (start_instead).
    Expected<std::uint64_t> follow(const std::atomic<bool>& stop);
    static constexpr std::uint64_t kStartTheWorld = ~std::uint64_t{0};
    /// No longer standing by: this coordinator runs the frames (take_over, start_instead).
    void lead();
    void take_over(const wire::FrameGo& last);
    /// Commands read while standing by, neither applied nor answered by the coordinator that went: this
    /// one's now, accepted or refused in the order read. Returns how many.
    std::size_t decide_standing_commands();
    /// The coordinator went while it read the scene, before any worker had a word of the world: this standby
    /// becomes the coordinator, under the next term, and run() loads the scene as the coordinator would have.
    void start_instead();
    /// A standby forgets the lapses of workers that a frame start says ended a frame begun after them.
    void forget_lapses_outlived(const wire::FrameGo& go);
    /// Writes a FrameAck (as a standby).
    void acknowledge(std::uint64_t frame);
    /// Reads the other coordinator's frame starts and a standby's acknowledgements (the coordinator's part).
    void watch_coordinators();
    /// Answers `c` refused; `first_request` (not 0): the answer stands for every request of its client from
    /// there to c's.
    void refuse(const wire::Command& c, const std::string& reason, std::uint64_t first_request = 0);
    /// The run of commands refused for their client's rate, not answered yet: one answer for all.
    struct OverRate {
        wire::Command last;
        std::uint64_t first_request = 0;
    };
    std::optional<OverRate> over_rate;
    void answer_over_rate();
    /// A client's commands travel in one DDS instance, its last kCommandDelivery.depth kept: with more in
    /// flight at once, the oldest are lost on the way. Those skipped before `c` are refused, named, so
    /// that no command goes without an answer.
    void refuse_lost(const wire::Command& c);
    std::unordered_map<std::string, std::uint64_t> last_request;  ///< by client: the newest request read
    bool wait_for_frame(std::uint64_t f, const std::atomic<bool>& stop);
    void collect_handoffs(std::uint64_t f);
    /// Once every live worker has ended frame f: the frames the workers taken as gone did not finish,
    /// stepped again here, and every sector they owned (or were to own from f + 1) sent whole to its
    /// holders under an assignment that gives their ranges to their neighbours on the curve, from f + 1.
    void restore_gone(std::uint64_t f);
    /// Every worker gone during frame f: the copy of the world holds every sector as last published, and
    /// waits (up to options.worker_wait) for a worker to join, restarted or new, to take them all. False if
    /// none comes, or on a stop.
    bool hold_until_a_worker_joins(std::uint64_t f, const std::atomic<bool>& stop);
    /// Frame f's start written again, under `epoch`, with the next assignment: how workers learn of an
    /// assignment made while no frame runs.
    void write_start_again(std::uint32_t epoch);
    /// The workers admitted by hold_until_a_worker_joins, which take every sector at once.
    std::set<std::uint32_t> held_for;
    SectorAssignment balanced(const std::set<std::uint32_t>& workers) const;
    std::map<std::uint32_t, double> worker_loads(const SectorAssignment& assignment) const;
    void reassign(SectorAssignment fresh, std::uint64_t from_frame, const char* why);
    SectorAssignment assignment_for(std::uint64_t f) const { return next.from_frame <= f ? next : current; }
    /// The next assignment as it goes on the wire, with this coordinator's id and term.
    wire::Assignment assignment_on_wire() const {
        wire::Assignment a = dds::to_wire(next, settings, largest_radius);
        a.coordinator(options.id);
        a.term(term);
        return a;
    }
    /// Announces `next`; the samples written under it that came before are taken in now.
    void publish_assignment();
    /// Frames go on without a standby that is gone (its lease lapsed): the latest start is written again
    /// without it, for the workers that wait for its word.
    void drop_standby();
    /// Whether every sector sample worker `w` lists in its mark of frame `f` is held (at f or later).
    bool holds_samples_of(std::uint32_t w, std::uint64_t f) const;
    /// The workers a sector's samples go to under `assignment`: the owners of the neighbouring sectors its
    /// bodies come near (as a worker decides for its own sectors).
    std::vector<std::uint32_t> recipients(const SectorKey& key, const std::vector<wire::BodyState>& bodies,
                                          const std::vector<double>& radii,
                                          const SectorAssignment& assignment) const;
};

}  // namespace lpss::coordinator
