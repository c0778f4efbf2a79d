// lpss::Client: reads an lpss world over DDS, whole or a region, in double-precision global coordinates,
// one consistent frame at a time, and sends commands. No DDS types here: link lpss::client and include
// this header.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "lpss/common/body_desc.hpp"
#include "lpss/common/expected.hpp"
#include "lpss/common/sector_grid.hpp"
#include "lpss/common/world_settings.hpp"

namespace lpss {

/// Sectors with indices in [lo, hi] on each axis.
struct Region {
    SectorKey lo;
    SectorKey hi;
    bool contains(const SectorKey& k) const {
        return k.i >= lo.i && k.i <= hi.i && k.j >= lo.j && k.j <= hi.j && k.k >= lo.k && k.k <= hi.k;
    }
};

/// Parses "i_lo,i_hi,j_lo,j_hi,k_lo,k_hi" (the --region option of the client programs); the error says what
/// is wrong.
Expected<Region> parse_region(const std::string& text);

/// What each frame a client returns holds.
enum class FrameContent {
    /// Every body of the region: simple, and costs per frame what the region holds; a client that fell N
    /// frames behind gets N views of its whole region from one poll (for a large world, take changes).
    every_body,
    changes,  ///< what changed since the frame before (the first frame: every body); costs what moves
};

struct ClientOptions {
    int domain = 0;
    std::string profile;  ///< Fast DDS XML profile; empty: the built-in local one
    /// DDS Security identity folder (deploy/security/identities.sh: an observer's, or an operator's to send
    /// commands); empty: none, and a secured cluster is then out of reach.
    std::string security;
    std::string name = "client";   ///< names this client's commands
    std::optional<Region> region;  ///< follow only these sectors (filtered by DDS); the whole world if empty
    FrameContent content = FrameContent::every_body;
};

/// One body in a frame.
struct BodyView {
    BodyId id = 0;
    SectorPosition position;  ///< exact
    Eigen::Vector3d global = Eigen::Vector3d::Zero();
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
    Eigen::Vector3d linear_velocity = Eigen::Vector3d::Zero();
    Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();
    bool awake = false;
    std::uint32_t worker = 0;  ///< the worker that owns its sector in this frame (0 for planes)
};

/// A body that crossed into a sector of another worker, as the worker it left reported it.
struct HandoffView {
    BodyId body = 0;
    std::uint32_t from_worker = 0;
    std::uint32_t to_worker = 0;
    SectorKey sector;         ///< the sector it entered
    std::uint64_t frame = 0;  ///< the frame it crossed at
};

/// What a worker reported at the end of a frame (its whole share, not only the region followed).
struct WorkerView {
    std::uint32_t id = 0;
    std::uint32_t sectors = 0;  ///< sectors it owns that hold bodies
    std::uint32_t bodies = 0;
    std::uint32_t awake = 0;
    std::uint32_t ghosts = 0;  ///< other workers' bodies it holds next to its sectors
    std::uint32_t clones = 0;  ///< copies of bodies near borders in the neighbouring sectors' worlds
    float step_ms = 0.0f;      ///< its engine time for the frame
};

/// A frame: every body of the region, ordered by id; or, with FrameContent::changes, the bodies that
/// moved, woke, fell asleep or arrived since the frame returned before (ordered by id; maybe a few that did
/// not change) and the ids of those that left the region or the world.
struct WorldFrame {
    std::uint64_t frame = 0;
    std::vector<BodyView> bodies;  ///< in id order, planes among them
    std::vector<BodyId> departed;  ///< with FrameContent::changes: gone since the frame before
    bool every_body = true;        ///< `bodies` holds every body of the region (a first frame of changes)
    /// When the coordinator started the frame (wall clock): frames of a --realtime cluster come dt apart,
    /// and a pause shows as a longer gap.
    std::chrono::system_clock::time_point started{};
    /// Seconds of real time a --realtime cluster has let go so far: after a pause (a worker gone, a slow
    /// frame) it goes on at the scene's rate from where it is instead of catching up in a burst.
    double time_lost_s = 0.0;
    /// Handoffs reported in the frames since the frame returned before (this one included), of bodies
    /// entering sectors this client follows.
    std::vector<HandoffView> handoffs;
    /// Every worker of the assignment in force, as it reported this frame.
    std::vector<WorkerView> workers;
};

/// What following the world has cost a client so far.
struct ClientStats {
    /// Syncs: the first, then one for each time it fell behind (lost frame marks) and asked the workers for
    /// the inventories of its sectors again.
    std::uint64_t syncs = 0;
    /// Bodies received in complete sector samples (answers to inventories, sectors asked for whole, a
    /// sector's first sample from a new owner): what a sync costs grows with it.
    std::uint64_t bodies_in_complete_samples = 0;
};

/// What became of a command.
struct CommandOutcome {
    bool applied = false;
    std::uint64_t order = 0;  ///< the order commands are applied in, across all clients
    std::uint64_t frame = 0;  ///< the frame it was applied at (or would have been)
    std::string reason;       ///< why it was refused
};

class Client {
public:
    /// Joins the domain. Refused with the reason when the profile is unreadable or DDS cannot start.
    static Expected<std::unique_ptr<Client>> connect(const ClientOptions& options);
    ~Client();

