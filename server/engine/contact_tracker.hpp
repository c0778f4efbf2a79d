// Contact events. Each sector keeps the pairs that touched at its last step; a pair may be seen by
// several sectors (an original and the clone of its partner on each side of a border), so the tracker
// counts the sectors reporting each pair. The events of a frame compare each changed pair's count before
// and after the frame: from zero, it began; to zero, it ended. A body changing sector is seen by its new
// sector in the same frame as it leaves the old one, and so causes no event. A sector not stepped keeps
// its pairs: nothing in it moved. No Bullet here: the sectors hand over what their steps saw.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <unordered_map>
#include <utility>
#include <vector>

#include "lpss/common/body_desc.hpp"
#include "lpss/common/sector_key.hpp"
#include "lpss/engine/world.hpp"

namespace lpss::engine {

/// A touching pair seen by one sector's last step, with the ids the user knows.
struct ContactRecord {
    BodyId a = 0;  ///< a < b
    BodyId b = 0;
    Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< sector-local
    Eigen::Vector3f normal = Eigen::Vector3f::Zero();
    float impulse = 0.0f;
};

/// Counts the sectors that see each touching pair and makes the Begin and End events. Serial only: the
/// world calls it between parallel steps, never from them.
class ContactTracker {
public:
    /// A sector's pairs of its previous step (`old_pairs`) give way to those of this one (`new_pairs`);
    /// both sorted by (a, b).
    void replace(const SectorKey& where, const std::vector<ContactRecord>& old_pairs,
                 const std::vector<ContactRecord>& new_pairs);
    /// Ends there the pairs of `pairs` (a sector's) that involve `id`, and takes them out.
    void forget(std::vector<ContactRecord>& pairs, const SectorKey& where, BodyId id);
    /// Ends there every pair of `pairs` (a sector going away), and empties it.
    void forget_all(std::vector<ContactRecord>& pairs, const SectorKey& where);
    /// Turns the changes since the last call into events, sorted by kind and ids.
    void make_events();

    /// The events of the last make_events().
    const std::vector<ContactEvent>& events() const { return events_; }
    /// Pairs some sector sees touching.
    std::size_t touching_pairs() const { return touching_.size(); }
    /// How many sectors see `a` and `b` (a < b) touching.
    int sectors_seeing(BodyId a, BodyId b) const;

private:
    void count(const ContactRecord& contact, const SectorKey& where, int delta);

    struct PairHash {
        std::size_t operator()(const std::pair<BodyId, BodyId>& p) const {
            return std::hash<BodyId>()(p.first * 0x9E3779B97F4A7C15ULL ^ p.second);
        }
    };
    /// A pair whose count changed since the last events were made: its count before, and where and how
    /// it was first seen touching (for the Begin event).
    struct PairChange {
        int before = 0;
        ContactRecord record;
        SectorKey where;
        bool seen = false;
    };
    /// How many sectors currently report each touching pair: a pair begins at 1 and ends at 0.
    std::unordered_map<std::pair<BodyId, BodyId>, int, PairHash> touching_;
    std::unordered_map<std::pair<BodyId, BodyId>, PairChange, PairHash> changed_pairs_;
    std::vector<ContactEvent> events_;  ///< of the last step, and of commands before it
};

}  // namespace lpss::engine
