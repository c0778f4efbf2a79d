// A worker joining a running cluster (a new worker, or one restarted under the id of one that is gone): it
// asks with a frame-0 mark naming the assignment it saw in force; the coordinator gives it sectors from a
// later frame, and their owners send them whole at the frame before, as in any rebalance.
#include "worker_state.hpp"

#include <spdlog/spdlog.h>

#include "lpss_dds/convert.hpp"

namespace lpss::worker {
namespace {

/// A request to join not answered by then is made again.
constexpr std::chrono::seconds kJoinPatience{5};

}  // namespace

Worker::State::Joining Worker::State::join(const wire::FrameGo& latest) {
    const SectorAssignment announced = dds::from_wire(latest.next());
    const bool given =
        asked_to_join && announced.epoch != joined_from.epoch &&
        std::find(announced.workers.begin(), announced.workers.end(), options.id) != announced.workers.end();
    if (announced.epoch == latest.epoch() && !given) {
        // No change under way: ask, once for each assignment seen in force (an answer may be a change made
        // for another reason, such as a worker gone, that leaves this one out).
        // Once for each, and again if no answer comes (a request the coordinator never read: written before
        // its reader matched this writer, or lost with a coordinator that went).
        if (asked_to_join && joined_from.epoch == announced.epoch && Clock::now() - asked_at < kJoinPatience)
            return Joining::waiting;
        // Not before every worker and the coordinator can reach it and it them: its first frame needs their
        // samples at once, and discovery that matched one side only took seconds at times (seen: a joiner
        // that started its first frame without its sectors, 2 s later, and showed bodies twice).
        const int peers = static_cast<int>(announced.workers.size()) + 1;
        bool reachable = frames_in->matched() >= peers && marks_in->matched() >= peers &&
                         frames_out->matched() >= peers && marks_out->matched() >= peers;
        for (std::uint32_t w : announced.workers) {
            auto reader = sector_readers.find(w);
            reachable = reachable && (w == options.id || (heard.count(w) && reader != sector_readers.end() &&
                                                          frames_out->reaches(reader->second)));
        }
        if (!reachable) {
            if (Clock::now() - join_noted > std::chrono::seconds(5)) {
                join_noted = Clock::now();
                std::string heard_from;
                for (std::uint32_t w : heard)
                    heard_from += " " + std::to_string(w);
                spdlog::info(
                    "worker {}: waiting to reach the cluster's {} workers and coordinator before joining: "
                    "matched {} sector writers, {} mark writers, {} readers of its sectors, {} of its marks; "
                    "marks heard from workers{}",
                    options.id, announced.workers.size(), frames_in->matched(), marks_in->matched(),
                    frames_out->matched(), marks_out->matched(), heard_from);
            }
            return Joining::waiting;
        }
        if (!asked_to_join) {
            spdlog::info("worker {}: the cluster is running (frame {}): asking to join", options.id,
                         latest.frame());
        } else if (joined_from.epoch == announced.epoch) {
            spdlog::warn("worker {}: no answer to its request to join after {} s: asking again", options.id,
                         kJoinPatience.count());
        }
        asked_to_join = true;
        asked_at = Clock::now();
        joined_from = announced;
        // What came before is history: the coordinator's first state and restored sectors, addressed to a
        // worker of this id that is gone (seen: a restarted worker showed a body where it was at frame 0).
        intake.start_over(latest.frame());
        wire::WorkerFrame ask = mark_of(0);
        ask.epoch(announced.epoch);
        marks_out->write(ask);
        return Joining::waiting;
    }
    if (!given) return Joining::waiting;
    // Given sectors from a later frame, whose owners send them whole at the frame before; or from the latest
    // frame, whose start came before this worker read the one that announced it (two starts in one read):
    // it has not started here yet, and the whole samples of the frame before are on their way.
    if (announced.from_frame < latest.frame()) {
        spdlog::error("worker {}: given sectors from frame {}, but frame {} has started already", options.id,
                      announced.from_frame, latest.frame());
        return Joining::failed;
    }
    if (early_planes.size() < latest.planes()) return Joining::waiting;
    if (!create_world(latest.next())) return Joining::failed;
    halo.follow(joined_from, announced, latest.next().largest_radius());
    // Not joined_from: assignments may have come between (its sectors' whole samples of the frame before
    // are under the epoch then in force, unknown here, and so let through).
    learn(announced);
    halo.apply(*world, {}, take_early_planes());
    // It is as if it had ended the frame before its sectors become its own: that frame's samples (its
    // sectors whole, and its halo) are the ones it starts from.
    frame = announced.from_frame - 1;
    gate.started(frame);
    spdlog::info("worker {}: joins the cluster with sectors of epoch {} from frame {}", options.id,
                 announced.epoch, announced.from_frame);
    return Joining::joined;
}

}  // namespace lpss::worker
