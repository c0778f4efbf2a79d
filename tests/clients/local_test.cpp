// lpss-view and lpss-dis talk to this machine only unless told otherwise: counted, as for the cluster
// (Cluster.NothingLeavesThisMachineWithTheBuiltInProfile), on an interface besides loopback in this test's
// network namespace. Then datagrams of lpss-dis's sender to an address beyond it must be counted, to show
// that the count sees them.
#include <gtest/gtest.h>

#include <regex>
#include <thread>

#include "cluster_harness.hpp"
#include "dis/entity_state_pdu.hpp"
#include "dis/udp_sender.hpp"
#include "leak_counter.hpp"

namespace lpss {
namespace {

using testing::read_file;
using testing::start_cluster;

TEST(Clients, ViewAndDisSendNothingOffThisMachineByDefault) {
    const int domain = 148;
    const testing::DomainCleanup cleanup(domain);
    testing::LeakCounter leak;
    if (!leak.ok()) GTEST_SKIP() << "cannot add an interface to this network namespace (needs root)";
    const std::uint64_t before = leak.sent();
    auto cluster = start_cluster(LPSS_SOURCE_DIR "/deploy/scenes/ecef_convoy.textproto", domain, 2, 600);
    ASSERT_TRUE(cluster.process);
    const std::string view_log = cluster.log_dir + "-view.out", dis_log = cluster.log_dir + "-dis.out";
    auto view = runtime::ChildProcess::start(LPSS_VIEW, {"--domain", std::to_string(domain), "--port", "0"},
                                             view_log);
    auto dis = runtime::ChildProcess::start(
        LPSS_DIS, {"--domain", std::to_string(domain), "--dis-port", "39148", "--frames", "300"}, dis_log);
    ASSERT_TRUE(view && dis);
    std::string url;
    const std::regex address(R"(http://127\.0\.0\.1:([0-9]+)/)");
    for (int n = 0; n < 300 && url.empty(); ++n) {
        std::smatch m;
        const std::string text = read_file(view_log);
        if (std::regex_search(text, m, address)) url = m[1];
        if (url.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    ASSERT_FALSE(url.empty()) << read_file(view_log);
    // A page's stream until its first frame (at most 20 s: the cluster may still be starting), read the way
    // a browser would (bash's /dev/tcp: no other tool needed).
    const std::string events = cluster.log_dir + "-events.txt";
    const std::string get = "bash -c 'exec 3<>/dev/tcp/127.0.0.1/" + url +
                            "; printf \"GET /events HTTP/1.1\\r\\nHost: x\\r\\n\\r\\n\" >&3; timeout 20 sed "
                            "\"/event: frame/q\" <&3 > " +
                            events + "' 2>/dev/null";
    std::system(get.c_str());
    ASSERT_TRUE(dis->wait(std::chrono::seconds(60))) << read_file(dis_log);
    EXPECT_EQ(dis->exit_code().value_or(-1), 0) << read_file(dis_log);
    EXPECT_NE(read_file(events).find("event: frame"), std::string::npos)
        << "the page's stream carried no frame";
    const std::string dis_said = read_file(dis_log);
    std::smatch sent;
    ASSERT_TRUE(std::regex_search(dis_said, sent, std::regex(R"(([0-9]+) PDUs \()"))) << dis_said;
    EXPECT_GT(std::stoull(sent[1]), 20u) << "lpss-dis sent too little for the count to mean anything";
    const std::uint64_t by_default = leak.sent() - before;
    EXPECT_EQ(by_default, 0u) << "packets out of a non-loopback interface from lpss-view and lpss-dis";

    // Sent beyond this machine, lpss-dis's datagrams are seen leaving: its sender (the one lpss-dis uses) to
    // an address on the interface's subnet, whose neighbour entry is set so that they go out, not wait for
    // ARP.
    ASSERT_EQ(std::system("ip neigh replace 10.253.0.2 lladdr 02:00:00:00:00:02 dev lpssleak0"), 0);
    auto away = dis::UdpSender::open("10.253.0.2", 39148, false, 1);
    ASSERT_TRUE(away) << away.error().message;
    const auto pdu = dis::encode(dis::EntityStatePdu{});
    for (int n = 0; n < 10; ++n)
        EXPECT_TRUE(away->send(pdu.data(), pdu.size()));
    const std::uint64_t told = leak.sent() - before - by_default;
    EXPECT_GE(told, 10u) << "PDUs sent to 10.253.0.2 should have left through the interface";
    std::printf(
        "packets out of a non-loopback interface: %llu from lpss-view and lpss-dis by default (%s PDUs); "
        "%llu when its sender sent 10 PDUs to 10.253.0.2\n",
        static_cast<unsigned long long>(by_default), sent[1].str().c_str(),
        static_cast<unsigned long long>(told));
    view->stop();
    cluster.process->stop();
}

}  // namespace
}  // namespace lpss
