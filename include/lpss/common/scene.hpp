// Scenes: world settings plus bodies, read from Protobuf text files (common/proto/scene.proto) and
// validated as a whole, so that a bad scene is refused before anything of it is loaded.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "lpss/common/body_desc.hpp"
#include "lpss/common/expected.hpp"
#include "lpss/common/world_settings.hpp"

namespace lpss {

struct Scene {
    WorldSettings settings;
    std::vector<BodyDesc> bodies;
};

/// Checks one body against the settings it will live in: finite numbers, positive sizes, mass >= 0,
/// static planes, a bounding box no larger than the sector (when `sectorized`), a reachable position.
/// The message names the body and the field.
Status validate_body(const BodyDesc& body, const WorldSettings& settings, bool sectorized = true);

/// Validates the settings, every body and the uniqueness of ids; lists every problem found.
Status validate_scene(const Scene& scene, bool sectorized = true);

/// Parses a scene in Protobuf text format and validates it. `source` names the text in messages.
Expected<Scene> parse_scene(std::string_view text, std::string_view source = "scene", bool sectorized = true);

/// Reads and parses a scene file.
Expected<Scene> load_scene(const std::string& path, bool sectorized = true);

/// The scene in Protobuf text format, readable by parse_scene (numbers keep all 17 digits).
std::string format_scene(const Scene& scene);

}  // namespace lpss
