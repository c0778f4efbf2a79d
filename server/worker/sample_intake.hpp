// The sector samples a worker reads from the other workers and the coordinator. Each is checked (plausible
// for the frames known here; written by its sector's owner under the assignments announced; usable on its
// sector's chain of samples) and queued by frame, until the worker starts the frame after it and applies
// it to its halo: a faster worker's future must not leak into a frame. A sample whose base is missing (lost
// to newer ones on a loaded machine) is refused, and its sector asked for whole.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "lpss.h"
#include "lpss/common/assignment.hpp"
#include "lpss_dds/sample_check.hpp"
#include "lpss_dds/sample_owners.hpp"
#include "lpss_dds/sector_chain.hpp"
#include "lpss_dds/whole_sector_asks.hpp"

namespace lpss::worker {

class SampleIntake {
public:
    explicit SampleIntake(std::uint32_t worker)
        : worker_(worker), refused_("worker " + std::to_string(worker)) {}

    /// A sample read. `known`: the latest frame started or announced here; `ahead`: how far past it a
    /// sample may be (more for a worker not yet in the world, which reads history in bursts).
    void take(wire::SectorFrame sample, std::uint64_t known, std::uint64_t ahead);
    /// An assignment announced: the samples held until their writers' ownership was known are taken again.
    void learn(const SectorAssignment& assignment, std::uint64_t known, std::uint64_t ahead);
    /// The sectors to ask for whole now (their samples refused for a missing base); empty if none.
    std::vector<wire::SectorKey> whole_due() { return wanted_whole_.due(std::chrono::steady_clock::now()); }
    /// The queued samples of frames up to `up_to`, oldest first, for the halo to apply. They stay here
    /// (and the pointers valid) until `applied`, or any other call that changes the queue.
    std::vector<const wire::SectorFrame*> through(std::uint64_t up_to);
    /// Drops the samples of frames up to `up_to` once they are applied, and what the chain and the owners
    /// kept for them.
    void applied(std::uint64_t up_to);
    /// The samples queued for `frame`; null if none.
    const std::vector<wire::SectorFrame>* of_frame(std::uint64_t frame) const;
    /// Which samples are usable: the frame gate asks it whether the samples a mark lists have come.
    const dds::SectorChain& chain() const { return chain_; }
    /// The serialized bytes of the samples of `frame` read; those of that frame and before are forgotten.
    std::uint64_t take_received_bytes(std::uint64_t frame);
    /// Forgets every sample, and what the chain, the owners and the sectors asked for whole held: samples
    /// of frames before `floor` are history (a worker that joins a running cluster, restarted perhaps under
    /// the id of one that is gone). The bytes counted and the refusals logged are kept.
    void start_over(std::uint64_t floor);

private:
    std::uint32_t worker_;
    std::uint64_t floor_ = 0;
    std::map<std::uint64_t, std::vector<wire::SectorFrame>> queued_;  ///< by frame
    dds::SectorChain chain_;
    dds::SampleOwners owners_;           ///< whose samples are whose to write, by the assignments announced
    dds::WholeSectorAsks wanted_whole_;  ///< sectors whose partial samples were refused
    dds::RefusedSamples refused_;
    std::map<std::uint64_t, std::uint64_t> received_bytes_;  ///< by frame
};

}  // namespace lpss::worker
