#include "lpss/common/process_memory.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>
#include <csignal>
#include <cstring>
#include <memory>

namespace {

constexpr std::size_t kMiB = 1024 * 1024;

TEST(ProcessMemory, ResidentMemoryFollowsWhatIsTouched) {
    const std::optional<lpss::MemoryUse> before = lpss::memory_use();
    ASSERT_TRUE(before);
    EXPECT_GE(before->peak_bytes, before->resident_bytes);
    const std::size_t size = 64 * kMiB;
    std::unique_ptr<char[]> block(new char[size]);
    std::memset(block.get(), 1, size);  // resident only once written
    const std::optional<lpss::MemoryUse> after = lpss::memory_use();
    ASSERT_TRUE(after);
    EXPECT_GE(after->resident_bytes, before->resident_bytes + 60 * kMiB);
    EXPECT_LE(after->resident_bytes, before->resident_bytes + 80 * kMiB);
    EXPECT_EQ(block[size / 2], 1);
}

TEST(ProcessMemory, PagesSharedWithAnotherProcessCountHalfInTheProportionalSet) {
    const std::size_t size = 64 * kMiB;
    std::unique_ptr<char[]> block(new char[size]);
    std::memset(block.get(), 1, size);
    const std::optional<std::uint64_t> alone = lpss::proportional_resident_bytes();
    const std::optional<lpss::MemoryUse> resident = lpss::memory_use();
    ASSERT_TRUE(alone && resident);
    EXPECT_GT(*alone, 60 * kMiB);
    EXPECT_LE(*alone, resident->resident_bytes);
    // A child made by fork shares every page with its parent until one of them writes it.
    int ready[2];
    ASSERT_EQ(::pipe(ready), 0);
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        char c = 1;
        (void)!::write(ready[1], &c, 1);
        ::pause();
        ::_exit(0);
    }
    char c = 0;
    ASSERT_EQ(::read(ready[0], &c, 1), 1);
    const std::optional<std::uint64_t> shared = lpss::proportional_resident_bytes(child);
    const std::optional<lpss::MemoryUse> child_resident = lpss::memory_use(child);
    ::kill(child, SIGKILL);
    ::waitpid(child, nullptr, 0);
    ::close(ready[0]);
    ::close(ready[1]);
    ASSERT_TRUE(shared && child_resident);
    EXPECT_GT(child_resident->resident_bytes, 60 * kMiB);
    // The block counts half in the child's proportional set (the rest: pages shared with more processes).
    EXPECT_LT(*shared, child_resident->resident_bytes - 30 * kMiB);
    EXPECT_GT(*shared, 28 * kMiB);
    EXPECT_EQ(block[size - 1], 1);
}

TEST(ProcessMemory, AProcessThatIsGoneHasNoMemory) {
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) ::_exit(0);
    ::waitpid(child, nullptr, 0);
    EXPECT_FALSE(lpss::memory_use(child));
    EXPECT_FALSE(lpss::proportional_resident_bytes(child));
}

}  // namespace
