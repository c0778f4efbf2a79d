// Whether a worker still hears a coordinator: the liveliness of the coordinators' frame start writers (the
// coordinator's, a standby's). None alive, once some were, means the worker is cut off from them (a link
// down) or every coordinator is gone; a lapse counts only once confirmed (ConfirmedLapses), and what the
// writers did lately is kept for the log of a worker that takes itself as cut off.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <set>
#include <string>
#include <vector>

#include "lpss_dds/confirmed_lapses.hpp"
#include "lpss_dds/participant.hpp"

namespace lpss::worker {

class CoordinatorWatch {
public:
    explicit CoordinatorWatch(std::uint32_t worker) : worker_(worker) {}

    /// The liveliness changes the frame start reader reported since the last call, in order.
    void follow(const std::vector<dds::Inbox::Liveliness>& changes);
    /// A frame start a writer wrote (its DDS source timestamp, ns): it shows that writer alive.
    void heard(const dds::fdds::InstanceHandle_t& writer, std::int64_t written_ns) {
        lapses_.heard(writer, written_ns);
    }
    /// Some coordinator's writer was alive once, and none is now.
    bool cut_off() const { return heard_any_ && alive_.empty() && alive_count_ == 0; }
    /// The latest liveliness news, for the log ("none" if there is none).
    std::string history() const;

private:
    using Clock = std::chrono::steady_clock;
    void note(const dds::fdds::InstanceHandle_t& writer, const char* what, std::int32_t alive_count);

    std::uint32_t worker_;
    /// The writers taken as alive. A report that merged two writers' changes names one of them
    /// (Inbox::Liveliness): a standby's writer that became alive with the coordinator's was missing from the
    /// set, and the worker took itself as cut off when the coordinator died although it heard the standby
    /// take over. `alive_count_` says what the set may have missed.
    std::set<dds::fdds::InstanceHandle_t> alive_;
    /// How many of the coordinators' writers the frame start reader counts alive, by its last report.
    std::int32_t alive_count_ = 0;
    dds::ConfirmedLapses<dds::fdds::InstanceHandle_t> lapses_;
    bool heard_any_ = false;
    /// Under AddressSanitizer a worker took itself as cut off as a standby took over, and its log could not
    /// say why: the last few changes are kept.
    struct News {
        Clock::time_point at;
        std::size_t writer;  ///< in the order first heard of: 1, 2, ...
        const char* what;
        std::int32_t alive_count;
    };
    std::deque<News> news_;
    std::vector<dds::fdds::InstanceHandle_t> writers_;  ///< by the numbers in news_
};

}  // namespace lpss::worker
