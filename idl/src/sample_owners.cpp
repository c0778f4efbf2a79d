#include "lpss_dds/sample_owners.hpp"

#include <algorithm>
#include <string>
#include <utility>

#include "lpss_dds/convert.hpp"

namespace lpss::dds {
namespace {

std::string sector_text(const SectorKey& key) {
    return "(" + std::to_string(key.i) + ", " + std::to_string(key.j) + ", " + std::to_string(key.k) + ")";
}

}  // namespace

std::vector<wire::SectorFrame> SampleOwners::learn(const SectorAssignment& assignment) {
    // A word about the same frames or later ones replaces what was planned for them: an assignment the
    // coordinator dropped (a worker gone before it came into force) or one a coordinator that was replaced
    // announced never comes into force.
    by_from_frame_.erase(by_from_frame_.lower_bound(assignment.from_frame), by_from_frame_.end());
    by_from_frame_[assignment.from_frame] = assignment;
    // Only the last few matter: samples come at most a few frames late (older ones are stale to every
    // reader's chain), and the one in force at the oldest of them is kept.
    while (by_from_frame_.size() > 8)
        by_from_frame_.erase(by_from_frame_.begin());
    newest_epoch_ = 0;
    for (const auto& [from, known] : by_from_frame_)
        newest_epoch_ = std::max(newest_epoch_, known.epoch);
    return std::exchange(held_, {});
}

const SectorAssignment* SampleOwners::in_force(std::uint64_t frame) const {
    auto it = by_from_frame_.upper_bound(frame);
    return it == by_from_frame_.begin() ? nullptr : &std::prev(it)->second;
}

bool SampleOwners::admit(const wire::SectorFrame& sample, RefusedSamples& refused) {
    // The coordinator's own; or nothing known yet to judge by (a reader before its first assignment: a
    // client starting, a worker before the world's first state or while it waits to join).
    if (sample.worker() == 0 || by_from_frame_.empty()) return true;
    if (sample.epoch() > newest_epoch_) {
        if (held_.size() >= kMostHeld) {
            refused.refuse("sample of frame " + std::to_string(held_.front().frame()) + " from worker " +
                           std::to_string(held_.front().worker()) + ": its epoch " +
                           std::to_string(held_.front().epoch()) + " never came (too many held)");
            held_.erase(held_.begin());
        }
        held_.push_back(sample);
        return false;
    }
    const SectorAssignment* assignment = in_force(sample.frame());
    if (assignment == nullptr) return true;  // before every assignment known: cannot be judged
    const SectorKey key = from_wire(sample.sector());
    // Named only when refused: every sample every reader takes comes through here.
    auto where = [&] {
        return "sample of sector " + sector_text(key) + " frame " + std::to_string(sample.frame()) +
               " from worker " + std::to_string(sample.worker());
    };
    if (sample.epoch() < assignment->epoch) {
        refused.refuse(where() + ": its epoch " + std::to_string(sample.epoch()) +
                       " is older than the one in force at its frame (" + std::to_string(assignment->epoch) +
                       ")");
        return false;
    }
    if (sample.epoch() > assignment->epoch) {
        for (const auto& [from, known] : by_from_frame_) {
            if (known.epoch == sample.epoch()) {
                refused.refuse(where() + ": its epoch " + std::to_string(sample.epoch()) +
                               " is in force only from frame " + std::to_string(from));
                return false;
            }
        }
        return true;  // an assignment this reader missed (two written before it read one): cannot be judged
    }
    if (const std::uint32_t owner = assignment->owner_of(key); owner != sample.worker()) {
        refused.refuse(where() + ": the sector is worker " + std::to_string(owner) + "'s in epoch " +
                       std::to_string(assignment->epoch));
        return false;
    }
    return true;
}

void SampleOwners::applied(std::uint64_t frame, RefusedSamples& refused) {
    auto late = std::stable_partition(held_.begin(), held_.end(),
                                      [&](const wire::SectorFrame& s) { return s.frame() > frame; });
    for (auto it = late; it != held_.end(); ++it) {
        refused.refuse("sample of frame " + std::to_string(it->frame()) + " from worker " +
                       std::to_string(it->worker()) + ": its epoch " + std::to_string(it->epoch()) +
                       " never came (the newest known is " + std::to_string(newest_epoch_) + ")");
    }
    held_.erase(late, held_.end());
}

}  // namespace lpss::dds
