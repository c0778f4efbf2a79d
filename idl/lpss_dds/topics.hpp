// The lpss topics: names, and the QoS of their writers and readers, in one place (docs/protocol.md has
// the same as a table).
#pragma once

#include <chrono>

#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>

namespace lpss::dds {

inline constexpr const char* kSectorFrames = "lpss/sector_frames";
inline constexpr const char* kBodyDescriptions = "lpss/body_descriptions";
inline constexpr const char* kSectorOwners = "lpss/sector_owners";
inline constexpr const char* kWorkerFrames = "lpss/worker_frames";
inline constexpr const char* kFrameGo = "lpss/frame_go";
inline constexpr const char* kCommands = "lpss/commands";
inline constexpr const char* kCommandResults = "lpss/command_results";
inline constexpr const char* kSectorRequests = "lpss/sector_requests";
inline constexpr const char* kStatus = "lpss/status";
inline constexpr const char* kFrameAcks = "lpss/frame_acks";

/// How a topic is delivered.
struct Delivery {
    bool durable = false;   ///< TRANSIENT_LOCAL: a late joiner gets the last sample of every instance
    int depth = 1;          ///< KEEP_LAST depth per instance
    bool disposes = false;  ///< instances are disposed (see with_delivery in participant.cpp)
    /// > 0: writers' liveliness is asserted by their participant (LivelinessBeat, participant.hpp) within
    /// this lease, in milliseconds, and readers ask for it: a reader learns within the lease that a writer
    /// is gone (killed, or cut off).
    int lease_ms = 0;
    /// > 0: a writer drops a sample from its history this many milliseconds after writing it (DDS lifespan),
    /// whatever its depth; readers keep what they took. 0: samples stay until the depth pushes them out.
    int lifespan_ms = 0;
};

/// Body descriptions and the cluster's status: durable, the latest sample per instance; descriptions are
/// disposed.
inline constexpr Delivery kStateDelivery{true, 1, true};
/// Assignments: durable, the last 16 of each coordinator. A reader must learn every assignment of the frames
/// it shows, not only the latest: two written a few frames apart (a worker gone, then one joining) left a
/// reader of depth 1 that took the second without the first, waiting for a gone worker's end of a frame.
inline constexpr Delivery kAssignmentDelivery{true, 16};
/// Sector frames as a worker writes them: all in one instance (idl/lpss.idl), its last 2048 samples kept,
/// oldest out first, so that its history has no holes (see SectorFrame), and none older than half a second.
/// A partial sample is of use only on the sample before it: a reader that lost one (a socket or
/// shared-memory port full while it was busy) gets it repaired from there at the next heartbeat (100 ms;
/// 2048 samples last 170 ms at the 12,000 a second of the drifting late-join scene), or else asks for the
/// sector whole, as a reader that joins late does. Kept by count alone, the history held seconds of
/// samples, most of a worker's memory beyond its world's: with cluster-scale's 10,000-body scene on two
/// workers (`lpss-cluster SCENE --workers 2 --frames 1200`), the busier worker held 65-66 MiB, 37-40 with
/// the lifespan, and the cluster 145-164 MiB against 123-129. Half a second covers the repair with room.
/// 8192 samples cost a worker 18 MiB more at 10,000 bodies.
inline constexpr Delivery kSectorFrameDelivery{true, 2048, false, 0, 500};
/// The coordinator's: one instance per sector (the world's first state, written once; the sectors of a
/// worker that is gone), a few deep.
inline constexpr Delivery kFirstStateDelivery{true, 8};
/// Readers keep more, per instance: a burst of sectors sent whole (a rebalance) is not taken until written.
inline constexpr Delivery kSectorFrameReading{true, 8192};
/// Body descriptions as read: every instance's latest.
inline constexpr Delivery kDescriptionReading{true, 1, true};
/// Frame starts and worker frames: durable, a few frames deep per instance so that a slow reader does
/// not lose a frame's marker to the next one.
inline constexpr Delivery kFrameDelivery{true, 8};
/// Marks as clients read them: two seconds of frames per worker, so that a client busy taking a burst of
/// sector samples (another reader joined, a rebalance) loses none and need not ask for inventories again.
inline constexpr Delivery kMarksReading{true, 120};
/// A worker's marks, as the workers write them and the coordinator reads them: they carry the worker's
/// liveliness, so that a worker killed or cut off is found within the lease (0.3 s, and 0.15 s more to be
/// sure: server/coordinator/confirmed_lapses.hpp), not after seconds of silence. Other readers of the marks
/// ask for no lease and match the coordinator's marks too.
inline constexpr Delivery kWorkerMarks{true, 8, false, 300};
/// Frame starts as the coordinator writes them, and a standby's acknowledgements: each writer's liveliness is
/// asserted by a thread of its own within 0.3 s (confirmed as above), so that a standby learns within the
/// lease that the coordinator is gone, and the coordinator that its standby is. Workers read both without a
/// lease.
inline constexpr Delivery kCoordinatorWords{true, 8, false, 300};
/// Commands and sector requests: volatile, deep enough for bursts. A client's commands are one instance
/// (idl/lpss.idl): as many as the coordinator's default rate lets through at once (1,000) fit in flight;
/// more are lost on the way and refused as lost.
inline constexpr Delivery kCommandDelivery{false, 1024};
/// Command results: durable, the last 256 per client (results are keyed by client), so that a client
/// whose reader a worker matched only after answering still gets the answer (seen: a spawn's answer lost
/// to discovery that had matched one side only).
inline constexpr Delivery kResultDelivery{true, 256};

/// How often a writer with a lease asserts its liveliness (LivelinessBeat): six times a lease. Fast DDS 2.9
/// at times reports a live writer lapsed when another's lease runs out, and takes it back at its next beat
/// (server/coordinator/confirmed_lapses.hpp): the sooner that beat, the less a loaded machine must delay it
/// for the lapse to be confirmed falsely.
inline constexpr std::chrono::milliseconds beat_period(const Delivery& delivery) {
    return std::chrono::milliseconds(delivery.lease_ms / 6);
}

eprosima::fastdds::dds::DataWriterQos writer_qos(const Delivery& delivery);
eprosima::fastdds::dds::DataReaderQos reader_qos(const Delivery& delivery);
/// The same, received on a UDP port of the reader's own (on every interface its participant may use),
/// not the one its participant shares among all its readers: what floods this reader (a client's
/// commands) then fills only that socket, and the participant's other traffic goes on. The port is one the
/// system had free.
eprosima::fastdds::dds::DataReaderQos reader_qos_on_own_port(const Delivery& delivery);

}  // namespace lpss::dds
