#include "lpss_dds/shm_cleanup.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <string>

namespace lpss::dds {
namespace {

namespace fs = std::filesystem;
const fs::path kShmDir = "/dev/shm";

// Fast DDS keeps an "_el" lock file beside each participant segment, held (flock) for as long as the
// segment's owner lives: if we can take it exclusively, the owner is gone. This is the test that
// `fastdds shm clean` uses.
bool lock_is_free(const fs::path& lock_file) {
    const int fd = ::open(lock_file.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return false;
    const bool free = ::flock(fd, LOCK_EX | LOCK_NB) == 0;
    ::close(fd);
    return free;
}

// A port is in use while some process has its file mapped: senders map it too, and hold no lock.
std::set<std::string> mapped_shm_files() {
    std::set<std::string> mapped;
    std::error_code error;
    for (const fs::directory_entry& process : fs::directory_iterator("/proc", error)) {
        const std::string pid = process.path().filename().string();
        if (pid.find_first_not_of("0123456789") != std::string::npos) continue;
        std::ifstream maps(process.path() / "maps");
        std::string line;
        while (std::getline(maps, line)) {
            const auto at = line.find("/dev/shm/");
            if (at != std::string::npos) mapped.insert(fs::path(line.substr(at)).filename().string());
        }
    }
    return mapped;
}

// Since the file last changed (written, or created).
std::chrono::seconds age(const fs::path& file) {
    struct stat status {};
    if (::stat(file.c_str(), &status) != 0) return std::chrono::seconds(0);
    const std::time_t changed = std::max(status.st_mtime, status.st_ctime);
    return std::chrono::seconds(std::max<std::time_t>(0, std::time(nullptr) - changed));
}

}  // namespace

std::size_t remove_abandoned_shm(int domain, std::chrono::seconds min_age) {
    static const std::regex segment_lock("fastrtps_[0-9a-f]{16}_el");
    static const std::regex port("fastrtps_port([0-9]+)(_el|_sl)?");
    // The RTPS well-known ports: every port of a domain lies in [7400 + 250 d, 7400 + 250 (d + 1)).
    const long first_port = 7400 + 250L * domain;
    const long end_port = first_port + 250;

    std::size_t removed = 0;
    auto remove = [&removed](const fs::path& file) {
        std::error_code error;
        if (fs::remove(file, error)) ++removed;
    };
    std::error_code error;
    std::set<std::string> mapped;
    bool mapped_known = false;
    for (const fs::directory_entry& entry : fs::directory_iterator(kShmDir, error)) {
        const std::string name = entry.path().filename().string();
        std::smatch match;
        if (std::regex_match(name, segment_lock)) {
            // A participant starting now creates its lock file a moment before it takes the lock; segments
            // belong to no domain, so this may be another program's.
            if (age(entry.path()) < min_age || !lock_is_free(entry.path())) continue;
            remove(kShmDir / name.substr(0, name.size() - 3));
            remove(entry.path());
        } else if (std::regex_match(name, match, port)) {
            const long number = std::stol(match[1]);
            if (number < first_port || number >= end_port) continue;
            if (!mapped_known) {
                mapped = mapped_shm_files();
                mapped_known = true;
            }
            const std::string port_file = "fastrtps_port" + match[1].str();
            if (mapped.count(port_file) != 0) continue;
            // A listener holds the port's "_el"/"_sl" lock while it lives.
            const bool is_lock = match[2].matched;
            if (is_lock && !lock_is_free(entry.path())) continue;
            remove(entry.path());
            if (!is_lock) remove(kShmDir / ("sem." + port_file + "_mutex"));
        }
    }
    return removed;
}

std::optional<int> participant_id_with_fresh_ports(int domain, const std::set<int>& avoid) {
    // RTPS well-known ports: 7400 + 250 d + 10 + 2 id (discovery), + 11 + 2 id (user data); Fast DDS names
    // a shared-memory port after its number (fastrtps_port<N>, with _el, _sl and _mutex beside it).
    std::set<long> taken;
    static const std::regex port("fastrtps_port([0-9]+)(_el|_sl|_mutex)?");
    std::error_code error;
    for (const fs::directory_entry& entry : fs::directory_iterator(kShmDir, error)) {
        const std::string name = entry.path().filename().string();
        std::smatch match;
        if (std::regex_match(name, match, port)) taken.insert(std::stol(match[1].str()));
    }
    if (error) return std::nullopt;
    const long base = 7400 + 250L * domain;
    for (int id = 0; 11 + 2 * id < 250; ++id) {
        if (!avoid.count(id) && !taken.count(base + 10 + 2 * id) && !taken.count(base + 11 + 2 * id))
            return id;
    }
    return std::nullopt;
}

}  // namespace lpss::dds
