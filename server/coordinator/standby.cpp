// A standby coordinator: it reads what the coordinator reads (the workers' marks and sector samples, the
// clients' commands) and the coordinator's frame starts, keeps the same copy of the world, and says of each
// frame start that it holds it (FrameAck); a worker starts a frame that names the standby only then, so the
// standby knows every frame any worker has started. When the coordinator's liveliness lease runs out, it
// takes over under a higher term from the coordinator's last frame start: it waits for that frame's end, as
// the coordinator would have, and starts the next. Workers drop the words of lower terms, and a coordinator
// that hears of a higher term stops (it was stopped or cut off, not dead).
#include <spdlog/spdlog.h>

#include <algorithm>

#include "coordinator_state.hpp"
#include "heap.hpp"
#include "lpss_dds/convert.hpp"
#include "lpss_dds/topics.hpp"

namespace lpss::coordinator {

namespace {
/// Sector samples a standby takes between two looks for a frame start: a start waits for this many at most
/// (a few dozen microseconds of work).
constexpr std::uint64_t kSamplesBetweenStarts = 16;
}  // namespace

void Coordinator::State::acknowledge(std::uint64_t f) {
    if (start_acks.acknowledged(term, f)) return;  // on sight, as it came
    acks_out->write(frame_ack(options.id, term, f));
    start_acks.note_acknowledged(term, f);
}

void Coordinator::State::follow_bodies(const wire::Command& c) {
    if (c.kind() == wire::kCommandSpawn) {
        const BodyDesc body = dds::from_wire(c.spawn());
        statics.emplace(body.id, body.is_static());
        if (!is_plane(body.shape)) largest_radius = std::max(largest_radius, bounding_radius(body.shape));
    } else if (c.kind() == wire::kCommandRemove) {
        statics.erase(c.body());
        planes.erase(c.body());
        plane_descriptions.erase(c.body());
    }
}

Expected<std::uint64_t> Coordinator::State::follow(const std::atomic<bool>& stop) {
    standing_by = true;
    spdlog::info("coordinator {}: standing by on domain {}", options.id, participant->domain());
    term = 0;  // the followed coordinator's, once its first start comes
    acknowledge(0);
    // The starts are taken as they come from now on, and acknowledged there when they may be; no longer once
    // this standby stops following (it took over, or stops).
    start_acks.start_taking(options.id, go_in->raw(), acks_out.get());
    struct StopTaking {
        StartAcknowledger& acks;
        ~StopTaking() { acks.stop_taking(); }
    } stop_taking{start_acks};
    std::map<std::uint64_t, wire::FrameGo> starts;  ///< read, not yet followed
    std::optional<wire::FrameGo> last;              ///< the latest followed (and acknowledged if it asked)
    auto forget = [&](const std::string& client, std::uint64_t request) {
        standing_commands.forget(client, request, request);
    };
    // The frame starts read, followed in order. Each is acknowledged as soon as it is read: workers wait for
    // the acknowledgement before they step, so what the follow costs after it (the frame's samples into
    // the copy of the world) is off their path. Nothing when the follow goes on; else what follow() returns.
    auto follow_starts = [&]() -> std::optional<Expected<std::uint64_t>> {
        start_acks.take_all([&](const wire::FrameGo& go, const dds::fdds::SampleInfo& info) {
            if (!info.valid_data || go.coordinator() == options.id || go.term() < term) return;
            lapses.heard(info.publication_handle, info.source_timestamp.to_ns());
            if (go.term() > term) {
                term = go.term();
                starts.clear();
            }
            primary_writer = info.publication_handle;
            if (!last || go.frame() > last->frame())
                starts[go.frame()] = go;  // a start written again replaces
        });
        while (!starts.empty()) {
            const wire::FrameGo& go = starts.begin()->second;
            if (go.stop()) {
                if (go.standby() == options.id) acknowledge(go.frame());  // (workers stop without it)
                spdlog::info("coordinator {}: the coordinator stopped the cluster after frame {}", options.id,
                             go.frame() - 1);
                return std::uint64_t{0};
            }
            // Every start in order from frame 1: one missed (read too late, while no frame waited for this
            // standby) may have carried commands and handoffs this copy of the world lacks.
            const std::uint64_t expected = last ? last->frame() + 1 : 1;
            if (go.frame() != expected)
                return Error{
                    expected == 1
                        ? "the world already runs (frame " + std::to_string(go.frame()) +
                              "): a standby must be there before frame 1"
                        : "missed the start of frame " + std::to_string(expected) +
                              " (the next read is of frame " + std::to_string(go.frame()) +
                              ") while the coordinator went on without this standby: it cannot take over"};
            // Frame 1 starts the world from its first state: held first, whole.
            if (go.frame() == 1) {
                bool held = first_state.has_value();
                for (std::size_t n = 0; held && n < first_state->size(); ++n)
                    held = intake.chain().holds((*first_state)[n], 0, ~std::uint64_t{0});
                if (!held) break;
            }
            frame = go.frame();
            next = dds::from_wire(go.next());
            if (next.from_frame <= frame || current.workers.empty()) current = next;
            largest_radius = std::max(largest_radius, go.next().largest_radius());
            for (std::uint32_t w : next.workers)
                joining.erase(w);
            for (std::size_t n = 0; n < go.commands().size(); ++n) {
                follow_bodies(go.commands()[n]);
                forget(go.commands()[n].client(), go.commands()[n].request());
                if (n < go.command_sequence().size())
                    followed_order = std::max(followed_order, go.command_sequence()[n]);
            }
            if (go.standby() == options.id) acknowledge(frame);
            forget_lapses_outlived(go);
            take_sector_samples();
            take_samples(frame - 1);
            // The world's first state is in the copy now, and the samples that carried it are freed: their
            // memory goes back, as the coordinator's does (about 0.18 KB a body, which the standby held
            // beyond the coordinator for the whole run). At frame 1, once acknowledged: the workers build and
            // step their first frame meanwhile. (At frame 3 it held back the acknowledgement of frame 4, and
            // every worker with it: 0.25-0.29 s at a million bodies.)
            if (frame == 1) runtime::give_back_free_memory();
            for (auto it = marks.begin(); it != marks.end();)
                it = it->first.second + 1 < frame ? marks.erase(it) : std::next(it);
            last = go;
            starts.erase(starts.begin());
        }
        return std::nullopt;
    };
    for (;;) {
        if (stop.load()) return std::uint64_t{0};
        // The samples read meanwhile, which may be many, a few at a time with the starts looked for in
        // between: taken all at once, a start read meanwhile waited for all of them, and every worker with
        // it. Those that come while this goes on wait for the next round, so that the other readers are
        // looked at too.
        if (auto ended = follow_starts()) return std::move(*ended);
        pump(false);
        for (std::uint64_t left = sectors_in->unread(); left > 0;) {
            const int taken = take_sector_samples(std::min<std::uint64_t>(left, kSamplesBetweenStarts));
            if (taken == 0) break;
            left -= std::min<std::uint64_t>(left, static_cast<std::uint64_t>(taken));
            if (auto ended = follow_starts()) return std::move(*ended);
        }
        if (auto ended = follow_starts()) return std::move(*ended);
        assignment_in->take_all([&](const wire::Assignment& a, const dds::fdds::SampleInfo& info) {
            if (!info.valid_data || a.coordinator() == options.id) return;
            settings = dds::from_wire(a.settings());
            grid = SectorGrid(settings.sector_size);
            largest_radius = std::max(largest_radius, a.largest_radius());
        });
        planes_in->take_all([&](const wire::BodyDescription& d, const dds::fdds::SampleInfo& info) {
            if (!info.valid_data) return;  // removals come as commands
            planes[d.id()] = dds::from_wire(d);
            plane_descriptions[d.id()] = d;
            statics[d.id()] = true;
        });
        commands_in->take_all([&](const wire::Command& c, const dds::fdds::SampleInfo& info) {
            if (info.valid_data) standing_commands.add(c);
        });
        // Answered (refused by the coordinator, or applied and answered by a worker): not this one's.
        results_in->take_all([&](const wire::CommandResult& r, const dds::fdds::SampleInfo& info) {
            if (!info.valid_data) return;
            const bool run = r.first_request() != 0 && r.first_request() < r.request();
            standing_commands.forget(r.client(), run ? r.first_request() : r.request(), r.request());
        });
        // The coordinator's first word names its participant: before frame 1 that is how its end is known.
        status_in->take_all([&](const wire::ClusterStatus& st, const dds::fdds::SampleInfo& info) {
            if (!info.valid_data || st.coordinator() == options.id || primary_participant) return;
            primary_participant = dds::participant_of(info.publication_handle);
            status_writers = status_in->matched();
        });
        // Before any frame start was read (once one was, the coordinator is known by its writer, and a start
        // read and not yet followed waits for the first state whole, then is taken over from as usual).
        const bool before_any_start = !last && !primary_writer && starts.empty();
        // Its participant gone (its lease ran out), should its writers' lapse not have been heard here (a
        // coordinator killed before its first liveliness beat reached this standby).
        const bool participant_gone =
            before_any_start && primary_participant && status_in->matched() < status_writers;
        if (participant_gone) primary_lost = true;
        if (before_any_start && primary_participant && !said_it_follows &&
            heard_alive_before_frame_1.count(*primary_participant)) {
            said_it_follows = true;
            spdlog::info(
                "coordinator {}: follows the coordinator, which reads the scene; should it go before it "
                "sends any of the world, this standby starts the world",
                options.id);
        }
        if (primary_lost && before_any_start) {
            // Gone before frame 1. While it read the scene no worker had a word of the world, and this
            // standby can start it from the scene as well (a million bodies take half a minute to read: a
            // coordinator killed then ended the world). Once some of the first state went out, workers may
            // hold part of it, from a writer now gone: a second start over that is not attempted.
            if (!first_state_begun) return kStartTheWorld;
            // A lapse alone is not an end here: a coordinator sending a large world on a loaded machine
            // misses its 0.3 s lease now and then (seen under AddressSanitizer: the standby stopped, and the
            // world ran without one). Nothing could be taken over from anyway, so this standby waits for the
            // coordinator's writers to come back, or for its participant to go (its lease, 20 s).
            if (participant_gone)
                return Error{
                    "the coordinator is gone while it sent the world's first state, before frame 1: this "
                    "standby cannot take over (it takes over from a frame start, and none came)"};
            if (!said_lapse_in_first_state) {
                said_lapse_in_first_state = true;
                spdlog::warn(
                    "coordinator {}: the coordinator's lease lapsed while it sent the world's first state; "
                    "this standby waits for it to come back (or for its participant to go, then stops: "
                    "there is no frame start to take over from)",
                    options.id);
            }
        } else if (said_lapse_in_first_state && before_any_start) {
            said_lapse_in_first_state = false;
            spdlog::info("coordinator {}: the coordinator is back; this standby follows it again",
                         options.id);
        }
        if (primary_lost && last) {
            // A start acknowledged on sight since the loop last looked is followed first: workers may have
            // started it, so the takeover is from it. None is acknowledged from now on.
            start_acks.stop_taking();
            if (auto ended = follow_starts()) return std::move(*ended);
            if (last->standby() != options.id)
                return Error{
                    "the coordinator is gone, and it had stopped waiting for this standby at frame " +
                    std::to_string(last->frame()) +
                    ": frames may have started that this standby does not know; it cannot take over"};
            take_over(*last);
            return last->frame();
        }
        inbox.wait(std::chrono::milliseconds(5));
    }
}

void Coordinator::State::forget_lapses_outlived(const wire::FrameGo& go) {
    // A lapse noted at frame F is over for a worker that ended frame F + 1 or later: no worker starts a
    // frame before this standby has acknowledged its start, and that of F + 1 was acknowledged after the
    // lapse was noted, so the worker under that id was alive since. Its marks alone do not always say so: a
    // worker restarted under the id writes with another writer, which this standby may not have matched yet
    // (discovery is slow on a loaded machine), and at its takeover it took that live worker as gone (seen
    // under AddressSanitizer, "taken as gone ... 0.00 s into the frame"). The coordinator's frame starts
    // name the workers that ended the frame before.
    // (Unless frames started without it: the coordinator dropped this standby for a while.)
    if (go.standby() != options.id) started_without_standby = go.frame();
    for (std::uint32_t w : go.ended()) {
        auto since = lost_since.find(w);
        if (since == lost_since.end() || go.frame() < since->second.frame + 2 ||
            started_without_standby > since->second.frame)
            continue;
        spdlog::info("coordinator {}: worker {} ended frame {}, begun after its lease lapsed: alive",
                     options.id, w, go.frame() - 1);
        forget_lapse(w);
    }
}

void Coordinator::State::lead() {
    standing_by = false;
    marks_in->wake(dds::Wake::on_data);  // a coordinator waits for the marks of each frame
}

void Coordinator::State::start_instead() {
    lead();
    // The coordinator that went never started a frame: its term was the first.
    term = 2;
    // What it wrote of the world before it went (the planes, durable) comes again from the scene.
    statics.clear();
    planes.clear();
    plane_descriptions.clear();
    largest_radius = 0.0;
    dds::Participant& p = *participant;
    first_state_out = std::make_unique<dds::Writer<wire::SectorFrame>>(
        p.sector_publisher(), p.topic<wire::SectorFramePubSubType>(dds::kSectorFrames),
        dds::writer_qos(dds::kFirstStateDelivery));
    status("loading", 0.0, 0);
    spdlog::warn(
        "coordinator {}: the coordinator is gone before frame 1, and no worker had any of the world: this "
        "standby reads the scene and starts the world under term {}",
        options.id, term);
}

std::size_t Coordinator::State::decide_standing_commands() {
    const std::vector<wire::Command> standing = standing_commands.take_all();
    for (const wire::Command& c : standing)
        decide(c);
    answer_over_rate();
    last_request = standing_commands.newest();
    return standing.size();
}

void Coordinator::State::take_over(const wire::FrameGo& go) {
    lead();
    term = go.term() + 1;
    frame = go.frame();
    last_go = go;
    // The cluster as the coordinator left it at its last start: that frame's assignment, handoffs and
    // commands, the workers that run it.
    next = dds::from_wire(go.next());
    if (next.from_frame <= frame) current = next;
    live = std::set<std::uint32_t>(current.workers.begin(), current.workers.end());
    admitted.clear();
    for (std::uint32_t w : next.workers) {
        if (!live.count(w)) admitted[w] = next.from_frame;
    }
    // The lapses of workers the coordinator no longer ran were its to act on, and it did: it took them as
    // gone. A worker it let in again under such an id writes with another writer; one it let in whose own
    // writer (the newest heard under its id) lapsed is dead, and that lapse stays.
    for (auto it = lost_since.begin(); it != lost_since.end();) {
        const auto newest = newest_writer.find(it->first);
        const bool joiners_own =
            admitted.count(it->first) && newest != newest_writer.end() && newest->second == it->second.writer;
        if (live.count(it->first) || joiners_own) {
            ++it;
            continue;
        }
        lost.erase(it->first);
        it = lost_since.erase(it);  // (forget_lapse would leave `it` dangling)
    }
    in_flight = go.handoffs();
    commands_in_flight = go.commands();
    command_order_in_flight = go.command_sequence();
    next_order = followed_order + 1;
    wrote_sectors = false;
    frame_started = Clock::now();
    for (std::uint32_t w : live)
        last_heard[w] = frame_started;
    // A gone worker's sectors it restored at this frame: the next start says so, for the workers to wait for.
    wrote_sectors = primary_wrote.count(frame) != 0;
    // Commands read and neither applied nor answered are this coordinator's now, in the order read.
    // Their request numbers have gaps where the coordinator answered: not lost, so not checked for gaps;
    // those are looked for from the newest request read of each client on.
    const std::size_t standing = decide_standing_commands();
    publish_assignment();
    // The coordinator's last frame start may not have reached every worker: a writer killed while it
    // delivers a sample leaves some readers without it, and nobody sends it again (seen: a worker restarted
    // earlier never had frame 231's start while the others stepped it, and was taken as gone 5 s later).
    // It is written again under this term: a worker that had it has started that frame and looks no more
    // at its start; one still waiting (for it, or for the acknowledgement of the standby it named) starts.
    // The planes' descriptions went with the coordinator's writer; a worker that joins from now on waits for
    // as many as a start counts.
    for (const auto& [id, description] : plane_descriptions)
        planes_out->write(description);
    last_go.coordinator(options.id);
    last_go.term(term);
    last_go.standby(standby);
    go_out->write(last_go);
    status("running", 0.0, statics.size());
    spdlog::warn(
        "coordinator {}: the coordinator's lease ran out after it started frame {}: taking over under term "
        "{} "
        "({} workers, {} bodies, {} commands it had not applied or answered)",
        options.id, frame, term, live.size(), statics.size(), standing);
}

}  // namespace lpss::coordinator
