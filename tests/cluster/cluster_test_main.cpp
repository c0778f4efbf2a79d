// The cluster tests run, with every process they start, in a network namespace of their own that holds
// only loopback, so that nothing can leave this machine whatever a profile says. Creating one needs
// root (CAP_SYS_ADMIN); without it the tests run anyway and rely on the built-in profile, which uses
// shared memory and 127.0.0.1 only, and say so.
#include <gtest/gtest.h>
#include <sched.h>
#include "lpss_dds/shm_cleanup.hpp"

#include <cstdio>
#include <cstdlib>

int main(int argc, char** argv) {
    ::testing::InitGoogleTest(&argc, argv);
    if (unshare(CLONE_NEWNET) == 0 && std::system("ip link set lo up") == 0) {
        std::printf("cluster tests: in a private network namespace (loopback only)\n");
    } else {
        std::printf(
            "cluster tests: no private network namespace here; the built-in profile keeps traffic on "
            "shared memory and 127.0.0.1\n");
    }
    const int result = RUN_ALL_TESTS();
    // Workers the tests kill leave shared memory behind, and every participant leaves its port files:
    // remove what no live process uses on the domains these tests own (120-129).
    for (int domain = 120; domain <= 129; ++domain)
        lpss::dds::remove_abandoned_shm(domain);
    return result;
}
