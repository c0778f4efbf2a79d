// Liveliness lapses as Fast DDS 2.9 reports them, confirmed before they count: a writer reported not alive
// is taken as lost only if it is not alive again within a grace of a few beats. Why: with several writers
// under one lease, a participant's LivelinessManager at times reports a live writer lost in the instant a
// dead one's lease runs out (its timer, fired for the dead writer, marks whichever writer an assertion has
// just made the timer's next owner, and timer_expired does not look at the time); that writer's next beat
// makes it alive again. Seen: a standby taking over took a live worker as gone in the same millisecond as
// the dead one. Such a false report comes right after a real one: a lapse reported within moments of
// another is given a longer grace, which a real second death (two processes killed together) pays in time
// to be found. One object per participant, for every writer whose lease its readers ask for: the reports
// it correlates come from that participant's one LivelinessManager.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <vector>

#include "lpss_dds/wall_clock.hpp"

namespace lpss::dds {

template <class Key>
class ConfirmedLapses {
public:
    using Clock = std::chrono::steady_clock;

    /// A lapse counts after `grace` (three beats: beat_period in topics.hpp); one reported within
    /// `correlated_within` of another writer's, after `correlated_grace`.
    explicit ConfirmedLapses(Clock::duration grace = std::chrono::milliseconds(150),
                             Clock::duration correlated_grace = std::chrono::milliseconds(450),
                             Clock::duration correlated_within = std::chrono::milliseconds(25))
        : grace_(grace), correlated_grace_(correlated_grace), correlated_within_(correlated_within) {}

    /// What DDS said of a writer: alive again (forgets a suspicion), or not alive (suspected from now).
    void reported(const Key& key, bool alive, Clock::time_point now) {
        if (alive) {
            suspected_.erase(key);
            return;
        }
        const bool correlated = reported_any_ && now - last_report_ < correlated_within_;
        reported_any_ = true;
        last_report_ = now;
        suspected_.emplace(key, Suspicion{now + (correlated ? correlated_grace_ : grace_), wall_clock_ns()});
    }
    /// Data the writer wrote (its DDS source timestamp, system clock ns): written after it was suspected, it
    /// shows the writer alive, should DDS's liveliness not say so in time (seen: a standby thawed from
    /// SIGSTOP took the coordinator as gone while it read the coordinator's newer frame starts).
    void heard(const Key& key, std::int64_t written_ns) {
        auto it = suspected_.find(key);
        if (it != suspected_.end() && written_ns > it->second.since_ns) suspected_.erase(it);
    }
    /// The writers not alive again within their grace, each once: they count as lost from now.
    std::vector<Key> confirmed(Clock::time_point now) {
        std::vector<Key> out;
        for (auto it = suspected_.begin(); it != suspected_.end();) {
            if (now < it->second.until) {
                ++it;
                continue;
            }
            out.push_back(it->first);
            it = suspected_.erase(it);
        }
        return out;
    }
    void forget(const Key& key) { suspected_.erase(key); }

private:
    Clock::duration grace_;
    Clock::duration correlated_grace_;
    Clock::duration correlated_within_;
    bool reported_any_ = false;
    Clock::time_point last_report_{};
    struct Suspicion {
        Clock::time_point until;  ///< given to come back until then
        std::int64_t since_ns;    ///< reported then (system clock, as DDS source timestamps)
    };
    std::map<Key, Suspicion> suspected_;
};

}  // namespace lpss::dds
