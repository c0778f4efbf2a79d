// What a worker holds besides its own sectors: the sectors of other workers whose samples are addressed to
// it, whose bodies come near its own sectors it keeps as ghosts in its engine so that they are cloned
// across its borders exactly as in one process; and, for its own sectors, which workers it addresses them
// to: the owners of the neighbouring sectors that some body comes near (common/border_reach.hpp). Whoever
// owns a body decides who holds it, from where the body is now, so that an empty region of the grid costs
// its owner nothing. A sector comes whole once one of its bodies comes near, but only the bodies that come
// near (and every body of a sector this worker owns or is about to own) are built in the engine: the rest
// are kept as their last state and kind (a few hundred bytes instead of a body's two kilobytes) until they
// come near.
#pragma once

#include <cstdint>
#include <map>
#include <set>
#include <unordered_map>
#include <vector>

#include "lpss.h"
#include "lpss/common/assignment.hpp"
#include "lpss/engine/world.hpp"

namespace lpss::worker {

/// The bounding radii of bodies (World::bounding_radius), in their order: what Halo::near takes.
std::vector<double> radii_of(const World& world, const std::vector<BodySnapshot>& bodies);

class Halo {
public:
    explicit Halo(std::uint32_t self) : self_(self) {}

    /// The assignment in force and the one announced (the same one when none is announced), and the
    /// largest bounding radius of the world's bodies.
    void follow(const SectorAssignment& current, const SectorAssignment& next, double largest_radius);
    const SectorAssignment& current() const { return current_; }
    const SectorAssignment& next() const { return next_; }
    double largest_radius() const { return largest_radius_; }
    /// Whether `next` takes effect with the frame after `frame`.
    bool switching_after(std::uint64_t frame) const {
        return next_.epoch != current_.epoch && next_.from_frame == frame + 1;
    }
    bool owns(const SectorKey& key) const { return current_.owner_of(key) == self_; }
    /// Whether it owns the sector now or under the assignment announced.
    bool owns_now_or_next(const SectorKey& key) const { return owns(key) || next_.owner_of(key) == self_; }

    /// The neighbouring sectors a body comes near, as a mask (bit 9(i+1) + 3(j+1) + (k+1) for the
    /// neighbour at offset (i, j, k)): SectorPublisher keeps them with the body.
    std::uint32_t near(const WorldSettings& settings, const BodySnapshot& body, double radius) const;
    std::vector<std::uint32_t> near(const World& world, const std::vector<BodySnapshot>& bodies,
                                    const std::vector<double>& radii) const;
    /// Whether a body of sector `key` with that mask comes near a sector this worker owns now.
    bool comes_near_own(const SectorKey& key, std::uint32_t near) const;
    /// Whether a body of another worker's sector `key` must be a ghost in the engine here: the sector is
    /// this worker's now or next, or the body comes near one that is (a little wider than its owner's
    /// mask, which it computed from the double offset this worker may have only as a float).
    bool needs_ghost(const WorldSettings& settings, const SectorKey& key, const BodySnapshot& body,
                     double radius);

    /// Who one of its own sectors goes to now, given the neighbours its bodies come near: their owners
    /// (and, at the frame before an assignment change, their owners under the next one too, and the next
    /// owner of the sector). `gained`: recipients it had not been sent to (they need it whole);
    /// `released`: those it no longer goes to (the sample still reaches them, to say so). A worker no
    /// longer needed keeps the sector for kKeepUnneeded frames; `emptied`: the sector has no body left,
    /// every recipient is released at once.
    struct Addressing {
        std::vector<std::uint32_t> recipients;
        std::vector<std::uint32_t> released;
        bool gained = false;
        bool changed() const { return gained || !released.empty(); }
    };
    Addressing address(const SectorKey& key, std::uint32_t near, bool emptied, std::uint64_t frame);
    static constexpr std::uint64_t kKeepUnneeded = 60;
    /// Forgets a sector given away (its new owner addresses it from now on).
    void forget(const SectorKey& key) { addressed_.erase(key); }
    /// One of its own sectors as another writer addressed it (the coordinator, with the world's first
    /// state): those recipients hold it whole as of `frame`.
    void addressed(const SectorKey& key, const std::vector<std::uint32_t>& recipients, std::uint64_t frame);
    /// A worker that holds a sector taken over (its old owner), to be told whether it still does.
    void reached(const SectorKey& key, std::uint32_t worker) { addressed_[key] = {{worker, 0}}; }

    /// Whether a sector of another worker is held here (its samples are addressed to this worker).
    bool holds(const SectorKey& key) const { return held_.count(key) != 0; }
    /// Bodies of sectors held here kept out of the engine (they come near none of this worker's sectors).
    std::size_t dormant() const { return dormant_.size(); }

    /// Applies other workers' samples (in frame order) to the engine's ghosts: states follow, bodies that
    /// arrive are built from their kinds where they need to be ghosts (needs_ghost; the others are kept
    /// dormant, and built once they come near or the assignment or the largest radius changes), and those
    /// that left what this worker holds are dropped (as are sectors that release it). Its own bodies are
    /// never touched. The coordinator's samples of the world's first state rank their bodies: those are
    /// added in the scene's order, together with `also` (ranked bodies, the world's planes).
    void apply(World& world, const std::vector<const wire::SectorFrame*>& samples,
               const std::vector<std::pair<std::uint64_t, BodyDesc>>& also = {});

private:
    std::uint32_t self_;
    SectorAssignment current_;
    SectorAssignment next_;
    double largest_radius_ = 0.0;
    struct Recipient {
        std::uint32_t worker = 0;
        std::uint64_t needed = 0;  ///< the last frame a body came near its sectors
    };
    std::unordered_map<SectorKey, std::vector<Recipient>, SectorKeyHash> addressed_;  ///< own sectors
    std::set<SectorKey> held_;  ///< other workers' sectors addressed here

    /// A body of a held sector that is not a ghost in the engine: what it takes to build it when it is.
    struct Dormant {
        wire::BodyState state;
        Eigen::Vector3d local;  ///< its offset, in double where a complete sample gave it
        wire::BodyKind kind;
        double radius = 0.0;
    };
    using DormantKey = std::pair<SectorKey, BodyId>;  ///< by sector first: a sector's bodies together
    std::map<DormantKey, Dormant> dormant_;
    std::unordered_map<BodyId, SectorKey> dormant_sector_;
    std::size_t reserved_ = 0;  ///< the engine's room for bodies, as last asked
    /// Since the last apply the assignment changed (dormant bodies of sectors with more of their
    /// neighbours this worker's may come near now), or the largest radius did (any dormant body may).
    bool assignment_changed_ = false;
    bool reach_changed_ = false;
    /// For sectors with bodies held here: which of their neighbours (bits as Halo::near's, bit 13 the
    /// sector itself) this worker owns now or next, as of the last apply.
    std::unordered_map<SectorKey, std::uint32_t, SectorKeyHash> own_around_;
    std::uint32_t own_around(const SectorKey& key) const;
    std::uint32_t cached_own_around(const SectorKey& key);
    /// needs_ghost, given own_around of the body's sector.
    bool comes_near(const WorldSettings& settings, std::uint32_t own, const BodySnapshot& body,
                    double radius) const;
    void forget_dormant(BodyId id);
};

}  // namespace lpss::worker