    /// Waits up to `limit` for a running cluster (its sector assignment), and for this client's commands to
    /// reach the coordinator and the results to come back from it and every worker (commands are not
    /// kept for late readers: one sent before that is lost). False if no cluster appeared; true also when
    /// the limit came before the commands could reach it (reaches_cluster() tells).
    bool wait_for_cluster(std::chrono::milliseconds limit);
    /// Whether this client's commands reach the coordinator and the results come back from it and every
    /// worker of the assignment it knows (what wait_for_cluster waits for), as of the last wait or poll.
    bool reaches_cluster() const;
    /// Takes what arrived, waiting up to `wait` for it, and returns every frame that became complete, in
    /// order (also passed to the on_frame callback). Call it at least every two seconds (120 frames at
    /// 60 Hz): a client polled less often has lost frame marks and asks the workers for its sectors again.
    std::vector<WorldFrame> poll(std::chrono::milliseconds wait = std::chrono::milliseconds(0));
    /// Called from poll() with each complete frame.
    void on_frame(std::function<void(const WorldFrame&)> callback);
    /// The newest complete frame, if any.
    const std::optional<WorldFrame>& latest() const;
    /// What a body is (shape, mass, material), from the cluster's durable descriptions.
    std::optional<BodyDesc> description(BodyId id) const;
    /// What a body of the latest frame is, found in its sector: cheap enough to call for every body.
    std::optional<BodyDesc> description(const BodyView& body) const;
    /// The grid of the world (its sector size), once a cluster is seen.
    std::optional<SectorGrid> grid() const;
    /// The world's settings (sector size, step, gravity, where it is on the Earth), once a cluster is seen.
    std::optional<WorldSettings> settings() const;
    /// The region this client follows, if it follows one.
    const std::optional<Region>& region() const;
    /// What following the world has cost so far (as of the last poll).
    ClientStats stats() const;
    /// The world's last frame, once the coordinator running it has said it stopped there (its frames ran
    /// out, or it was stopped), as of the last poll: no frame after it comes. None while it runs, and none
    /// for a cluster that vanished (killed, cut off): that one only falls silent.
    std::optional<std::uint64_t> stopped_after() const;

    /// Commands: each returns a request number; outcome() tells what became of it (the newest 4,096
    /// outcomes are kept).
    std::uint64_t spawn(const BodyDesc& body);
    std::uint64_t remove(BodyId id);
    std::uint64_t apply_impulse(BodyId id, const Eigen::Vector3d& impulse,
                                const Eigen::Vector3d& offset = Eigen::Vector3d::Zero());
    std::uint64_t set_velocity(BodyId id, const Eigen::Vector3d& linear, const Eigen::Vector3d& angular);
    std::optional<CommandOutcome> outcome(std::uint64_t request) const;
    /// Polls until the outcome of `request` arrives or `limit` passes.
    std::optional<CommandOutcome> wait_outcome(std::uint64_t request, std::chrono::milliseconds limit);

    struct State;

private:
    explicit Client(std::unique_ptr<State> state);
    std::unique_ptr<State> state_;
};

}  // namespace lpss
