// dis: what lpss-dis puts on a DIS exercise, against one Entity State PDU per body per frame. The ECEF
// convoy scene (deploy/scenes) runs in one process, with 0, 1,000 and 10,000 parked vehicles (asleep) added
// beside the road; each frame's changes go through the gateway (lpss::dis::DisGateway, as lpss-dis runs
// it) with DRM_RVW or DRM_FVW and the DIS thresholds or tighter ones. Counts, not timings: the same
// scene gives the same PDUs on any machine.
#include <fmt/format.h>

#include <cmath>

#include "subcommands.hpp"

#if LPSS_BENCH_DRIVER
#include <unordered_map>

#include "dis_gateway.hpp"
#include "geodesy.hpp"
#include "lpss/common/scene.hpp"
#endif

namespace lpss::bench {

#if LPSS_BENCH_DRIVER
namespace {

/// The convoy scene with `parked` vehicles at rest (asleep) in rows north of the road.
Scene with_parked(Scene scene, int parked) {
    // The scene is in ECEF; its ground plane is tangent at the reference point of make_ecef_convoy.py.
    const dis::GeocentricFrame enu = dis::GeocentricFrame::local_tangent(51.1950, -1.8500, 130.0);
    const Eigen::Vector3d east = enu.rotation().col(0), north = enu.rotation().col(1),
                          up = enu.rotation().col(2);
    Eigen::Matrix3d axes;
    axes << east, -north, -up;  // DIS body axes: x forward, y right, z down
    const Eigen::Quaterniond facing_east(axes);
    const int per_row = 100;
    for (int n = 0; n < parked; ++n) {
        BodyDesc b;
        b.id = 1000 + static_cast<BodyId>(n);
        b.name = fmt::format("parked-{}", n + 1);
        b.shape = Box{Eigen::Vector3d(2.25, 0.9, 0.75)};
        b.mass = 9000.0;
        b.position = Eigen::Vector3d(enu.origin() + east * (-400.0 + 8.0 * (n % per_row)) +
                                     north * (40.0 + 6.0 * (n / per_row)) + up * 0.75);
        b.orientation = facing_east;
        b.asleep = true;
        scene.bodies.push_back(b);
    }
    return scene;
}

BodyView view_of(const BodySnapshot& s, const SectorGrid& grid) {
    BodyView b;
    b.id = s.id;
    b.position = s.position;
    b.global = grid.to_global(s.position);
    b.orientation = s.orientation;
    b.linear_velocity = s.linear_velocity;
    b.angular_velocity = s.angular_velocity;
    b.awake = s.awake;
    return b;
}

bool same(const BodySnapshot& a, const BodySnapshot& b) {
    return a.position.sector == b.position.sector && a.position.local == b.position.local &&
           a.orientation.coeffs() == b.orientation.coeffs() && a.linear_velocity == b.linear_velocity &&
           a.angular_velocity == b.angular_velocity && a.awake == b.awake;
}

}  // namespace
#endif

void run_dis(const Context& context) {
#if LPSS_BENCH_DRIVER
    auto convoy = load_scene(std::string(LPSS_SOURCE_DIR) + "/deploy/scenes/ecef_convoy.textproto");
    if (!convoy) throw std::runtime_error(convoy.error().message);
    const int frames = context.quick ? 360 : 1800;  // 6 s or 30 s of world time
    struct Setting {
        const char* name;
        std::uint8_t algorithm;
        double position_m;
        double orientation_deg;
    };
    const Setting settings[] = {
        {"RVW 1 m 3 deg (DIS defaults)", dis::dead_reckoning_algorithm::kRvw, 1.0, 3.0},
        {"FVW 1 m 3 deg", dis::dead_reckoning_algorithm::kFvw, 1.0, 3.0},
        {"RVW 0.1 m 1 deg", dis::dead_reckoning_algorithm::kRvw, 0.1, 1.0},
    };
    Table table({"scene", "entities", "dead_reckoning", "pdus_per_s", "bytes_per_s", "every_frame_pdus_per_s",
                 "fraction", "heartbeats_per_s"});
    std::string md;
    for (int parked : context.quick ? std::vector<int>{0, 1000} : std::vector<int>{0, 1000, 10000}) {
        const Scene scene = with_parked(*convoy, parked);
        for (const Setting& setting : settings) {
            progress(fmt::format("dis: {} parked, {}", parked, setting.name));
            World world = make_world(scene, EngineOptions{});
            const SectorGrid grid(scene.settings.sector_size);
            dis::GatewayOptions options;
            options.algorithm = setting.algorithm;
            options.thresholds.position_m = setting.position_m;
            options.thresholds.orientation_rad = setting.orientation_deg * M_PI / 180.0;
            options.relative_timestamps = true;
            auto made = dis::DisGateway::create(scene.settings, options);
            if (!made) throw std::runtime_error(made.error().message);
            dis::DisGateway& gateway = made.value();
            std::unordered_map<BodyId, BodyDesc> descs;
            for (const BodyDesc& b : scene.bodies)
                descs[b.id] = b;
            const dis::DisGateway::Describe describe = [&descs](const BodyView& b) {
                auto it = descs.find(b.id);
                return it == descs.end() ? std::optional<BodyDesc>() : std::optional<BodyDesc>(it->second);
            };
            // Frames of changes, as lpss::Client gives them to lpss-dis: every body first, then those
            // whose state changed.
            std::unordered_map<BodyId, BodySnapshot> before;
            std::uint64_t pdus_after_start = 0, heartbeats_at_start = 0;
            const int settle = 60;  // the first second sends every entity once: not the steady rate
            for (int f = 1; f <= frames; ++f) {
                world.step();
                WorldFrame frame;
                frame.frame = static_cast<std::uint64_t>(f);
                frame.every_body = f == 1;
                for (const BodySnapshot& s : world.snapshot()) {
                    auto it = before.find(s.id);
                    if (f == 1 || it == before.end() || !same(it->second, s))
                        frame.bodies.push_back(view_of(s, grid));
                    before[s.id] = s;
                }
                const std::size_t sent = gateway.take(frame, describe).size();
                if (f > settle) pdus_after_start += sent;
                if (f == settle) heartbeats_at_start = gateway.counts().heartbeats;
            }
            const double seconds = static_cast<double>(frames - settle) * scene.settings.dt;
            const double entities = static_cast<double>(scene.bodies.size() - 1);  // the ground is no entity
            const double pdus_per_s = static_cast<double>(pdus_after_start) / seconds;
            const double every = entities / scene.settings.dt;
            const double heartbeats =
                static_cast<double>(gateway.counts().heartbeats - heartbeats_at_start) / seconds;
            table.add({fmt::format("convoy + {} parked", parked), num(entities, 6), setting.name,
                       num(pdus_per_s, 4), num(pdus_per_s * dis::kEntityStatePduSize, 4), num(every, 4),
                       num(pdus_per_s / every, 3), num(heartbeats, 4)});
        }
    }
    md += fmt::format(
        "The ECEF convoy scene (deploy/scenes/ecef_convoy.textproto: 12 vehicles driving at 12 m/s that "
        "meet, "
        "20 crates at rest, on a ground plane tangent to the Earth 6.4e6 m from the origin) with 0 to 10,000 "
        "parked vehicles added (asleep), run in one process for {} frames at 60 Hz; each frame's changed "
        "bodies go through lpss-dis's gateway. Rates are over the world's time after its first second (which "
        "sends every entity once). every_frame_pdus_per_s: one Entity State PDU per entity per frame; "
        "fraction: what the gateway sends of that. PDUs are 144 bytes (no variable parameters).\n\n",
        frames);
    md += table.markdown();
    const std::string plot = R"(set title 'lpss-dis: Entity State PDUs per second'
set ylabel 'PDUs per second (log)'
set logscale y
set yrange [1:*]
set xrange [-0.6:*]
set style data histograms
set style histogram clustered gap 1
set style fill solid 0.8 border -1
set xtics rotate by -20 noenhanced
set key top left noenhanced
plot '$CSV' every ::1 using 4:xtic(stringcolumn(1).' / '.stringcolumn(3)) title 'lpss-dis (dead reckoned)', \
     '' every ::1 using 6 title 'one PDU per body per frame'
)";
    publish(context, "dis", table, "dis: what lpss-dis sends against one PDU per body per frame", md, plot);
#else
    (void)context;
    throw std::runtime_error("dis runs in the float build only");
#endif
}

}  // namespace lpss::bench
