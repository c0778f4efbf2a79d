// What lpss-view sends each page: every body first, then only what changed, however many frames passed.
#include <gtest/gtest.h>

#include <cmath>

#include "page_feed.hpp"

namespace lpss::view {
namespace {

BodyView body(BodyId id, double x, std::uint32_t worker = 1) {
    BodyView b;
    b.id = id;
    b.global = Eigen::Vector3d(x, 0, 0);
    b.position.local = b.global;
    b.worker = worker;
    b.awake = true;
    return b;
}

WorldFrame frame(std::uint64_t n, std::vector<BodyView> bodies, bool every_body,
                 std::vector<BodyId> departed = {}) {
    WorldFrame f;
    f.frame = n;
    f.bodies = std::move(bodies);
    f.every_body = every_body;
    f.departed = std::move(departed);
    return f;
}

const PageFeed::Describe kSpheres = [](const BodyView& b) {
    BodyDesc d;
    d.id = b.id;
    d.name = "s\"" + std::to_string(b.id);  // a quote, which JSON must escape
    d.shape = Sphere{0.5};
    d.mass = 1.0;
    return std::optional<BodyDesc>(d);
};

std::size_t count(const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1))
        ++n;
    return n;
}

TEST(PageFeed, APageWaitsForTheWorldThenGetsEveryBodyThenOnlyWhatChanged) {
    PageFeed feed(std::nullopt);
    const std::uint64_t page = feed.subscribe();
    EXPECT_FALSE(feed.has_news(page)) << "nothing before the world is known";
    WorldSettings settings;
    settings.sector_size = 64.0;
    feed.set_world(settings);
    EXPECT_FALSE(feed.has_news(page)) << "nothing before a frame";
    feed.take(frame(1, {body(1, 1e12 + 0.375), body(2, 5.0)}, true), kSpheres);
    ASSERT_TRUE(feed.has_news(page));
    const std::string first = feed.events_for(page);
    EXPECT_NE(first.find("event: world\ndata: {\"sector_size\":64,"), std::string::npos) << first;
    EXPECT_NE(first.find("\"name\":\"s\\\"1\""), std::string::npos) << first;
    EXPECT_NE(first.find("[\"1\",1000000000000.375,"), std::string::npos)
        << "17 digits keep 1e12's fractions: " << first;
    EXPECT_NE(first.find("\"every_body\":true"), std::string::npos);
    EXPECT_FALSE(feed.has_news(page));
    EXPECT_EQ(feed.events_for(page), "");

    // Three frames pass before the page is sent again: body 2 moves in the first, body 1 leaves in the
    // last, body 3 arrives. The page gets one frame event with what changed, and kinds only for body 3.
    feed.take(frame(2, {body(2, 6.0)}, false), kSpheres);
    feed.take(frame(3, {body(3, 7.0, 2)}, false), kSpheres);
    feed.take(frame(4, {}, false, {1}), kSpheres);
    const std::string later = feed.events_for(page);
    EXPECT_EQ(count(later, "event: frame"), 1u) << later;
    EXPECT_EQ(count(later, "event: world"), 0u);
    EXPECT_NE(later.find("\"frame\":4,\"every_body\":false,\"bodies\":[[\"2\",6,"), std::string::npos)
        << later;
    EXPECT_NE(later.find("[\"3\",7,"), std::string::npos) << later;
    EXPECT_EQ(later.find("[\"1\","), std::string::npos) << "body 1 left: " << later;
    EXPECT_NE(later.find("\"departed\":[\"1\"]"), std::string::npos) << later;
    EXPECT_EQ(count(later, "\"id\":\"3\","), 1u) << later;
    EXPECT_EQ(count(later, "\"id\":\"2\","), 0u) << "a kind is sent once: " << later;

    // A page that connects now gets the world as it is: bodies 2 and 3, every one.
    const std::uint64_t second = feed.subscribe();
    const std::string whole = feed.events_for(second);
    EXPECT_NE(whole.find("\"every_body\":true,\"bodies\":[[\"2\",6,"), std::string::npos) << whole;
    EXPECT_NE(whole.find("[\"3\",7,"), std::string::npos) << whole;
    EXPECT_EQ(whole.find("[\"1\","), std::string::npos) << whole;
}

TEST(PageFeed, ABodyWhoseSphereCrossesASectorBorderIsMarkedOnTheBorder) {
    PageFeed feed(std::nullopt);
    const std::uint64_t page = feed.subscribe();
    WorldSettings settings;
    settings.sector_size = 64.0;
    feed.set_world(settings);
    feed.take(frame(1, {body(1, 31.7), body(2, 10.0)}, true), kSpheres);  // radius 0.5, border at 32
    const std::string text = feed.events_for(page);
    EXPECT_NE(text.find(",1,1,1]"), std::string::npos) << "body 1: worker 1, awake, on a border: " << text;
    EXPECT_NE(text.find(",1,1,0]"), std::string::npos) << "body 2: not on a border: " << text;
}

TEST(PageFeed, IdsPastTwoToTheFiftyThreeAndNumbersThatAreNotFiniteStayValidJson) {
    PageFeed feed(std::nullopt);
    const std::uint64_t page = feed.subscribe();
    feed.set_world(WorldSettings{});
    WorldFrame f = frame(1, {body((1ull << 60) + 1, 2.0)}, true);
    f.workers.push_back(WorkerView{1, 1, 1, 1, 0, 0, std::nanf("")});
    feed.take(f, kSpheres);
    const std::string text = feed.events_for(page);
    EXPECT_NE(text.find("[\"1152921504606846977\","), std::string::npos) << text;
    EXPECT_NE(text.find("\"id\":\"1152921504606846977\""), std::string::npos) << text;
    EXPECT_NE(text.find("\"step_ms\":null"), std::string::npos) << text;
    EXPECT_EQ(text.find("nan"), std::string::npos) << text;
}

}  // namespace
}  // namespace lpss::view
