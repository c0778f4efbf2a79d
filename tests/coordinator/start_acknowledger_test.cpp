// A standby's quick answer to frame starts: it acknowledges on sight only the start a worker may step next
// (named for it, of the term it follows, the frame after the last acknowledged), never frame 1, a new term
// or a start after a gap; the follow loop still gets every start, in the order it came.
#include <gtest/gtest.h>

#include <vector>

#include "eventually.hpp"
#include "lpssPubSubTypes.h"
#include "lpss_dds/participant.hpp"
#include "lpss_dds/shm_cleanup.hpp"
#include "lpss_dds/topics.hpp"
#include "start_acknowledger.hpp"

namespace lpss::coordinator {
namespace {

// A domain of this test's own, so that suites can run side by side.
constexpr int kDomain = 188;

class RemoveSharedMemory : public ::testing::Environment {
public:
    void TearDown() override { dds::remove_abandoned_shm(kDomain); }
};
const ::testing::Environment* const kRemoveSharedMemory =
    ::testing::AddGlobalTestEnvironment(new RemoveSharedMemory);  // gtest owns it

constexpr std::uint32_t kStandby = 2;

wire::FrameGo start(std::uint64_t frame, std::uint32_t term, std::uint32_t standby = kStandby,
                    std::uint32_t coordinator = 1) {
    wire::FrameGo go;
    go.coordinator(coordinator);
    go.term(term);
    go.frame(frame);
    go.standby(standby);
    return go;
}

using lpss::testing::eventually;

TEST(StartAcknowledger, AcknowledgesOnSightOnlyTheNextStartOfItsTermAndPassesEveryStartOn) {
    using namespace dds;
    auto coordinator = Participant::create(kDomain, "", "start-acks-coordinator");
    auto standby = Participant::create(kDomain, "", "start-acks-standby");
    ASSERT_TRUE(coordinator.ok()) << coordinator.error().message;
    ASSERT_TRUE(standby.ok()) << standby.error().message;
    Participant& c = **coordinator;
    Participant& s = **standby;

    Inbox coordinator_inbox;
    Writer<wire::FrameGo> starts(c, c.topic<wire::FrameGoPubSubType>(kFrameGo),
                                 writer_qos(kCoordinatorWords));
    Reader<wire::FrameAck> acks_read(c, c.topic<wire::FrameAckPubSubType>(kFrameAcks),
                                     reader_qos(kCoordinatorWords), &coordinator_inbox);
    Inbox inbox;
    StartAcknowledger acknowledger(inbox);
    Reader<wire::FrameGo> starts_read(s, s.topic<wire::FrameGoPubSubType>(kFrameGo),
                                      reader_qos(kCoordinatorWords), &acknowledger);
    Writer<wire::FrameAck> acks(s, s.topic<wire::FrameAckPubSubType>(kFrameAcks),
                                writer_qos(kCoordinatorWords));
    ASSERT_TRUE(starts.ok() && acks_read.ok() && starts_read.ok() && acks.ok());
    ASSERT_TRUE(eventually([&] { return starts.matched() == 1 && acks.matched() == 1; }));

    std::vector<std::pair<std::uint32_t, std::uint64_t>>
        acknowledged;  // (term, frame), as the coordinator reads
    auto read_acks = [&] {
        acks_read.take_all([&](const wire::FrameAck& a, const fdds::SampleInfo& info) {
            if (info.valid_data) acknowledged.emplace_back(a.term(), a.frame());
        });
    };
    std::vector<std::uint64_t> passed_on;  // the frames the follow loop gets, in order
    auto follow = [&] {
        acknowledger.take_all(
            [&](const wire::FrameGo& go, const fdds::SampleInfo&) { passed_on.push_back(go.frame()); });
    };

    // Before it takes: the start stays in the reader. Once it takes, it gets it, and frame 1 is never
    // acknowledged on sight (it waits for the world's first state).
    ASSERT_TRUE(starts.write(start(1, 5)));
    ASSERT_TRUE(eventually([&] { return starts_read.unread() == 1; }));
    acknowledger.note_acknowledged(0, 0);  // the hello, as follow() writes it
    acknowledger.start_taking(kStandby, starts_read.raw(), &acks);
    EXPECT_EQ(starts_read.unread(), 0u);
    follow();
    EXPECT_EQ(passed_on, (std::vector<std::uint64_t>{1}));
    EXPECT_FALSE(acknowledger.acknowledged(5, 1));

    // The loop acknowledged frame 1 under term 5. None of these may be acknowledged on sight: after a gap,
    // not named, of another term, its own. Each is looked at once the loop has it (the listener decides
    // before it passes a start on).
    acknowledger.note_acknowledged(5, 1);
    const wire::FrameGo not_on_sight[] = {start(3, 5), start(2, 5, 0), start(2, 6),
                                          start(2, 5, kStandby, kStandby)};
    for (const wire::FrameGo& go : not_on_sight) {
        const std::size_t before = passed_on.size();
        ASSERT_TRUE(starts.write(go));
        ASSERT_TRUE(eventually([&] {
            follow();
            return passed_on.size() == before + 1;
        }));
        EXPECT_FALSE(acknowledger.acknowledged(5, 2)) << "frame " << go.frame() << " term " << go.term();
        EXPECT_FALSE(acknowledger.acknowledged(5, 3));
        EXPECT_FALSE(acknowledger.acknowledged(6, 2));
    }
    // This one may, and its acknowledgement is the first the coordinator reads (one writer, in order).
    ASSERT_TRUE(starts.write(start(2, 5)));
    ASSERT_TRUE(eventually([&] {
        read_acks();
        return !acknowledged.empty();
    }));
    EXPECT_EQ(acknowledged, (std::vector<std::pair<std::uint32_t, std::uint64_t>>{{5, 2}}));
    EXPECT_TRUE(acknowledger.acknowledged(5, 2));
    follow();
    EXPECT_EQ(passed_on, (std::vector<std::uint64_t>{1, 3, 2, 2, 2, 2}));

    // A new term, once the loop acknowledged its first start: its next start goes on sight.
    acknowledger.note_acknowledged(6, 3);
    ASSERT_TRUE(starts.write(start(4, 6)));
    ASSERT_TRUE(eventually([&] {
        read_acks();
        return acknowledged.size() == 2;
    }));
    EXPECT_EQ(acknowledged.back(), (std::pair<std::uint32_t, std::uint64_t>{6, 4}));

    // Stopped taking (it takes over): starts stay in the reader, unacknowledged.
    acknowledger.stop_taking();
    ASSERT_TRUE(starts.write(start(5, 6)));
    ASSERT_TRUE(eventually([&] { return starts_read.unread() == 1; }));
    read_acks();
    EXPECT_EQ(acknowledged.size(), 2u);
}

}  // namespace
}  // namespace lpss::coordinator
