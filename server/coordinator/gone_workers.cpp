// Workers that are gone (killed, cut off, silent past their lease): the frame a gone worker did not finish is
// stepped here from the coordinator's copy of the world (restore_gone), its sectors go to the others, and a
// world whose every worker is gone waits for one to join. The writers' histories the coordinator holds for
// that (hold_history) are given back once every reader has them.
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <unordered_map>
#include <utility>

#include "commands.hpp"
#include "coordinator_state.hpp"
#include "heap.hpp"
#include "lost_frame.hpp"
#include "lpss/common/border_reach.hpp"
#include "lpss_dds/convert.hpp"

namespace lpss::coordinator {

void Coordinator::State::take_as_gone(std::uint32_t w, const char* why) {
    live.erase(w);
    restarted.erase(w);
    going.emplace(w, Going{why, seconds_since(frame_started)});
    // Its writers' later liveliness news is old news: a worker restarted under its id is another writer.
    forget_lapse(w);
    running_writer.erase(w);
    for (auto it = writer_of.begin(); it != writer_of.end();) {
        if (it->second != w) {
            ++it;
            continue;
        }
        lapses.forget(it->first);
        it = writer_of.erase(it);
    }
    spdlog::warn("coordinator: worker {} is taken as gone during frame {} ({}, {:.2f} s into the frame)", w,
                 frame, why, seconds_since(frame_started));
}

bool Coordinator::State::holds_samples_of(std::uint32_t w, std::uint64_t f) const {
    auto mark = marks.find({w, f});
    if (mark == marks.end()) return false;
    for (const wire::WrittenSector& written : mark->second.written()) {
        if (!intake.chain().holds(dds::from_wire(written.sector()), f, ~std::uint64_t{0})) return false;
    }
    return true;
}

wire::SectorFrame Coordinator::State::whole_from_mirror(const SectorKey& key, std::uint64_t f) const {
    wire::SectorFrame sample;
    sample.sector(dds::to_wire(key));
    sample.frame(f);
    sample.base(f);
    sample.worker(0);
    sample.complete(true);
    auto it = mirror.sectors().find(key);
    if (it == mirror.sectors().end()) return sample;
    for (const dds::SectorMirror::Body& body : it->second) {
        sample.bodies().push_back(dds::to_wire(body.state));
        sample.kinds().push_back(mirror.kind(body));
    }
    return sample;
}

void Coordinator::State::restore_gone(std::uint64_t f) {
    // Once every live worker has ended frame f: the workers taken as gone during it, all at once (two gone
    // in one frame, restored one after the other, sent the first one's sectors to the second).
    const auto started = Clock::now();
    std::set<std::uint32_t> unfinished;
    std::string names;
    for (const auto& [w, going_why] : going) {
        names += (names.empty() ? "" : ", ") + std::to_string(w);
        bool ended = marks.count({w, f}) != 0;
        if (ended && !holds_samples_of(w, f)) {
            // Its mark came, not yet every sample it lists (other topics, other queues): those in flight
            // come within moments, or never, from a dead writer. Without them its sectors cannot be restored
            // as it left them (seen: a body that moved between two of its sectors missing from both), so the
            // frame is stepped again here, as for a worker that did not end it.
            const auto until = Clock::now() + std::chrono::milliseconds(200);
            while (!holds_samples_of(w, f) && Clock::now() < until) {
                inbox.wait(std::chrono::milliseconds(5));
                pump();
            }
            if (!holds_samples_of(w, f)) {
                ended = false;
                spdlog::warn("coordinator: worker {} ended frame {}, but not every sample it wrote came", w,
                             f);
            }
        }
        if (ended) {
            // Its samples and requests of the frame stand.
            gone_after_ending.insert(w);
            spdlog::error(
                "coordinator: worker {} is gone after ending frame {} ({}); its sectors go to the others", w,
                f, going_why.why);
        } else {
            unfinished.insert(w);
            spdlog::error(
                "coordinator: worker {} is gone during frame {} ({}, {:.2f} s into the frame); its sectors "
                "go "
                "to the others",
                w, f, going_why.why, going_why.into_frame);
        }
    }
    // A sector whose samples came without their base, its whole sample not come yet: the copy holds it as
    // of an older frame, and nothing better is left of it once its owner is gone. Said, not hidden.
    for (const auto& [key, bodies] : mirror.sectors()) {
        if (going.count(current.owner_of(key)) && intake.wants_whole(key))
            spdlog::error(
                "coordinator: sector ({}, {}, {}) of worker {} is restored as of frame {}: its samples since "
                "came without their base, and it was gone before its whole sample came",
                key.i, key.j, key.k, current.owner_of(key), intake.chain().newest(key));
    }
    // The frames they did not finish, each stepped here from the world as every body was last published
    // (frame f - 1: everything received of it), with the handoffs and commands of frame f.
    take_samples(f - 1);
    std::vector<wire::SectorFrame> stepped;
    std::set<SectorKey> keys;
    std::vector<std::uint32_t> not_stepped;
    // How many sectors away a body awake can make another be stepped: two bodies are partners once their fat
    // boxes meet (each its bounding sphere widened by the border band, as the halo counts it, and by a slack
    // and a stretch along its velocity of up to L/8 each: L/2 for the two), so one sector for bodies small
    // beside a sector, more for bodies as wide as one.
    const double sector_size = settings.sector_size;
    const auto ring =
        1 + static_cast<std::int64_t>(std::floor(
                (2.0 * border_reach(settings, largest_radius, largest_radius, 0.0) + sector_size / 2.0) /
                sector_size));
    auto for_each_near = [ring](const SectorKey& key, auto&& each) {  // the sector itself included
        for (std::int64_t i = -ring; i <= ring; ++i)
            for (std::int64_t j = -ring; j <= ring; ++j)
                for (std::int64_t k = -ring; k <= ring; ++k)
                    each(key + SectorKey{i, j, k});
    };
    // Where something can change in the frame: near a sector with a body awake (a body there may wake
    // others), or one where a body is handed in. A sector with nothing of that near it is asleep throughout
    // the frame, as the engine leaves it: its state at f is its state at f - 1. Known only if every sample of
    // f - 1 is here (a sector woken then would look asleep): if not, everything may change.
    bool whole_frame_before = true;
    for (const auto& [key, mark] : marks) {
        if (key.second == f - 1)
            whole_frame_before = whole_frame_before && holds_samples_of(key.first, f - 1);
    }
    std::set<SectorKey> may_change;
    for (const auto& [key, bodies] : mirror.sectors()) {
        if (std::any_of(bodies.begin(), bodies.end(),
                        [](const dds::SectorMirror::Body& b) { return b.state.awake(); }))
            for_each_near(key, [&](const SectorKey& near) { may_change.insert(near); });
    }
    for (const wire::Handoff& h : in_flight)
        for_each_near(dds::from_wire(h.sector()), [&](const SectorKey& near) { may_change.insert(near); });
    for (std::uint32_t w : unfinished) {
        const auto step_start = Clock::now();
        // Only its sectors that may change are stepped again, with the sectors around them; the rest go to
        // their new owners as last published (building a world of every body it held took 3.6 s, the world
        // stopped meanwhile, for 252,000 bodies of a million resting ones on four workers). A command of the
        // frame may touch any sector: then all of them.
        const bool everything = !commands_in_flight.empty() || !whole_frame_before;
        std::set<SectorKey> own, to_step, around;
        for (const auto& [key, bodies] : mirror.sectors()) {
            if (current.owner_of(key) != w) continue;
            own.insert(key);
            if (everything || may_change.count(key)) to_step.insert(key);
        }
        // A sector a body is handed into may be empty so far, and in no copy.
        for (const wire::Handoff& h : in_flight) {
            if (h.to_worker() == w) to_step.insert(dds::from_wire(h.sector()));
        }
        for (const SectorKey& key : to_step) {
            for_each_near(key, [&](const SectorKey& near) {
                if (mirror.sectors().count(near)) around.insert(near);
            });
        }
        worker::LostFrameInput in;
        in.settings = settings;
        in.assignment = current;
        in.largest_radius = largest_radius;
        in.worker = w;
        in.frame = f;
        for (const SectorKey& key : around)
            in.sectors.push_back(whole_from_mirror(key, f - 1));
        for (const auto& [id, plane] : planes)
            in.planes.push_back(plane);
        in.handoffs = in_flight;
        in.commands = commands_in_flight;
        in.command_order = command_order_in_flight;
        Expected<worker::LostFrame> lost_frame = worker::step_lost_frame(in);
        in = {};
        if (!lost_frame) {
            spdlog::error(
                "coordinator: the frame worker {} did not finish cannot be stepped again ({}); its bodies "
                "are "
                "restored as last published",
                w, lost_frame.error().message);
            not_stepped.push_back(w);
            continue;
        }
        for (wire::SectorFrame& sample : lost_frame->sectors) {
            keys.insert(dds::from_wire(sample.sector()));
            stepped.push_back(std::move(sample));
        }
        // A worker that ended the frame answered its commands already.
        if (!marks.count({w, f})) {
            for (const wire::CommandResult& r : lost_frame->results)
                results_out->write(r);
        }
        stood_in.insert(stood_in.end(), lost_frame->leaving.begin(), lost_frame->leaving.end());
        // What the log says follows the decision taken above, not the conditions alone.
        std::string why;
        if (everything && !commands_in_flight.empty()) {
            why = fmt::format(" (all: the frame carries {} command(s))", commands_in_flight.size());
        } else if (everything) {
            why = " (all: a sample of the frame before has not come)";
        }
        spdlog::info(
            "coordinator: frame {} of worker {} stepped again here: {} of its {} sectors may change{}, "
            "stepped with {} sectors around them ({} bodies of its own; the rest, asleep throughout the "
            "frame, as they were), {:.3f} s",
            f, w, to_step.size(), own.size(), why, around.size(), lost_frame->bodies,
            seconds_since(step_start));
    }
    take_samples(f, stepped);
    // Not stepped: its bodies lose frame f's motion, restored as last published, and those handed to it at
    // frame f (its samples never showed them) from their grants.
    for (std::uint32_t w : not_stepped) {
        for (const wire::Handoff& h : in_flight) {
            if (h.to_worker() == w) mirror.insert(dds::from_wire(h.sector()), h.state(), h.kind());
        }
    }
    // The gone workers' ranges go to their neighbours on the curve. The live workers keep every sector they
    // have: a change from frame f + 1 is learnt at its start, too late for an owner to send a sector away
    // whole, so a sector moved between live workers here would reach its new owner empty. A change already
    // under way from f + 1 (announced with frame f, sent whole at f) goes on; one from a later frame is
    // dropped, and the workers it was to admit are admitted again later.
    SectorAssignment base = current;
    if (next.epoch != current.epoch) {
        if (next.from_frame <= f + 1) {
            base = next;
        } else {
            spdlog::warn("coordinator: the assignment of epoch {} from frame {} is dropped: a worker is gone",
                         next.epoch, next.from_frame);
            for (const auto& [w, from] : admitted) {
                joining.insert(w);
                joining_since[w] = Clock::now();
            }
            admitted.clear();
        }
    }
    std::vector<std::pair<SectorKey, double>> loads;
    for (const auto& [key, bodies] : mirror.sectors())
        loads.push_back({key, static_cast<double>(bodies.size())});
    SectorAssignment fresh = base;
    if (!held_for.empty()) {
        // No worker was left: the world goes to those that joined while it waited.
        fresh = SectorAssignment::balanced(
            loads, std::vector<std::uint32_t>(held_for.begin(), held_for.end()), options.block_size);
    } else {
        for (const auto& [w, going_why] : going)
            fresh = fresh.without(w, loads);
    }
    // Every sector a gone worker owned, or was to own from f + 1, whole at frame f to its holders under the
    // new assignment.
    for (const auto& [key, bodies] : mirror.sectors()) {
        if (going.count(current.owner_of(key)) || going.count(base.owner_of(key))) keys.insert(key);
    }
    std::vector<std::uint32_t> gone;
    for (const auto& [w, going_why] : going)
        gone.push_back(w);
    going.clear();
    send_restored(f, fresh, keys, gone, started);
    reassign(std::move(fresh), f + 1, ("worker(s) " + names + " gone").c_str());
    if (!held_for.empty()) {
        // The joiners learn their sectors from frame f's start, written again (they asked under its epoch).
        write_start_again(last_go.epoch());
        spdlog::info("coordinator: the world goes on from frame {} on worker(s) {}", f + 1,
                     fmt::join(held_for, ", "));
        held_for.clear();
    }
}

bool Coordinator::State::hold_until_a_worker_joins(std::uint64_t f, const std::atomic<bool>& stop) {
    const auto since = Clock::now();
    spdlog::error(
        "coordinator: every worker is gone during frame {}: the world ({} sectors) waits up to {} s for a "
        "worker to join",
        f, mirror.sectors().size(), options.worker_wait.count() / 1000.0);
    status("waiting for workers", 0.0, statics.size());
    // An assignment of no worker, in frame f's start written again: a worker asks to join under it without
    // first waiting to reach the workers that are gone (Worker::join). Only there, not on the assignment
    // topic: clients that read it there stopped at frame f (it names no worker to wait for, and they had
    // followed frame f under the assignment before).
    SectorAssignment none;
    none.block_size = options.block_size;
    none.epoch = next.epoch + 1;
    none.from_frame = f + 1;
    next = none;
    write_start_again(next.epoch);
    // Workers admitted from a later frame were to get their sectors from workers now gone: they read that
    // start too, and ask again (or, with a world already, join again as fresh workers).
    admitted.clear();
    for (std::uint32_t w : joining)
        joining_since[w] = Clock::now();
    // Only an ask under that assignment: it comes from a worker that has read it, whatever it did before.
    auto asked_under_it = [&](std::uint32_t w) {
        auto ask = marks.find({w, 0});
        return ask != marks.end() && ask->second.epoch() == next.epoch;
    };
    for (;;) {
        pump(sectors_in->unread() > kSampleBacklog);
        if (fenced || stop.load()) return false;
        for (auto it = joining.begin(); it != joining.end();) {
            if (!asked_under_it(*it) || !not_reaching(*it).empty()) {
                ++it;
                continue;
            }
            held_for.insert(*it);
            admitted[*it] = f + 1;
            joining_since.erase(*it);
            it = joining.erase(it);
        }
        if (!held_for.empty()) {
            spdlog::info("coordinator: worker(s) {} joined the world waiting at frame {}, after {:.2f} s",
                         fmt::join(held_for, ", "), f, seconds_since(since));
            return true;
        }
        if (Clock::now() - since > options.worker_wait) {
            spdlog::error("coordinator: every worker is gone, and none joined within {} s",
                          options.worker_wait.count() / 1000.0);
            return false;
        }
        inbox.wait(std::chrono::milliseconds(5));
    }
}

void Coordinator::State::write_start_again(std::uint32_t epoch) {
    last_go.epoch(epoch);
    last_go.next(assignment_on_wire());
    go_out->write(last_go);
}

void Coordinator::State::send_restored(std::uint64_t f, const SectorAssignment& fresh,
                                       const std::set<SectorKey>& keys,
                                       const std::vector<std::uint32_t>& gone, Clock::time_point started) {
    wire::WorkerFrame restored;
    restored.worker(0);
    restored.frame(f);
    restored.epoch(fresh.epoch);
    restored.stands_for(gone);
    std::size_t bodies = 0;
    for (const SectorKey& key : keys) {
        wire::SectorFrame sample = whole_from_mirror(key, f);
        sample.epoch(fresh.epoch);
        std::vector<double> radii;
        for (const wire::BodyKind& kind : sample.kinds())
            radii.push_back(bounding_radius(dds::from_wire(kind).shape));
        sample.recipients(recipients(key, sample.bodies(), radii, fresh));
        bodies += sample.bodies().size();
        sample.slot(slot_of(key));
        sectors_out->write(sample);
        intake.wrote(sample);
        wire::WrittenSector entry;
        entry.sector(sample.sector());
        entry.recipients(sample.recipients());
        restored.written().push_back(std::move(entry));
    }
    marks_out->write(restored);
    wrote_sectors = true;
    hold_history(f);
    spdlog::info(
        "coordinator: {} bodies in {} sectors sent to their new owners, {:.3f} s after the frame ended",
        bodies, keys.size(), seconds_since(started));
}

void Coordinator::State::hold_history(std::uint64_t f) {
    if (history_from) return;
    history_from = f;
    history_written_at = Clock::now();
}

void Coordinator::State::release_history(std::uint64_t f) {
    if (!history_from || f <= *history_from) return;
    // A reader that has not acknowledged them by then is dead (Fast DDS unmatches a dead participant's
    // readers after its lease, 20 s by default) or stalled; should it come back, it asks the sectors' owners
    // for them whole, as a reader that joins late does.
    constexpr auto kKeptAtMost = std::chrono::seconds(25);
    auto acknowledged_by_all = [](dds::Writer<wire::SectorFrame>& writer) {
        return writer.raw()->wait_for_acknowledgments(eprosima::fastrtps::Duration_t(0, 0)) ==
               eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK;
    };
    const bool acknowledged =
        acknowledged_by_all(*sectors_out) && (!first_state_out || acknowledged_by_all(*first_state_out));
    if (!acknowledged && Clock::now() - history_written_at < kKeptAtMost) return;
    std::size_t removed = 0;
    sectors_out->raw()->clear_history(&removed);
    // The first state's writer goes with what it held: its history and its copy of each sector's first
    // sample. Its readers lose a writer that will write nothing more.
    const bool first_state = first_state_out != nullptr;
    first_state_out.reset();
    spdlog::info(
        "coordinator: {} written from frame {} on ({} samples) leave the writer's history after frame {}: {}",
        first_state ? "the world's first state and the sectors" : "the sectors", *history_from,
        first_state ? std::string("all") : std::to_string(removed), f,
        acknowledged ? "every reader has them" : "a reader has not acknowledged them in 25 s");
    history_from.reset();
    runtime::give_back_free_memory();
}

}  // namespace lpss::coordinator
