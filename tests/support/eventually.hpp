// Waiting in tests for what another thread or process does: polls a condition until it holds or a limit
// passes, and says which.
#pragma once

#include <chrono>
#include <thread>

namespace lpss::testing {

/// Polls `pred` every 5 ms until it holds (true) or `limit` has passed (its last answer).
template <class Pred>
bool eventually(Pred pred, std::chrono::milliseconds limit = std::chrono::seconds(10)) {
    const auto end = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < end) {
        if (pred()) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return pred();
}

}  // namespace lpss::testing
