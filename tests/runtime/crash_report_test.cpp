// A process that faults says where before it ends: run in gtest's death tests (a child process each).
#include "crash_report.hpp"

#include <gtest/gtest.h>
#include <sys/mman.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace lpss {
namespace {

/// True where something (a sanitizer) already handles `sig`: the report then stays out of its way.
bool handled_already(int sig) {
    struct sigaction installed {};
    sigaction(sig, nullptr, &installed);
    return (installed.sa_flags & SA_SIGINFO) != 0 ? installed.sa_sigaction != nullptr
                                                  : installed.sa_handler != SIG_DFL;
}

/// Maps a page of a file, cuts the file to nothing and reads the page: SIGBUS, as a truncated segment gives.
void read_a_page_past_its_file(const std::string& path) {
    FILE* file = std::fopen(path.c_str(), "w+");
    if (file == nullptr) std::abort();
    const long page = sysconf(_SC_PAGESIZE);
    if (ftruncate(fileno(file), page) != 0) std::abort();
    auto* bytes = static_cast<volatile char*>(
        mmap(nullptr, static_cast<std::size_t>(page), PROT_READ, MAP_SHARED, fileno(file), 0));
    if (bytes == MAP_FAILED) std::abort();
    if (ftruncate(fileno(file), 0) != 0) std::abort();
    std::printf("%d\n", bytes[0]);  // faults
}

TEST(CrashReport, ASigbusOnAMappedFileNamesTheSignalItsCodeTheFileAndTheStack) {
    if (handled_already(SIGBUS)) GTEST_SKIP() << "SIGBUS is handled already here (a sanitizer's handler)";
    testing::GTEST_FLAG(death_test_style) = "threadsafe";
    // The "threadsafe" style runs this body again in a new process: the file it makes there is named by the
    // parent's pid, passed down in the environment (setenv does not replace it there), so that the parent
    // removes it. Named by each process's own pid, the child's file was left in the temp folder.
    setenv("LPSS_CRASH_TEST_FILE",
           (::testing::TempDir() + "lpss_crash_report_" + std::to_string(getpid())).c_str(), 0);
    const std::string path = std::getenv("LPSS_CRASH_TEST_FILE");
    EXPECT_EXIT(
        {
            runtime::install_crash_report("crash-test");
            read_a_page_past_its_file(path);
        },
        ::testing::KilledBySignal(SIGBUS),
        "crash-test: fatal SIGBUS \\(BUS_ADRERR.*at address 0x[0-9a-f]+\n"
        "  in the mapping: [0-9a-f]+-[0-9a-f]+ r..s .*lpss_crash_report_[0-9]+\n"
        "  stack .*\n.*\\(\\+0x[0-9a-f]+\\)");
    std::remove(path.c_str());
    unsetenv("LPSS_CRASH_TEST_FILE");
}

TEST(CrashReport, AnAbortSaysItWasRaisedByTheProcessAndEndsAsAnAbort) {
    if (handled_already(SIGABRT)) GTEST_SKIP() << "SIGABRT is handled already here";
    testing::GTEST_FLAG(death_test_style) = "threadsafe";
    EXPECT_EXIT(
        {
            runtime::install_crash_report("crash-test");
            std::abort();
        },
        ::testing::KilledBySignal(SIGABRT), "crash-test: fatal SIGABRT \\(raised by the process itself");
}

TEST(CrashReport, AHandlerInstalledBeforeStays) {
    // A sanitizer installs its handlers before main: the report must not replace them.
    EXPECT_EXIT(
        {
            struct sigaction mine {};
            mine.sa_handler = [](int) { _exit(42); };
            sigemptyset(&mine.sa_mask);
            sigaction(SIGSEGV, &mine, nullptr);
            runtime::install_crash_report("crash-test");
            raise(SIGSEGV);
        },
        ::testing::ExitedWithCode(42), "");
}

}  // namespace
}  // namespace lpss
