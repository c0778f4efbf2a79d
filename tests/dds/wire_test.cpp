// The wire layer: the built-in local profile lets participants find each other, samples keep their
// keys and floats, a late joiner gets durable samples, a region filter keeps only its sectors, a
// process's own sector samples stay out of its own sector reader, and a worker's sector writer keeps none
// older than its lifespan.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <thread>

#include "eventually.hpp"
#include "lpssPubSubTypes.h"
#include "lpss_dds/convert.hpp"
#include "lpss_dds/participant.hpp"
#include "lpss_dds/shm_cleanup.hpp"
#include "lpss_dds/topics.hpp"

namespace lpss::dds {
namespace {

// Domains of these tests' own, so that suites can run side by side: ctest runs each test as a process of
// its own, in parallel, and these are not in network namespaces (seen: the own-partition test's samples
// reached the late joiner's readers when the two ran together under -j2).
constexpr int kDomain = 171;
constexpr int kOwnPartitionDomain = 189;
constexpr int kLifespanDomain = 194;

// Every participant leaves port files in /dev/shm; the suite removes its domain's when it ends.
class RemoveSharedMemory : public ::testing::Environment {
public:
    void TearDown() override {
        remove_abandoned_shm(kDomain);
        remove_abandoned_shm(kOwnPartitionDomain);
        remove_abandoned_shm(kLifespanDomain);
    }
};
const ::testing::Environment* const kRemoveSharedMemory =
    ::testing::AddGlobalTestEnvironment(new RemoveSharedMemory);  // gtest owns it

/// A sample of `key` in instance `slot` (the coordinator gives each sector of the world's first state its
/// own: idl/lpss.idl).
wire::SectorFrame frame_of(const SectorKey& key, std::uint64_t frame, BodyId id, std::uint32_t slot) {
    wire::SectorFrame f;
    f.sector(to_wire(key));
    f.slot(slot);
    f.frame(frame);
    f.complete(true);
    BodySnapshot b;
    b.id = id;
    b.position = SectorPosition{key, Eigen::Vector3d(1.5, -2.25, 63.75)};
    b.linear_velocity = Eigen::Vector3d(1, 2, 3);
    b.awake = true;
    f.bodies().push_back(to_wire(b));
    return f;
}

using lpss::testing::eventually;

TEST(Wire, LateJoinerAndRegionFilter) {
    auto pub = Participant::create(kDomain, "", "wire-test-pub");
    ASSERT_TRUE(pub.ok()) << pub.error().message;
    Writer<wire::SectorFrame> writer(**pub, (*pub)->topic<wire::SectorFramePubSubType>(kSectorFrames),
                                     writer_qos(kStateDelivery));
    ASSERT_TRUE(writer.ok());
    const SectorKey far{(std::int64_t{1} << 61) + 3, -7, 0};
    ASSERT_TRUE(writer.write(frame_of({0, 0, 0}, 5, 1, 0)));
    ASSERT_TRUE(writer.write(frame_of(far, 5, 2, 1)));
    ASSERT_TRUE(writer.write(frame_of({1, 0, 0}, 5, 3, 2)));

    // Joins after the samples were written: gets the last sample of each instance.
    auto sub = Participant::create(kDomain, "", "wire-test-sub");
    ASSERT_TRUE(sub.ok());
    Inbox inbox;
    fdds::Topic* topic = (*sub)->topic<wire::SectorFramePubSubType>(kSectorFrames);
    Reader<wire::SectorFrame> all(**sub, topic, reader_qos(kStateDelivery), &inbox);
    const std::int64_t lo[3] = {0, -100, -5}, hi[3] = {0, 100, 5};
    Reader<wire::SectorFrame> region(**sub, (*sub)->sector_region(kSectorFrames, lo, hi),
                                     reader_qos(kStateDelivery), &inbox);
    ASSERT_TRUE(all.ok());
    ASSERT_TRUE(region.ok());

    std::map<BodyId, BodySnapshot> seen;
    std::vector<BodyId> in_region;
    ASSERT_TRUE(eventually([&] {
        all.take_all([&](const wire::SectorFrame& f, const fdds::SampleInfo& info) {
            if (!info.valid_data) return;
            for (const auto& b : f.bodies())
                seen[b.id()] = from_wire(b, from_wire(f.sector()));
        });
        region.take_all([&](const wire::SectorFrame& f, const fdds::SampleInfo& info) {
            if (info.valid_data) in_region.push_back(f.bodies().front().id());
        });
        return seen.size() == 3 && !in_region.empty();
    })) << seen.size()
        << " seen, " << in_region.size() << " in region";
    EXPECT_EQ(seen.at(2).position.sector, far) << "keys are exact at any index";
    EXPECT_EQ(seen.at(2).position.local, Eigen::Vector3d(1.5, -2.25, 63.75));
    EXPECT_EQ(seen.at(3).linear_velocity, Eigen::Vector3d(1, 2, 3));
    EXPECT_TRUE(seen.at(1).awake);
    // Absence decided by an event, not a wait: a last sample, in the region, written after the others. One
    // reliable writer's samples arrive in order, so once it is in, any other that passed the filter is too.
    ASSERT_TRUE(writer.write(frame_of({0, 0, 1}, 6, 4, 3)));
    ASSERT_TRUE(eventually([&] {
        region.take_all([&](const wire::SectorFrame& f, const fdds::SampleInfo& info) {
            if (info.valid_data) in_region.push_back(f.bodies().front().id());
        });
        return !in_region.empty() && in_region.back() == 4;
    }));
    EXPECT_EQ(in_region, (std::vector<BodyId>{1, 4})) << "only sectors (0,0,0) and (0,0,1) lie in the region";
}

TEST(Wire, BodyDescriptionsRoundTrip) {
    BodyDesc box;
    box.id = 42;
    box.name = "crate";
    box.shape = Box{{1, 2, 3}};
    box.mass = 5;
    box.material = Material{0.3, 0.1};
    BodySnapshot at;
    at.position = SectorPosition{{1, 2, 3}, {4, 5, 6}};
    box.asleep = true;
    BodyDesc back = from_wire(describe(box, at));
    EXPECT_TRUE(back.asleep);
    EXPECT_EQ(back.id, 42u);
    EXPECT_EQ(back.name, "crate");
    EXPECT_EQ(std::get<Box>(back.shape).half_extents, Eigen::Vector3d(1, 2, 3));
    EXPECT_EQ(std::get<SectorPosition>(back.position).sector, (SectorKey{1, 2, 3}));
    EXPECT_EQ(back.material.friction, 0.3);
}

TEST(Wire, BodyStatesRoundTripThroughTheirPackedForm) {
    // What a writer publishes (to_wire of a snapshot), what a mirror keeps (pack of the wire state) and
    // what a client shows (unpack) are the same floats, each field in its place.
    BodySnapshot body;
    body.id = 7;
    body.position = SectorPosition{{-3, 0, 9}, {1.5, -2.25, 63.75}};
    // (w, x, y, z) each its own, so that no two can change places unseen; exact in float, and not a unit
    // quaternion, which the conversions do not ask for.
    body.orientation = Eigen::Quaterniond(0.125, -0.25, 0.375, 0.5);
    body.linear_velocity = Eigen::Vector3d(1, -2, 3);
    body.angular_velocity = Eigen::Vector3d(-0.25, 0.5, -4);
    body.awake = true;
    const wire::BodyState wired = to_wire(body);
    const PackedBodyState packed = pack(wired);
    EXPECT_TRUE(packed.same_motion(pack(body)));
    EXPECT_EQ(packed.id, 7u);
    const BodySnapshot back = unpack(packed, body.position.sector);
    EXPECT_EQ(back.id, body.id);
    EXPECT_EQ(back.position.sector, body.position.sector);
    EXPECT_EQ(back.position.local, body.position.local);
    EXPECT_EQ(back.orientation.coeffs(), body.orientation.coeffs());
    EXPECT_EQ(back.linear_velocity, body.linear_velocity);
    EXPECT_EQ(back.angular_velocity, body.angular_velocity);
    EXPECT_TRUE(back.awake);
    const wire::BodyState again = to_wire(packed);
    EXPECT_EQ(again.orientation().x(), -0.25f);
    EXPECT_EQ(again.orientation().y(), 0.375f);
    EXPECT_EQ(again.orientation().z(), 0.5f);
    EXPECT_EQ(again.orientation().w(), 0.125f);
    EXPECT_EQ(again.linear_velocity().y(), -2.0f);
    EXPECT_EQ(again.angular_velocity().z(), -4.0f);
    EXPECT_EQ(again.flags(), 1u);
    body.awake = false;
    EXPECT_FALSE(pack(to_wire(body)).awake());
}

TEST(Wire, WorldSettingsRoundTrip) {
    // Workers build their worlds from the settings the coordinator sends: every field must arrive.
    WorldSettings s;
    s.sector_size = 96;
    s.dt = 1.0 / 90.0;
    s.precision_radius = 1e4;
    s.gravity = Eigen::Vector3d(0.5, -9.81, 0.25);
    s.hysteresis = 0.2;
    s.sleeping = false;
    s.substeps = 3;
    s.solver_iterations = 25;
    s.friction_combine = CombineRule::geometric_mean;
    s.restitution_combine = CombineRule::min;
    s.geo = GeoReference{GeoReference::Frame::local_tangent, 51.195, -1.85, 130.0};
    const WorldSettings back = from_wire(to_wire(s));
    EXPECT_EQ(back.sector_size, s.sector_size);
    EXPECT_EQ(back.dt, s.dt);
    EXPECT_EQ(back.precision_radius, s.precision_radius);
    EXPECT_EQ(back.gravity, s.gravity);
    EXPECT_EQ(back.hysteresis, s.hysteresis);
    EXPECT_EQ(back.sleeping, s.sleeping);
    EXPECT_EQ(back.substeps, s.substeps);
    EXPECT_EQ(back.solver_iterations, s.solver_iterations);
    EXPECT_EQ(back.friction_combine, CombineRule::geometric_mean);
    EXPECT_EQ(back.restitution_combine, CombineRule::min);
    EXPECT_EQ(back.geo.frame, GeoReference::Frame::local_tangent);  // clients (lpss-dis) read it
    EXPECT_EQ(back.geo.latitude_deg, 51.195);
    EXPECT_EQ(back.geo.longitude_deg, -1.85);
    EXPECT_EQ(back.geo.height_m, 130.0);
}

TEST(Wire, UnreadableProfileIsRefused) {
    auto p = Participant::create(kDomain, "/nonexistent/profile.xml", "x");
    ASSERT_FALSE(p.ok());
    EXPECT_NE(p.error().message.find("cannot read the DDS profile"), std::string::npos);
}

/// A sample written by `worker` (the body's id is the worker's, to tell them apart).
wire::SectorFrame sample_from(std::uint32_t worker) {
    wire::SectorFrame f = frame_of({0, 0, 0}, 1, worker, 0);
    f.worker(worker);
    return f;
}

// Own partitions (own_partition.hpp): a process's own sector samples do not come back to its own sector
// reader, every other process's do, and a reader in the default partition (a client, another vendor) gets
// all.
TEST(Wire, ASectorReaderGetsEveryOtherProcesssSamplesAndNotItsOwn) {
    auto a = Participant::create(kOwnPartitionDomain, "", "own-partition-a");
    auto b = Participant::create(kOwnPartitionDomain, "", "own-partition-b");
    auto client = Participant::create(kOwnPartitionDomain, "", "own-partition-client");
    ASSERT_TRUE(a.ok() && b.ok() && client.ok());
    const auto qos = writer_qos(kSectorFrameDelivery);
    Writer<wire::SectorFrame> a_out((*a)->sector_publisher(),
                                    (*a)->topic<wire::SectorFramePubSubType>(kSectorFrames), qos);
    Writer<wire::SectorFrame> b_out((*b)->sector_publisher(),
                                    (*b)->topic<wire::SectorFramePubSubType>(kSectorFrames), qos);
    Inbox inbox;
    Reader<wire::SectorFrame> a_in((*a)->sector_subscriber(),
                                   (*a)->topic<wire::SectorFramePubSubType>(kSectorFrames),
                                   reader_qos(kSectorFrameReading), &inbox);
    Reader<wire::SectorFrame> b_in((*b)->sector_subscriber(),
                                   (*b)->topic<wire::SectorFramePubSubType>(kSectorFrames),
                                   reader_qos(kSectorFrameReading), &inbox);
    // A client's reader, in the default partition as every reader but a worker's or a coordinator's.
    Reader<wire::SectorFrame> everything(**client,
                                         (*client)->topic<wire::SectorFramePubSubType>(kSectorFrames),
                                         reader_qos(kSectorFrameReading), &inbox);
    ASSERT_TRUE(a_out.ok() && b_out.ok() && a_in.ok() && b_in.ok() && everything.ok());
    ASSERT_TRUE(eventually([&] {
        return a_out.matched() == 2 && b_out.matched() == 2 && everything.matched() == 2;
    })) << "a's writer matched "
        << a_out.matched() << " readers, b's " << b_out.matched() << "; the client's reader "
        << everything.matched() << " writers";
    ASSERT_TRUE(a_out.write(sample_from(1)));
    ASSERT_TRUE(b_out.write(sample_from(2)));
    std::vector<std::uint32_t> to_a, to_b, to_client;
    auto take = [](Reader<wire::SectorFrame>& reader, std::vector<std::uint32_t>& into) {
        reader.take_all([&](const wire::SectorFrame& f, const fdds::SampleInfo& info) {
            if (info.valid_data) into.push_back(f.worker());
        });
    };
    ASSERT_TRUE(eventually([&] {
        take(a_in, to_a);
        take(b_in, to_b);
        take(everything, to_client);
        return to_a.size() >= 1 && to_b.size() >= 1 && to_client.size() >= 2;
    }));
    std::this_thread::sleep_for(std::chrono::milliseconds(300));  // anything more that would come
    take(a_in, to_a);
    take(b_in, to_b);
    take(everything, to_client);
    EXPECT_EQ(to_a, std::vector<std::uint32_t>{2});
    EXPECT_EQ(to_b, std::vector<std::uint32_t>{1});
    std::sort(to_client.begin(), to_client.end());
    EXPECT_EQ(to_client, (std::vector<std::uint32_t>{1, 2}));
    EXPECT_EQ(a_in.matched(), 1);
    EXPECT_EQ(b_in.matched(), 1);
}

// A worker's sector writer keeps its samples half a second (kSectorFrameDelivery's lifespan), not as long
// as its depth would: most of a worker's memory beyond its world's was seconds of old samples. A reader that
// joins later gets none of them (it asks for what it lacks, docs/protocol.md), while a writer with the same
// QoS but no lifespan still hands its late joiner every one: the lifespan, not discovery's timing, is what
// drops them.
TEST(Wire, AWorkersSectorWriterKeepsNoSampleOlderThanItsLifespan) {
    auto pub = Participant::create(kLifespanDomain, "", "lifespan-pub");
    ASSERT_TRUE(pub.ok()) << pub.error().message;
    fdds::Topic* topic = (*pub)->topic<wire::SectorFramePubSubType>(kSectorFrames);
    ASSERT_GT(kSectorFrameDelivery.lifespan_ms, 0);
    Delivery without_lifespan = kSectorFrameDelivery;
    without_lifespan.lifespan_ms = 0;
    Writer<wire::SectorFrame> bounded(**pub, topic, writer_qos(kSectorFrameDelivery));
    Writer<wire::SectorFrame> unbounded(**pub, topic, writer_qos(without_lifespan));
    ASSERT_TRUE(bounded.ok() && unbounded.ok());
    auto sample = [](std::uint32_t worker, std::uint64_t frame) {
        wire::SectorFrame f = frame_of({0, 0, 0}, frame, static_cast<BodyId>(frame + 1), 0);
        f.worker(worker);  // the instance: one per writer
        return f;
    };
    constexpr std::uint64_t kOld = 10;
    for (std::uint64_t frame = 0; frame < kOld; ++frame) {
        ASSERT_TRUE(bounded.write(sample(1, frame)));
        ASSERT_TRUE(unbounded.write(sample(2, frame)));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2 * kSectorFrameDelivery.lifespan_ms + 200));

