// When a worker takes itself as cut off from every coordinator: only once a writer it heard has lapsed for
// its grace, never while the frame start reader still counts one alive (a report that merged two writers'
// changes names one of them), not if the writer's newer frame starts show it alive, and, when a standby
// followed the frame, not before the standby has had its time to take over (its coming alive may have gone
// unreported altogether).
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "coordinator_watch.hpp"

namespace lpss::worker {
namespace {

dds::fdds::InstanceHandle_t writer(std::uint8_t n) {
    dds::fdds::InstanceHandle_t h;
    h.value[0] = n;
    return h;
}

dds::Inbox::Liveliness change(std::uint8_t n, bool alive, std::int32_t alive_count, bool merged = false) {
    dds::Inbox::Liveliness c;
    c.writer = writer(n);
    c.alive = alive;
    c.alive_count = alive_count;
    c.merged = merged;
    return c;
}

/// Longer than any grace a lapse gets (ConfirmedLapses: 150 ms, or 450 ms for one beside another's).
void past_grace() { std::this_thread::sleep_for(std::chrono::milliseconds(600)); }

using dds::wall_clock_ns;

TEST(CoordinatorWatch, IsNotCutOffBeforeAnyCoordinatorWasHeard) {
    CoordinatorWatch watch(1);
    watch.follow({});
    EXPECT_FALSE(watch.cut_off());
    EXPECT_EQ(watch.history(), "none");
}

TEST(CoordinatorWatch, ALapseCutsOffOnlyOnceItsGraceHasPassed) {
    CoordinatorWatch watch(1);
    watch.follow({change(1, true, 1)});
    EXPECT_FALSE(watch.cut_off());
    watch.follow({change(1, false, 0)});
    EXPECT_FALSE(watch.cut_off()) << "within the lapse's grace";
    past_grace();
    watch.follow({});
    EXPECT_TRUE(watch.cut_off());
    const std::string history = watch.history();
    EXPECT_NE(history.find("writer 1 alive"), std::string::npos) << history;
    EXPECT_NE(history.find("writer 1 lapse confirmed"), std::string::npos) << history;
}

TEST(CoordinatorWatch, AWriterComingBackAliveWithinItsGraceIsNotALapse) {
    CoordinatorWatch watch(1);
    watch.follow({change(1, true, 1), change(1, false, 0), change(1, true, 1)});
    past_grace();
    watch.follow({});
    EXPECT_FALSE(watch.cut_off());
    EXPECT_EQ(watch.history().find("lapse confirmed"), std::string::npos) << watch.history();
}

TEST(CoordinatorWatch, AFrameStartWrittenAfterTheLapseShowsTheWriterAlive) {
    CoordinatorWatch watch(1);
    watch.follow({change(1, true, 1), change(1, false, 0)});
    watch.heard(writer(1), wall_clock_ns() + 1'000'000);
    past_grace();
    watch.follow({});
    EXPECT_FALSE(watch.cut_off());
}

TEST(CoordinatorWatch, AStandbyWhoseComingAliveWasMergedIntoTheCoordinatorsReportStillCounts) {
    // The coordinator's and the standby's writers come alive in one report that names the coordinator's
    // alone; the coordinator then dies. The standby's writer, never named alive, is still counted.
    CoordinatorWatch watch(1);
    watch.follow({change(1, true, 2, true)});
    watch.follow({change(1, false, 1)});
    past_grace();
    watch.follow({});
    EXPECT_FALSE(watch.cut_off()) << "the reader counts one writer alive";
    // Then the standby's lapses too: its report is the first to name it.
    watch.follow({change(2, false, 0)});
    EXPECT_FALSE(watch.cut_off()) << "within the lapse's grace";
    past_grace();
    watch.follow({});
    EXPECT_TRUE(watch.cut_off());
    EXPECT_NE(watch.history().find("writer 2 lapse confirmed"), std::string::npos) << watch.history();
}

/// A watch that heard the coordinator's writer alone alive (the standby's coming alive lost, as Fast
/// DDS 2.9's unlocked count can lose it), whose frame named a standby (or none), and whose one writer's lapse
/// is confirmed.
CoordinatorWatch lapsed_alone(bool standby_follows) {
    CoordinatorWatch watch(1);
    watch.follow({change(1, true, 1)});
    watch.standby_follows(standby_follows);
    watch.follow({change(1, false, 0)});
    past_grace();
    watch.follow({});
    return watch;
}

TEST(CoordinatorWatch, WithAStandbyFollowingNoneAliveCutsOffOnlyOnceItsTimeToTakeOverHasPassed) {
    // The coordinator's writer lapsed: the standby may be taking over.
    CoordinatorWatch watch = lapsed_alone(true);
    EXPECT_TRUE(watch.none_alive());
    EXPECT_FALSE(watch.cut_off()) << "within the standby's time to take over";
    // A frame start written before the lapse (the dead coordinator's, late) shows no one alive.
    watch.heard(writer(1), wall_clock_ns() - 5'000'000'000);
    EXPECT_TRUE(watch.none_alive());
    std::this_thread::sleep_for(CoordinatorWatch::kTakeover);
    watch.follow({});
    EXPECT_TRUE(watch.cut_off()) << "no standby took over within its time";
}

TEST(CoordinatorWatch, AStandbyTakingOverUnreportedIsHeardByItsFrameStartsAndItsLapseCutsOff) {
    CoordinatorWatch watch = lapsed_alone(true);
    ASSERT_TRUE(watch.none_alive());
    // The standby takes over: its first frame start comes, its liveliness says nothing (alive all along).
    watch.heard(writer(2), wall_clock_ns() + 1'000'000);
    EXPECT_FALSE(watch.none_alive());
    EXPECT_NE(watch.history().find("writer 2 heard writing"), std::string::npos) << watch.history();
    // Its frames name no standby; when it lapses in turn, the reader's count (one short) goes below zero.
    watch.standby_follows(false);
    watch.follow({change(2, false, -1)});
    EXPECT_FALSE(watch.cut_off()) << "within the lapse's grace";
    past_grace();
    watch.follow({});
    EXPECT_TRUE(watch.cut_off());
}

TEST(CoordinatorWatch, AStandbysFrameStartThatComesBeforeTheLapseIsConfirmedCounts) {
    // A worker busy with a long frame confirms the coordinator's lapse late: the standby has taken over and
    // written its first starts before. They count as they come.
    CoordinatorWatch watch(1);
    watch.follow({change(1, true, 1)});
    watch.standby_follows(true);
    watch.follow({change(1, false, 0)});
    watch.heard(writer(2), wall_clock_ns() + 1'000'000);
    watch.standby_follows(false);  // the standby's starts name no standby
    past_grace();
    watch.follow({});
    EXPECT_NE(watch.history().find("writer 1 lapse confirmed"), std::string::npos) << watch.history();
    EXPECT_FALSE(watch.none_alive());
    EXPECT_FALSE(watch.cut_off());
}

TEST(CoordinatorWatch, FrameStartsWrittenBeforeTheWatchBeganAreHistory) {
    // A worker that joins reads the frame starts a writer keeps: they show no coordinator alive now.
    CoordinatorWatch watch(1);
    watch.follow({change(1, true, 1)});
    watch.heard(writer(2), wall_clock_ns() - 5'000'000'000);
    watch.follow({change(1, false, 0)});
    past_grace();
    watch.follow({});
    EXPECT_TRUE(watch.cut_off());
}

TEST(CoordinatorWatch, WithoutAStandbyNoneAliveCutsOffAtOnce) { EXPECT_TRUE(lapsed_alone(false).cut_off()); }

}  // namespace
}  // namespace lpss::worker
