// The cluster tests run, with every process they start, in a network namespace of their own that holds
// only loopback, so that nothing can leave this machine whatever a profile says. Creating one needs
// root (CAP_SYS_ADMIN); without it the tests run anyway and rely on the built-in profile, which uses
// shared memory and 127.0.0.1 only, and say so. Their files go in a folder of the process's own
// (test_workspace.hpp), removed when every test passed.
#include <gtest/gtest.h>
#include <sched.h>

#include <cstdio>
#include <cstdlib>

#include "test_workspace.hpp"

int main(int argc, char** argv) {
    ::testing::InitGoogleTest(&argc, argv);
    ::testing::UnitTest::GetInstance()->listeners().Append(new lpss::testing::WorkspaceCleanup);
    if (unshare(CLONE_NEWNET) == 0 && std::system("ip link set lo up") == 0) {
        std::printf("cluster tests: in a private network namespace (loopback only)\n");
    } else {
        std::printf(
            "cluster tests: no private network namespace here; the built-in profile keeps traffic on "
            "shared memory and 127.0.0.1\n");
    }
    return RUN_ALL_TESTS();
}
