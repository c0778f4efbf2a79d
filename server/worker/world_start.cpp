// A worker's start in a world that begins: the engine under the coordinator's settings, built from the
// world's first state (the coordinator's samples of the sectors it holds, and the planes).
#include "worker_state.hpp"

#include <spdlog/spdlog.h>

#include <unordered_map>

#include "heap.hpp"
#include "lpss_dds/convert.hpp"
#include "lpss_dds/topics.hpp"

namespace lpss::worker {

bool Worker::State::start_world(const wire::FrameGo& go, const std::atomic<bool>& stop) {
    const SectorAssignment current = dds::from_wire(go.next());
    halo.follow(current, current, go.next().largest_radius());
    learn(current);
    if (!create_world(go.next())) return false;
    // The world's first state: the coordinator's samples of the sectors this worker holds, and the planes.
    // Waits as long as the coordinator is there: a large world takes a while to send.
    const auto started = Clock::now();
    auto last_word = started;
    constexpr auto kNotYet = Clock::time_point::max();
    auto planes_matched_at = kNotYet;  // when this planes reader first had a writer
    auto planes_patience = std::chrono::seconds(5);
    while (!stop.load() && (!gate.whole(0, {}, true, intake.chain()) || early_planes.size() < go.planes())) {
        if (!coordinator_present()) {
            spdlog::error("worker {}: the coordinator went away while sending the world", options.id);
            return false;
        }
        inbox.wait(std::chrono::milliseconds(50));
        pump();
        // The planes are durable samples the coordinator wrote before this start: a reader matched to their
        // writer has them within moments. Twice a secured cluster's worker waited 30 s for "0 of 1 planes"
        // (2026-12-05; whether its reader had matched was not logged then). A new reader is a new match,
        // to which the writer sends its history again. Its patience doubles each time: a new reader starts
        // its matching over, and one matched only to the standby's writer (which writes no plane) must
        // not be made anew faster than a loaded machine matches the coordinator's.
        if (early_planes.size() < go.planes() && planes_in->matched() > 0) {
            if (planes_matched_at == kNotYet) {
                planes_matched_at = Clock::now();
            } else if (Clock::now() - planes_matched_at > planes_patience) {
                spdlog::warn(
                    "worker {}: {} of {} planes after {:.0f} s from {} matched writer(s): reading them anew",
                    options.id, early_planes.size(), go.planes(),
                    std::chrono::duration<double>(Clock::now() - started).count(), planes_in->matched());
                read_planes();
                if (!planes_in->ok()) {
                    spdlog::error("worker {}: cannot make its reader of the world's planes anew", options.id);
                    return false;
                }
                planes_matched_at = kNotYet;
                planes_patience *= 2;
            }
        }
        if (Clock::now() - last_word > std::chrono::seconds(5)) {
            last_word = Clock::now();
            spdlog::warn(
                "worker {}: still waiting for the world's first state after {:.0f} s: the coordinator's "
                "mark of it {}, {} of {} planes ({} writers of planes matched), {} sector samples of "
                "frame 0, {} writers of sector frames matched",
                options.id, std::chrono::duration<double>(Clock::now() - started).count(),
                gate.has_mark(0, 0) ? "here" : "missing", early_planes.size(), go.planes(),
                planes_in->matched(), intake.of_frame(0) ? intake.of_frame(0)->size() : 0,
                frames_in->matched());
        }
    }
    if (stop.load()) return false;
    const std::vector<std::pair<std::uint64_t, BodyDesc>> ranked_planes = take_early_planes();
    // Readers hold this worker's sectors as the coordinator sent them, from the coordinator's history:
    // publishing them again would send the whole world at frame 1 (200 MB for a million bodies) and stall
    // the first frames. Their first samples are partial, on the coordinator's.
    std::unordered_map<SectorKey, std::vector<std::uint32_t>, SectorKeyHash> seed_recipients;
    if (const std::vector<wire::SectorFrame>* first = intake.of_frame(0)) {
        for (const wire::SectorFrame& f : *first) {
            const SectorKey key = dds::from_wire(f.sector());
            if (f.worker() == 0 && halo.owns(key)) seed_recipients[key] = f.recipients();
        }
    }
    apply_samples(0, ranked_planes);
    for (const SectorKey& key : world->sectors()) {
        if (!halo.owns(key)) continue;
        auto seeded = seed_recipients.find(key);
        if (seeded == seed_recipients.end()) {
            adopted.insert(key);  // not from the coordinator's first state: published whole at frame 1
            continue;
        }
        const std::vector<BodySnapshot> all = world->sector_bodies(key);
        const dds::SectorPublisher::Counts before = publisher.counts(key);
        publisher.adopt(key, all, halo.near(*world, all, radii_of(*world, all)), 0);
        count_load(key, before);  // its load counts from now, though it may never change
        halo.addressed(key, seeded->second, 0);
    }
    // Building the world left the heap full of the freed samples that carried it: given back here, before
    // frame 1 is stepped, rather than after it, where it stalled the running world (0.37-0.41 s at a million
    // bodies, the whole cluster waiting on frame 2).
    runtime::give_back_free_memory();
    // A neighbour's sector comes here whole once one of its bodies comes near; only the bodies that come
    // near are ghosts in the engine, the rest wait as records (Halo::dormant).
    const double built_s = std::chrono::duration<double>(Clock::now() - started).count();
    std::size_t own_sectors = 0, ghosts = 0;
    for (const SectorKey& key : world->sectors()) {
        if (halo.owns(key)) {
            ++own_sectors;
            continue;
        }
        ghosts += world->sector_bodies(key).size();
    }
    spdlog::info(
        "worker {}: holds {} bodies in {} sectors ({} of its own) after {:.2f} s; {} of them ghosts near its "
        "own sectors; {} bodies of the sectors around kept out of the engine",
        options.id, world->body_count(), world->sectors().size(), own_sectors, built_s, ghosts,
        halo.dormant());
    return true;
}

bool Worker::State::create_world(const wire::Assignment& announced) {
    EngineOptions engine;
    engine.threads = options.threads;
    engine.owns = [this](const SectorKey& key) { return halo.owns(key); };
    Expected<World> created = World::create(dds::from_wire(announced.settings()), engine);
    if (!created) {
        spdlog::error("worker {}: the coordinator's settings are refused: {}", options.id,
                      created.error().message);
        return false;
    }
    world.emplace(std::move(created).value());
    return true;
}

void Worker::State::read_planes() {
    planes_in.reset();  // its endpoint goes before the new one is made
    dds::Participant& p = *participant;
    planes_in = std::make_unique<dds::Reader<wire::BodyDescription>>(
        p, p.topic<wire::BodyDescriptionPubSubType>(dds::kBodyDescriptions),
        dds::reader_qos(dds::kDescriptionReading), &inbox);
}

std::vector<std::pair<std::uint64_t, BodyDesc>> Worker::State::take_early_planes() {
    std::vector<std::pair<std::uint64_t, BodyDesc>> ranked;
    for (auto& [id, plane] : early_planes) {
        ranked.push_back(std::move(plane));
        planes.insert(id);
    }
    early_planes.clear();
    return ranked;
}

}  // namespace lpss::worker
