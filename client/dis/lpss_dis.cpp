// lpss-dis: puts the bodies of a running lpss world on a DIS exercise (IEEE 1278.1, protocol version 7) as
// Entity State PDUs over UDP, dead reckoned as DIS senders do. A client of the cluster like any other
// (lpss::Client, frames of changes). Sends to 127.0.0.1 unless told otherwise.
#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>

#include "crash_report.hpp"
#include "dis_gateway.hpp"
#include "lpss/client/client.hpp"
#include "stop_signal.hpp"
#include "udp_sender.hpp"

int main(int argc, char** argv) {
    lpss::runtime::install_crash_report("lpss-dis");
    CLI::App app{"lpss-dis: publishes a running lpss world as DIS Entity State PDUs"};
    lpss::ClientOptions options;
    options.name = "lpss-dis";
    options.content = lpss::FrameContent::changes;
    lpss::dis::GatewayOptions gateway;
    std::string region, address = "127.0.0.1", algorithm = "rvw";
    std::uint16_t port = 3000;
    int exercise = 1, ttl = 1, wait_s = 30;
    bool broadcast = false;
    std::uint64_t frames = 0;
    double orientation_deg = 3.0;
    app.add_option("--domain", options.domain, "DDS domain id")->check(CLI::Range(0, 232));
    app.add_option("--profile", options.profile,
                   "Fast DDS XML profile (default: built-in, this machine only)");
    app.add_option("--security", options.security,
                   "DDS Security identity folder (deploy/security/identities.sh; default: none)");
    app.add_option("--region", region, "follow only sectors i_lo,i_hi,j_lo,j_hi,k_lo,k_hi");
    app.add_option("--dis-address", address,
                   "where PDUs go (default 127.0.0.1; a broadcast one needs --broadcast)");
    app.add_option("--dis-port", port, "UDP port of the exercise (DIS's usual 3000)");
    app.add_flag("--broadcast", broadcast, "allow a broadcast --dis-address");
    app.add_option("--multicast-ttl", ttl, "hops for a multicast --dis-address")->check(CLI::Range(0, 255));
    app.add_option("--exercise", exercise, "DIS exercise id")->check(CLI::Range(0, 255));
    app.add_option("--site", gateway.site, "DIS site number of every entity (1-65534)")
        ->check(CLI::Range(1, 65534));
    app.add_option("--application", gateway.application, "DIS application number of every entity (1-65534)")
        ->check(CLI::Range(1, 65534));
    app.add_option("--dead-reckoning", algorithm, "rvw (DRM_RVW, rotating, acceleration) or fvw (DRM_FVW)")
        ->check(CLI::IsMember({"rvw", "fvw"}));
    app.add_option("--position-threshold", gateway.thresholds.position_m,
                   "send when receivers' dead-reckoned position is off by more than this many metres")
        ->check(CLI::PositiveNumber);
    app.add_option("--orientation-threshold", orientation_deg,
                   "... or their orientation by more than this (degrees)")
        ->check(CLI::PositiveNumber);
    app.add_option("--heartbeat", gateway.thresholds.heartbeat_s, "send every entity at least this often (s)")
        ->check(CLI::PositiveNumber);
    app.add_flag("--relative-timestamps", gateway.relative_timestamps,
                 "stamp PDUs with the world's time (frame * dt) instead of the wall clock");
    app.add_option("--frames", frames, "exit after this many frames (0: until Ctrl-C)");
    app.add_option("--name", options.name, "this client's name on the domain (unique per domain)");
    app.add_option("--wait-s", wait_s, "how long to wait for a cluster");
    CLI11_PARSE(app, argc, argv);
    gateway.exercise = static_cast<std::uint8_t>(exercise);
    gateway.algorithm = algorithm == "fvw" ? lpss::dis::dead_reckoning_algorithm::kFvw
                                           : lpss::dis::dead_reckoning_algorithm::kRvw;
    gateway.thresholds.orientation_rad = orientation_deg * M_PI / 180.0;
    if (!region.empty()) {
        auto r = lpss::parse_region(region);
        if (!r) {
            std::fprintf(stderr, "lpss-dis: %s\n", r.error().message.c_str());
            return 2;
        }
        options.region = r.value();
    }
    auto sender = lpss::dis::UdpSender::open(address, port, broadcast, ttl);
    if (!sender) {
        std::fprintf(stderr, "lpss-dis: %s\n", sender.error().message.c_str());
        return 2;
    }
    auto client = lpss::Client::connect(options);
    if (!client) {
        std::fprintf(stderr, "lpss-dis: cannot start: %s\n", client.error().message.c_str());
        return 2;
    }
    const std::atomic<bool>& stop = lpss::runtime::install_stop_signal();
    lpss::Client& c = **client;
    if (!c.wait_for_cluster(std::chrono::seconds(wait_s))) {
        std::fprintf(stderr, "lpss-dis: no lpss cluster found on domain %d within %d s\n", options.domain,
                     wait_s);
        return 3;
    }
    auto made = lpss::dis::DisGateway::create(*c.settings(), gateway);
    if (!made) {
        std::fprintf(stderr, "lpss-dis: %s\n", made.error().message.c_str());
        return 2;
    }
    std::optional<lpss::dis::DisGateway> dis(std::move(made).value());
    std::printf("lpss-dis: world of domain %d to DIS exercise %d at %s:%u\n", options.domain, exercise,
                address.c_str(), static_cast<unsigned>(port));
    std::fflush(stdout);
    const lpss::dis::DisGateway::Describe describe = [&c](const lpss::BodyView& b) {
        return c.description(b);
    };
    std::uint64_t seen = 0, bytes = 0, pdus = 0, last_pdus = 0, last_body_frames = 0, last_bytes = 0;
    auto send_all = [&](const std::vector<lpss::dis::EntityStatePdu>& out) {
        for (const lpss::dis::EntityStatePdu& pdu : out) {
            const auto wire = lpss::dis::encode(pdu);
            if (sender->send(wire.data(), wire.size())) bytes += wire.size();
        }
        pdus += out.size();
    };
    auto last_print = std::chrono::steady_clock::now();
    auto last_data = last_print;
    std::optional<lpss::WorldFrame> last;
    // Whether the world keeps the receivers' pace: measured over the first frames, said once.
    std::optional<lpss::WorldFrame> pace_from;
    bool pace_said = false;
    int exit_code = 0;
    while ((frames == 0 || seen < frames) && !stop.load()) {
        for (lpss::WorldFrame& f : c.poll(std::chrono::milliseconds(50))) {
            if (last && f.frame < last->frame) {
                // Frame numbers went back: another cluster on the domain. Its bodies are new entities.
                std::fprintf(
                    stderr, "lpss-dis: frame %llu after %llu: a new cluster; its entities start over\n",
                    static_cast<unsigned long long>(f.frame), static_cast<unsigned long long>(last->frame));
                send_all(dis->deactivate_all(*last));
                auto again = lpss::dis::DisGateway::create(*c.settings(), gateway);
                if (!again) {
                    std::fprintf(stderr, "lpss-dis: %s\n", again.error().message.c_str());
                    return 2;
                }
                dis.emplace(std::move(again).value());
                pace_from.reset();
            }
            ++seen;
            last_data = std::chrono::steady_clock::now();
            send_all(dis->take(f, describe));
            if (!pace_from) pace_from = f;
            if (!pace_said && f.frame >= pace_from->frame + 120) {
                const double world_s = static_cast<double>(f.frame - pace_from->frame) * c.settings()->dt;
                const double wall_s = std::chrono::duration<double>(f.started - pace_from->started).count();
                if (world_s > 1.5 * wall_s) {
                    std::fprintf(
                        stderr,
                        "lpss-dis: the world runs %.1fx faster than real time (a cluster without "
                        "--realtime): DIS receivers dead-reckon on their own clocks and will lag it\n",
                        world_s / wall_s);
                }
                pace_said = true;
            }
            last = std::move(f);
        }
        const auto now = std::chrono::steady_clock::now();
        if (now - last_data > std::chrono::seconds(wait_s)) {
            std::fprintf(stderr, "lpss-dis: no frame for %d s: the cluster is gone\n", wait_s);
            exit_code = 3;
            break;
        }
        if (now - last_print >= std::chrono::seconds(5)) {
            const double s = std::chrono::duration<double>(now - last_print).count();
            const std::uint64_t body_frames = dis->counts().body_frames;
            fmt::print(
                "lpss-dis: {:.0f} PDUs/s, {:.0f} B/s; one PDU per body per frame would be {:.0f}/s; {} send "
                "errors\n",
                (pdus - last_pdus) / s, (bytes - last_bytes) / s, (body_frames - last_body_frames) / s,
                sender->errors());
            std::fflush(stdout);
            last_pdus = pdus, last_bytes = bytes, last_body_frames = body_frames, last_print = now;
        }
    }
    // Whatever ends it (Ctrl-C, --frames, the cluster gone), receivers are told the entities are gone.
    if (last) send_all(dis->deactivate_all(*last));
    std::fprintf(stderr, "lpss-dis: %llu frames, %llu PDUs (%llu deactivations), %llu bytes\n",
                 static_cast<unsigned long long>(seen), static_cast<unsigned long long>(pdus),
                 static_cast<unsigned long long>(dis->counts().deactivations),
                 static_cast<unsigned long long>(bytes));
    return exit_code;
}
