// Liveliness lapses as Fast DDS 2.9 reports them, confirmed before they count: a writer reported not alive
// is taken as lost only if it is not alive again within a grace of a beat or so. Why: with several writers
// under one lease, a participant's LivelinessManager at times reports a live writer lost in the instant a
// dead one's lease runs out (its timer, restarted from an interval computed before the live writer's last
// beat, fires for it, and timer_expired does not look at the time); that writer's next beat makes it alive
// again. Seen: a standby taking over took a live worker as gone in the same millisecond as the dead one.
// Such a false report comes right after a real one (the timer fires for the dead writer, then marks the
// writer an assertion has just made its next owner): a lapse reported within moments of another is given a
// longer grace, which a real second death (two processes killed together) pays in time to be found.
#pragma once

#include <chrono>
#include <map>
#include <vector>

namespace lpss::coordinator {

template <class Key>
class ConfirmedLapses {
public:
    using Clock = std::chrono::steady_clock;

    ConfirmedLapses(Clock::duration grace, Clock::duration correlated_grace)
        : grace_(grace), correlated_grace_(correlated_grace) {}

    /// What DDS said of a writer: alive again (forgets a suspicion), or not alive (suspected from now;
    /// `correlated`: reported within moments of another writer's lapse, given the longer grace).
    void reported(const Key& key, bool alive, Clock::time_point now, bool correlated = false) {
        if (alive) {
            suspected_.erase(key);
        } else {
            suspected_.emplace(key, now + (correlated ? correlated_grace_ : grace_));
        }
    }
    /// The writers not alive again within the grace, each once: they count as lost from now.
    std::vector<Key> confirmed(Clock::time_point now) {
        std::vector<Key> out;
        for (auto it = suspected_.begin(); it != suspected_.end();) {
            if (now < it->second) {
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
    std::map<Key, Clock::time_point> suspected_;  ///< until when each is given to come back
};

}  // namespace lpss::coordinator
