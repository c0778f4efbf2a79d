#include "lpss/common/logging.hpp"

#include <spdlog/spdlog.h>

#include <string>

namespace lpss {

Status set_log_level(std::string_view level) {
    spdlog::level::level_enum value = spdlog::level::from_str(std::string(level));
    // from_str answers "off" for any name it does not know: tell a typo from a real "off".
    if (value == spdlog::level::off && level != "off") {
        return Error{"unknown log level '" + std::string(level) + "' (trace, debug, info, warn, error, off)"};
    }
    spdlog::set_level(value);
    return {};
}

}  // namespace lpss
