// The cluster tests run, with every process they start, in a network namespace of their own that holds
// only loopback, so that nothing can leave this machine whatever a profile says. Creating one needs
// root (CAP_SYS_ADMIN); without it the tests run anyway and rely on the built-in profile, which uses
// shared memory and 127.0.0.1 only, and say so.
#include <gtest/gtest.h>
#include <sched.h>

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
    return RUN_ALL_TESTS();
}
