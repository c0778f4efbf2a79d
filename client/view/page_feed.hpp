// What lpss-view sends each page: the world as a client sees it, kept once, and for each page what it has
// not been told yet. A page gets every body when it connects, then only the bodies that changed since the
// events it was last sent, however many world frames passed in between: a slow page skips frames, it does
// not fall behind. Events are server-sent events (text/event-stream) holding JSON; the page's side of the
// format is client/view/page/viewer.js, and docs/clients.md describes it.
//
// Not thread-safe: the view server calls it under its lock.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "lpss/client/client.hpp"

namespace lpss::view {

class PageFeed {
public:
    /// Tells what a body is (shape, name, mass) the first time it is seen; nothing if unknown.
    using Describe = std::function<std::optional<BodyDesc>(const BodyView&)>;

    /// A feed for pages of a client following `region` (the whole world if empty). Pages wait until the
    /// world is known (set_world) and its first frame has come.
    explicit PageFeed(std::optional<Region> region);

    /// The world's settings, once a cluster is found.
    void set_world(const WorldSettings& settings);

    /// Takes a frame of changes (FrameContent::changes) from the client.
    void take(const WorldFrame& frame, const Describe& describe);

    std::uint64_t subscribe();
    void unsubscribe(std::uint64_t page);
    /// Whether a world frame came that this page has not been sent.
    bool has_news(std::uint64_t page) const;
    /// The events this page has not had (world, kinds of new bodies, the frame), as SSE text; empty if
    /// nothing is new.
    std::string events_for(std::uint64_t page);

    std::size_t bodies() const { return bodies_.size(); }
    std::uint64_t frame() const { return frame_; }

private:
    struct Body {
        BodyView view;
        bool on_border = false;  ///< its bounding sphere reaches into a neighbouring sector's cell
    };
    struct Page {
        bool every_body = true;  ///< send every body (a page that just connected)
        bool world_sent = false;
        std::uint64_t frame_sent = 0;
        std::unordered_set<BodyId> changed;
        std::unordered_set<BodyId> departed;
        std::unordered_set<BodyId> described;  ///< bodies whose kind the page was sent
        std::vector<HandoffView> handoffs;     ///< since the last frame sent, the newest few
    };

    bool on_border(const BodyView& body, double radius) const;
    std::string world_event() const;
    static std::string kind_json(const BodyDesc& desc);
    void body_json(std::string& out, const Body& body) const;

    std::optional<WorldSettings> settings_;
    std::optional<Region> region_;
    std::unordered_map<BodyId, Body> bodies_;
    std::unordered_map<BodyId, std::string> kinds_;  ///< each body's kind as JSON, made once
    std::unordered_map<BodyId, double> radii_;
    std::vector<WorkerView> workers_;
    std::vector<std::uint32_t> worker_ids_;  ///< of the assignment in force, for the world event
    std::uint64_t frame_ = 0;
    double time_lost_s_ = 0.0;
    std::int64_t started_ms_ = 0;
    std::map<std::uint64_t, Page> pages_;
    std::uint64_t next_page_ = 1;
};

}  // namespace lpss::view
