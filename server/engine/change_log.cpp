#include "change_log.hpp"

#include <algorithm>

namespace lpss::engine {

void ChangeLog::end_frame() {
    last_.swap(gathering_);
    gathering_.clear();
    sectors_.clear();
    sectors_.reserve(last_.size());
    for (const auto& [key, entry] : last_)
        sectors_.push_back(key);
    std::sort(sectors_.begin(), sectors_.end());
}

}  // namespace lpss::engine
