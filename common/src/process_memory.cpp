#include "lpss/common/process_memory.hpp"

#include <cstdio>
#include <cstring>
#include <string>

namespace lpss {

std::optional<MemoryUse> memory_use(pid_t pid) {
    const std::string path = pid == 0 ? "/proc/self/status" : "/proc/" + std::to_string(pid) + "/status";
    std::FILE* file = std::fopen(path.c_str(), "r");
    if (file == nullptr) return std::nullopt;
    MemoryUse use;
    bool found = false;
    char line[256];
    while (std::fgets(line, sizeof line, file) != nullptr) {
        unsigned long long kib = 0;
        if (std::sscanf(line, "VmRSS: %llu kB", &kib) == 1) {
            use.resident_bytes = kib * 1024;
            found = true;
        } else if (std::sscanf(line, "VmHWM: %llu kB", &kib) == 1) {
            use.peak_bytes = kib * 1024;
        } else if (std::sscanf(line, "RssShmem: %llu kB", &kib) == 1) {
            use.shared_bytes = kib * 1024;
        }
    }
    std::fclose(file);
    if (!found || use.resident_bytes == 0) return std::nullopt;  // gone, or a zombie not yet reaped
    return use;
}

std::optional<std::uint64_t> proportional_resident_bytes(pid_t pid) {
    const std::string path =
        pid == 0 ? "/proc/self/smaps_rollup" : "/proc/" + std::to_string(pid) + "/smaps_rollup";
    std::FILE* file = std::fopen(path.c_str(), "r");
    if (file == nullptr) return std::nullopt;
    std::optional<std::uint64_t> bytes;
    char line[256];
    while (!bytes && std::fgets(line, sizeof line, file) != nullptr) {
        unsigned long long kib = 0;
        if (std::sscanf(line, "Pss: %llu kB", &kib) == 1) bytes = kib * 1024;
    }
    std::fclose(file);
    return bytes;
}

}  // namespace lpss
