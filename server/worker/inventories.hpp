// Readers that start (a client, a worker joining) ask each worker for an inventory of its sectors in a
// region: which sectors exist, and as of which frame. A worker answers in the mark of the first frame its
// sector writer reaches the reader (what a writer sends before it has matched a reader never reaches it),
// and sends the sectors the reader lacks whole, a few bodies' worth a frame: the first share just before
// that mark, the rest in the frames after.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "lpss.h"
#include "lpss/common/sector_key.hpp"
#include "lpss_dds/participant.hpp"
#include "lpss_dds/sector_publisher.hpp"

namespace lpss::worker {

class Inventories {
public:
    /// A request not reached by then is dropped (the reader asks again if it is still there).
    static constexpr std::chrono::seconds kPatience{10};
    /// The sectors an inventory lists go whole at most this many bodies a frame: a whole-world joiner of a
    /// million bodies cost a worker half a million in one frame, which starved a two-core machine long
    /// enough for liveliness leases to lapse. The joiner's first frame comes once its last sector has.
    static constexpr std::uint32_t kBodiesPerFrame = 20000;

    /// A reader's request (a SectorRequest that asks for an inventory); it replaces that reader's earlier
    /// one.
    void ask(const wire::SectorRequest& request);
    /// Takes up the requests whose readers this worker's sector writer reaches now (`reaches`): answered in
    /// this frame's mark, their sectors queued to go whole, but those the reader already holds as of their
    /// latest sample (listed only).
    void take_up(const std::function<bool(const dds::GuidBytes&)>& reaches,
                 const dds::SectorPublisher& publisher);
    /// The queued sectors to send whole in this frame: this frame's share, those still published.
    std::set<SectorKey> due_now(const dds::SectorPublisher& publisher);
    /// The answers to the requests taken up in this frame, for its mark; they are forgotten here.
    std::vector<wire::SectorInventory> answers(const dds::SectorPublisher& publisher);

private:
    struct Request {
        std::string reader;
        std::uint64_t request = 0;
        SectorKey lo, hi;
        std::optional<dds::GuidBytes> frames_reader;  ///< none: answered at once
        std::chrono::steady_clock::time_point asked;
        /// The reader holds every sector as of this frame: those not written since are listed, not sent.
        std::uint64_t held_through = 0;

        bool covers(const SectorKey& key) const {
            return key.i >= lo.i && key.i <= hi.i && key.j >= lo.j && key.j <= hi.j && key.k >= lo.k &&
                   key.k <= hi.k;
        }
    };
    std::map<std::string, Request> asked_;  ///< not answered yet: by reader, the latest request of each
    std::vector<Request> answering_;        ///< taken up in this frame
    /// Sectors of answered inventories still to send whole, in order.
    std::vector<SectorKey> due_;
    std::set<SectorKey> queued_;
};

}  // namespace lpss::worker
