#include "coordinator_watch.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

namespace lpss::worker {

void CoordinatorWatch::note(const dds::fdds::InstanceHandle_t& writer, const char* what,
                            std::int32_t alive_count) {
    auto known = std::find(writers_.begin(), writers_.end(), writer);
    if (known == writers_.end()) known = writers_.insert(known, writer);
    const auto number = static_cast<std::size_t>(known - writers_.begin()) + 1;
    news_.push_back({Clock::now(), number, what, alive_count});
    if (news_.size() > 12) news_.pop_front();
}

void CoordinatorWatch::follow(const std::vector<dds::Inbox::Liveliness>& changes) {
    const auto now = Clock::now();
    const bool none_before = none_counted();
    for (const dds::Inbox::Liveliness& change : changes) {
        note(change.writer, change.alive ? "alive" : (change.merged ? "lapsed (merged)" : "lapsed"),
             change.alive_count);
        lapses_.reported(change.writer, change.alive, now);
        if (change.merged)
            spdlog::info("worker {}: one liveliness report of two coordinators' writers ({} alive now)",
                         worker_, change.alive_count);
        if (change.alive || change.alive_count > 0) heard_any_ = true;
        // A writer that lapsed while its coming alive went unreported was alive all the same: in the set, it
        // gets the grace of any lapse (ConfirmedLapses) before the worker can count itself cut off.
        if (change.alive || change.alive_count < alive_count_) alive_.insert(change.writer);
        alive_count_ = change.alive_count;
    }
    for (const dds::fdds::InstanceHandle_t& writer : lapses_.confirmed(now)) {
        note(writer, "lapse confirmed", alive_count_);
        alive_.erase(writer);
        lapsed_at_ns_[writer] = dds::wall_clock_ns();
    }
    if (!none_before && none_counted()) none_alive_since_ = now;
}

void CoordinatorWatch::heard(const dds::fdds::InstanceHandle_t& writer, std::int64_t written_ns) {
    lapses_.heard(writer, written_ns);
    // A frame start written since this watch began and since the writer's last confirmed lapse: a
    // coordinator speaks (a standby that took over, or one heard again once a link came back), whatever
    // its DDS liveliness said or did not say. Counted as it comes, even before the old coordinator's lapse
    // is confirmed: a standby's first starts can come first.
    auto lapsed = lapsed_at_ns_.find(writer);
    const std::int64_t after = std::max(began_ns_, lapsed == lapsed_at_ns_.end() ? 0 : lapsed->second);
    if (written_ns > after && alive_.insert(writer).second) note(writer, "heard writing", alive_count_);
}

bool CoordinatorWatch::cut_off() const {
    return none_alive() && (!standby_follows_ || Clock::now() - none_alive_since_ >= kTakeover);
}

std::string CoordinatorWatch::history() const {
    std::string out;
    const auto now = Clock::now();
    for (const News& n : news_) {
        out +=
            fmt::format("{}{:.3f} s ago, coordinators' writer {} {} ({} alive)", out.empty() ? "" : "; ",
                        std::chrono::duration<double>(now - n.at).count(), n.writer, n.what, n.alive_count);
    }
    return out.empty() ? "none" : out;
}

}  // namespace lpss::worker
