#include "view_server.hpp"

#include <httplib.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "page_assets.hpp"

namespace lpss::view {

namespace {

/// The three.js files the page loads, as Debian's libjs-three (r111) installs them.
/// three.js itself, its orbit camera, and the convex hull of a hull shape's points (ConvexHull before
/// ConvexGeometry, which uses it).
constexpr const char* kThreeFiles[] = {"three.min.js", "examples/js/controls/OrbitControls.js",
                                       "examples/js/math/ConvexHull.js",
                                       "examples/js/geometries/ConvexGeometry.js"};

}  // namespace

ViewServer::ViewServer(const ViewServerOptions& options, PageFeed feed)
    : options_(options), http_(std::make_unique<httplib::Server>()), feed_(std::move(feed)) {}

Expected<std::unique_ptr<ViewServer>> ViewServer::start(const ViewServerOptions& options, PageFeed feed) {
    for (const char* file : kThreeFiles) {
        if (!std::filesystem::exists(std::filesystem::path(options.three_dir) / file)) {
            return Error{"three.js not found: " + options.three_dir + "/" + file +
                         " is missing (install Debian's libjs-three, or give --three-dir)"};
        }
    }
    std::unique_ptr<ViewServer> server(new ViewServer(options, std::move(feed)));
    httplib::Server& http = *server->http_;
    for (const PageAsset& asset : page_assets()) {
        http.Get(asset.path, [&asset](const httplib::Request&, httplib::Response& res) {
            res.set_header("Cache-Control", "no-cache");
            res.set_content(asset.content.data(), asset.content.size(), asset.mime);
        });
    }
    http.Get("/", [](const httplib::Request&, httplib::Response& res) { res.set_redirect("/index.html"); });
    // Only the files the page loads, not the whole folder.
    for (const char* file : kThreeFiles) {
        const std::string path = (std::filesystem::path(options.three_dir) / file).string();
        const std::string url = std::string("/three/") + std::filesystem::path(file).filename().string();
        http.Get(url, [path](const httplib::Request&, httplib::Response& res) {
            std::ifstream in(path, std::ios::binary);
            std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
            if (!in.good() && !in.eof()) {
                res.status = 500;
                return;
            }
            res.set_content(text, "text/javascript");
        });
    }  // A thread per open page and a few for the files.
    const std::size_t threads = options.max_pages + 4;
    http.new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
    // One request per connection ("Connection: close"): an idle keep-alive connection holds one of those
    // threads, and one the server closes after its timeout can be picked by the browser for its next
    // request at that moment. Chromium resends such a request once; a page that lost two that way (a
    // slow page under load, several idle sockets closed at once) failed to load with
    // net::ERR_SOCKET_NOT_CONNECTED and never ran its script (seen in the View test, a few times in
    // many runs). The page's dozen files over loopback cost nothing more this way.
    http.set_keep_alive_max_count(1);
    ViewServer* self = server.get();
    http.Get("/events", [self](const httplib::Request& req, httplib::Response& res) {
        // A page may ask for fewer frames a second than --max-rate (?rate=N), never for more.
        double rate = self->options_.max_rate_hz;
        if (req.has_param("rate")) {
            const double asked = std::strtod(req.get_param_value("rate").c_str(), nullptr);
            if (asked > 0.0 && asked < rate) rate = std::max(asked, 0.1);
        }
        std::uint64_t page = 0;
        {
            std::lock_guard<std::mutex> lock(self->mutex_);
            // Each open page holds one of the server's threads: beyond --max-pages a page is told so at once
            // instead of waiting for a thread that never comes free.
            if (self->pace_.size() >= self->options_.max_pages) {
                res.status = 503;
                res.set_content("lpss-view serves " + std::to_string(self->options_.max_pages) +
                                    " pages at most (--max-pages); close one",
                                "text/plain");
                return;
            }
            page = self->feed_.subscribe();
            self->pace_[page] = Pace{std::chrono::steady_clock::now(),
                                     std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                         std::chrono::duration<double>(1.0 / rate))};
        }
        res.set_header("Cache-Control", "no-cache");
        res.set_chunked_content_provider(
            "text/event-stream",
            [self, page](std::size_t, httplib::DataSink& sink) {
                std::string text = self->next_events(page);
                if (self->stopping_) return false;
                if (text.empty()) text = ": waiting for the world\n\n";
                return sink.write(text.data(), text.size());
            },
            [self, page](bool) {
                std::lock_guard<std::mutex> lock(self->mutex_);
                self->feed_.unsubscribe(page);
                self->pace_.erase(page);
            });
    });
    if (options.port == 0) {
        server->port_ = http.bind_to_any_port(options.listen);
        if (server->port_ < 0) return Error{"cannot serve on " + options.listen + ": no free port"};
    } else {
        if (!http.bind_to_port(options.listen, options.port)) {
            return Error{"cannot serve on " + options.listen + ":" + std::to_string(options.port) +
                         " (in use, or not an address of this machine)"};
        }
        server->port_ = options.port;
    }
    server->serving_ = std::thread([self] { self->http_->listen_after_bind(); });
    // stop() does nothing before the server runs: a server destroyed at once would otherwise never end.
    for (int n = 0; n < 2000 && !http.is_running(); ++n)
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    return server;
}

ViewServer::~ViewServer() {
    {
        // Under the lock: a page thread between its check and its wait would miss the wake-up.
        std::lock_guard<std::mutex> lock(mutex_);
        stopping_ = true;
    }
    news_.notify_all();
    http_->stop();
    if (serving_.joinable()) serving_.join();
}

void ViewServer::set_world(const WorldSettings& settings) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        feed_.set_world(settings);
    }
    news_.notify_all();
}

void ViewServer::take(const WorldFrame& frame, const PageFeed::Describe& describe) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        feed_.take(frame, describe);
    }
    news_.notify_all();
}

std::size_t ViewServer::pages() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return pace_.size();
}

std::string ViewServer::next_events(std::uint64_t page) {
    std::unique_lock<std::mutex> lock(mutex_);
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(1);
    Pace& pace = pace_[page];
    auto& next = pace.next;
    for (;;) {
        if (stopping_) return {};
        const auto now = std::chrono::steady_clock::now();
        if (feed_.has_news(page) && now >= next) break;
        const auto until = feed_.has_news(page) ? std::min(next, give_up) : give_up;
        if (now >= give_up) return {};
        news_.wait_until(lock, until);
    }
    next = std::chrono::steady_clock::now() + pace.interval;
    return feed_.events_for(page);
}

}  // namespace lpss::view
