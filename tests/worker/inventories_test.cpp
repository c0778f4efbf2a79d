// How a worker answers readers that ask for an inventory of its sectors: in the mark of the first frame its
// writer reaches them, listing every sector of their region it publishes with its latest frame, and sending
// those the reader lacks whole, at most Inventories::kBodiesPerFrame bodies' worth a frame.
#include <gtest/gtest.h>

#include <algorithm>

#include "inventories.hpp"
#include "lpss_dds/convert.hpp"

namespace lpss::worker {
namespace {

std::vector<BodySnapshot> bodies_in(const SectorKey& key, BodyId first, std::uint32_t count) {
    std::vector<BodySnapshot> out(count);
    for (std::uint32_t n = 0; n < count; ++n) {
        out[n].id = first + n;
        out[n].position = SectorPosition{key, Eigen::Vector3d(0.001 * n, 0, 0)};
    }
    return out;
}

/// A publisher of sectors (i, 0, 0), i = 0..3, each with `per_sector` bodies, sector i last written at frame
/// 10 + i.
dds::SectorPublisher publishing(std::uint32_t per_sector) {
    dds::SectorPublisher p;
    for (std::int64_t i = 0; i < 4; ++i) {
        const SectorKey key{i, 0, 0};
        const std::vector<BodySnapshot> all =
            bodies_in(key, 1 + static_cast<BodyId>(i) * per_sector, per_sector);
        p.adopt(key, all, std::vector<std::uint32_t>(all.size(), 1u << 13),
                10 + static_cast<std::uint64_t>(i));
    }
    return p;
}

wire::SectorRequest asking(const std::string& reader, SectorKey lo, SectorKey hi,
                           std::uint64_t held_through = 0) {
    wire::SectorRequest r;
    r.reader(reader);
    r.request(7);
    r.inventory(true);
    r.lo(dds::to_wire(lo));
    r.hi(dds::to_wire(hi));
    r.held_through(held_through);
    return r;
}

const auto kReachesNone = [](const dds::GuidBytes&) { return false; };

std::vector<std::int64_t> listed(const wire::SectorInventory& inventory) {
    std::vector<std::int64_t> out;
    for (const wire::SectorStamp& s : inventory.sectors())
        out.push_back(dds::from_wire(s.sector()).i);
    std::sort(out.begin(), out.end());
    return out;
}

TEST(Inventories, ARequestIsAnsweredWithTheSectorsOfItsRegionAndThoseGoWhole) {
    const dds::SectorPublisher p = publishing(10);
    Inventories inventories;
    inventories.ask(asking("client", {1, 0, 0}, {2, 5, 5}));
    EXPECT_TRUE(inventories.answers(p).empty()) << "not taken up yet";
    inventories.take_up(kReachesNone, p);  // no reader named: answered at once
    const std::vector<wire::SectorInventory> answers = inventories.answers(p);
    ASSERT_EQ(answers.size(), 1u);
    EXPECT_EQ(answers[0].reader(), "client");
    EXPECT_EQ(answers[0].request(), 7u);
    EXPECT_EQ(listed(answers[0]), (std::vector<std::int64_t>{1, 2}));
    for (const wire::SectorStamp& s : answers[0].sectors())
        EXPECT_EQ(s.frame(), 10u + static_cast<std::uint64_t>(dds::from_wire(s.sector()).i));
    EXPECT_EQ(inventories.due_now(p), (std::set<SectorKey>{{1, 0, 0}, {2, 0, 0}}));
    EXPECT_TRUE(inventories.due_now(p).empty()) << "sent once";
    EXPECT_TRUE(inventories.answers(p).empty()) << "answered once";
}

TEST(Inventories, ARequestWaitsUntilTheWriterReachesItsReader) {
    const dds::SectorPublisher p = publishing(10);
    Inventories inventories;
    wire::SectorRequest r = asking("joiner", {0, 0, 0}, {3, 0, 0});
    r.frames_reader(std::vector<std::uint8_t>(16, 0xab));
    inventories.ask(r);
    inventories.take_up(kReachesNone, p);
    EXPECT_TRUE(inventories.answers(p).empty());
    EXPECT_TRUE(inventories.due_now(p).empty());
    bool asked_about_its_reader = false;
    inventories.take_up(
        [&](const dds::GuidBytes& reader) {
            asked_about_its_reader = reader == dds::GuidBytes{0xab, 0xab, 0xab, 0xab, 0xab, 0xab, 0xab, 0xab,
                                                              0xab, 0xab, 0xab, 0xab, 0xab, 0xab, 0xab, 0xab};
            return true;
        },
        p);
    EXPECT_TRUE(asked_about_its_reader);
    const std::vector<wire::SectorInventory> answers = inventories.answers(p);
    ASSERT_EQ(answers.size(), 1u);
    EXPECT_EQ(listed(answers[0]), (std::vector<std::int64_t>{0, 1, 2, 3}));
}

TEST(Inventories, SectorsTheReaderHoldsAreListedButNotSentAgain) {
    const dds::SectorPublisher p = publishing(10);
    Inventories inventories;
    inventories.ask(asking("behind", {0, 0, 0}, {3, 0, 0}, 11));  // holds every sector as of frame 11
    inventories.take_up(kReachesNone, p);
    const std::vector<wire::SectorInventory> answers = inventories.answers(p);
    ASSERT_EQ(answers.size(), 1u);
    EXPECT_EQ(listed(answers[0]), (std::vector<std::int64_t>{0, 1, 2, 3}));
    EXPECT_EQ(inventories.due_now(p), (std::set<SectorKey>{{2, 0, 0}, {3, 0, 0}}))
        << "written after frame 11";
}

TEST(Inventories, AReaderThatHoldsNothingGetsEvenSectorsNeverWrittenSinceTheFirstState) {
    // Sectors adopted from the coordinator's first state have stamp 0; a reader that holds nothing says 0.
    dds::SectorPublisher p;
    const std::vector<BodySnapshot> all = bodies_in({0, 0, 0}, 1, 3);
    p.adopt({0, 0, 0}, all, std::vector<std::uint32_t>(all.size(), 1u << 13), 0);
    Inventories inventories;
    inventories.ask(asking("new client", {0, 0, 0}, {0, 0, 0}, 0));
    inventories.take_up(kReachesNone, p);
    EXPECT_EQ(inventories.due_now(p), (std::set<SectorKey>{{0, 0, 0}}));
}

TEST(Inventories, ASectorGivenAwayBeforeItsTurnIsNotSent) {
    dds::SectorPublisher p = publishing(10);
    Inventories inventories;
    inventories.ask(asking("client", {0, 0, 0}, {1, 0, 0}));
    inventories.take_up(kReachesNone, p);
    p.forget({1, 0, 0});  // its new owner's sample says so
    EXPECT_EQ(inventories.due_now(p), (std::set<SectorKey>{{0, 0, 0}}));
}

TEST(Inventories, LargeSectorsGoWholeAShareAFrame) {
    // Four sectors of 12,000 bodies: two a frame fit the share (the second goes over it), then two more.
    const dds::SectorPublisher p = publishing(12000);
    Inventories inventories;
    inventories.ask(asking("whole world", {-100, -100, -100}, {100, 100, 100}));
    inventories.take_up(kReachesNone, p);
    std::set<SectorKey> sent;
    std::vector<std::size_t> per_frame;
    for (int frame = 0; frame < 4; ++frame) {
        const std::set<SectorKey> now = inventories.due_now(p);
        per_frame.push_back(now.size());
        sent.insert(now.begin(), now.end());
    }
    EXPECT_EQ(per_frame, (std::vector<std::size_t>{2, 2, 0, 0}));
    EXPECT_EQ(sent.size(), 4u);
}

}  // namespace
}  // namespace lpss::worker
