#include "stability_cases.hpp"

#include <cmath>
#include <limits>
#include <sstream>

namespace lpss::stability {
namespace {

using scenes::Centre;
using scenes::shifted;
using Vec = Eigen::Vector3d;

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Runs a scene and watches its health: every body finite, owned by a live sector, none lost.
class Run {
public:
    explicit Run(const Scene& scene, const EngineOptions& options = {})
        : expected_bodies_(scene.bodies.size()) {
        Expected<World> created = World::create(scene, options);
        if (!created) {
            health = "scene refused: " + created.error().message;
            return;
        }
        world_.emplace(std::move(created).value());
    }

    bool ok() const { return world_.has_value() && health.empty(); }
    World& world() { return *world_; }

    /// Steps n frames, calling each(frame) after every one; checks health every 30 frames and at the end.
    void frames(int n, const std::function<void(int)>& each = {}) {
        if (!world_) return;
        for (int f = 0; f < n; ++f) {
            world_->step();
            const FrameStats& s = world_->last_frame_stats();
            engine_seconds += s.total_seconds;
            sector_changes += s.sector_changes;
            ++frames_run;
            if (each) each(f);
            if (f % 30 == 29 || f == n - 1) check();
        }
    }

    Vec at(BodyId id, const Centre& centre) const {
        std::optional<BodySnapshot> b = world_->body(id);
        if (!b) return Vec::Constant(std::numeric_limits<double>::quiet_NaN());
        return scenes::relative_position(world_->grid(), *b, centre);
    }
    Vec velocity(BodyId id) const { return world_->body(id)->linear_velocity; }
    double ms_per_frame() const { return frames_run ? 1e3 * engine_seconds / frames_run : 0.0; }

    std::string health;
    double engine_seconds = 0.0;
    int frames_run = 0;
    std::size_t sector_changes = 0;

private:
    void check() {
        if (!health.empty()) return;
        if (Status st = world_->check_consistency(); !st) {
            health = "frame " + std::to_string(world_->frame()) + ": " + st.error().message;
        } else if (world_->body_count() != expected_bodies_) {
            health = "frame " + std::to_string(world_->frame()) + ": bodies lost";
        }
    }

