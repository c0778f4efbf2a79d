// The sectors a reader wants whole: their partial samples were refused (SectorChain: the base was lost),
// and only a complete sample mends them. They are asked for on lpss/sector_requests, each at most every
// 100 ms until a usable sample comes (a request can be lost, and the owner answers in its next frame).
// Clients, workers and the coordinators ask alike (SampleIntake).
#pragma once

#include <chrono>
#include <set>
#include <unordered_map>
#include <vector>

#include "lpss.h"
#include "lpss/common/sector_key.hpp"
#include "lpss_dds/convert.hpp"

namespace lpss::dds {

class WholeSectorAsks {
public:
    using Clock = std::chrono::steady_clock;

    /// A partial sample of `key` was refused.
    void want(const SectorKey& key) { wanted_.insert(key); }
    /// A usable sample of `key` came.
    void got(const SectorKey& key) {
        if (wanted_.erase(key)) asked_.erase(key);
    }
    /// Whether `key` waits for a usable sample.
    bool wanted(const SectorKey& key) const { return wanted_.count(key) != 0; }
    /// The sectors to ask for now (none asked within the last 100 ms); empty if none.
    std::vector<wire::SectorKey> due(Clock::time_point now) {
        std::vector<wire::SectorKey> out;
        for (const SectorKey& key : wanted_) {
            auto last = asked_.find(key);
            if (last != asked_.end() && now - last->second < std::chrono::milliseconds(100)) continue;
            asked_[key] = now;
            out.push_back(to_wire(key));
        }
        return out;
    }

private:
    std::set<SectorKey> wanted_;
    std::unordered_map<SectorKey, Clock::time_point, SectorKeyHash> asked_;
};

}  // namespace lpss::dds
