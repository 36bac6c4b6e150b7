// Linked into every executable of the sanitizer build (-DBW_SANITIZE=ON) and every test of the
// fuzz tree (-DBW_FUZZ=ON) only: dlclose() that leaves the library loaded. Terminating the EGL
// display unloads Mesa's driver and the LLVM it compiles shaders with; the allocations they still
// hold were reachable from the driver's own globals, and once those are unmapped LeakSanitizer
// reports them at exit as leaks from an "<unknown module>" that no suppression can name. With the
// libraries kept they stay reachable and no suppression is needed. The project itself never unloads
// a library.
extern "C" int dlclose(void*) {
    return 0;
}
