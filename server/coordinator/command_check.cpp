#include "command_check.hpp"

#include <cmath>

#include "lpss/common/scene.hpp"
#include "lpss_dds/convert.hpp"

namespace lpss::coordinator {

std::string refusal(const wire::Command& c, const WorldSettings& settings,
                    const std::unordered_map<BodyId, bool>& bodies, BodyDesc& spawned) {
    auto finite = [](const wire::Vec3d& v) {
        return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z());
    };
    auto known = bodies.find(c.body());
    switch (c.kind()) {
        case wire::kCommandSpawn: {
            spawned = dds::from_wire(c.spawn());
            if (c.spawn_global()) spawned.position = dds::from_wire(c.spawn().offset());
            if (Status st = validate_body(spawned, settings); !st) return st.error().message;
            if (bodies.count(spawned.id)) return describe_body(spawned) + ": id is used by another body";
            return {};
        }
        case wire::kCommandRemove:
            if (known == bodies.end()) return "unknown body id " + std::to_string(c.body());
            return {};
        case wire::kCommandImpulse:
        case wire::kCommandSetVelocity:
            if (known == bodies.end()) return "unknown body id " + std::to_string(c.body());
            if (known->second)
                return "body id " + std::to_string(c.body()) + ": is static and cannot be pushed";
            if (!finite(c.vector1()) || !finite(c.vector2()))
                return "body id " + std::to_string(c.body()) + ": command vectors must be finite";
            return {};
        default:
            return "unknown command kind " + std::to_string(c.kind());
    }
}

}  // namespace lpss::coordinator
