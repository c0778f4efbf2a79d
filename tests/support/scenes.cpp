#include "scenes.hpp"

#include <cmath>

namespace lpss::scenes {

SectorPosition centre_on(const SectorGrid& grid, const Centre& centre) {
    if (const auto* global = std::get_if<Eigen::Vector3d>(&centre))
        return grid.from_global(*global).value();
    return grid.canonical(std::get<SectorPosition>(centre)).value();
}

Centre shifted(const Centre& centre, const Eigen::Vector3d& by) {
    if (const auto* global = std::get_if<Eigen::Vector3d>(&centre))
        return Eigen::Vector3d(*global + by);
    SectorPosition p = std::get<SectorPosition>(centre);
    p.local += by;
    return p;
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
    BodyDesc ground;
    ground.id = 1000;
    ground.name = "ground";
    ground.shape = Plane{Eigen::Vector3d::UnitY(), 0.0};
    ground.position = base;
    scene.bodies.push_back(ground);
    for (int n = 0; n < count; ++n) {
        BodyDesc box;
        box.id = static_cast<BodyId>(n + 1);
        box.name = "box" + std::to_string(n + 1);
        box.shape = Box{Eigen::Vector3d::Constant(0.5)};
        box.mass = 1.0;
        box.position = shifted(base, Eigen::Vector3d(0, 0.5 + n, 0));
        scene.bodies.push_back(box);
    }
    return scene;
}

Eigen::Vector3d relative_position(const SectorGrid& grid, const BodySnapshot& body, const Centre& centre) {
    SectorPosition c = centre_on(grid, centre);
    return grid.offset_in(body.position, c.sector) - c.local;
}

}  // namespace lpss::scenes
