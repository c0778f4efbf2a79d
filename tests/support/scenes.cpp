#include "scenes.hpp"

#include <cmath>

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

Eigen::Vector3d relative_position(const SectorGrid& grid, const BodySnapshot& body, const Centre& centre) {
    SectorPosition c = centre_on(grid, centre);
    return grid.offset_in(body.position, c.sector) - c.local;
}

}  // namespace lpss::scenes
