// CLN allocates a few bytes at start-up that it never frees; under AddressSanitizer that
// would fail every program linking GiNaC, so LeakSanitizer is told to ignore CLN's own
// leaks. A source of each executable (npend-gen, the generator's tests), not of the library:
// the sanitizer runtime looks this function up in the program, and a static library's unused
// object would not be linked in.
#if defined(__SANITIZE_ADDRESS__)
extern "C" const char* __lsan_default_suppressions() { return "leak:libcln.so\n"; }
#endif
