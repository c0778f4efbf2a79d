#include "standing_commands.hpp"

#include <algorithm>

namespace lpss::coordinator {

void StandingCommands::add(const wire::Command& c) {
    std::uint64_t& newest = newest_[c.client()];
    newest = std::max(newest, c.request());
    Key key{c.client(), c.request()};
    if (answered_early_.erase(key) != 0) return;
    if (order_of_.count(key) != 0) return;  // read twice: once is enough
    order_of_.emplace(key, next_order_);
    by_order_.emplace(next_order_++, c);
}

void StandingCommands::forget(const std::string& client, std::uint64_t first, std::uint64_t last) {
    // The standing ones of the run, however long it is (a flood is answered in runs of thousands): found by
    // range, at a cost that follows the commands standing, not the run's length.
    const auto from = order_of_.lower_bound(Key{client, first});
    const auto to = order_of_.upper_bound(Key{client, last});
    standing_scratch_.clear();  // in increasing request order, as the map holds them
    for (auto it = from; it != to; ++it) {
        standing_scratch_.push_back(it->first.second);
        by_order_.erase(it->second);
    }
    order_of_.erase(from, to);
    // The others may come later: remembered as answered early, only the newest kMostEarlyAnswers.
    if (last - first >= kMostEarlyAnswers) first = last - kMostEarlyAnswers + 1;
    auto next_standing = std::lower_bound(standing_scratch_.begin(), standing_scratch_.end(), first);
    for (std::uint64_t request = first; request <= last; ++request) {
        if (next_standing != standing_scratch_.end() && *next_standing == request) {
            ++next_standing;
            continue;
        }
        Key key{client, request};
        if (!answered_early_.insert(key).second) continue;
        answered_early_order_.push_back(std::move(key));
        if (answered_early_order_.size() > kMostEarlyAnswers) {
            answered_early_.erase(answered_early_order_.front());
            answered_early_order_.pop_front();
        }
    }
}

std::vector<wire::Command> StandingCommands::take_all() {
    std::vector<wire::Command> left;
    left.reserve(by_order_.size());
    for (auto& [order, c] : by_order_)
        left.push_back(std::move(c));
    by_order_.clear();
    order_of_.clear();
    return left;
}

}  // namespace lpss::coordinator
