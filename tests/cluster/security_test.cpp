// DDS Security as a cluster runs it (docs/security.md): identities from deploy/security/identities.sh, a
// secured lpss-cluster, and what access control and encryption keep out. Each test makes its own CAs and
// identities in a folder of its own, and uses a DDS domain of its own.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <linux/if_ether.h>
#include <linux/if_packet.h>
#include <net/if.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <thread>

#include "cluster_harness.hpp"
#include "lpssPubSubTypes.h"
#include "lpss_dds/convert.hpp"
#include "lpss_dds/participant.hpp"
#include "lpss_dds/topics.hpp"
#include "scenes.hpp"

namespace lpss {
namespace {

using testing::read_file;
using testing::run_sim;
using testing::start_cluster;
using testing::write_scene;

constexpr double kL = 64.0;
/// A name and a position that no one without the keys may read off the wire.
constexpr const char* kSecretName = "lpss-secret-plinth";
const Eigen::Vector3d kSecretAt(2 * kL + 9.125, 7.25, -3.5);  // local (9.125, 7.25, -3.5) in sector (2, 0, 0)

/// Bodies crossing two sector borders, and a static plinth with a name, in sectors of 64.
Scene secret_scene() {
    Scene scene = scenes::sphere_pair(Eigen::Vector3d(0.5 * kL, 0, 0), kL);
    BodyDesc runner = scenes::sphere_body(3, 0.5, 1.0, Eigen::Vector3d(20, 5, 0));
    runner.linear_velocity = Eigen::Vector3d(40, 0, 0);
    scene.bodies.push_back(runner);
    BodyDesc plinth = scenes::box_body(4, Eigen::Vector3d(1, 1, 1), 0.0, kSecretAt);
    plinth.name = kSecretName;
    scene.bodies.push_back(plinth);
    return scene;
}

/// A folder of identities made by deploy/security/identities.sh (removed at the end), with, besides the four
/// roles, an expired worker identity and a revoked operator.
class Identities {
public:
    Identities() {
        dir_ = testing::workspace() / "identities";
        std::filesystem::remove_all(dir_);
        const std::string script = std::string(LPSS_SOURCE_DIR) + "/deploy/security/identities.sh";
        const std::string quiet = " > " + (dir_.string() + ".log") + " 2>&1";
        ok_ =
            std::system((script + " init " + dir_.string() + quiet).c_str()) == 0 &&
            std::system((script + " expired " + dir_.string() + " old-worker worker" + quiet).c_str()) == 0 &&
            std::system((script + " add " + dir_.string() + " gone-operator operator" + quiet).c_str()) ==
                0 &&
            std::system((script + " revoke " + dir_.string() + " gone-operator" + quiet).c_str()) == 0;
    }
    ~Identities() {
        std::filesystem::remove_all(dir_);
        std::filesystem::remove(dir_.string() + ".log");
    }
    bool ok() const { return ok_; }
    std::string root() const { return dir_.string(); }
    std::string operator[](const std::string& name) const { return (dir_ / name).string(); }
    std::string log() const { return read_file(dir_.string() + ".log"); }

private:
    std::filesystem::path dir_;
    bool ok_ = false;
};

std::unique_ptr<Client> secured_client(int domain, const std::string& name, const std::string& identity) {
    return testing::connect(domain, name, {}, FrameContent::every_body, identity);
}

/// Every packet on loopback while it lives (a raw socket in the test's own network namespace).
class LoopbackCapture {
public:
    LoopbackCapture() {
        socket_ = ::socket(AF_PACKET, SOCK_RAW, htons(ETH_P_ALL));
        if (socket_ < 0) return;
        sockaddr_ll at{};
        at.sll_family = AF_PACKET;
        at.sll_protocol = htons(ETH_P_ALL);
        at.sll_ifindex = static_cast<int>(if_nametoindex("lo"));
        timeval timeout{0, 100000};
        setsockopt(socket_, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
        int buffer = 8 << 20;
        setsockopt(socket_, SOL_SOCKET, SO_RCVBUF, &buffer, sizeof buffer);
        if (bind(socket_, reinterpret_cast<sockaddr*>(&at), sizeof at) != 0) {
            ::close(socket_);
            socket_ = -1;
            return;
        }
        reader_ = std::thread([this] {
            std::vector<char> packet(1 << 16);
            while (!stop_) {
                const ssize_t n = ::recv(socket_, packet.data(), packet.size(), 0);
                if (n <= 0) continue;
                std::lock_guard<std::mutex> lock(mutex_);
                bytes_.append(packet.data(), static_cast<std::size_t>(n));
                ++packets_;
            }
        });
    }
    ~LoopbackCapture() {
        stop_ = true;
        if (reader_.joinable()) reader_.join();
        if (socket_ >= 0) ::close(socket_);
    }
    bool ok() const { return socket_ >= 0; }
    /// How many times `pattern` occurs in what was captured.
    std::size_t count(const std::string& pattern) {
        std::lock_guard<std::mutex> lock(mutex_);
        std::size_t n = 0;
        for (auto at = bytes_.find(pattern); at != std::string::npos; at = bytes_.find(pattern, at + 1))
            ++n;
        return n;
    }
    std::size_t packets() {
        std::lock_guard<std::mutex> lock(mutex_);
        return packets_;
    }

private:
    int socket_ = -1;
    std::atomic<bool> stop_{false};
    std::thread reader_;
    std::mutex mutex_;
    std::string bytes_;
    std::size_t packets_ = 0;
};

/// The plinth's sector-local position as the wire carries it: three little-endian floats.
std::string secret_position_bytes() {
    const float local[3] = {static_cast<float>(kSecretAt.x() - 2 * kL), static_cast<float>(kSecretAt.y()),
                            static_cast<float>(kSecretAt.z())};
    return std::string(reinterpret_cast<const char*>(local), sizeof local);
}

/// Runs the scene on a cluster (secured with `identities` when given) with a client reading every frame (with
/// the identity in `client_identity`), and returns what a loopback capture saw of the plinth's name and
/// position.
std::pair<std::size_t, std::size_t> capture_a_run(int domain, const std::string& identities,
                                                  const std::string& client_identity) {
    const testing::DomainCleanup cleanup(domain);
    const std::string path = write_scene(secret_scene(), "secret" + std::to_string(domain));
    LoopbackCapture capture;
    EXPECT_TRUE(capture.ok()) << "no raw socket on loopback: " << std::strerror(errno);
    constexpr int kFrames = 120;
    ClientOptions o;
    o.domain = domain;
    o.name = "capture";
    o.security = client_identity;
    auto client = Client::connect(o);
    EXPECT_TRUE(client.ok());
    // Frame 1 waits for the client (an unpaced run is over in a second); awaiting a client takes one that
    // may say it is ready, which is a command: the secured run's client is an operator.
    std::vector<std::string> extra = {"--no-standby", "--await-clients", "1"};
    if (!identities.empty()) extra.insert(extra.end(), {"--security", identities});
    auto cluster = start_cluster(path, domain, 2, kFrames, extra, /*fast=*/true);
    EXPECT_TRUE(cluster.process);
    const auto frames = client ? testing::collect(**client, kFrames, std::chrono::seconds(60))
                               : std::map<std::uint64_t, WorldFrame>{};
    EXPECT_EQ(cluster.process->stop(std::chrono::seconds(20)), 0) << "logs: " << cluster.log_dir;
    EXPECT_FALSE(frames.empty()) << "the client saw no frame";
    if (!identities.empty()) {
        // The coordinator role may ask for sectors whole (identities.sh grants it): its writer was made.
        const std::string log = read_file(cluster.log_dir + "/coordinator.log");
        EXPECT_EQ(log.find("cannot write on lpss/sector_requests"), std::string::npos) << log;
        EXPECT_NE(log.find("coordinator"), std::string::npos) << "no coordinator log in " << cluster.log_dir;
    }
    bool plinth = false;
    if (!frames.empty()) {
        for (const BodyView& b : frames.rbegin()->second.bodies)
            plinth = plinth || b.id == 4;
    }
    EXPECT_TRUE(plinth) << "the last frame lacks the plinth";
    std::printf("%s run: %zu packets captured on loopback\n", identities.empty() ? "plain" : "secured",
                capture.packets());
    return {capture.count(kSecretName), capture.count(secret_position_bytes())};
}

TEST(Security, TheExamplesTakeTheirIdentitiesOnASecuredCluster) {
    // The examples of client/examples on a secured cluster: the game backend with an operator's identity
    // spawns its players; with an observer's, each spawn is refused (access control refused its commands
    // writer); the observer with an observer's identity sees the stack 1e9 units out.
    const int domain = 162;
    const testing::DomainCleanup cleanup(domain);
    Identities ids;
    ASSERT_TRUE(ids.ok()) << ids.log();
    auto cluster = start_cluster(std::string(LPSS_SOURCE_DIR) + "/deploy/scenes/far_stacks.textproto", domain,
                                 2, 3600, {"--security", ids.root()});
    ASSERT_TRUE(cluster.process);
    const std::string game_out = cluster.log_dir + "-game.out", denied_out = cluster.log_dir + "-denied.out",
                      observer_out = cluster.log_dir + "-observer.out";
    auto game = runtime::ChildProcess::start(LPSS_EXAMPLE_GAME,
                                             {std::to_string(domain), "2", ids["operator"]}, game_out);
    auto denied = runtime::ChildProcess::start(LPSS_EXAMPLE_GAME,
                                               {std::to_string(domain), "1", ids["observer"]}, denied_out);
    auto observer = runtime::ChildProcess::start(
        LPSS_EXAMPLE_OBSERVER, {std::to_string(domain), "120", ids["observer"]}, observer_out);
    ASSERT_TRUE(game && denied && observer);
    for (auto* p : {&*game, &*denied, &*observer})
        EXPECT_TRUE(p->wait(std::chrono::seconds(90)));
    EXPECT_EQ(game->exit_code().value_or(-1), 0) << read_file(game_out);
    EXPECT_EQ(denied->exit_code().value_or(-1), 0) << read_file(denied_out);
    EXPECT_EQ(observer->exit_code().value_or(-1), 0) << read_file(observer_out);
    cluster.process->stop();
    const std::string game_text = read_file(game_out), denied_text = read_file(denied_out);
    for (int n = 0; n < 4; ++n) {
        const std::string player = "player " + std::to_string(9000 + n);
        EXPECT_NE(game_text.find(player + " spawned at frame"), std::string::npos) << game_text;
        EXPECT_NE(denied_text.find(player + " not spawned: this client's identity"), std::string::npos)
            << denied_text;
    }
    const std::string observed = read_file(observer_out);
    EXPECT_NE(observed.find("6 bodies in the region"), std::string::npos) << observed;
}

TEST(Security, ACaptureOfASecuredRunHoldsNoNameOrPositionInClear) {
    if (!LoopbackCapture().ok()) GTEST_SKIP() << "no raw socket on loopback here (needs CAP_NET_RAW)";
    const Identities ids;
    ASSERT_TRUE(ids.ok()) << ids.log();
    // The control: without security, the plinth's name and position cross loopback in clear.
    const auto [plain_names, plain_positions] = capture_a_run(154, "", "");
    std::printf("plain run: the name %zu times, the position %zu times\n", plain_names, plain_positions);
    EXPECT_GT(plain_names, 0u);
    EXPECT_GT(plain_positions, 0u);
    const auto [names, positions] = capture_a_run(154, ids.root(), ids["operator"]);
    std::printf("secured run: the name %zu times, the position %zu times\n", names, positions);
    EXPECT_EQ(names, 0u);
    EXPECT_EQ(positions, 0u);
}

TEST(Security, OnlyIdentitiesOfTheClustersCasTakePartEachInItsRole) {
    const int domain = 155;
    const testing::DomainCleanup cleanup(domain);
    const Identities ids;
    ASSERT_TRUE(ids.ok()) << ids.log();
    const std::string path = write_scene(secret_scene(), "secured");
    constexpr int kFrames = 240;
    auto sim = run_sim(path, kFrames);
    ASSERT_EQ(sim.size(), kFrames + 1u);

    // An operator is awaited (it may say it is ready: that is a command); an observer reads beside it.
    auto operator_client = secured_client(domain, "operator", ids["operator"]);
    auto observer = secured_client(domain, "observer", ids["observer"]);
    ASSERT_TRUE(operator_client && observer);
    // Without an identity from these CAs: a client, and a peer writing sector samples of a body no one has.
    auto outsider = testing::connect(domain, "outsider");
    ASSERT_TRUE(outsider);
    // A revoked operator whose folder still holds an old list (none): it starts, and the cluster, whose
    // lists name it, refuses it at the handshake.
    const std::string stale = ids["gone-operator"] + "-without-the-new-list";
    std::filesystem::copy(ids["gone-operator"], stale);
    std::filesystem::remove(stale + "/crl.pem");
    auto revoked = secured_client(domain, "revoked", stale);
    ASSERT_TRUE(revoked);
    auto peer = dds::Participant::create(domain, "", "a-peer-without-identity");
    ASSERT_TRUE(peer.ok());
    // In a partition of its own, as lpss's sector writers (own_partition.hpp): lpss's readers match it.
    dds::Writer<wire::SectorFrame> garbage((*peer)->sector_publisher(),
                                           (*peer)->topic<wire::SectorFramePubSubType>(dds::kSectorFrames),
                                           dds::writer_qos(dds::kSectorFrameDelivery));
    ASSERT_TRUE(garbage.ok());

    auto cluster =
        start_cluster(path, domain, 2, kFrames, {"--security", ids.root(), "--await-clients", "1"});
    ASSERT_TRUE(cluster.process);
    ASSERT_TRUE(operator_client->wait_for_cluster(std::chrono::seconds(60))) << "logs: " << cluster.log_dir;

    // A worker's identity may not publish the assignment: DDS access control refuses the writer. The
    // coordinator's identity may (the control).
    for (const auto& [role, allowed] :
         {std::pair<std::string, bool>{"worker", false}, {"coordinator", true}}) {
        auto as =
            dds::Participant::create(domain, "", "a-" + role + "-writing-the-assignment", {}, ids[role]);
        ASSERT_TRUE(as.ok()) << as.error().message;
        dds::Writer<wire::Assignment> assignment(**as,
                                                 (*as)->topic<wire::AssignmentPubSubType>(dds::kSectorOwners),
                                                 dds::writer_qos(dds::kAssignmentDelivery));
        EXPECT_EQ(assignment.ok(), allowed) << role;
    }
    // Expired and revoked identities: Fast DDS refuses to create a participant with them.
    for (const char* refused : {"old-worker", "gone-operator"}) {
        auto as = dds::Participant::create(domain, "", refused, {}, ids[refused]);
        EXPECT_FALSE(as.ok()) << refused << " was let in";
        if (!as.ok()) {
            EXPECT_NE(as.error().message.find("Fast DDS refused it"), std::string::npos);
        }
    }

    std::map<std::uint64_t, WorldFrame> frames;
    std::uint64_t spawn = 0, refused_spawn = 0, written = 0;
    std::vector<std::pair<std::uint64_t, std::string>> hostile;
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (std::chrono::steady_clock::now() < end && (frames.empty() || frames.rbegin()->first < kFrames)) {
        for (WorldFrame& f : observer->poll(std::chrono::milliseconds(10)))
            frames[f.frame] = std::move(f);
        operator_client->poll(std::chrono::milliseconds(0));
        EXPECT_TRUE(outsider->poll(std::chrono::milliseconds(0)).empty())
            << "a client without identity saw a frame";
        EXPECT_TRUE(revoked->poll(std::chrono::milliseconds(0)).empty()) << "a revoked identity saw a frame";
        const std::uint64_t now = frames.empty() ? 1 : frames.rbegin()->first;
        if (now >= 60 && spawn == 0) {
            // An observer may not command; an operator may. Both spawn far from everything else.
            BodyDesc a = scenes::sphere_body(100, 0.5, 1.0, Eigen::Vector3d(10 * kL, 0, 0));
            BodyDesc b = scenes::sphere_body(101, 0.5, 1.0, Eigen::Vector3d(12 * kL, 0, 0));
            refused_spawn = observer->spawn(a);
            spawn = operator_client->spawn(b);
            // A permitted but buggy operator: its hostile commands pass access control and are refused by
            // the coordinator, each with its reason, as without security (CommandsFromTwoClients...).
            hostile = {
                {operator_client->apply_impulse(3, {std::nan(""), 0, 0}), "finite"},
                {operator_client->remove(~BodyId{0}), "unknown body id 18446744073709551615"},
                {operator_client->spawn(scenes::sphere_body(102, 0.5, 1.0, Eigen::Vector3d(1e300, 0, 0))),
                 "beyond"},
            };
        }
        wire::SectorFrame sample;
        sample.sector(dds::to_wire(SectorKey{0, 0, 0}));
        sample.recipients({1, 2});
        sample.frame(now + 1);
        sample.base(now + 1);
        sample.worker(7);
        sample.complete(true);
        BodySnapshot body;
        body.id = 9999;
        sample.bodies().push_back(dds::to_wire(body));
        sample.kinds().emplace_back();
        sample.kinds().back().id(9999);
        garbage.write(sample);
        ++written;
    }
    EXPECT_EQ(hostile.size(), 3u);
    for (const auto& [request, reason] : hostile) {
        const auto outcome = operator_client->wait_outcome(request, std::chrono::seconds(10));
        ASSERT_TRUE(outcome.has_value()) << "no answer to a hostile command (" << reason << ")";
        EXPECT_FALSE(outcome->applied);
        EXPECT_NE(outcome->reason.find(reason), std::string::npos) << outcome->reason;
    }
    const auto applied = operator_client->wait_outcome(spawn, std::chrono::seconds(10));
    const auto refused = observer->outcome(refused_spawn);
    EXPECT_EQ(cluster.process->stop(std::chrono::seconds(20)), 0) << "logs: " << cluster.log_dir;

    ASSERT_FALSE(frames.empty());
    EXPECT_EQ(frames.rbegin()->first, static_cast<std::uint64_t>(kFrames));
    ASSERT_TRUE(applied.has_value());
    EXPECT_TRUE(applied->applied) << applied->reason;
    ASSERT_TRUE(refused.has_value());
    EXPECT_FALSE(refused->applied);
    EXPECT_NE(refused->reason.find("DDS access control"), std::string::npos) << refused->reason;
    // Up to the spawn, the secured world is lpss-sim's, and the peer's samples never show.
    std::map<std::uint64_t, WorldFrame> before;
    for (auto& [f, frame] : frames) {
        for (const BodyView& b : frame.bodies)
            EXPECT_NE(b.id, BodyId{9999}) << "the peer's body shows at frame " << f;
        if (f < 60) before[f] = frame;
    }
    double worst = 0.0;
    EXPECT_EQ(testing::against_sim(before, sim, worst, kL), "");
    std::printf(
        "secured: %zu frames seen by the observer, %llu samples from a peer without identity, largest "
        "difference from lpss-sim %.3g; the operator's spawn applied at frame %llu, the observer's "
        "refused: %s\n",
        frames.size(), static_cast<unsigned long long>(written), worst,
        static_cast<unsigned long long>(applied->frame), refused->reason.c_str());
    EXPECT_LE(worst, 1e-3);
    bool operator_body = false;
    for (const BodyView& b : frames.rbegin()->second.bodies) {
        EXPECT_NE(b.id, BodyId{100}) << "the observer's spawn was applied";
        operator_body = operator_body || b.id == 101;
    }
    EXPECT_TRUE(operator_body) << "the operator's spawn never showed";
}

TEST(Security, AWorkerWhoseIdentityLacksTheSectorPartitionsSaysSoAndStops) {
    // Workers and coordinators write and read sector frames in partitions of their own (own_partition.hpp),
    // which an identity made before those partitions does not permit: the worker must say what to do.
    const int domain = 187;
    const testing::DomainCleanup cleanup(domain);
    const Identities ids;
    ASSERT_TRUE(ids.ok()) << ids.log();
    const std::string old = ids["worker"] + "-before-the-partitions";
    std::filesystem::copy(ids["worker"], old);
    // Its permissions as the script wrote them before, signed by the same permissions CA.
    std::string permissions = read_file(old + "/permissions.xml");
    const std::string granted =
        "<partitions><partition></partition><partition>lpss-from-*</partition></partitions>";
    for (auto at = permissions.find(granted); at != std::string::npos; at = permissions.find(granted))
        permissions.erase(at, granted.size());
    ASSERT_EQ(permissions.find("lpss-from-"), std::string::npos) << permissions;
    std::ofstream(old + "/permissions.xml") << permissions;
    const std::string ca = ids.root() + "/ca/";
    ASSERT_EQ(std::system(("openssl smime -sign -in " + old + "/permissions.xml -text -out " + old +
                           "/permissions.p7s -signer " + ca + "permissions_ca.pem -inkey " + ca +
                           "permissions_ca.key")
                              .c_str()),
              0);
    for (const auto& [folder, refused] : {std::pair<std::string, bool>{old, true}, {ids["worker"], false}}) {
        const std::string out = old + (refused ? ".refused.out" : ".taken.out");
        auto worker = runtime::ChildProcess::start(LPSS_WORKER,
                                                   {"--domain", std::to_string(domain), "--id", "1",
                                                    "--security", folder, "--coordinator-wait-s", "1"},
                                                   out);
        ASSERT_TRUE(worker);
        ASSERT_TRUE(worker->wait(std::chrono::seconds(30))) << read_file(out);
        if (refused) {
            EXPECT_EQ(worker->exit_code().value_or(-1), 2) << read_file(out);
            EXPECT_NE(read_file(out).find("\"lpss-from-*\"? identities made by deploy/security/identities.sh "
                                          "before 2026-12-05 do not: make them again"),
                      std::string::npos)
                << read_file(out);
        } else {
            // The control: the same identity as the script makes it now starts, and gives up for want of a
            // coordinator.
            EXPECT_EQ(read_file(out).find("cannot create"), std::string::npos) << read_file(out);
            EXPECT_NE(read_file(out).find("waiting for the coordinator"), std::string::npos)
                << read_file(out);
        }
    }
}

}  // namespace
}  // namespace lpss
