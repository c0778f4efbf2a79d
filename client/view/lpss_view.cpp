// lpss-view: serves a web page, on this machine only unless told otherwise, that shows a running lpss world
// live in 3D: every body with its shape, coloured by the worker that owns it, sector borders, bodies on
// borders and handoffs on demand, and a panel with the cluster's figures. A client of the cluster like any
// other (lpss::Client, frames of changes); the page renders around a floating origin, so a body 10^12
// units out is drawn as precisely as one at the origin.
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>

#include "crash_report.hpp"
#include "lpss/client/client.hpp"
#include "stop_signal.hpp"
#include "view_server.hpp"

int main(int argc, char** argv) {
    lpss::runtime::install_crash_report("lpss-view");
    CLI::App app{"lpss-view: shows a running lpss world in a web browser"};
    lpss::ClientOptions options;
    options.name = "lpss-view";
    options.content = lpss::FrameContent::changes;
    lpss::view::ViewServerOptions serve;
    std::string region;
    int wait_s = 0;
    app.add_option("--domain", options.domain, "DDS domain id")->check(CLI::Range(0, 232));
    app.add_option("--profile", options.profile,
                   "Fast DDS XML profile (default: built-in, this machine only)");
    app.add_option("--security", options.security,
                   "DDS Security identity folder (deploy/security/identities.sh; default: none)");
    app.add_option("--region", region, "follow only sectors i_lo,i_hi,j_lo,j_hi,k_lo,k_hi");
    app.add_option("--port", serve.port, "HTTP port (0: any free one, printed)")->check(CLI::Range(0, 65535));
    app.add_option(
        "--listen", serve.listen,
        "address to serve on (default 127.0.0.1: this machine only; 0.0.0.0 opens it to the network)");
    app.add_option("--max-rate", serve.max_rate_hz, "frames sent to each page per second at most")
        ->check(CLI::Range(1.0, 240.0));
    app.add_option("--max-pages", serve.max_pages, "pages open at once (each holds a thread)")
        ->check(CLI::Range(1, 64));
    app.add_option("--three-dir", serve.three_dir, "where three.js is (Debian's libjs-three)");
    app.add_option("--name", options.name, "this client's name on the domain (unique per domain)");
    app.add_option("--wait-s", wait_s, "how long to wait for a cluster (0: as long as it takes)");
    CLI11_PARSE(app, argc, argv);
    if (!region.empty()) {
        auto r = lpss::parse_region(region);
        if (!r) {
            std::fprintf(stderr, "lpss-view: %s\n", r.error().message.c_str());
            return 2;
        }
        options.region = r.value();
    }
    auto client = lpss::Client::connect(options);
    if (!client) {
        std::fprintf(stderr, "lpss-view: cannot start: %s\n", client.error().message.c_str());
        return 2;
    }
    const std::atomic<bool>& stop = lpss::runtime::install_stop_signal();
    // Served at once, so that the page can be opened before the cluster starts: it waits for the world.
    auto server = lpss::view::ViewServer::start(serve, lpss::view::PageFeed((*client)->region()));
    if (!server) {
        std::fprintf(stderr, "lpss-view: %s\n", server.error().message.c_str());
        return 2;
    }
    std::printf("lpss-view: http://%s:%d/ shows the world of domain %d\n",
                serve.listen == "0.0.0.0" ? "127.0.0.1" : serve.listen.c_str(), (*server)->port(),
                options.domain);
    std::fflush(stdout);
    const auto looking = std::chrono::steady_clock::now();
    bool said_waiting = false;
    while (!stop.load() && !(*client)->wait_for_cluster(std::chrono::seconds(1))) {
        if (wait_s > 0 && std::chrono::steady_clock::now() - looking > std::chrono::seconds(wait_s)) {
            std::fprintf(stderr, "lpss-view: no lpss cluster found on domain %d within %d s\n",
                         options.domain, wait_s);
            return 3;
        }
        if (!said_waiting)
            std::fprintf(stderr, "lpss-view: waiting for a cluster on domain %d\n", options.domain);
        said_waiting = true;
    }
    if (stop.load()) return 0;
    (*server)->set_world(*(*client)->settings());
    lpss::Client& c = **client;
    const lpss::view::PageFeed::Describe describe = [&c](const lpss::BodyView& b) {
        return c.description(b);
    };
    auto last_data = std::chrono::steady_clock::now();
    bool said_gone = false;
    while (!stop.load()) {
        for (const lpss::WorldFrame& f : c.poll(std::chrono::milliseconds(50))) {
            (*server)->take(f, describe);
            last_data = std::chrono::steady_clock::now();
            said_gone = false;
        }
        // The page keeps showing the last frame.
        if (!said_gone && std::chrono::steady_clock::now() - last_data > std::chrono::seconds(30)) {
            std::fprintf(stderr, "lpss-view: no frame for 30 s: the cluster is gone or stopped\n");
            said_gone = true;
        }
    }
    return 0;
}
