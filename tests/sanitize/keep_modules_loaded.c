/* Preloaded by scripts/sanitize.sh: dlclose does nothing, so shared libraries the GL driver loads
 * (Mesa's gallium/llvmpipe, LLVM) stay mapped until the process exits. Without it, LeakSanitizer
 * runs after the driver's modules are unloaded: their globals, which still reference the driver's
 * allocations, are gone, so every such allocation is reported as a leak from "<unknown module>",
 * a stack no suppression can name. */
int dlclose(void* handle) {
    (void)handle;
    return 0;
}
