// Changes of who simulates what: handoffs of bodies crossing into other workers' sectors (granted in the
// next start), joiners admitted once every worker reaches them, and the balanced assignment a rebalance
// (decided in run, by kRebalanceGain) or a change of workers takes on.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <map>
#include <set>
#include <unordered_map>

#include "coordinator_state.hpp"
#include "lpss_dds/convert.hpp"

namespace lpss::coordinator {

void Coordinator::State::collect_handoffs(std::uint64_t f) {
    // Requests of frame f become grants of frame f + 1, each body once, to the owner of the sector it enters
    // under the assignment in force then.
    const SectorAssignment then = assignment_for(f + 1);
    std::set<BodyId> granted;
    auto grant = [&](const std::vector<wire::Handoff>& requests) {
        for (wire::Handoff h : requests) {
            if (!statics.count(h.body()) || !granted.insert(h.body()).second) continue;
            const std::uint32_t to = then.owner_of(dds::from_wire(h.sector()));
            if (to == h.from_worker()) continue;
            h.to_worker(to);
            grants.push_back(h);
            ++handoffs;
        }
    };
    std::set<std::uint32_t> ended_frame = gone_after_ending;
    ended_frame.insert(live.begin(), live.end());
    for (std::uint32_t w : ended_frame) {
        auto it = marks.find({w, f});
        if (it != marks.end()) grant(it->second.leaving());
    }
    grant(stood_in);
    stood_in.clear();
    gone_after_ending.clear();
    for (auto it = marks.begin(); it != marks.end();)
        it = it->first.second < f ? marks.erase(it) : std::next(it);
}

std::vector<std::uint32_t> Coordinator::State::not_reaching(std::uint32_t joiner) const {
    std::vector<std::uint32_t> out;
    auto reader = joiner_readers.find(joiner);
    if (reader == joiner_readers.end()) return out;  // a worker that names no reader: nothing to wait for
    if (!sectors_out->reaches(reader->second)) out.push_back(0);
    for (std::uint32_t w : members()) {
        auto r = reaching.find(w);
        if (w != joiner && (r == reaching.end() || !r->second.count(joiner))) out.push_back(w);
    }
    return out;
}

void Coordinator::State::admit(std::uint64_t f) {
    std::set<std::uint32_t> workers = members();
    std::string names;
    for (auto it = joining.begin(); it != joining.end();) {
        const std::uint32_t w = *it;
        if (const std::vector<std::uint32_t> missing = not_reaching(w); !missing.empty()) {
            // Said once after a second: discovery that completes on one side only is what this waits out.
            auto since = joining_since.find(w);
            if (since != joining_since.end() && Clock::now() - since->second > std::chrono::seconds(1)) {
                std::string who;
                for (std::uint32_t m : missing)
                    who += (who.empty() ? "" : ", ") +
                           (m == 0 ? std::string("the coordinator") : std::to_string(m));
                spdlog::warn(
                    "coordinator: worker {} waits to join: not reached yet by the sector writer of {}", w,
                    who);
                joining_since.erase(since);
            }
            ++it;
            continue;
        }
        workers.insert(w);
        admitted[w] = f + 2;
        names += (names.empty() ? "" : ", ") + std::to_string(w);
        joining_since.erase(w);
        it = joining.erase(it);
    }
    if (names.empty()) return;
    reassign(balanced(workers), f + 2, ("worker(s) " + names + " joined").c_str());
}

SectorAssignment Coordinator::State::balanced(const std::set<std::uint32_t>& workers) const {
    std::vector<std::pair<SectorKey, double>> loads;
    for (const auto& [block, reported] : block_loads) {
        // A block's load stands for its first sector: balanced() groups sectors into the same blocks.
        loads.push_back(
            {SectorKey{block.i * next.block_size, block.j * next.block_size, block.k * next.block_size},
             static_cast<double>(reported.load)});
    }
    if (loads.empty()) {
        for (const auto& [key, bodies] : mirror.sectors())
            loads.push_back({key, static_cast<double>(bodies.size())});
    }
    return SectorAssignment::balanced(loads, std::vector<std::uint32_t>(workers.begin(), workers.end()),
                                      options.block_size);
}

std::map<std::uint32_t, double> Coordinator::State::worker_loads(const SectorAssignment& assignment) const {
    std::map<std::uint32_t, double> per_worker;
    for (const auto& [block, reported] : block_loads) {
        const std::int64_t n = current.block_size;  // the blocks the workers reported in
        per_worker[assignment.owner_of({block.i * n, block.j * n, block.k * n})] += reported.load;
    }
    return per_worker;
}

void Coordinator::State::reassign(SectorAssignment fresh, std::uint64_t from_frame, const char* why) {
    fresh.epoch = next.epoch + 1;
    fresh.from_frame = from_frame;
    next = fresh;
    publish_assignment();
    spdlog::info("coordinator: assignment epoch {} from frame {} ({})", next.epoch, from_frame, why);
}

}  // namespace lpss::coordinator
