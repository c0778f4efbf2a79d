// When a worker may start a frame: the marks of the frame before from every worker it waits for, and each
// sample they list as written for it; and which of those samples it still lacks long after their mark came,
// to ask for them whole.
#include <gtest/gtest.h>

#include "frame_gate.hpp"
#include "lpss_dds/convert.hpp"

namespace lpss::worker {
namespace {

constexpr std::uint32_t kSelf = 1;
const SectorKey kNear{0, 0, 0}, kAlsoNear{1, 0, 0}, kForAnother{5, 0, 0};
const FrameGate::Clock::time_point kCame{std::chrono::seconds(100)};
const FrameGate::Clock::time_point kLater = kCame + std::chrono::seconds(1);

/// Worker `worker`'s end of `frame`: `mine` written for this worker (and worker 3), `other` for worker 3
/// alone.
wire::WorkerFrame mark(std::uint32_t worker, std::uint64_t frame, const std::vector<SectorKey>& mine,
                       const std::vector<SectorKey>& other) {
    wire::WorkerFrame m;
    m.worker(worker);
    m.frame(frame);
    auto add = [&](const SectorKey& key, std::vector<std::uint32_t> recipients) {
        wire::WrittenSector w;
        w.sector(dds::to_wire(key));
        w.recipients(std::move(recipients));
        m.written().push_back(std::move(w));
    };
    for (const SectorKey& key : mine)
        add(key, {kSelf, 3});
    for (const SectorKey& key : other)
        add(key, {3});
    return m;
}

wire::SectorFrame whole_sample(const SectorKey& key, std::uint64_t frame) {
    wire::SectorFrame f;
    f.sector(dds::to_wire(key));
    f.frame(frame);
    f.base(frame);
    f.complete(true);
    return f;
}

TEST(FrameGate, WaitsForEverySampleListedForItAndSaysWhichHaveNotCome) {
    FrameGate gate(kSelf);
    dds::SectorChain chain;
    const std::vector<std::uint32_t> workers{kSelf, 2};
    // Worker 2's end of frame 7 has not come: nothing is known to be missing yet, and the frame waits.
    EXPECT_FALSE(gate.whole(7, workers, false, chain));
    EXPECT_TRUE(gate.samples_not_come(7, workers, false, chain, kLater).empty());

    gate.take_mark(mark(2, 7, {kNear, kAlsoNear}, {kForAnother}), kCame);
    ASSERT_TRUE(chain.accept(whole_sample(kNear, 7)));
    EXPECT_FALSE(gate.whole(7, workers, false, chain));
    EXPECT_EQ(gate.samples_not_come(7, workers, false, chain, kLater), std::vector<SectorKey>{kAlsoNear})
        << "only what was written for this worker and has not come";
    EXPECT_TRUE(gate.samples_not_come(7, workers, false, chain, kCame).empty())
        << "a mark that came at the time asked about lists nothing as lost yet";
    EXPECT_NE(gate.missing(7, workers, false, chain).find("sector (1, 0, 0)"), std::string::npos);

    // A sample of a later frame does too (the owner's answer to a request for the sector whole).
    ASSERT_TRUE(chain.accept(whole_sample(kAlsoNear, 8)));
    EXPECT_TRUE(gate.whole(7, workers, false, chain));
    EXPECT_TRUE(gate.samples_not_come(7, workers, false, chain, kLater).empty());
    EXPECT_EQ(gate.missing(7, workers, false, chain), "");
}

TEST(FrameGate, TheCoordinatorsSamplesAreWaitedForOnlyWhenItWroteAndNeverTakenAsLost) {
    FrameGate gate(kSelf);
    dds::SectorChain chain;
    gate.take_mark(mark(0, 0, {kNear}, {}), kCame);  // the coordinator's first state, as worker 0
    EXPECT_TRUE(gate.whole(0, {kSelf}, false, chain));
    EXPECT_FALSE(gate.whole(0, {kSelf}, true, chain));
    EXPECT_TRUE(gate.samples_not_come(0, {kSelf}, true, chain, kLater).empty())
        << "the coordinator's writers keep their samples for repair: none is taken as lost";
    ASSERT_TRUE(chain.accept(whole_sample(kNear, 0)));
    EXPECT_TRUE(gate.whole(0, {kSelf}, true, chain));
}

}  // namespace
}  // namespace lpss::worker
