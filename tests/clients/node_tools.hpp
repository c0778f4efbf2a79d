// The npm test tools (tests/node, pinned by its lockfile and installed by deploy/setup.sh): a test that
// needs one is skipped, saying why, on a machine where the npm registry could not be reached.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <string>

namespace lpss::testing {

/// Why `module` cannot be used ("" if it can): not installed, or no Node.js.
inline std::string node_tool_missing(const std::string& module) {
    const std::filesystem::path installed =
        std::filesystem::path(LPSS_SOURCE_DIR) / "tests/node/node_modules" / module / "package.json";
    if (!std::filesystem::exists(installed))
        return "npm's " + module +
               " is not installed in tests/node (deploy/setup.sh could not reach the npm registry; see "
               "build/npm-ci.log)";
    if (std::system("node --version > /dev/null 2>&1") != 0)
        return "no Node.js (Debian's nodejs) on this machine";
    return {};
}

}  // namespace lpss::testing
