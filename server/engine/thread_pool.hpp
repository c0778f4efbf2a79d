// A small fork-join pool: the calling thread and threads-1 workers share the indices of one task.
// Each index runs exactly once, on the worker whose number is passed along, so per-worker scratch
// (a Bullet solver) is never used by two threads at once.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace lpss::engine {

class ThreadPool {
public:
    /// threads >= 1; the caller is worker 0.
    explicit ThreadPool(int threads);
    ~ThreadPool();
    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    int size() const { return static_cast<int>(workers_.size()) + 1; }

    /// Runs task(index, worker) for every index in [0, count) and returns when all have run.
    void run(std::size_t count, const std::function<void(std::size_t, int)>& task);

private:
    void work(int worker);
    void drain(int worker);

    std::vector<std::thread> workers_;
    std::mutex mutex_;
    std::condition_variable wake_;
    std::condition_variable done_;
    const std::function<void(std::size_t, int)>* task_ = nullptr;
    std::size_t count_ = 0;
    std::atomic<std::size_t> next_{0};
    std::size_t generation_ = 0;
    int busy_ = 0;
    bool stopping_ = false;
};

}  // namespace lpss::engine
