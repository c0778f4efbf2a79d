// Built into every program and test when lpss is configured with -DLPSS_SANITIZE=...: the sanitizer
// options lpss runs with, so that child processes started by tests get them too.
extern "C" {

// Fast DDS 2.9.1 itself deletes its statistics readers through a base pointer of another size
// (StatisticsReaderImpl is allocated with 64 bytes and freed as RTPSReader's 56): a report inside the
// library that would end every process using DDS. Only that one check is off (for lpss's own code too: it
// cannot be turned off per library); every other check stays on in every process.
const char* __asan_default_options() { return "new_delete_type_mismatch=0"; }

// Reports name file and line, and a finding ends the process with an error.
const char* __ubsan_default_options() { return "print_stacktrace=1:halt_on_error=1"; }
}
