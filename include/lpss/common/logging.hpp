// Logging set-up shared by the lpss programs (spdlog).
#pragma once

#include <string_view>

#include "lpss/common/expected.hpp"

namespace lpss {

/// Sets the level of spdlog's default logger from a name: trace, debug, info, warn, error, off.
Status set_log_level(std::string_view level);

}  // namespace lpss
