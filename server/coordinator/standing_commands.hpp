// The commands a standby coordinator has read and the coordinator it follows has neither applied nor
// answered: those left when it takes over are its own to accept or refuse, in the order read. A flood of
// commands must not cost it more than their number (it acknowledges every frame start, and frames wait for
// that): each is found by its client and request, not by a search.
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <set>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "lpss.h"

namespace lpss::coordinator {

class StandingCommands {
public:
    /// How many answers it remembers for commands not read yet (an answer can come before its command).
    static constexpr std::size_t kMostEarlyAnswers = 4096;

    /// A command read; ignored if its answer came first.
    void add(const wire::Command& c);
    /// Applied or answered by the coordinator followed, requests `first` to `last` of `client` (an answer
    /// can stand for a run of them): not this one's.
    void forget(const std::string& client, std::uint64_t first, std::uint64_t last);
    /// Those left, in the order read; none are kept.
    std::vector<wire::Command> take_all();
    /// The newest request read of each client: where the coordinator looks for gaps from, once it takes over.
    const std::unordered_map<std::string, std::uint64_t>& newest() const { return newest_; }
    std::size_t size() const { return by_order_.size(); }

private:
    using Key = std::pair<std::string, std::uint64_t>;
    std::uint64_t next_order_ = 0;
    std::map<std::uint64_t, wire::Command> by_order_;
    std::map<Key, std::uint64_t> order_of_;
    std::set<Key> answered_early_;
    std::deque<Key> answered_early_order_;  ///< oldest first, to bound answered_early_
    std::unordered_map<std::string, std::uint64_t> newest_;
    std::vector<std::uint64_t> standing_scratch_;  ///< forget's, kept to avoid allocation per answer
};

}  // namespace lpss::coordinator
