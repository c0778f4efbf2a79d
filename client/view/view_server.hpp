// lpss-view's web server: the page, three.js from Debian's libjs-three, and the world as server-sent
// events. cpp-httplib (Debian's libcpp-httplib-dev) serves it: a small, well-kept HTTP library whose
// chunked responses carry server-sent events, which is all the page needs (the world flows one way; a
// WebSocket library would bring Boost or Asio for nothing more). Each page holds one of the server's
// threads while it is connected.
#pragma once

#include <atomic>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "lpss/common/expected.hpp"
#include "page_feed.hpp"

namespace httplib {
class Server;
}

namespace lpss::view {

struct ViewServerOptions {
    std::string listen = "127.0.0.1";  ///< the address to serve on: this machine only unless told
    int port = 8090;                   ///< 0: any free port (see ViewServer::port)
    double max_rate_hz = 30.0;         ///< frames sent to a page per second at most
    std::size_t max_pages = 8;         ///< pages open at once; more are answered 503
    std::string three_dir = "/usr/share/javascript/three";  ///< Debian's libjs-three
};

class ViewServer {
public:
    /// Binds and starts serving; refused with the reason (address in use, three.js missing).
    static Expected<std::unique_ptr<ViewServer>> start(const ViewServerOptions& options, PageFeed feed);
    ~ViewServer();
    ViewServer(const ViewServer&) = delete;
    ViewServer& operator=(const ViewServer&) = delete;

    int port() const { return port_; }
    /// Tells the pages what world they show, once a cluster is found.
    void set_world(const WorldSettings& settings);
    /// Passes a client frame to the pages (from the thread that polls the client).
    void take(const WorldFrame& frame, const PageFeed::Describe& describe);
    /// Pages connected now.
    std::size_t pages() const;

private:
    explicit ViewServer(const ViewServerOptions& options, PageFeed feed);
    /// Waits up to a second for events the page has not had, no sooner than the rate allows; empty if
    /// none came (the stream then sends a comment, which also tells that the page is gone).
    std::string next_events(std::uint64_t page);

    ViewServerOptions options_;
    std::unique_ptr<httplib::Server> http_;
    std::thread serving_;
    int port_ = 0;
    mutable std::mutex mutex_;
    std::condition_variable news_;
    PageFeed feed_;
    struct Pace {
        std::chrono::steady_clock::time_point next;
        std::chrono::steady_clock::duration interval;
    };
    std::map<std::uint64_t, Pace> pace_;  ///< per page: when it may be sent its next frame
    std::atomic<bool> stopping_{false};
};

}  // namespace lpss::view
