// Partial sector samples: a reader uses one only on the complete sample it adds to, and rebuilds each
// sector from complete and partial samples applied in frame order.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>

#include "lpss_dds/convert.hpp"
#include "lpss_dds/sample_check.hpp"
#include "lpss_dds/sector_chain.hpp"
#include "lpss_dds/sector_mirror.hpp"

namespace lpss::dds {
namespace {

const SectorKey kSector{3, -1, 7};

wire::BodyState state_of(BodyId id, double x) {
    BodySnapshot b;
    b.id = id;
    b.position = SectorPosition{kSector, Eigen::Vector3d(x, 0, 0)};
    return to_wire(b);
}

wire::SectorFrame complete(std::uint64_t frame, std::vector<wire::BodyState> bodies) {
    wire::SectorFrame f;
    f.sector(to_wire(kSector));
    f.frame(frame);
    f.base(frame);
    f.complete(true);
    f.bodies(std::move(bodies));
    return f;
}

wire::SectorFrame partial(std::uint64_t frame, std::uint64_t base, std::vector<wire::BodyState> bodies,
                          std::vector<std::uint64_t> departed = {}) {
    wire::SectorFrame f = complete(frame, std::move(bodies));
    f.base(base);
    f.complete(false);
    f.departed(std::move(departed));
    return f;
}

TEST(SectorChain, APartialSampleNeedsTheSectorHeldFromItsBaseOn) {
    SectorChain chain;
    EXPECT_FALSE(chain.accept(partial(11, 10, {})));  // joined late: the base was never seen
    EXPECT_EQ(chain.refused(), 1u);
    EXPECT_EQ(chain.newest(kSector), 0u);
    EXPECT_TRUE(chain.accept(complete(20, {})));
    EXPECT_TRUE(chain.accept(partial(21, 20, {})));
    EXPECT_TRUE(chain.accept(partial(24, 20, {})));   // 22 and 23 lost: 24 still holds every change since 20
    EXPECT_FALSE(chain.accept(partial(31, 30, {})));  // the complete sample of frame 30 was lost
    EXPECT_EQ(chain.newest(kSector), 24u);
    EXPECT_TRUE(chain.holds(kSector, 22, 25));
    EXPECT_FALSE(chain.holds(kSector, 25, 40));
}

TEST(SectorChain, ASampleArrivingLateIsUsableOnAnEarlierFrameItHolds) {
    // Two writers at an ownership change: the new owner's complete sample may arrive before the old
    // owner's last partial one, which still applies (in frame order) on the frames held before it.
    SectorChain chain;
    EXPECT_TRUE(chain.accept(complete(10, {})));
    EXPECT_TRUE(chain.accept(complete(13, {})));
    EXPECT_TRUE(chain.accept(partial(12, 10, {})));
    EXPECT_FALSE(chain.accept(partial(9, 8, {})));  // before anything held
}

TEST(SectorChain, ForgettingAppliedFramesKeepsTheNewestOfEachSector) {
    SectorChain chain;
    chain.accept(complete(10, {}));
    chain.accept(partial(11, 10, {}));
    chain.accept(partial(15, 10, {}));
    chain.forget_applied(12);
    EXPECT_FALSE(chain.holds(kSector, 10, 10));
    EXPECT_TRUE(chain.holds(kSector, 11, 11));
    EXPECT_TRUE(chain.accept(partial(16, 10, {})));  // 11 and 15 still hold the base's sector
}

TEST(SectorChain, ASampleOlderThanWhatWasAppliedIsStaleAndRefused) {
    // A reader that joins gets the coordinator's first state (frame 0) and a worker's newer samples from
    // two histories, in any order: the first state must not take a sector back once a newer one applied.
    SectorChain chain;
    ASSERT_TRUE(chain.accept(complete(40, {})));
    chain.forget_applied(40);
    EXPECT_TRUE(chain.stale(complete(0, {})));
    EXPECT_FALSE(chain.accept(complete(0, {})));
    EXPECT_EQ(chain.refused(), 0u) << "a stale sample is not a broken chain";
    EXPECT_FALSE(chain.holds(kSector, 0, 0));
    // Not stale: newer than anything applied, or of a sector the reader holds nothing of.
    EXPECT_FALSE(chain.stale(partial(41, 40, {})));
    wire::SectorFrame elsewhere = complete(0, {});
    elsewhere.sector().i(kSector.i + 1);
    EXPECT_FALSE(chain.stale(elsewhere));
    EXPECT_TRUE(chain.accept(elsewhere));
}

TEST(SectorMirror, CompleteSamplesReplaceAndPartialOnesUpdate) {
    SectorMirror mirror;
    const wire::SectorFrame first = complete(10, {state_of(1, 1.0), state_of(2, 2.0), state_of(3, 3.0)});
    const wire::SectorFrame second = partial(11, 10, {state_of(2, 2.5)}, {3});
    mirror.apply({&first, &second});
    const SectorMirror::Bodies& bodies = mirror.sectors().at(kSector);
    ASSERT_EQ(bodies.size(), 2u);
    EXPECT_EQ(bodies[0].state.id, 1u);
    EXPECT_EQ(bodies[0].state.position[0], 1.0f);  // unchanged, not resent
    EXPECT_EQ(bodies[1].state.id, 2u);
    EXPECT_EQ(bodies[1].state.position[0], 2.5f);
    const wire::SectorFrame whole = complete(12, {state_of(4, 4.0)});
    mirror.apply({&whole});  // whole: what is not in it is not in the sector
    ASSERT_EQ(mirror.sectors().at(kSector).size(), 1u);
    EXPECT_EQ(mirror.sectors().at(kSector)[0].state.id, 4u);
    const wire::SectorFrame empty = complete(13, {});
    mirror.apply({&empty});
    EXPECT_TRUE(mirror.sectors().empty());
}

TEST(SectorMirror, APartialSampleIsAppliedWhateverTheOrderOfItsIds) {
    // A writer sends ids in order, and the mirror searches onwards from the last one it found; a peer may
    // not, and the mirror must then hold the same bodies all the same.
    SectorMirror mirror;
    std::vector<wire::BodyState> first;
    for (BodyId id = 2; id <= 40; id += 2)
        first.push_back(state_of(id, static_cast<double>(id)));
    const wire::SectorFrame whole = complete(10, first);
    wire::SectorFrame changes = partial(11, 10,
                                        {state_of(40, -40.0), state_of(3, -3.0), state_of(2, -2.0),
                                         state_of(41, -41.0), state_of(17, -17.0), state_of(6, -6.0)},
                                        {30, 6, 100, 4});
    for (BodyId arrival : {3u, 41u}) {
        wire::BodyKind kind;
        kind.id(arrival);
        changes.kinds().push_back(kind);
    }
    mirror.apply({&whole, &changes});
    std::map<BodyId, float> held;
    for (const SectorMirror::Body& b : mirror.sectors().at(kSector))
        held[b.state.id] = b.state.position[0];
    std::map<BodyId, float> want;
    for (BodyId id = 2; id <= 40; id += 2)
        want[id] = static_cast<float>(id);
    want.erase(30);  // departed (6 and 4 too, and 100 was never there)
    want.erase(6);   // departed, then changed without a kind: a body the mirror does not hold, not shown
    want.erase(4);
    want[40] = -40.0f;
    want[2] = -2.0f;
    want[3] = -3.0f;    // arrived, with its kind
    want[41] = -41.0f;  // arrived, with its kind; 17 came without one and is not shown
    EXPECT_EQ(held, want);
    const SectorMirror::Bodies& bodies = mirror.sectors().at(kSector);
    EXPECT_TRUE(std::is_sorted(bodies.begin(), bodies.end(),
                               [](const auto& a, const auto& b) { return a.state.id < b.state.id; }));
}

TEST(SectorMirror, DroppingAStaleSectorLetsGoOnlyOfTheBodiesNoOtherSectorHolds) {
    // A stale state of kSector (bodies 1 and 2) held beside the current one of another sector that holds
    // body 2 now: dropping kSector takes body 1 out of what the mirror holds, not body 2.
    SectorMirror mirror;
    const wire::SectorFrame stale = complete(0, {state_of(1, 1.0), state_of(2, 2.0)});
    wire::SectorFrame elsewhere = complete(40, {state_of(2, 5.0)});
    elsewhere.sector(to_wire(SectorKey{4, -1, 7}));
    mirror.apply({&stale, &elsewhere});
    std::vector<BodyId> left;
    mirror.drop({kSector, SectorKey{9, 9, 9}}, &left);
    EXPECT_EQ(left, std::vector<BodyId>{1});
    EXPECT_EQ(mirror.sectors().count(kSector), 0u);
    ASSERT_EQ(mirror.sectors().count(SectorKey{4, -1, 7}), 1u);
    EXPECT_EQ(mirror.sectors().at(SectorKey{4, -1, 7}).front().state.id, 2u);
}

TEST(SampleCheck, GarbageFromAPeerIsRefusedWithItsReason) {
    // A real sample of the frame being stepped, or the next one, passes; each kind of garbage a peer on the
    // domain could write is named.
    const auto with_kind = [](wire::SectorFrame f) {
        f.kinds().resize(f.bodies().size());
        return f;
    };
    EXPECT_EQ(implausible(with_kind(complete(100, {state_of(1, 2.0)})), 100), "");
    EXPECT_EQ(implausible(with_kind(complete(102, {state_of(1, 2.0)})), 100), "");
    EXPECT_EQ(implausible(partial(101, 90, {state_of(1, 2.0)}), 100), "");
    auto why = [](const wire::SectorFrame& f) { return implausible(f, 100); };
    EXPECT_NE(why(with_kind(complete(~std::uint64_t{0}, {}))).find("ahead of the newest started (100)"),
              std::string::npos);
    EXPECT_NE(why(with_kind(complete(103, {}))).find("ahead"), std::string::npos);
    wire::SectorFrame far = with_kind(complete(100, {}));
    far.sector(to_wire(SectorKey{INT64_MAX, 0, 0}));
    EXPECT_NE(why(far).find("sector index beyond 2^62"), std::string::npos);
    wire::BodyState nan = state_of(7, 1.0);
    nan.linear_velocity().y(std::nanf(""));
    EXPECT_NE(why(with_kind(complete(100, {nan}))).find("body 7 has a state that is not finite"),
              std::string::npos);
    wire::BodyState zero = state_of(8, 1.0);
    zero.orientation(wire::Quatf{});
    EXPECT_NE(why(with_kind(complete(100, {zero}))).find("body 8"), std::string::npos);
    EXPECT_NE(why(complete(100, {state_of(1, 2.0)})).find("a kind for every body"), std::string::npos);
    EXPECT_NE(why(partial(100, 101, {})).find("base frame 101 does not fit"), std::string::npos);
    wire::SectorFrame offsets = with_kind(complete(100, {state_of(1, 2.0)}));
    offsets.offsets().resize(3);
    EXPECT_NE(why(offsets).find("offsets do not match"), std::string::npos);
}

}  // namespace
}  // namespace lpss::dds
