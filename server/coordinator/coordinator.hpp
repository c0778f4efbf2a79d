// The coordinator: loads the scene, assigns sectors to workers (ranges of the Morton curve of blocks,
// balanced by load, with an epoch), starts every frame, arbitrates handoffs so that every body has
// exactly one owner in every frame, orders clients' commands, and moves sectors between workers when the
// load shifts or a worker stops answering. A second one may stand by (standby.cpp) and take over.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>

#include "lpss/common/expected.hpp"

namespace lpss::coordinator {

struct CoordinatorOptions {
    std::string scene_path;
    int domain = 0;
    std::string profile;   ///< Fast DDS XML profile; empty: the built-in local one
    std::string security;  ///< DDS Security identity folder (a coordinator's); empty: none
    std::uint32_t workers = 1;
    std::uint64_t frames = 0;  ///< stop after this many frames; 0: run until stopped
    bool realtime = false;     ///< pace frames at the scene's dt; otherwise as fast as the workers go
    std::int64_t block_size = 4;
    std::uint64_t rebalance_every = 300;  ///< frames between load checks; 0: never move sectors
    double rebalance_threshold = 1.5;  ///< move sectors when the busiest worker has this times the mean load
    std::chrono::milliseconds worker_wait{30000};    ///< for the workers to appear
    std::chrono::milliseconds worker_timeout{5000};  ///< silence after which a worker is taken as gone
    /// Frame 1 waits until this many clients (by name) have said they matched every topic they read: a
    /// synchronization point, as HLA federations have, so that recorders miss nothing.
    std::uint32_t await_clients = 0;
    /// Commands a second one client may send (bursts of as many); beyond, each is refused with the reason.
    /// 0: no limit.
    double command_rate = 1000.0;
    /// This coordinator's id (its FrameGo's key): 1 for the one that starts the world, another for a standby.
    std::uint32_t id = 1;
    /// Stand by: follow the coordinator that runs the world (hold its world copy, acknowledge each frame it
    /// starts), and take over, with a higher term, when its liveliness lease runs out.
    bool standby = false;
    /// Frame 1 waits until a standby coordinator follows the world; from then on, each frame waits until
    /// the standby holds its start.
    bool await_standby = false;
    /// How long frame 1 waits for the standby's hello (await_standby): a standby gone before its hello
    /// reached this coordinator is never heard, and the world then starts without one.
    std::chrono::milliseconds standby_wait{20000};
};

class Coordinator {
public:
    /// Joins the domain; refused with the reason. The scene is loaded by run(), which shows its progress.
    static Expected<std::unique_ptr<Coordinator>> create(const CoordinatorOptions& options);
    ~Coordinator();
    /// Runs the cluster until the frames are done or `stop` is set. Returns the process exit code.
    int run(const std::atomic<bool>& stop);

    struct State;

private:
    explicit Coordinator(std::unique_ptr<State> state);
    std::unique_ptr<State> state_;
};

}  // namespace lpss::coordinator