    auto sub = Participant::create(kLifespanDomain, "", "lifespan-late-joiner");
    ASSERT_TRUE(sub.ok()) << sub.error().message;
    Inbox inbox;
    Reader<wire::SectorFrame> late(**sub, (*sub)->topic<wire::SectorFramePubSubType>(kSectorFrames),
                                   reader_qos(kSectorFrameReading), &inbox);
    ASSERT_TRUE(late.ok());
    ASSERT_TRUE(eventually([&] { return late.matched() == 2; })) << late.matched() << " writers matched";
    // One sample more from the bounded writer, after the match: a reliable writer's samples come in order,
    // so once it is in, whatever that writer's history held is in too.
    ASSERT_TRUE(bounded.write(sample(1, 100)));
    std::map<std::uint32_t, std::vector<std::uint64_t>> frames_from;
    ASSERT_TRUE(eventually([&] {
        late.take_all([&](const wire::SectorFrame& f, const fdds::SampleInfo& info) {
            if (info.valid_data) frames_from[f.worker()].push_back(f.frame());
        });
        return !frames_from[1].empty() && frames_from[1].back() == 100 && frames_from[2].size() == kOld;
    })) << frames_from[1].size()
        << " samples from the writer with a lifespan, " << frames_from[2].size() << " from the one without";
    EXPECT_EQ(frames_from[1], std::vector<std::uint64_t>{100}) << "samples older than the lifespan were kept";
    std::vector<std::uint64_t> all_old(kOld);
    for (std::uint64_t frame = 0; frame < kOld; ++frame)
        all_old[frame] = frame;
    EXPECT_EQ(frames_from[2], all_old);
}

}  // namespace
}  // namespace lpss::dds
