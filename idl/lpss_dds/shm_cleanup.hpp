// Removing the shared-memory files that Fast DDS leaves in /dev/shm when a process dies without closing
// its participant (SIGKILL, a crash): a test suite or a cluster that has stopped should leave the machine
// as it found it.
#pragma once

#include <chrono>
#include <cstddef>
#include <optional>
#include <set>

namespace lpss::dds {

/// Removes Fast DDS's abandoned shared-memory files: participant segments (of any domain) whose lock no
/// live process holds and that have not changed for `min_age`, and the port files of `domain` that no live
/// process maps. Call it for a domain whose participants (yours) have ended: a participant that starts
/// on `domain` while this runs could lose its port. Returns how many files it removed.
std::size_t remove_abandoned_shm(int domain, std::chrono::seconds min_age = std::chrono::seconds(10));

/// The lowest participant id on `domain` whose shared-memory ports have no file in /dev/shm: neither a live
/// participant's nor one a dead process left. Why not Fast DDS's own choice (the lowest id no live process
/// holds): a process that takes the ports of one that died finds them "zombie" and removes them without a
/// mark, and a writer that had opened them again meanwhile (to the dead reader, before its participant
/// lapses) keeps a removed segment that no one reads, and that looks healthy for ever (Fast DDS 2.9's
/// SharedMemGlobal). Seen: a worker restarted under its id matched the coordinator's writer and never
/// received a frame start. Ids in `avoid` are not taken. Empty if every id of the domain's port range is
/// taken.
std::optional<int> participant_id_with_fresh_ports(int domain, const std::set<int>& avoid = {});

}  // namespace lpss::dds
