// A sector worker: runs the engine on the sectors the coordinator assigns it and keeps every other body
// as a ghost, updated from the other workers' sector frames, so that bodies near the border with another
// worker's sectors are cloned as in one process. Frames start when the coordinator says so and the
// previous frame's data of every other worker has arrived.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <set>
#include <string>

#include "lpss/common/expected.hpp"

namespace lpss::worker {

struct WorkerOptions {
    std::uint32_t id = 1;
    int domain = 0;
    std::string profile;   ///< Fast DDS XML profile; empty: the built-in local one
    std::string security;  ///< DDS Security identity folder (a worker's); empty: none
    int threads = 1;
    /// How long a frame waits for the other workers' data of the previous frame before it starts
    /// without it (logged as degraded).
    std::chrono::milliseconds border_wait{2000};
    /// How long to wait for a coordinator before giving up.
    std::chrono::milliseconds coordinator_wait{30000};
    /// DDS participant ids not to take: those of this process's earlier workers (see Participant::create).
    std::set<int> avoid_participant_ids;
};

/// What Worker::run returns when this worker is out of the cluster while it runs: the coordinator took it
/// as gone (it was stopped or starved past its lease), or it heard no coordinator for the lease (cut off).
/// It published nothing since; a fresh worker of the same id (a new DDS participant) may join again.
inline constexpr int kTakenAsGone = 5;

class Worker {
public:
    static Expected<std::unique_ptr<Worker>> create(const WorkerOptions& options);
    ~Worker();
    /// Runs until the coordinator stops the cluster, `stop` is set, or it is out of the cluster
    /// (kTakenAsGone). Returns the process exit code.
    int run(const std::atomic<bool>& stop);
    /// Its DDS participant id (-1 if Fast DDS chose it).
    int participant_id() const;

    struct State;

private:
    explicit Worker(std::unique_ptr<State> state);
    std::unique_ptr<State> state_;
};

}  // namespace lpss::worker
