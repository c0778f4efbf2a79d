// Whether a worker still hears a coordinator: the liveliness of the coordinators' frame start writers (the
// coordinator's, a standby's), and the frame starts they write. None alive, once some were, means the worker
// is cut off from them (a link down) or every coordinator is gone; a lapse counts only once confirmed
// (ConfirmedLapses), and what the writers did lately is kept for the log of a worker that takes itself as
// cut off. Where the frames named a standby, none alive counts only once the standby has had the time to
// take over and has not: Fast DDS 2.9 can lose a writer's coming alive outright (below).
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "lpss_dds/confirmed_lapses.hpp"
#include "lpss_dds/participant.hpp"
#include "lpss_dds/wall_clock.hpp"

namespace lpss::worker {

class CoordinatorWatch {
public:
    explicit CoordinatorWatch(std::uint32_t worker) : worker_(worker), began_ns_(dds::wall_clock_ns()) {}

    /// The liveliness changes the frame start reader reported since the last call, in order.
    void follow(const std::vector<dds::Inbox::Liveliness>& changes);
    /// A frame start a writer wrote (its DDS source timestamp, system clock ns): written since the writer's
    /// last confirmed lapse, it shows that writer alive.
    void heard(const dds::fdds::InstanceHandle_t& writer, std::int64_t written_ns);
    /// Whether the frame this worker runs named a standby that holds its start: one that takes over when the
    /// coordinator goes.
    void standby_follows(bool follows) { standby_follows_ = follows; }
    /// No coordinator's writer is alive, though one was; and if a standby followed, it has not taken over
    /// within `kTakeover` of the last lapse.
    bool cut_off() const;
    /// No coordinator's writer is alive, though one was (cut off, or waiting for a standby to take over).
    bool none_alive() const { return heard_any_ && none_counted(); }
    /// How long a standby may take to take over, counted from a worker's confirmed lapse of the coordinator:
    /// the standby confirms the same lapse within its grace (450 ms at most, ConfirmedLapses), then writes
    /// its first frame start. A cut-off worker learns it that much later, and publishes no degraded frame
    /// meanwhile (worker.cpp).
    static constexpr std::chrono::milliseconds kTakeover{1500};
    /// The latest liveliness news, for the log ("none" if there is none).
    std::string history() const;

private:
    using Clock = std::chrono::steady_clock;
    void note(const dds::fdds::InstanceHandle_t& writer, const char* what, std::int32_t alive_count);
    /// Neither the set nor the reader's count has a writer alive (a count the race below left one short
    /// goes below zero when the last writer lapses).
    bool none_counted() const { return alive_.empty() && alive_count_ <= 0; }

    std::uint32_t worker_;
    /// The writers taken as alive. A report that merged two writers' changes names one of them
    /// (Inbox::Liveliness): a standby's writer that became alive with the coordinator's was missing from the
    /// set, and the worker took itself as cut off when the coordinator died although it heard the standby
    /// take over. `alive_count_` says what the set may have missed.
    std::set<dds::fdds::InstanceHandle_t> alive_;
    /// How many of the coordinators' writers the frame start reader counts alive, by its last report.
    /// Neither the set nor the count can be trusted to hold every live writer: Fast DDS 2.9 adds a change
    /// into the reader's count unlocked (WLP::update_liveliness_changed_status, on each receive thread), so
    /// two writers coming alive at once can leave a count of one and one report. Seen in CI: a worker heard
    /// the coordinator alive and never its standby, took itself as cut off when the coordinator was killed,
    /// and cost the world 5 s. The standby's DDS liveliness, alive from then on, reports nothing more: its
    /// frame starts (heard) are what shows it.
    std::int32_t alive_count_ = 0;
    dds::ConfirmedLapses<dds::fdds::InstanceHandle_t> lapses_;
    bool heard_any_ = false;
    bool standby_follows_ = false;
    /// Since when none is alive (none_counted), by the last `follow`.
    Clock::time_point none_alive_since_{};
    /// When this watch began, and when each writer's last lapse was confirmed (system clock, ns): frame
    /// starts written before are history, not a coordinator heard.
    std::int64_t began_ns_;
    std::map<dds::fdds::InstanceHandle_t, std::int64_t> lapsed_at_ns_;
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
