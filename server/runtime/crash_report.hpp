// A process that dies of a fault (SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT) says where before it goes: the
// signal and its code, the faulting address and the mapping that holds it (a SIGBUS on a file-backed page
// names the file), and the call stack as module+offset (`addr2line -e PROGRAM OFFSET` names the line).
// Seen: a coordinator in CI ended with exit 135 (SIGBUS) 0.4 s into its start and its log said nothing.
#pragma once

namespace lpss::runtime {

/// Installs the report for `program` (its name in the report) where no handler is installed already (a
/// sanitizer's own stays); the fault then takes its default action, so the exit status is unchanged.
void install_crash_report(const char* program);

}  // namespace lpss::runtime
