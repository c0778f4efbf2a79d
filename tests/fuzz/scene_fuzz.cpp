// libFuzzer target: a scene file's text, as lpss-sim and the coordinator read it (parse and validate).
// Whatever the bytes, the loader must return a scene or a refusal that names the problem: no crash, no
// hang, no sanitizer finding.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "lpss/common/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    const lpss::Expected<lpss::Scene> scene = lpss::parse_scene(text, "fuzz");
    if (!scene && scene.error().message.empty()) __builtin_trap();  // a refusal must say why
    return 0;
}
