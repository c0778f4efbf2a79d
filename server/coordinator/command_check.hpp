// What the coordinator refuses of a client's command before it orders it: any peer on the domain (or a
// permitted but buggy client) can send anything, and a refusal names the reason. The rate limit is
// command_rate.hpp's; this is the command itself.
#pragma once

#include <string>
#include <unordered_map>

#include "lpss.h"
#include "lpss/common/body_desc.hpp"
#include "lpss/common/world_settings.hpp"

namespace lpss::coordinator {

/// Why `command` cannot be applied to a world of `settings` holding `bodies` (each body id, and whether it
/// is static); empty when it can. A spawn's body, when accepted, is left in `spawned`. A body must be valid
/// as a scene's (validate_body) with an id no body has; a removal, impulse or velocity must name a body;
/// a push cannot move a static body, and its vectors must be finite; other kinds are unknown. (A client's
/// "ready" is not a command to check: the coordinator answers it.)
std::string refusal(const wire::Command& command, const WorldSettings& settings,
                    const std::unordered_map<BodyId, bool>& bodies, BodyDesc& spawned);

}  // namespace lpss::coordinator
