#include "crash_report.hpp"

#include <execinfo.h>
#include <fcntl.h>
#include <unistd.h>

#include <csignal>
#include <cstdint>
#include <cstring>
#include <initializer_list>

namespace lpss::runtime {
namespace {

// Only what a signal handler may touch: set once before the handlers are installed, read after.
const char* report_program = "lpss";
char alternate_stack[64 * 1024];

// Async-signal-safe output: write(2) on stderr, no allocation, no stdio.
void say(const char* text) {
    std::size_t left = std::strlen(text);
    while (left > 0) {
        const ssize_t n = ::write(STDERR_FILENO, text, left);
        if (n <= 0) return;
        text += n;
        left -= static_cast<std::size_t>(n);
    }
}

void say_hex(std::uintptr_t value) {
    char digits[2 + 2 * sizeof(value) + 1];
    char* p = digits + sizeof(digits) - 1;
    *p = '\0';
    do {
        *--p = "0123456789abcdef"[value & 0xf];
        value >>= 4;
    } while (value != 0);
    *--p = 'x';
    *--p = '0';
    say(p);
}

void say_int(long value) {
    char digits[24];
    char* p = digits + sizeof(digits) - 1;
    *p = '\0';
    const bool negative = value < 0;
    unsigned long magnitude =
        negative ? 0ul - static_cast<unsigned long>(value) : static_cast<unsigned long>(value);
    do {
        *--p = static_cast<char>('0' + magnitude % 10);
        magnitude /= 10;
    } while (magnitude != 0);
    if (negative) *--p = '-';
    say(p);
}

// strtoull is not on the async-signal-safe list: the hex numbers of /proc/self/maps by hand.
std::uintptr_t parse_hex(const char*& p) {
    std::uintptr_t value = 0;
    for (;; ++p) {
        const char c = *p;
        if (c >= '0' && c <= '9')
            value = value * 16 + static_cast<std::uintptr_t>(c - '0');
        else if (c >= 'a' && c <= 'f')
            value = value * 16 + static_cast<std::uintptr_t>(c - 'a' + 10);
        else
            return value;
    }
}

const char* signal_name(int sig) {
    switch (sig) {
        case SIGSEGV:
            return "SIGSEGV";
        case SIGBUS:
            return "SIGBUS";
        case SIGILL:
            return "SIGILL";
        case SIGFPE:
            return "SIGFPE";
        case SIGABRT:
            return "SIGABRT";
        default:
            return "a fault";
    }
}

const char* code_name(int sig, int code) {
    if (code == SI_USER) return "sent by kill() from another process";
    if (code == SI_TKILL) return "raised by the process itself (abort, raise)";
    if (sig == SIGBUS) {
        if (code == BUS_ADRALN) return "BUS_ADRALN, misaligned address";
        if (code == BUS_ADRERR)
            return "BUS_ADRERR, no page behind the address (a mapped file shorter than its mapping?)";
        if (code == BUS_OBJERR) return "BUS_OBJERR, an error reading the mapped object";
    }
    if (sig == SIGSEGV) {
        if (code == SEGV_MAPERR) return "SEGV_MAPERR, no mapping at the address";
        if (code == SEGV_ACCERR) return "SEGV_ACCERR, no permission for the access";
    }
    return "code not named here";
}

// The line of /proc/self/maps whose range holds `address`, written out; nothing if none does.
void say_mapping_of(std::uintptr_t address) {
    const int fd = ::open("/proc/self/maps", O_RDONLY | O_CLOEXEC);
    if (fd < 0) return;
    char line[512];
    std::size_t used = 0;
    bool found = false;
    char chunk[4096];
    ssize_t n;
    while (!found && (n = ::read(fd, chunk, sizeof(chunk))) > 0) {
        for (ssize_t i = 0; i < n && !found; ++i) {
            if (chunk[i] != '\n') {
                if (used + 1 < sizeof(line)) line[used++] = chunk[i];
                continue;
            }
            line[used] = '\0';
            // "start-end perms offset dev inode path"
            const char* p = line;
            const std::uintptr_t from = parse_hex(p);
            const std::uintptr_t to = *p == '-' ? parse_hex(++p) : 0;
            if (address >= from && address < to) {
                say("  in the mapping: ");
                say(line);
                say("\n");
                found = true;
            }
            used = 0;
        }
    }
    ::close(fd);
    if (!found) say("  in no mapping of the process\n");
}

extern "C" void on_fault(int sig, siginfo_t* info, void*) {
    say("\n");
    say(report_program);
    say(": fatal ");
    say(signal_name(sig));
    if (info != nullptr) {
        say(" (");
        say(code_name(sig, info->si_code));
        say(", si_code ");
        say_int(info->si_code);
        say(")");
        if (info->si_code <= 0) {  // sent, not a fault: si_addr holds nothing, si_pid the sender
            say(" from process ");
            say_int(info->si_pid);
            say("\n");
        } else if (sig != SIGABRT) {
            say(" at address ");
            say_hex(reinterpret_cast<std::uintptr_t>(info->si_addr));
            say("\n");
            say_mapping_of(reinterpret_cast<std::uintptr_t>(info->si_addr));
        } else {
            say("\n");
        }
    } else {
        say("\n");
    }
    say("  stack (module(+offset); `addr2line -f -C -e MODULE OFFSET` names the line):\n");
    void* frames[64];
    const int depth = ::backtrace(frames, 64);
    ::backtrace_symbols_fd(frames, depth, STDERR_FILENO);
    // SA_RESETHAND restored the default action: the process ends as the fault would have ended it.
    ::raise(sig);
}

}  // namespace

void install_crash_report(const char* program) {
    report_program = program;
    // backtrace() loads libgcc on its first call, which may allocate: do it now, not in the handler.
    void* warm[1];
    ::backtrace(warm, 1);
    // A stack of its own, so that a stack overflow can still be reported (on the main thread).
    stack_t stack{};
    stack.ss_sp = alternate_stack;
    stack.ss_size = sizeof(alternate_stack);
    ::sigaltstack(&stack, nullptr);
    for (const int sig : {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT}) {
        struct sigaction installed {};
        if (::sigaction(sig, nullptr, &installed) != 0) continue;
        const bool has_handler = (installed.sa_flags & SA_SIGINFO) != 0 ? installed.sa_sigaction != nullptr
                                                                        : installed.sa_handler != SIG_DFL;
        if (has_handler) continue;  // AddressSanitizer's, say: its report says more
        struct sigaction action {};
        action.sa_sigaction = on_fault;
        action.sa_flags = SA_SIGINFO | SA_RESETHAND | SA_ONSTACK;
        sigemptyset(&action.sa_mask);
        ::sigaction(sig, &action, nullptr);
    }
}

}  // namespace lpss::runtime
