#include "shape_library.hpp"

#include <algorithm>
#include <cstring>
#include <functional>

#include "collision_shapes.hpp"

namespace lpss::engine {

namespace {

// Exact values, bit for bit: two bodies share a shape only where Bullet would build the same one.
void mix(std::size_t& h, double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    h ^= std::hash<std::uint64_t>{}(bits) + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
}

void mix(std::size_t& h, const Eigen::Vector3d& v) {
    for (int a = 0; a < 3; ++a)
        mix(h, v[a]);
}

std::size_t hash_of(const Shape& shape) {
    std::size_t h = shape.index();
    struct Visitor {
        std::size_t& h;
        void operator()(const Sphere& s) const { mix(h, s.radius); }
        void operator()(const Box& b) const { mix(h, b.half_extents); }
        void operator()(const Capsule& c) const {
            mix(h, c.radius);
            mix(h, c.height);
        }
        void operator()(const ConvexHull& c) const {
            for (const Eigen::Vector3d& p : c.points)
                mix(h, p);
        }
        void operator()(const Plane& p) const {
            mix(h, p.normal);
            mix(h, p.offset);
        }
    };
    std::visit(Visitor{h}, shape);
    return h;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool same_bits(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return same_bits(a.x(), b.x()) && same_bits(a.y(), b.y()) && same_bits(a.z(), b.z());
}

bool same_shape(const Shape& a, const Shape& b) {
    if (a.index() != b.index()) return false;
    if (const auto* s = std::get_if<Sphere>(&a)) return same_bits(s->radius, std::get<Sphere>(b).radius);
    if (const auto* x = std::get_if<Box>(&a))
        return same_bits(x->half_extents, std::get<Box>(b).half_extents);
    if (const auto* c = std::get_if<Capsule>(&a)) {
        const auto& d = std::get<Capsule>(b);
        return same_bits(c->radius, d.radius) && same_bits(c->height, d.height);
    }
    if (const auto* c = std::get_if<ConvexHull>(&a)) {
        const auto& d = std::get<ConvexHull>(b);
        if (c->points.size() != d.points.size()) return false;
        for (std::size_t n = 0; n < c->points.size(); ++n) {
            if (!same_bits(c->points[n], d.points[n])) return false;
        }
        return true;
    }
    const auto& p = std::get<Plane>(a);
    const auto& q = std::get<Plane>(b);
    return same_bits(p.normal, q.normal) && same_bits(p.offset, q.offset);
}

}  // namespace

std::shared_ptr<btCollisionShape> ShapeLibrary::get(const Shape& shape) {
    const std::size_t h = hash_of(shape);
    auto [first, last] = by_hash_.equal_range(h);
    for (auto it = first; it != last; ++it) {
        if (!same_shape(it->second.value, shape)) continue;
        if (std::shared_ptr<btCollisionShape> held = it->second.bullet.lock()) return held;
        std::shared_ptr<btCollisionShape> made = make_collision_shape(shape);
        it->second.bullet = made;
        return made;
    }
    std::shared_ptr<btCollisionShape> made = make_collision_shape(shape);
    by_hash_.emplace(h, Entry{shape, made});
    if (by_hash_.size() >= sweep_at_) sweep();
    return made;
}

std::size_t ShapeLibrary::live() const {
    std::size_t n = 0;
    for (const auto& [h, entry] : by_hash_)
        n += entry.bullet.expired() ? 0 : 1;
    return n;
}

void ShapeLibrary::sweep() {
    for (auto it = by_hash_.begin(); it != by_hash_.end();)
        it = it->second.bullet.expired() ? by_hash_.erase(it) : std::next(it);
    sweep_at_ = std::max<std::size_t>(64, 2 * by_hash_.size());
}

}  // namespace lpss::engine
