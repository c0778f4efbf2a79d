// The sector samples a reader takes in, the same for a worker, a coordinator and a client: each is checked
// (plausible for the frames known to the reader; written by its sector's owner under the assignments
// announced; usable on its sector's chain of samples) and queued by frame until the reader applies the
// frames up to it. A partial sample whose base is missing (lost to newer ones on a loaded machine) is
// refused and its sector marked to be asked for whole: without that the sector stays stale until its
// owner happens to send it whole (seen: a worker degraded 2 s a frame for minutes). What to do with the
// queued samples (a halo, a mirror) and whom to ask is the reader's.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "lpss.h"
#include "lpss/common/assignment.hpp"
#include "lpss/common/sector_key.hpp"
#include "lpss_dds/sample_check.hpp"
#include "lpss_dds/sample_owners.hpp"
#include "lpss_dds/sector_chain.hpp"
#include "lpss_dds/whole_sector_asks.hpp"

namespace lpss::dds {

class SampleIntake {
public:
    /// What became of a sample offered to take().
    enum class Taken {
        queued,        ///< usable: queued for its frame
        refused,       ///< implausible, not its writer's to write, from before the floor, or held until
                       ///< its writer's epoch is known (learn() gives it back)
        stale,         ///< the reader holds its sector as new or newer already
        without_base,  ///< partial, its base missing: its sector is now wanted whole
    };

    /// `reader` names the reader in its refusals' log lines ("worker 3", "coordinator", "client"), `asker`
    /// in its requests for whole sectors (SectorRequest::reader, "lpss-worker-3"). With `count_bytes`, the
    /// serialized bytes of the samples taken are summed by frame.
    SampleIntake(std::string reader, std::string asker, bool count_bytes = false)
        : asker_(std::move(asker)), refused_(std::move(reader)), count_bytes_(count_bytes) {}

    /// A sample read. `known`: the latest frame started or announced to the reader; `ahead`: how far past
    /// it a sample may be.
    Taken take(wire::SectorFrame sample, std::uint64_t known, std::uint64_t ahead);
    /// An assignment announced. Returns the samples held until their writers' epochs were known: the
    /// reader offers them to take() again (through its own checks, if it has any).
    std::vector<wire::SectorFrame> learn(const SectorAssignment& assignment) {
        return owners_.learn(assignment);
    }
    /// A sample the reader wrote itself (its own samples do not come back to it): its chain moves on. A
    /// sector wanted whole stays wanted: what the reader wrote is what it held, not what the owner holds.
    void wrote(const wire::SectorFrame& sample) { chain_.accept(sample); }

    /// The sectors to ask for whole now: partial samples refused, or wanted by the reader (want_whole),
    /// each at most every 100 ms until a usable sample comes. Empty if none.
    std::vector<wire::SectorKey> whole_due() { return wanted_whole_.due(std::chrono::steady_clock::now()); }
    /// A request for the sectors due whole (whole_due), numbered `next_number` (then counted on: request
    /// numbers increase per reader, and a client numbers its inventory requests alike); none if none is due.
    std::optional<wire::SectorRequest> whole_request(std::uint64_t& next_number);
    /// Whether `key` waits for a usable sample: what the reader holds of it may be stale.
    bool wants_whole(const SectorKey& key) const { return wanted_whole_.wanted(key); }
    /// The reader wants `key` whole for a reason of its own (a sample lost in flight, an inventory's).
    void want_whole(const SectorKey& key) { wanted_whole_.want(key); }

    /// The queued samples of frames up to `up_to`, oldest frame first. They stay queued (the pointers
    /// valid) until `applied` or another call that changes the queue.
    std::vector<const wire::SectorFrame*> through(std::uint64_t up_to) const;
    /// Drops the samples of frames up to `up_to` once the reader applied them, and what the chain and the
    /// owners kept for them.
    void applied(std::uint64_t up_to);
    /// The samples queued for `frame`; null if none.
    const std::vector<wire::SectorFrame>* of_frame(std::uint64_t frame) const;
    /// Drops the queued samples of frames up to `up_to` for which `drop` says so.
    void drop_queued(std::uint64_t up_to, const std::function<bool(const wire::SectorFrame&)>& drop);

    /// Which samples are usable: which sectors the reader holds as of which frames.
    const SectorChain& chain() const { return chain_; }
    /// The assignments known, by the frames they are in force from.
    const SampleOwners& owners() const { return owners_; }
    /// The samples refused so far.
    std::uint64_t refused() const { return refused_.count(); }

    /// With count_bytes: the serialized bytes of the samples of `frame` taken; that frame's and the ones
    /// before are forgotten.
    std::uint64_t take_received_bytes(std::uint64_t frame);
    /// Forgets every sample, and what the chain, the owners and the sectors wanted whole held: samples of
    /// frames before `floor` are history (a worker that joins a running cluster). The bytes counted and the
    /// refusals logged are kept.
    void start_over(std::uint64_t floor);

private:
    std::string asker_;
    std::uint64_t floor_ = 0;
    std::map<std::uint64_t, std::vector<wire::SectorFrame>> queued_;  ///< by frame
    SectorChain chain_;
    SampleOwners owners_;           ///< whose samples are whose to write, by the assignments announced
    WholeSectorAsks wanted_whole_;  ///< sectors whose partial samples were refused, or wanted otherwise
    RefusedSamples refused_;
    bool count_bytes_;
    std::map<std::uint64_t, std::uint64_t> received_bytes_;  ///< by frame
};

}  // namespace lpss::dds
