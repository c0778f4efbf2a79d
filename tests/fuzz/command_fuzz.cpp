// libFuzzer target: a client's command as the coordinator takes it off the wire from anyone on the domain,
// decoded from CDR and checked (coordinator::refusal). Whatever the bytes: no crash, no hang, no sanitizer
// finding, a refusal that says why, and nothing accepted that the world could not take (a spawn accepted is
// a valid body; a push accepted names a dynamic body with finite vectors).
#include <fastcdr/Cdr.h>
#include <fastcdr/FastBuffer.h>
#include <fastcdr/exceptions/Exception.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <new>
#include <vector>

#include "command_check.hpp"
#include "lpss.h"
#include "lpss/common/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::vector<char> bytes(data, data + size);
    eprosima::fastcdr::FastBuffer buffer(bytes.data(), bytes.size());
    eprosima::fastcdr::Cdr cdr(buffer, eprosima::fastcdr::Cdr::DEFAULT_ENDIAN,
                               eprosima::fastcdr::Cdr::DDS_CDR);
    lpss::wire::Command command;
    try {
        cdr.read_encapsulation();
        command.deserialize(cdr);
    } catch (const eprosima::fastcdr::exception::Exception&) {
        return 0;
    } catch (const std::bad_alloc&) {
        return 0;
    }
    lpss::WorldSettings settings;
    settings.sector_size = 64;
    const std::unordered_map<lpss::BodyId, bool> bodies = {{1, false}, {2, true}, {~lpss::BodyId{0}, false}};
    lpss::BodyDesc spawned;
    const std::string why = lpss::coordinator::refusal(command, settings, bodies, spawned);
    if (!why.empty()) return 0;  // refused, with a reason
    auto finite = [](const lpss::wire::Vec3d& v) {
        return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z());
    };
    switch (command.kind()) {
        case lpss::wire::kCommandSpawn:
            if (!lpss::validate_body(spawned, settings) || bodies.count(spawned.id)) __builtin_trap();
            break;
        case lpss::wire::kCommandImpulse:
        case lpss::wire::kCommandSetVelocity:
            if (!bodies.count(command.body()) || bodies.at(command.body()) || !finite(command.vector1()) ||
                !finite(command.vector2()))
                __builtin_trap();
            break;
        case lpss::wire::kCommandRemove:
            if (!bodies.count(command.body())) __builtin_trap();
            break;
        default:
            __builtin_trap();  // an unknown kind accepted
    }
    return 0;
}
