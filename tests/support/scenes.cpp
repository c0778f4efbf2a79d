#include "scenes.hpp"

#include <cmath>
#include <random>

namespace lpss::scenes {

SectorPosition centre_on(const SectorGrid& grid, const Centre& centre) {
    if (const auto* global = std::get_if<Eigen::Vector3d>(&centre)) return grid.from_global(*global).value();
    return grid.canonical(std::get<SectorPosition>(centre)).value();
}

Centre shifted(const Centre& centre, const Eigen::Vector3d& by) {
    if (const auto* global = std::get_if<Eigen::Vector3d>(&centre)) return Eigen::Vector3d(*global + by);
    SectorPosition p = std::get<SectorPosition>(centre);
    p.local += by;
    return p;
}

BodyDesc box_body(BodyId id, const Eigen::Vector3d& half_extents, double mass, const Centre& at) {
    BodyDesc b;
    b.id = id;
    b.name = "box" + std::to_string(id);
    b.shape = Box{half_extents};
    b.mass = mass;
    b.position = at;
    return b;
}

BodyDesc sphere_body(BodyId id, double radius, double mass, const Centre& at) {
    BodyDesc b;
    b.id = id;
    b.name = "sphere" + std::to_string(id);
    b.shape = Sphere{radius};
    b.mass = mass;
    b.position = at;
    return b;
}

BodyDesc ground_plane(BodyId id, const Centre& at, const Eigen::Vector3d& normal) {
    BodyDesc b;
    b.id = id;
    b.name = "ground";
    b.shape = Plane{normal.normalized(), 0.0};
    b.position = at;
    return b;
}

Scene sphere_pair(const Centre& centre, double sector_size, const Eigen::Vector3d& axis) {
    Scene scene;
    scene.settings.sector_size = sector_size;
    scene.settings.dt = 1.0 / 60.0;
    scene.settings.sleeping = false;
    const Eigen::Vector3d dir = axis.normalized();
    for (int n = 0; n < 2; ++n) {
        const double side = n == 0 ? -1.0 : 1.0;
        BodyDesc body;
        body.id = static_cast<BodyId>(n + 1);
        body.name = n == 0 ? "left" : "right";
        body.shape = Sphere{0.5};
        body.mass = 1.0;
        body.position = shifted(centre, side * 2.05 * dir);
        body.linear_velocity = -side * 2.0 * dir;
        body.material = Material{0.0, 1.0};
        scene.bodies.push_back(body);
    }
    return scene;
}

Scene sphere_octet(const Centre& centre, double sector_size) {
    Scene scene;
    scene.settings.sector_size = sector_size;
    scene.settings.sleeping = false;
    BodyId id = 1;
    for (int i = -1; i <= 1; i += 2) {
        for (int j = -1; j <= 1; j += 2) {
            for (int k = -1; k <= 1; k += 2) {
                Eigen::Vector3d dir = Eigen::Vector3d(i, j, k).normalized();
                BodyDesc body;
                body.id = id++;
                body.shape = Sphere{0.5};
                body.mass = 1.0;
                body.position = shifted(centre, 2.5 * dir);
                body.linear_velocity = -2.0 * dir;
                body.material = Material{0.0, 1.0};
                scene.bodies.push_back(body);
            }
        }
    }
    return scene;
}

Scene box_stack(const Centre& base, int count, double sector_size) {
    Scene scene;
    scene.settings.sector_size = sector_size;
    scene.settings.gravity = Eigen::Vector3d(0, -9.81, 0);
    scene.bodies.push_back(ground_plane(1000, base));
    for (int n = 0; n < count; ++n) {
        scene.bodies.push_back(box_body(static_cast<BodyId>(n + 1), Eigen::Vector3d::Constant(0.5), 1.0,
                                        shifted(base, Eigen::Vector3d(0, 0.5 + n, 0))));
    }
    return scene;
}

Scene resting_world(std::size_t resting, std::size_t moving, std::uint64_t seed) {
    Scene scene;
    scene.settings.sector_size = 64;
    scene.settings.gravity = Eigen::Vector3d(0, -9.81, 0);
    scene.settings.sleeping = true;
    scene.bodies.reserve(resting + moving + 1);
    scene.bodies.push_back(ground_plane(1, Eigen::Vector3d::Zero().eval()));
    const double spacing = 3.0;
    BodyId id = 2;
    const auto side = static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(resting))));
    // A square pyramid whose centre of mass is its origin: base 1 x 1 at y = -0.2, apex at y = 0.6.
    ConvexHull pyramid;
    for (double x : {-0.5, 0.5})
        for (double z : {-0.5, 0.5})
            pyramid.points.push_back(Eigen::Vector3d(x, -0.2, z));
    pyramid.points.push_back(Eigen::Vector3d(0, 0.6, 0));
    for (std::size_t n = 0; n < resting; ++n) {
        const double x = (static_cast<double>(n % side) - static_cast<double>(side) / 2) * spacing;
        const double z = (static_cast<double>(n / side) - static_cast<double>(side) / 2) * spacing;
        BodyDesc b;
        b.id = id++;
        b.mass = 1.0;
        b.asleep = true;
        double rest = 0.5;  // centre height at rest on the plane
        switch (n % 5) {
            case 0:
                b.shape = Box{Eigen::Vector3d::Constant(0.5)};
                break;
            case 1:
                b.shape = Sphere{0.5};
                break;
            case 2:
                b.shape = Capsule{0.4, 0.6};
                rest = 0.7;
                break;
            case 3:
                b.shape = pyramid;
                rest = 0.2;
                break;
            default:
                b.shape = Box{Eigen::Vector3d(0.8, 0.3, 0.4)};
                rest = 0.3;
                break;
        }
        b.position = Eigen::Vector3d(x, rest, z);
        scene.bodies.push_back(std::move(b));
    }
    // The balls: over a patch of about 100 x 100 units in the middle, between the resting bodies.
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<double> speed(-3.0, 3.0);
    const auto across = static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(moving))));
    for (std::size_t n = 0; n < moving; ++n) {
        const double x = (static_cast<double>(n % across) - static_cast<double>(across) / 2) * spacing + 1.5;
        const double z = (static_cast<double>(n / across) - static_cast<double>(across) / 2) * spacing + 1.5;
        BodyDesc ball = sphere_body(id++, 0.4, 1.0, Eigen::Vector3d(x, 2.0, z));
        ball.linear_velocity = Eigen::Vector3d(speed(random), 0.0, speed(random));
        ball.material = Material{0.3, 0.5};
        scene.bodies.push_back(std::move(ball));
    }
    return scene;
}

Scene drifting_lattice(int count, double sector_size, std::uint64_t seed) {
    Scene s;
    s.settings.sector_size = sector_size;
    s.settings.sleeping = false;
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<double> speed(-0.6, 0.6);
    // The smallest cube that holds them (std::cbrt(729) is 9.0000000000000018 here: its ceiling is 10).
    int side = 1;
    while (side * side * side < count)
        ++side;
    for (int n = 0; n < count; ++n) {
        Eigen::Vector3d p(1.2 * (n % side), 1.2 * (n / side % side), 1.2 * (n / (side * side)));
        BodyDesc b = n % 2 ? sphere_body(n + 1, 0.45, 1.0, p)
                           : box_body(n + 1, Eigen::Vector3d::Constant(0.4), 1.0, p);
        b.linear_velocity = Eigen::Vector3d(speed(random), speed(random), speed(random));
        s.bodies.push_back(b);
    }
    return s;
}

Eigen::Vector3d relative_position(const SectorGrid& grid, const BodySnapshot& body, const Centre& centre) {
    SectorPosition c = centre_on(grid, centre);
    return grid.offset_in(body.position, c.sector) - c.local;
}

}  // namespace lpss::scenes
