#include "page_feed.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "lpss/common/border_reach.hpp"

namespace lpss::view {

namespace {

/// Handoffs kept per page between two frames it is sent: the panel shows the latest few.
constexpr std::size_t kHandoffsKept = 16;

void append_json_string(std::string& out, const std::string& text) {
    out += '"';
    for (char c : text) {
        switch (c) {
            case '"':
                out += "\\\"";
                break;
            case '\\':
                out += "\\\\";
                break;
            case '\n':
                out += "\\n";
                break;
            default:
                if (static_cast<unsigned char>(c) < 0x20) {
                    out += fmt::format("\\u{:04x}", static_cast<unsigned>(c));
                } else {
                    out += c;
                }
        }
    }
    out += '"';
}

/// A double as JSON: 17 significant digits keep every bit (a body 1e12 out keeps its 1e-4 places);
/// JSON has no infinity or NaN, which the cluster never sends anyway.
std::string number(double v) { return std::isfinite(v) ? fmt::format("{:.17g}", v) : "null"; }

std::string vec(const Eigen::Vector3d& v) {
    return "[" + number(v.x()) + "," + number(v.y()) + "," + number(v.z()) + "]";
}

struct KindJson {
    std::string& out;
    void operator()(const Sphere& s) { out += ",\"shape\":\"sphere\",\"radius\":" + number(s.radius); }
    void operator()(const Box& b) { out += ",\"shape\":\"box\",\"half\":" + vec(b.half_extents); }
    void operator()(const Capsule& c) {
        out += ",\"shape\":\"capsule\",\"radius\":" + number(c.radius) + ",\"height\":" + number(c.height);
    }
    void operator()(const ConvexHull& h) {
        out += ",\"shape\":\"hull\",\"points\":[";
        for (std::size_t n = 0; n < h.points.size(); ++n)
            out += (n ? "," : "") + vec(h.points[n]);
        out += "]";
    }
    void operator()(const Plane& p) {
        out += ",\"shape\":\"plane\",\"normal\":" + vec(p.normal) + ",\"offset\":" + number(p.offset);
    }
};

}  // namespace

PageFeed::PageFeed(std::optional<Region> region) : region_(std::move(region)) {}

void PageFeed::set_world(const WorldSettings& settings) {
    settings_ = settings;
    for (auto& [id, page] : pages_)
        page.world_sent = false;
}

bool PageFeed::on_border(const BodyView& body, double radius) const {
    if (!std::isfinite(radius) || !settings_) return false;  // a plane is in no sector's world
    bool reaches = false;
    neighbours_within(body.position.local, settings_->sector_size, radius,
                      [&](const SectorKey&) { reaches = true; });
    return reaches;
}

void PageFeed::take(const WorldFrame& frame, const Describe& describe) {
    if (frame.every_body) {
        // Bodies not in a frame of every body have left: their kinds go with them.
        std::unordered_set<BodyId> now;
        for (const BodyView& b : frame.bodies)
            now.insert(b.id);
        for (auto it = kinds_.begin(); it != kinds_.end();)
            it = now.count(it->first) ? std::next(it) : kinds_.erase(it);
        for (auto it = radii_.begin(); it != radii_.end();)
            it = now.count(it->first) ? std::next(it) : radii_.erase(it);
        bodies_.clear();
        for (auto& [id, page] : pages_)
            page.every_body = true;
    }
    for (const BodyView& b : frame.bodies) {
        if (!kinds_.count(b.id)) {
            if (std::optional<BodyDesc> desc = describe(b)) {
                kinds_[b.id] = kind_json(*desc);
                radii_[b.id] = bounding_radius(desc->shape);
            }
        }
        auto radius = radii_.find(b.id);
        bodies_[b.id] = Body{b, radius != radii_.end() && on_border(b, radius->second)};
        for (auto& [id, page] : pages_) {
            page.changed.insert(b.id);
            page.departed.erase(b.id);
        }
    }
    for (BodyId id : frame.departed) {
        bodies_.erase(id);
        kinds_.erase(id);
        radii_.erase(id);
        for (auto& [at, page] : pages_) {
            page.changed.erase(id);
            page.described.erase(id);
            page.departed.insert(id);
        }
    }
    for (auto& [id, page] : pages_) {
        page.handoffs.insert(page.handoffs.end(), frame.handoffs.begin(), frame.handoffs.end());
        if (page.handoffs.size() > kHandoffsKept)
            page.handoffs.erase(page.handoffs.begin(), page.handoffs.end() - kHandoffsKept);
    }
    std::vector<std::uint32_t> ids;
    for (const WorkerView& w : frame.workers)
        ids.push_back(w.id);
    if (ids != worker_ids_) {
        worker_ids_ = std::move(ids);
        for (auto& [id, page] : pages_)
            page.world_sent = false;
    }
    workers_ = frame.workers;
    frame_ = frame.frame;
    time_lost_s_ = frame.time_lost_s;
    started_ms_ =
        std::chrono::duration_cast<std::chrono::milliseconds>(frame.started.time_since_epoch()).count();
}

std::uint64_t PageFeed::subscribe() {
    pages_[next_page_] = Page{};
    return next_page_++;
}

void PageFeed::unsubscribe(std::uint64_t page) { pages_.erase(page); }

bool PageFeed::has_news(std::uint64_t page) const {
    auto it = pages_.find(page);
    return it != pages_.end() && settings_ && frame_ != 0 &&
           (it->second.frame_sent != frame_ || !it->second.world_sent);
}

std::string PageFeed::world_event() const {
    std::string out = "event: world\ndata: {\"sector_size\":" + number(settings_->sector_size) +
                      ",\"hysteresis\":" + number(settings_->hysteresis) +
                      ",\"gravity\":" + vec(settings_->gravity) + ",\"region\":";
    if (region_) {
        out += fmt::format("{{\"lo\":[{},{},{}],\"hi\":[{},{},{}]}}", region_->lo.i, region_->lo.j,
                           region_->lo.k, region_->hi.i, region_->hi.j, region_->hi.k);
    } else {
        out += "null";
    }
    out += ",\"workers\":[";
    for (std::size_t n = 0; n < worker_ids_.size(); ++n)
        out += (n ? "," : "") + std::to_string(worker_ids_[n]);
    return out + "]}\n\n";
}

std::string PageFeed::kind_json(const BodyDesc& desc) {
    // Ids as strings: a JSON number past 2^53 loses digits in the browser.
    std::string out = "{\"id\":\"" + std::to_string(desc.id) + "\",\"name\":";
    append_json_string(out, desc.name);
    std::visit(KindJson{out}, desc.shape);
    return out + ",\"mass\":" + number(desc.mass) + "}";
}

void PageFeed::body_json(std::string& out, const Body& body) const {
    const BodyView& b = body.view;
    const Eigen::Quaterniond& q = b.orientation;
    out += fmt::format("[\"{}\",{},{},{},{},{},{},{},{},{},{}]", b.id, number(b.global.x()),
                       number(b.global.y()), number(b.global.z()), number(q.x()), number(q.y()),
                       number(q.z()), number(q.w()), b.worker, b.awake ? 1 : 0, body.on_border ? 1 : 0);
}

std::string PageFeed::events_for(std::uint64_t id) {
    auto it = pages_.find(id);
    if (it == pages_.end() || !has_news(id)) return {};
    Page& page = it->second;
    std::string out;
    if (!page.world_sent) {
        out += world_event();
        page.world_sent = true;
    }
    std::vector<const Body*> send;
    if (page.every_body) {
        page.described.clear();
        for (const auto& [bid, body] : bodies_)
            send.push_back(&body);
    } else {
        for (BodyId bid : page.changed) {
            if (auto b = bodies_.find(bid); b != bodies_.end()) send.push_back(&b->second);
        }
    }
    std::sort(send.begin(), send.end(), [](const Body* a, const Body* b) { return a->view.id < b->view.id; });
    std::string kinds;
    for (const Body* b : send) {
        auto kind = kinds_.find(b->view.id);
        if (kind == kinds_.end() || !page.described.insert(b->view.id).second) continue;
        kinds += (kinds.empty() ? "" : ",") + kind->second;
    }
    if (!kinds.empty()) out += "event: kinds\ndata: {\"bodies\":[" + kinds + "]}\n\n";
    out += fmt::format("event: frame\ndata: {{\"frame\":{},\"every_body\":{},\"bodies\":[", frame_,
                       page.every_body ? "true" : "false");
    for (std::size_t n = 0; n < send.size(); ++n) {
        if (n) out += ',';
        body_json(out, *send[n]);
    }
    out += "],\"departed\":[";
    if (!page.every_body) {
        std::vector<BodyId> departed(page.departed.begin(), page.departed.end());
        std::sort(departed.begin(), departed.end());
        for (std::size_t n = 0; n < departed.size(); ++n)
            out += fmt::format("{}\"{}\"", n ? "," : "", departed[n]);
    }
    out += "],\"handoffs\":[";
    for (std::size_t n = 0; n < page.handoffs.size(); ++n) {
        const HandoffView& h = page.handoffs[n];
        out += fmt::format("{}[\"{}\",{},{},{}]", n ? "," : "", h.body, h.from_worker, h.to_worker, h.frame);
    }
    out += "],\"workers\":[";
    for (std::size_t n = 0; n < workers_.size(); ++n) {
        const WorkerView& w = workers_[n];
        out += fmt::format(
            "{}{{\"id\":{},\"sectors\":{},\"bodies\":{},\"ghosts\":{},\"clones\":{},\"awake\":{},"
            "\"step_ms\":{}}}",
            n ? "," : "", w.id, w.sectors, w.bodies, w.ghosts, w.clones, w.awake, number(w.step_ms));
    }
    out += fmt::format("],\"time_lost\":{},\"started_ms\":{}}}\n\n", number(time_lost_s_), started_ms_);
    page.every_body = false;
    page.changed.clear();
    page.departed.clear();
    page.handoffs.clear();
    page.frame_sent = frame_;
    return out;
}

}  // namespace lpss::view
