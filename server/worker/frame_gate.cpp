#include "frame_gate.hpp"

#include <algorithm>

#include "lpss_dds/convert.hpp"

namespace lpss::worker {

void FrameGate::take_go(const wire::FrameGo& go) {
    if (go.term() < term_) return;
    if (go.term() > term_) {
        term_ = go.term();
        gos_.clear();  // words of the coordinator replaced: its frames start no more
    }
    gos_[go.frame()] = go;
}

void FrameGate::take_ack(const wire::FrameAck& ack) {
    std::uint64_t& frame = acked_[ack.coordinator()];
    frame = std::max(frame, ack.frame());
}

void FrameGate::take_mark(const wire::WorkerFrame& mark, Clock::time_point came) {
    if (mark.worker() == self_ && self_ != 0) return;
    Mark& kept = marks_[{mark.worker(), mark.frame()}];
    kept.came = came;
    std::vector<SectorKey>& written = kept.written;
    written.clear();
    for (const wire::WrittenSector& w : mark.written()) {
        if (std::find(w.recipients().begin(), w.recipients().end(), self_) != w.recipients().end())
            written.push_back(dds::from_wire(w.sector()));
    }
}

const wire::FrameGo* FrameGate::go(std::uint64_t frame) const {
    auto it = gos_.find(frame);
    if (it == gos_.end()) return nullptr;
    // A stop does not wait for the standby: there is no frame for it to take over (seen: a standby that
    // acknowledged the stop and ended at once, its acknowledgement never reaching two workers, which waited
    // for a coordinator that was gone).
    if (const std::uint32_t standby = it->second.standby(); standby != 0 && !it->second.stop()) {
        auto acked = acked_.find(standby);
        if (acked == acked_.end() || acked->second < frame) return nullptr;
    }
    return &it->second;
}

void FrameGate::started(std::uint64_t frame) { gos_.erase(gos_.begin(), gos_.upper_bound(frame)); }

bool FrameGate::whole(std::uint64_t previous, const std::vector<std::uint32_t>& workers,
                      bool coordinator_wrote, const dds::SectorChain& chain) const {
    bool all = true;
    for_each_awaited(previous, workers, coordinator_wrote, [&](std::uint32_t worker) {
        auto it = marks_.find({worker, previous});
        if (it == marks_.end()) {
            all = false;  // which sectors it wrote is not known yet
            return;
        }
        for (const SectorKey& key : it->second.written) {
            // A sample of that frame or later (a sample of frame 0, the world's first state, counts too).
            if (!chain.holds(key, previous, ~std::uint64_t{0})) all = false;
        }
    });
    return all;
}

std::string FrameGate::missing(std::uint64_t previous, const std::vector<std::uint32_t>& workers,
                               bool coordinator_wrote, const dds::SectorChain& chain) const {
    std::string out;
    for_each_awaited(previous, workers, coordinator_wrote, [&](std::uint32_t worker) {
        const std::string who =
            worker == 0 ? std::string("the coordinator") : "worker " + std::to_string(worker);
        auto it = marks_.find({worker, previous});
        if (it == marks_.end()) {
            out += (out.empty() ? "" : "; ") + who + "'s end of the frame";
            return;
        }
        for (const SectorKey& key : it->second.written) {
            if (chain.holds(key, previous, ~std::uint64_t{0})) continue;
            out +=
                (out.empty() ? "" : "; ") + who + "'s sample of sector (" + std::to_string(key.i) + ", " +
                std::to_string(key.j) + ", " + std::to_string(key.k) + ")" +
                (chain.newest(key) > 0 ? " (holds it as of frame " + std::to_string(chain.newest(key)) + ")"
                                       : "");
        }
    });
    return out;
}

std::vector<SectorKey> FrameGate::samples_not_come(std::uint64_t previous,
                                                   const std::vector<std::uint32_t>& workers,
                                                   bool coordinator_wrote, const dds::SectorChain& chain,
                                                   Clock::time_point listed_before) const {
    std::vector<SectorKey> out;
    for_each_awaited(previous, workers, coordinator_wrote, [&](std::uint32_t worker) {
        // The coordinator's samples stay in its writers' history until every reader has them: repair
        // brings them, however long they take (the world's first state, at a million bodies).
        if (worker == 0) return;
        auto it = marks_.find({worker, previous});
        if (it == marks_.end() || it->second.came >= listed_before) return;
        for (const SectorKey& key : it->second.written) {
            if (!chain.holds(key, previous, ~std::uint64_t{0})) out.push_back(key);
        }
    });
    return out;
}

void FrameGate::forget_before(std::uint64_t frame) {
    for (auto it = marks_.begin(); it != marks_.end();)
        it = it->first.second < frame ? marks_.erase(it) : std::next(it);
}

}  // namespace lpss::worker
