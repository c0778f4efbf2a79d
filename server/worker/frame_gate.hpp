// When a worker may start a frame: the coordinator has said so (FrameGo), the standby coordinator it names
// holds that word (FrameAck), and every worker that ended the frame before (and the coordinator, when it
// wrote sector samples itself) has said so, with every sample it lists as written there for this worker
// already received. Samples of later frames may be in too; the gate only says when the frame before is
// whole. Words of a coordinator's term lower than the highest seen are dropped: a standby that took over
// raised the term, and the coordinator it replaced may still be about (stopped, cut off).
#pragma once

#include <chrono>
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
    using Clock = std::chrono::steady_clock;

    explicit FrameGate(std::uint32_t self) : self_(self) {}

    /// A FrameGo read from the coordinator (kept until its frame starts).
    void take_go(const wire::FrameGo& go);
    /// A standby coordinator's word that it holds the FrameGo of a frame.
    void take_ack(const wire::FrameAck& ack);
    /// A WorkerFrame read from another worker or the coordinator (this worker's own are ignored), at `came`.
    void take_mark(const wire::WorkerFrame& mark, Clock::time_point came);

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
    /// The sectors whose samples from other workers `whole` waits for though the mark that lists them (as
    /// written for this worker, in `previous`) came before `listed_before`; a worker whose mark has not come
    /// is not counted, nor the coordinator (its writers keep what they wrote until every reader has it). A
    /// sample is written before its mark: one still missing long after its mark came was lost.
    std::vector<SectorKey> samples_not_come(std::uint64_t previous, const std::vector<std::uint32_t>& workers,
                                            bool coordinator_wrote, const dds::SectorChain& chain,
                                            Clock::time_point listed_before) const;

    /// Whether a worker's (0: the coordinator's) mark of `frame` has come.
    bool has_mark(std::uint32_t worker, std::uint64_t frame) const {
        return marks_.count({worker, frame}) != 0;
    }
    /// Forgets marks of frames before `frame`.
    void forget_before(std::uint64_t frame);

private:
    /// Calls `look(worker)` for each writer whose end of `previous` this worker waits for: the coordinator
    /// (worker 0) when it wrote, and past frame 0 every worker of `workers` but this one.
    template <class Look>
    void for_each_awaited(std::uint64_t previous, const std::vector<std::uint32_t>& workers,
                          bool coordinator_wrote, Look look) const {
        if (coordinator_wrote) look(0);
        if (previous == 0) return;  // workers write nothing before frame 1
        for (std::uint32_t worker : workers) {
            if (worker != self_) look(worker);
        }
    }

    std::uint32_t self_;
    std::uint32_t term_ = 0;
    std::map<std::uint64_t, wire::FrameGo> gos_;    ///< of term_
    std::map<std::uint32_t, std::uint64_t> acked_;  ///< standby -> the latest frame it holds
    struct Mark {
        std::vector<SectorKey> written;  ///< the sectors written for this worker
        Clock::time_point came;
    };
    std::map<std::pair<std::uint32_t, std::uint64_t>, Mark> marks_;  ///< (worker, frame) -> its mark
};

}  // namespace lpss::worker
