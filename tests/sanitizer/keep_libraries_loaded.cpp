// Preloaded by scripts/sanitize.sh into every process of the sanitizer stage: a dlclose() that
// keeps the library loaded.
//
// The Vulkan loader dlclose()s its driver (lavapipe, with its LLVM) and layers when the instance
// goes; LeakSanitizer, checking at exit, then finds memory those libraries' globals still pointed
// to, cannot see the globals any more, and reports it as leaked from "<unknown module>". Keeping
// every library mapped until exit makes that memory reachable again, and only in processes that
// open a driver at all (preloading the driver itself cost every process ~0.15 s under ASan, and
// most processes of the suite never touch Vulkan). Nothing of this project's is hidden: its own
// allocations are checked as before. Built without sanitizers, so that it needs no runtime of its
// own and runs before any.
extern "C" int dlclose(void* /*handle*/) { return 0; }
