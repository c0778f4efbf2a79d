#include "command_rate.hpp"

#include <algorithm>

namespace lpss::coordinator {

bool CommandRate::allow(const std::string& client, Clock::time_point now) {
    if (per_second_ <= 0.0) return true;
    auto [it, first] = buckets_.try_emplace(client, Bucket{per_second_, now});
    Bucket& b = it->second;
    if (!first) {
        const double seconds = std::chrono::duration<double>(now - b.filled).count();
        b.tokens = std::min(per_second_, b.tokens + seconds * per_second_);
        b.filled = now;
    }
    if (b.tokens < 1.0) return false;
    b.tokens -= 1.0;
    return true;
}

}  // namespace lpss::coordinator
