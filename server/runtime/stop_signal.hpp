// Ctrl-C and SIGTERM as a flag the main loop polls. A signal handler can only touch process-wide state,
// so this is the one global of the server programs.
#pragma once

#include <atomic>

namespace lpss::runtime {

/// Installs handlers for SIGINT and SIGTERM (and ignores SIGPIPE) and returns the flag they set.
const std::atomic<bool>& install_stop_signal();

}  // namespace lpss::runtime
