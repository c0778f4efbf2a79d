// The coordinator's start: reading the scene (its status says how far it is), then writing the world's
// planes and first state, sector by sector, for the workers and the standby.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <unordered_map>
#include <utility>

#include "coordinator_state.hpp"
#include "heap.hpp"
#include "lpss/common/scene.hpp"
#include "lpss_dds/convert.hpp"

namespace lpss::coordinator {

Status Coordinator::State::load_and_seed(const std::atomic<bool>& stop) {
    const auto load_start = Clock::now();
    spdlog::info("coordinator: loading {}", options.scene_path);
    Expected<Scene> loaded = load_scene(options.scene_path);
    if (!loaded) return Error{"scene refused:\n" + loaded.error().message};
    Scene scene = std::move(loaded).value();
    settings = scene.settings;
    grid = SectorGrid(settings.sector_size);
    spdlog::info("coordinator: {} bodies read and checked in {:.2f} s", scene.bodies.size(),
                 seconds_since(load_start));
    if (Status st = check_not_replaced(); !st) return st;
    status("loading", 1.0, scene.bodies.size());

    // The workers announce themselves with frame 0.
    const auto wait_start = Clock::now();
    for (;;) {
        pump();
        std::vector<std::uint32_t> missing;
        for (std::uint32_t w = 1; w <= options.workers; ++w) {
            if (!marks.count({w, 0})) missing.push_back(w);
        }
        if (missing.empty()) break;
        if (stop.load()) return Error{"stopped"};
        if (Status st = check_not_replaced(); !st) return st;
        if (Clock::now() - wait_start > options.worker_wait) {
            std::string list;
            for (std::uint32_t w : missing)
                list += (list.empty() ? "" : ", ") + std::to_string(w);
            return Error{"worker(s) " + list + " did not appear on domain " +
                         std::to_string(participant->domain()) + " within " +
                         std::to_string(options.worker_wait.count() / 1000) + " s"};
        }
        inbox.wait(std::chrono::milliseconds(50));
    }
    for (std::uint32_t w = 1; w <= options.workers; ++w)
        live.insert(w);
    if (Status st = check_not_replaced(); !st) return st;  // before the planes go out

    // The first assignment: bodies per sector, balanced along the Morton curve.
    std::unordered_map<SectorKey, std::vector<std::uint32_t>, SectorKeyHash> by_sector;
    std::vector<SectorPosition> at(scene.bodies.size());
    for (std::uint32_t n = 0; n < scene.bodies.size(); ++n) {
        const BodyDesc& b = scene.bodies[n];
        if (const auto* g = std::get_if<Eigen::Vector3d>(&b.position)) {
            at[n] = grid.from_global(*g).value();
        } else {
            at[n] = grid.canonical(std::get<SectorPosition>(b.position)).value();
        }
        statics.emplace(b.id, b.is_static());
        if (!is_plane(b.shape)) largest_radius = std::max(largest_radius, bounding_radius(b.shape));
        if (is_plane(b.shape)) {
            planes[b.id] = b;
            BodySnapshot anchor;
            anchor.id = b.id;
            anchor.position = at[n];
            anchor.orientation = b.orientation;
            wire::BodyDescription d = dds::describe(b, anchor);
            d.rank(n);
            planes_out->write(d);
            plane_descriptions[b.id] = d;
        } else {
            by_sector[at[n].sector].push_back(n);
        }
    }
    std::vector<std::pair<SectorKey, double>> loads;
    for (const auto& [key, members] : by_sector)
        loads.push_back({key, static_cast<double>(members.size())});
    current = SectorAssignment::balanced(loads, std::vector<std::uint32_t>(live.begin(), live.end()),
                                         options.block_size);
    current.epoch = 1;
    current.from_frame = 1;
    next = current;
    publish_assignment();

    if (Status st = check_not_replaced(); !st) return st;
    // The world's first state, sector by sector, to the workers that hold each (writers filter for their
    // readers' recipient filters), in the scene's order so that workers add bodies as lpss-sim does.
    // Workers that are there have matched this writer; a later one gets these samples from its history.
    const auto send_start = Clock::now();
    std::vector<SectorKey> keys;
    keys.reserve(by_sector.size());
    for (const auto& [key, members] : by_sector)
        keys.push_back(key);
    std::sort(keys.begin(), keys.end());
    wire::WorkerFrame seeded;
    seeded.worker(0);
    seeded.frame(0);
    seeded.epoch(current.epoch);
    std::size_t sent = 0;
    std::vector<double> radii;
    for (const SectorKey& key : keys) {
        wire::SectorFrame sample;
        sample.sector(dds::to_wire(key));
        sample.frame(0);
        sample.base(0);
        sample.worker(0);
        sample.slot(slot_of(key));
        sample.epoch(current.epoch);
        sample.complete(true);
        for (std::uint32_t n : by_sector[key]) {
            const BodyDesc& b = scene.bodies[n];
            BodySnapshot s;
            s.id = b.id;
            s.position = at[n];
            s.orientation = b.orientation.normalized();
            s.linear_velocity = b.linear_velocity;
            s.angular_velocity = b.angular_velocity;
            s.awake = b.mass > 0.0 && !b.asleep;
            sample.bodies().push_back(dds::to_wire(s));
            sample.offsets().push_back(dds::to_wire(at[n].local));
            sample.kinds().push_back(dds::kind_of(b));
            sample.ranks().push_back(n);
            radii.push_back(bounding_radius(b.shape));
        }
        sample.recipients(recipients(key, sample.bodies(), radii, current));
        radii.clear();
        first_state_out->write(sample);
        mirror.apply({&sample});
        intake.wrote(sample);  // the base of the workers' first samples of the sector
        wire::WrittenSector entry;
        entry.sector(sample.sector());
        entry.recipients(sample.recipients());
        seeded.written().push_back(std::move(entry));
        if (++sent % 256 == 0)
            status("sending", static_cast<double>(sent) / static_cast<double>(keys.size()),
                   scene.bodies.size());
        if (stop.load()) return Error{"stopped"};
    }
    marks_out->write(seeded);
    status("sending", 1.0, scene.bodies.size());
    // A synchronization point: the clients asked for have matched every topic they read.
    auto last_word = Clock::now();
    while (ready_clients.size() < options.await_clients) {
        if (stop.load()) return Error{"stopped"};
        if (Clock::now() - last_word > std::chrono::seconds(5)) {
            last_word = Clock::now();
            spdlog::info("coordinator: frame 1 waits for {} client(s); {} ready", options.await_clients,
                         ready_clients.size());
        }
        accept_commands();
        inbox.wait(std::chrono::milliseconds(20));
    }
    // A standby, if one was asked for: from frame 1 on, every frame waits until it holds the frame's start.
    // Not for ever: a standby killed before its hello reached this coordinator is never heard (seen: the
    // world never started, lpss-cluster having said its standby had ended).
    const auto standby_wait_start = Clock::now();
    for (auto said = Clock::now(); options.await_standby && standby == 0;) {
        if (stop.load()) return Error{"stopped"};
        if (Status st = check_not_replaced(); !st) return st;
        if (Clock::now() - standby_wait_start > options.standby_wait) {
            spdlog::warn(
                "coordinator {}: no standby coordinator said it stands by within {:.0f} s: the world starts "
                "without one (no takeover should this coordinator end; a standby that comes later is too "
                "late)",
                options.id, std::chrono::duration<double>(options.standby_wait).count());
            break;
        }
        if (Clock::now() - said > std::chrono::seconds(5)) {
            said = Clock::now();
            spdlog::info("coordinator: frame 1 waits for a standby coordinator");
        }
        pump();
        inbox.wait(std::chrono::milliseconds(20));
    }
    spdlog::info("coordinator: {} sectors sent to {} worker(s) in {:.2f} s", keys.size(), live.size(),
                 seconds_since(send_start));
    // The scene is in the workers' hands now: give its memory back.
    scene = Scene{};
    by_sector.clear();
    at = {};
    runtime::give_back_free_memory();
    wrote_sectors = true;
    hold_history(0);
    return {};
}

}  // namespace lpss::coordinator
