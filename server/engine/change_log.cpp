#include "change_log.hpp"

#include <algorithm>

namespace lpss::engine {

void ChangeLog::end_frame() {
    last_.swap(gathering_);
    sectors_.clear();
    for (const auto& [key, entry] : last_) {
        if (!entry.empty()) sectors_.push_back(key);
    }
    std::sort(sectors_.begin(), sectors_.end());
    // The frame before's entries are emptied and kept for the sectors that change again, as most do
    // frame after frame: a sector changing in every frame costs no allocation. One that stayed empty a
    // whole frame goes, so that the log holds no more than the sectors of the last two frames.
    for (auto it = gathering_.begin(); it != gathering_.end();) {
        if (it->second.empty()) {
            it = gathering_.erase(it);
        } else {
            it->second.touched.clear();
            it->second.left.clear();
            ++it;
        }
    }
}

}  // namespace lpss::engine