    std::optional<World> world_;
    std::size_t expected_bodies_;
};

Outcome outcome(const std::string& name, const Placement& where) {
    Outcome o;
    o.case_name = name;
    o.placement = where.name;
    return o;
}

void absorb(Outcome& o, const Run& run) {
    if (o.health.empty() && !run.health.empty()) o.health = run.health;
}

Scene empty_scene(double sector_size, bool gravity = true) {
    Scene s;
    s.settings.sector_size = sector_size;
    if (gravity) s.settings.gravity = Vec(0, -9.81, 0);
    return s;
}

// ---- stiff

Outcome mass_ratio(const Placement& where, double ratio) {
    Outcome o = outcome("stiff/mass_ratio_1:" + std::to_string(static_cast<int>(ratio)), where);
    Scene s = empty_scene(128);
    // Sequential impulses converge slowly on large mass ratios: with Bullet's defaults (one 1/60 s step,
    // 10 iterations) the heavy box squeezes the light one out and falls. A careful set-up: 4 substeps
    // (steps of 1/240 s, as Box2D v3 does by default), and 50 iterations for 1:1000.
    s.settings.substeps = 4;
    s.settings.solver_iterations = ratio > 500 ? 50 : 10;
    s.bodies.push_back(scenes::ground_plane(1000, where.centre));
    s.bodies.push_back(scenes::box_body(1, Vec::Constant(0.5), 1.0, shifted(where.centre, Vec(0, 0.5, 0))));
    s.bodies.push_back(scenes::box_body(2, Vec::Constant(0.5), ratio, shifted(where.centre, Vec(0, 1.5, 0))));
    Run run(s);
    run.frames(600);
    Vec top = run.at(2, where.centre);
    o.metrics.push_back({"heavy box sunk (units)", 1.5 - top.y(), ratio > 500 ? 0.05 : 0.01, false,
                         "the light box holds: it is pressed in by millimetres, not squeezed out"});
    o.metrics.push_back({"heavy box slid (units)", Vec(top.x(), 0, top.z()).norm(), ratio > 500 ? 0.05 : 0.02,
                         false, "nothing pushes it sideways: only solver creep (measured 0.003 and 0.026)"});
    o.ms_per_frame = run.ms_per_frame();
    absorb(o, run);
    return o;
}

Outcome tower(const Placement& where) {
    Outcome o = outcome("stiff/tower_30", where);
    // Bullet's defaults topple a 30-box tower anywhere but exactly at the origin (where rounding is
    // symmetric); 4 substeps and 20 iterations hold it.
    Scene s = scenes::box_stack(where.centre, 30, 128);
    s.settings.substeps = 4;
    s.settings.solver_iterations = 20;
    Run run(s);
    run.frames(600);
    Vec top = run.at(30, where.centre);
    o.metrics.push_back(
        {"top box height (units)", top.y(), 29.0, true, "standing: within a box of its 29.5 start"});
    o.metrics.push_back({"top box drift (units)", (top - Vec(0, 29.5, 0)).norm(), 0.15, false,
                         "with 4 substeps and 20 iterations the top creeps 0.01-0.05 in 10 s"});
    o.ms_per_frame = run.ms_per_frame();
    absorb(o, run);
    return o;
}

Outcome pyramid(const Placement& where) {
    // A two-dimensional pyramid: rows of 14, 13, ... 1 boxes (105 boxes), touching.
    Outcome o = outcome("stiff/pyramid_105", where);
    Scene s = empty_scene(128);
    s.bodies.push_back(scenes::ground_plane(1000, where.centre));
    std::vector<std::pair<BodyId, Vec>> start;
    BodyId id = 1;
    for (int row = 0; row < 14; ++row) {
        for (int n = 0; n < 14 - row; ++n) {
            Vec p(-6.5 + 0.5 * row + n, 0.5 + row, 0);
            s.bodies.push_back(scenes::box_body(id, Vec::Constant(0.5), 1.0, shifted(where.centre, p)));
            start.emplace_back(id++, p);
        }
    }
    Run run(s);
    run.frames(600);
    double worst = 0.0;
    for (const auto& [body, p] : start)
        worst = std::max(worst, (run.at(body, where.centre) - p).norm());
    o.metrics.push_back({"largest box displacement (units)", worst, 0.1, false,
                         "a resting pyramid only settles by solver slop, well under a tenth of a box"});
    o.ms_per_frame = run.ms_per_frame();
    absorb(o, run);
    return o;
}

// ---- fast

Scene wall_shot(const Centre& at, double sector_size, double speed, double wall_distance, bool ccd) {
    Scene s = empty_scene(sector_size, false);
    BodyDesc wall = scenes::box_body(2, Vec(0.05, 2, 2), 0.0, shifted(at, Vec(wall_distance, 0, 0)));
    s.bodies.push_back(wall);
    BodyDesc ball = scenes::sphere_body(1, 0.1, 0.1, at);
    ball.linear_velocity = Vec(speed, 0, 0);
    ball.ccd = ccd;
    s.bodies.push_back(ball);
    return s;
}

Outcome fast_wall(const Placement& where, bool ccd) {
    Outcome o =
        outcome(ccd ? "fast/1000_per_s_at_thin_wall_ccd" : "fast/1000_per_s_at_thin_wall_no_ccd", where);
    Run run(wall_shot(where.centre, 128, 1000.0, 20.0, ccd));
    run.frames(30);
    double x = run.at(1, where.centre).x();
    if (ccd) {
        o.metrics.push_back({"distance past the wall's face (units)", std::max(0.0, x - 19.95), 0.0, false,
                             "with continuous collision detection the ball must not pass a 0.1 thick wall"});
    } else {
        // Without ccd the ball moves 16.7 units a frame and a thin wall is missed, as in plain Bullet: it
        // ends past the wall, wherever it is; and far from the origin exactly as at it.
        o.metrics.push_back(
            {"distance past the wall's far face (units)", x - 20.05, 0.0, true,
             "no ccd: 16.7 units a frame tunnel through a 0.1 thick wall, as in plain Bullet"});
        if (where.name != "origin") {
            Run origin(wall_shot(Vec::Zero().eval(), 128, 1000.0, 20.0, false));
            origin.frames(30);
            o.metrics.push_back({"difference from the run at the origin (units)",
                                 std::fabs(x - origin.at(1, Vec::Zero().eval()).x()), 1e-3, false,
                                 "the same outcome as at the origin"});
            absorb(o, origin);
        }
    }
    o.ms_per_frame = run.ms_per_frame();
    absorb(o, run);
    return o;
}

Outcome fast_across_sectors(const Placement& where) {
    // L = 8 and 10 units a frame: the ball crosses more than a sector every frame and must still meet a
    // wall seven sectors ahead (found through its reach, cloned into its sector, hit by its ccd sweep).
    Outcome o = outcome("fast/several_sectors_per_frame", where);
    Scene s = wall_shot(where.centre, 8.0, 600.0, 60.0, true);
    Run run(s);
    int crossings_frames = 0;
    run.frames(20, [&](int) {
        if (run.world().last_frame_stats().sector_changes > 0) ++crossings_frames;
    });
    double x = run.at(1, where.centre).x();
    o.metrics.push_back({"distance past the wall's face (units)", std::max(0.0, x - 59.95), 0.0, false,
                         "the wall must stop the ball although it is many sectors ahead"});
    o.metrics.push_back({"frames with a sector change", static_cast<double>(crossings_frames), 4.0, true,
                         "the ball really crossed sectors on its way"});
    o.ms_per_frame = run.ms_per_frame();
    absorb(o, run);
    return o;
}

// ---- borders

Outcome resting_on(const Placement& where, bool corner) {
    // A box resting on the ground exactly astride a border (or centred on a corner of eight sectors),
    // awake for 60 s: it must neither jitter nor change sector back and forth.
    Outcome o =
        outcome(corner ? "borders/resting_on_eight_sector_corner" : "borders/resting_on_border", where);
    const double L = 64.0;
    Scene s = empty_scene(L);
    s.settings.sleeping = false;
    Vec box_at = corner ? Vec(L / 2, L / 2, L / 2) : Vec(L / 2, 0.5, 0);
    // Snap the border to the sector grid at the placement: the box straddles a real border there.
    SectorPosition base = scenes::centre_on(SectorGrid(L), where.centre);
    Centre grid_origin = SectorPosition{base.sector, Vec::Zero()};
    s.bodies.push_back(scenes::ground_plane(1000, shifted(grid_origin, box_at - Vec(0, 0.5, 0))));
    s.bodies.push_back(scenes::box_body(1, Vec::Constant(0.5), 1.0, shifted(grid_origin, box_at)));
    Run run(s);
    run.frames(60);  // settle for a second
    const std::size_t changes_before = run.sector_changes;
    Vec settled = run.at(1, grid_origin);
    Vec previous = settled;
    double jitter = 0.0;
    run.frames(3540, [&](int) {
        Vec now = run.at(1, grid_origin);
        jitter = std::max(jitter, (now - previous).norm());
        previous = now;
    });
    o.metrics.push_back({"sector changes after settling", double(run.sector_changes - changes_before), 0.0,
                         false, "hysteresis: a body resting on a border stays in its sector"});
    o.metrics.push_back({"largest move in one frame (units)", jitter, 1e-4, false,
                         "a resting box must not jitter: Bullet's own resting box moves by float noise"});
    o.metrics.push_back(
        {"drift over 59 s (units)", (previous - settled).norm(), 2e-3, false, "resting contact holds still"});
    o.ms_per_frame = run.ms_per_frame();
    absorb(o, run);
    return o;
}

Outcome oscillating(const Placement& where) {
    Outcome o = outcome("borders/oscillating_across_border", where);
    const double L = 64.0;
    Scene s = empty_scene(L, false);
    s.settings.sleeping = false;
    SectorPosition base = scenes::centre_on(SectorGrid(L), where.centre);
    Centre border = SectorPosition{base.sector, Vec(L / 2, 0, 0)};
    for (int n = 0; n < 2; ++n) {
        BodyDesc wall =
            scenes::box_body(10 + n, Vec(0.5, 3, 3), 0.0, shifted(border, Vec(n ? 12 : -12, 0, 0)));
        wall.material = Material{0, 1};
        s.bodies.push_back(wall);
    }
    BodyDesc ball = scenes::sphere_body(1, 0.5, 1.0, border);
    ball.linear_velocity = Vec(11, 0, 0);
    ball.material = Material{0, 1};
    s.bodies.push_back(ball);
    Run run(s);
    run.frames(3600);
    o.metrics.push_back({"sector changes in 60 s", double(run.sector_changes), 25.0, true,
                         "a round trip of 46 units at 11 units/s crosses the band twice: about 29 in 60 s"});
    // Two-sided: a ball that gains speed is as wrong as one that loses it (it gained 4.9% over 60 s while
    // Bullet's penetration push fed the bounces, and a one-sided "speed lost <= 0.05" passed it).
    o.metrics.push_back({"speed change either way (fraction)", std::fabs(1.0 - run.velocity(1).norm() / 11.0),
                         0.01, false,
                         "restitution 1 on ball and walls: about 30 bounces in 60 s keep the speed, border "
                         "crossings add and take nothing"});
    o.ms_per_frame = run.ms_per_frame();
    absorb(o, run);
    return o;
}

Scene pile(const Centre& corner, double sector_size) {
    // 1,000 bodies (spheres and boxes) in a 10 x 10 x 10 block around `corner`, falling on a ground 5
    // below it: with L = 16 and `corner` on a corner of the grid, the pile straddles eight sectors.
    Scene s = empty_scene(sector_size);
    s.bodies.push_back(scenes::ground_plane(5000, shifted(corner, Vec(0, -5, 0))));
    BodyId id = 1;
    for (int i = 0; i < 10; ++i) {
        for (int j = 0; j < 10; ++j) {
            for (int k = 0; k < 10; ++k) {
                Vec p(-4.95 + i * 1.1 + 0.03 * j, -4.4 + j * 1.1, -4.95 + k * 1.1 - 0.02 * j);
                Centre at = shifted(corner, p);
                s.bodies.push_back((i + j + k) % 2 ? scenes::sphere_body(id, 0.45, 1.0, at)
                                                   : scenes::box_body(id, Vec::Constant(0.4), 1.0, at));
                ++id;
            }
        }
    }
    return s;
}

struct PileShape {
    double mean_height = 0.0;
    double lowest = kInf;
    double kinetic = 0.0;      ///< per body
    double box_kinetic = 0.0;  ///< per box: boxes come to rest, spheres may roll away on the plane
    double fastest = 0.0;
};

PileShape measure_pile(Run& run, const Centre& corner) {
    PileShape p;
    int boxes = 0;
    for (BodyId id = 1; id <= 1000; ++id) {
        Vec at = run.at(id, corner);
        double ke = 0.5 * run.velocity(id).squaredNorm();
        p.mean_height += at.y() / 1000.0;
        p.lowest = std::min(p.lowest, at.y() + 5.0);
        p.kinetic += ke / 1000.0;
        p.fastest = std::max(p.fastest, run.velocity(id).norm());
        if (std::holds_alternative<Box>(run.world().description(id)->shape)) {
            p.box_kinetic += ke;
            ++boxes;
        }
    }
    p.box_kinetic /= boxes;
    return p;
}

Outcome dense_pile(const Placement& where) {
    Outcome o = outcome("borders/pile_1000_over_eight_sectors", where);
    const double L = 16.0;
    SectorPosition base = scenes::centre_on(SectorGrid(L), where.centre);
    Centre corner = SectorPosition{base.sector, Vec(L / 2, L / 2, L / 2)};
    Run run(pile(corner, L));
    run.frames(600);
    PileShape straddling = measure_pile(run, corner);
    // The same pile inside one sector (L = 128, centred), for reference. Spheres without rolling
    // friction roll away on the plane in both: kinetic energy is compared, not required to vanish.
    Run inside(pile(Vec::Zero().eval(), 128.0));
    inside.frames(600);
    PileShape reference = measure_pile(inside, Vec::Zero().eval());
    o.metrics.push_back({"mean height vs the same pile in one sector (units)",
                         std::fabs(straddling.mean_height - reference.mean_height), 0.25, false,
                         "the pile settles as it does without borders, within a quarter unit on average"});
    o.metrics.push_back({"lowest body centre above the ground (units)", straddling.lowest, 0.35, true,
                         "nothing sinks through the ground (boxes rest at 0.4, spheres at 0.45)"});
    o.metrics.push_back({"kinetic energy vs the same pile in one sector (ratio)",
                         straddling.kinetic / reference.kinetic, 1.5, false,
                         "borders add no energy: a chaotic pile varies by tens of percent, not by factors"});
    o.metrics.push_back({"fastest body vs the same pile in one sector (ratio)",
                         straddling.fastest / reference.fastest, 1.5, false,
                         "nothing is flung faster than without borders"});
    o.metrics.push_back({"kinetic energy per box after 10 s (J/kg)", straddling.box_kinetic, 0.05, false,
                         "the boxes come to rest"});
    o.ms_per_frame = run.ms_per_frame();
    absorb(o, run);
    absorb(o, inside);
    return o;
}

// ---- extremes

Outcome near_edge_of_grid(const Placement& where) {
    // Far placement for this case: sector indices near 2^62, the edge of the grid.
    Outcome o = outcome("extremes/sector_index_2^62", where);
    const std::int64_t edge = (std::int64_t{1} << 62) - 2;
    Centre at =
        where.name == "origin" ? where.centre : Centre(SectorPosition{{edge, -edge, edge}, Vec(10, 0, -20)});
    o.placement = where.name == "origin" ? "origin" : "sector (2^62-2, -(2^62-2), 2^62-2)";
    Run run(scenes::box_stack(at, 10, 128));
    run.frames(600);
    Vec top = run.at(10, at);
    o.metrics.push_back({"top box drift (units)", (top - Vec(0, 9.5, 0)).norm(), 0.15, false,
                         "a 10-box stack creeps about 0.06 in 10 s in Bullet"});
    Run spheres(scenes::sphere_pair(at, 128));
    spheres.frames(180);
    o.metrics.push_back({"spheres bounced (1 = yes)", spheres.velocity(1).x() < 0 ? 1.0 : 0.0, 1.0, true,
                         "they collide as at the origin"});
    o.ms_per_frame = run.ms_per_frame();
    absorb(o, run);
    absorb(o, spheres);
    return o;
}

Outcome time_step(const Placement& where, int hertz) {
    Outcome o = outcome("extremes/dt_1/" + std::to_string(hertz), where);
    Scene stack = scenes::box_stack(where.centre, 5, 128);
    stack.settings.dt = 1.0 / hertz;
    Run run(stack);
    run.frames(10 * hertz);
    Vec top = run.at(5, where.centre);
    o.metrics.push_back({"top box drift after 10 s (units)", (top - Vec(0, 4.5, 0)).norm(),
                         hertz < 30 ? 0.3 : 0.1, false,
                         "a 5-box stack stands at any step from 1/240 to 1/15 s (coarser steps creep more)"});
    Scene pair = scenes::sphere_pair(where.centre, 128);
    pair.settings.dt = 1.0 / hertz;
    Run spheres(pair);
    spheres.frames(3 * hertz);
    o.metrics.push_back({"spheres bounced (1 = yes)", spheres.velocity(1).x() < 0 ? 1.0 : 0.0, 1.0, true,
                         "4 units/s closing: even at 1/15 s a step moves 0.27, less than a radius"});
    o.ms_per_frame = run.ms_per_frame();
    absorb(o, run);
    absorb(o, spheres);
    return o;
}

Outcome tiny_bodies(const Placement& where) {
    Outcome o = outcome("extremes/tiny_bodies_0.01", where);
    Scene s = empty_scene(128);
    // At 0.02 a box moves a tenth of its size under gravity in one 1/60 s step, and Bullet's defaults
    // let the stack collapse; 4 substeps and 20 iterations hold it.
    s.settings.substeps = 4;
    s.settings.solver_iterations = 20;
    s.bodies.push_back(scenes::ground_plane(1000, where.centre));
    s.bodies.push_back(scenes::sphere_body(1, 0.01, 0.001, shifted(where.centre, Vec(0, 0.5, 0))));
    for (int n = 0; n < 5; ++n) {
        s.bodies.push_back(scenes::box_body(10 + n, Vec::Constant(0.01), 0.001,
                                            shifted(where.centre, Vec(1, 0.01 + 0.02 * n, 0))));
    }
    Run run(s);
    run.frames(300);
    o.metrics.push_back(
        {"sphere's rest height error (units)", std::fabs(run.at(1, where.centre).y() - 0.01), 0.001, false,
         "a 0.01 sphere dropped from 0.5 rests on the ground, not in it: within a tenth of its "
         "radius (measured 6e-10)"});
    o.metrics.push_back({"tiny stack top height (units)", run.at(14, where.centre).y(), 0.08, true,
                         "five 0.02 boxes stand (top at 0.09)"});
    o.ms_per_frame = run.ms_per_frame();
    absorb(o, run);
    return o;
}

Outcome sector_sized(const Placement& where) {
    // The largest body allowed (twice its bounding radius just under L) dropped across borders, and a
    // ball that rolls onto it.
    Outcome o = outcome("extremes/sector_sized_body", where);
    const double L = 32.0;
    const double h = 0.99 * L / (2.0 * std::sqrt(3.0));
    Scene s = empty_scene(L);
    SectorPosition base = scenes::centre_on(SectorGrid(L), where.centre);
    Centre grid_origin = SectorPosition{base.sector, Vec::Zero()};
    s.bodies.push_back(scenes::ground_plane(1000, grid_origin));
    s.bodies.push_back(
        scenes::box_body(1, Vec::Constant(h), 50.0, shifted(grid_origin, Vec(L / 2, h + 1, L / 2))));
    BodyDesc ball = scenes::sphere_body(2, 0.5, 1.0, shifted(grid_origin, Vec(L / 2, 2 * h + 4, L / 2 + 2)));
    s.bodies.push_back(ball);
    Run run(s);
    run.frames(300);
    Vec box = run.at(1, grid_origin);
    o.metrics.push_back({"big box rest height error (units)", std::fabs(box.y() - h), 0.05, false,
                         "it lands and rests on the ground across four sectors"});
    o.metrics.push_back({"ball height above the box top (units)", run.at(2, grid_origin).y() - 2 * h, 0.3,
                         true, "the ball lands on the big box, not through it"});
    o.ms_per_frame = run.ms_per_frame();
    absorb(o, run);
    return o;
}

// ---- conservation

Outcome conservation(const Placement& where) {
    // Spheres of mass 1 and 3 collide elastically on a border and inside one sector: momentum and
    // energy afterwards must agree.
    Outcome o = outcome("conservation/border_collision", where);
    auto make = [](const Centre& c) {
        Scene s = scenes::sphere_pair(c, 128);
        s.bodies[1].mass = 3.0;
        return s;
    };
    SectorPosition base = scenes::centre_on(SectorGrid(128), where.centre);
    Centre border = SectorPosition{base.sector, Vec(64, 0, 0)};
    Run across(make(border));
    Run inside(make(Vec::Zero().eval()));
    across.frames(180);
    inside.frames(180);
    auto momentum = [](Run& r) -> Vec { return r.velocity(1) + 3.0 * r.velocity(2); };
    auto energy = [](Run& r) {
        return 0.5 * r.velocity(1).squaredNorm() + 1.5 * r.velocity(2).squaredNorm();
    };
    o.metrics.push_back({"momentum difference (kg m/s)", (momentum(across) - momentum(inside)).norm(), 1e-4,
                         false, "the collision is computed alike on both sides of the border"});
    o.metrics.push_back({"energy difference (relative)", std::fabs(energy(across) / energy(inside) - 1.0),
                         1e-4, false, "no energy made or lost by the border"});
    o.metrics.push_back({"momentum drift across the border (kg m/s)",
                         (momentum(across) - Vec(2.0 - 3.0 * 2.0, 0, 0)).norm(), 0.05, false,
                         "total momentum before the collision was -4; Bullet's push-out adds a little"});
    o.ms_per_frame = across.ms_per_frame();
    absorb(o, across);
    absorb(o, inside);
    return o;
}

}  // namespace

bool Outcome::ok() const {
    if (!health.empty()) return false;
    for (const Metric& m : metrics) {
        if (!m.ok()) return false;
    }
    return true;
}

std::vector<Placement> placements() {
    // Far: 1e12 out on x and -1e12 on z, with offsets that are not sector multiples, so that the
    // sector-local coordinates differ from the origin's.
    return {{"origin", Vec::Zero().eval()}, {"far (1e12)", Vec(1e12 + 37.3, 0.0, -1e12 - 11.7)}};
}

std::vector<Case> all_cases() {
    return {
        {"stiff/mass_ratio_1:100", "a box 100 times heavier on a light one, 10 s",
         [](const Placement& p) { return mass_ratio(p, 100.0); }},
        {"stiff/mass_ratio_1:1000", "a box 1000 times heavier on a light one, 10 s",
         [](const Placement& p) { return mass_ratio(p, 1000.0); }},
        {"stiff/tower_30", "30 unit boxes stacked, 10 s", tower},
        {"stiff/pyramid_105", "a 2D pyramid of 105 boxes (base 14), 10 s", pyramid},
        {"fast/1000_per_s_at_thin_wall_ccd", "a 0.1 sphere at 1000 units/s at a 0.1 wall, ccd on",
         [](const Placement& p) { return fast_wall(p, true); }},
        {"fast/1000_per_s_at_thin_wall_no_ccd", "the same without ccd",
         [](const Placement& p) { return fast_wall(p, false); }},
        {"fast/several_sectors_per_frame", "L = 8, 10 units per frame, a wall 7 sectors ahead",
         fast_across_sectors},
        {"borders/resting_on_border", "a box resting astride a border, awake, 60 s",
         [](const Placement& p) { return resting_on(p, false); }},
        {"borders/resting_on_eight_sector_corner", "a box centred on a corner of 8 sectors, awake, 60 s",
         [](const Placement& p) { return resting_on(p, true); }},
        {"borders/oscillating_across_border", "a ball bouncing between walls across a border, 60 s",
         oscillating},
        {"borders/pile_1000_over_eight_sectors",
         "1,000 spheres and boxes falling on a corner of 8 sectors, 10 s", dense_pile},
        {"extremes/sector_index_2^62", "a stack and two spheres at sector indices near 2^62",
         near_edge_of_grid},
        {"extremes/dt_1/240", "a stack and two spheres at dt = 1/240 s",
         [](const Placement& p) { return time_step(p, 240); }},
        {"extremes/dt_1/15", "a stack and two spheres at dt = 1/15 s",
         [](const Placement& p) { return time_step(p, 15); }},
        {"extremes/tiny_bodies_0.01", "a 0.01 sphere and a stack of 0.02 boxes", tiny_bodies},
        {"extremes/sector_sized_body", "the largest body a sector allows, and a ball on it", sector_sized},
        {"conservation/border_collision", "momentum and energy of a 1:3 collision on a border", conservation},
    };
}

}  // namespace lpss::stability
