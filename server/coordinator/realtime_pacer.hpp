// Starts frames at the scene's rate. After a pause (a worker gone, a slow frame, a coordinator taken over)
// it goes on at that rate from where it is, rather than starting frames back to back until it has caught
// up on the wall time lost: a burst of frames would be a burst of motion for anyone watching in real time.
// A lag of a few frames is made up (jitter), more is let go, logged, and counted.
#pragma once

#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdint>
#include <thread>

namespace lpss::coordinator {

class RealtimePacer {
public:
    using Clock = std::chrono::steady_clock;

    /// Frame `first` is due at `start`; `lost`: seconds let go before (a coordinator that took over).
    RealtimePacer(Clock::time_point start, double dt, std::uint64_t first = 1, double lost = 0.0)
        : origin_(start), dt_(dt), first_(first), lost_(lost) {}
    void pace(std::uint64_t frame) {
        const auto due = origin_ + std::chrono::duration_cast<Clock::duration>(
                                       std::chrono::duration<double>(double(frame - first_) * dt_));
        const auto now = Clock::now();
        const double late = std::chrono::duration<double>(now - due).count();
        if (late <= kCatchUpFrames * dt_) {
            std::this_thread::sleep_until(due);
            return;
        }
        lost_ += late;
        origin_ = now;
        first_ = frame;
        if (late > 0.1)
            spdlog::warn(
                "coordinator: frame {} starts {:.2f} s late; real time goes on from here ({:.2f} s "
                "lost in all)",
                frame, late, lost_);
    }
    /// Seconds of real time let go so far.
    double lost() const { return lost_; }

private:
    static constexpr double kCatchUpFrames = 3.0;
    Clock::time_point origin_;
    double dt_;
    std::uint64_t first_ = 1;
    double lost_ = 0.0;
};

}  // namespace lpss::coordinator
