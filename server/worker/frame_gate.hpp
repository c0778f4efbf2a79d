// When a worker may start a frame: the coordinator has said so (FrameGo), the standby coordinator it names
// holds that word (FrameAck), and every worker that ended the frame before (and the coordinator, when it
// wrote sector samples itself) has said so, with every sample it lists as written there for this worker
// already received. Samples of later frames may be in too; the gate only says when the frame before is
// whole. Words of a coordinator's term lower than the highest seen are dropped: a standby that took over
// raised the term, and the coordinator it replaced may still be about (stopped, cut off).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "lpss.h"
#include "lpss/common/sector_key.hpp"
#include "lpss_dds/sector_chain.hpp"

namespace lpss::worker {

class FrameGate {
public:
    explicit FrameGate(std::uint32_t self) : self_(self) {}

    /// A FrameGo read from the coordinator (kept until its frame starts).
    void take_go(const wire::FrameGo& go);
    /// A standby coordinator's word that it holds the FrameGo of a frame.
    void take_ack(const wire::FrameAck& ack);
    /// A WorkerFrame read from another worker or the coordinator (this worker's own are ignored).
    void take_mark(const wire::WorkerFrame& mark);

    /// The coordinator's word for `frame`, if it has come and the standby it names holds it.
    const wire::FrameGo* go(std::uint64_t frame) const;
    /// The highest coordinator term seen.
    std::uint32_t term() const { return term_; }
    /// The coordinator's latest word, whatever its frame: what a worker joining a running cluster looks at.
    const wire::FrameGo* latest() const { return gos_.empty() ? nullptr : &gos_.rbegin()->second; }
    /// Drops the words for frames up to `frame`, once that frame has started.
    void started(std::uint64_t frame);

    /// Whether the frame `previous` is whole here: for every worker in `workers` (and the coordinator, as
    /// worker 0, if `coordinator_wrote`), its end of that frame has come, and `chain` holds each sector it
    /// lists as written for this worker, at that frame or later.
    bool whole(std::uint64_t previous, const std::vector<std::uint32_t>& workers, bool coordinator_wrote,
               const dds::SectorChain& chain) const;
    /// What `whole` still waits for, in words (a frame that starts without it says so).
    std::string missing(std::uint64_t previous, const std::vector<std::uint32_t>& workers,
                        bool coordinator_wrote, const dds::SectorChain& chain) const;

    /// Whether a worker's (0: the coordinator's) mark of `frame` has come.
    bool has_mark(std::uint32_t worker, std::uint64_t frame) const {
        return marks_.count({worker, frame}) != 0;
    }
    /// Forgets marks of frames before `frame`.
    void forget_before(std::uint64_t frame);

private:
    std::uint32_t self_;
    std::uint32_t term_ = 0;
    std::map<std::uint64_t, wire::FrameGo> gos_;    ///< of term_
    std::map<std::uint32_t, std::uint64_t> acked_;  ///< standby -> the latest frame it holds
    /// (worker, frame) -> the sectors it wrote for this worker in that frame
    std::map<std::pair<std::uint32_t, std::uint64_t>, std::vector<SectorKey>> marks_;
};

}  // namespace lpss::worker
