// What a worker holds besides its own sectors: the sectors of other workers whose samples are addressed to
// it, whose bodies it keeps as ghosts in its engine so that they are cloned across its borders exactly as
// in one process; and, for its own sectors, which workers it addresses them to: the owners of the
// neighbouring sectors that some body comes near (common/border_reach.hpp). Whoever owns a body decides who
// holds it, from where the body is now, so that an empty region of the grid costs its owner nothing.
#pragma once

#include <cstdint>
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

    /// The neighbouring sectors a body comes near, as a mask (bit 9(i+1) + 3(j+1) + (k+1) for the
    /// neighbour at offset (i, j, k)): SectorPublisher keeps them with the body.
    std::uint32_t near(const WorldSettings& settings, const BodySnapshot& body, double radius) const;
    std::vector<std::uint32_t> near(const World& world, const std::vector<BodySnapshot>& bodies,
                                    const std::vector<double>& radii) const;
    /// Whether a body of sector `key` with that mask comes near a sector this worker owns now.
    bool comes_near_own(const SectorKey& key, std::uint32_t near) const;

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

    /// Applies other workers' samples (in frame order) to the engine's ghosts: states follow, bodies that
    /// arrive are built from their kinds, and those that left what this worker holds are dropped (as are
    /// sectors that release it). Its own bodies are never touched. The coordinator's samples of the world's
    /// first state rank their bodies: those are added in the scene's order, together with `also` (ranked
    /// bodies, the world's planes).
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
};

}  // namespace lpss::worker
