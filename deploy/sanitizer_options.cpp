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

// Fast DDS 2.9.1's DDS Security authentication (PKIDH::process_handshake_request and
// begin_handshake_reply) leaks the OpenSSL objects of handshakes (seen in every secured test: 20-60 KB a
// process, with ASAN_OPTIONS=fast_unwind_on_malloc=0 to see past libcrypto, whose frames the fast unwinder
// cannot walk). lpss never calls OpenSSL itself, so leaks of memory libcrypto allocated are Fast DDS's;
// every other leak is still reported.
const char* __lsan_default_suppressions() { return "leak:libcrypto.so\n"; }
}
