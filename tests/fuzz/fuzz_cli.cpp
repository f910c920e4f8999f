// libFuzzer target: the command line's argument parsing (app/cli/cli.cpp runCommandLine and every
// command's options: Options, parseSize, parsePixel, --set, numbers with ranges, output plans,
// the inputs they name, down to the point where a command would open a GL context). The input is
// one argument per line. The context is refused by a hook (setBeforeHeadlessContext), so what is
// fuzzed is everything a command checks before it renders. A finding is a crash, a sanitizer
// report, or an exit code other than 0 and 2 that the hook did not cause (an InternalError, a
// std::out_of_range from stoi, bad_alloc: "internal error", exit 1).
//
// Arguments that could write outside the fuzzer's private folder (an absolute path other than
// /dev/..., or one with "..") are skipped: `compare --heatmap` and `scene --dump-triangles` write
// before any context is made. The display is unset by scripts/fuzz.sh, so `window` answers "no
// display" (exit 2) after parsing its options and script.
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli/cli.h"
#include "fuzz_common.h"
#include "gl/context.h"

namespace {

bool stopped = false;

struct ContextRefused : std::runtime_error {
    ContextRefused() : std::runtime_error("fuzz_cli: no GL context while fuzzing") {}
};

void refuseContext() {
    stopped = true;
    throw ContextRefused();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace shadowlab;
    static const bool ready = [] {
        setBeforeHeadlessContext(refuseContext);
        unsetenv("DISPLAY");
        unsetenv("WAYLAND_DISPLAY");
        return ::chdir(fuzz::folder().c_str()) == 0;
    }();
    if (!ready) std::abort();
    std::vector<std::string> args;
    std::string current;
    for (size_t i = 0; i < size; ++i) {
        const char c = char(data[i]);
        if (c == '\n') {
            args.push_back(current);
            current.clear();
        } else {
            current += c;
        }
    }
    if (!current.empty()) args.push_back(current);
    if (args.size() > 64) return 0;
    for (const std::string& a : args) {
        if (a.find("..") != std::string::npos) return 0;
        if (!a.empty() && (a[0] == '/' || a[0] == '~') && a.rfind("/dev/", 0) != 0) return 0;
        if (a.find("=/") != std::string::npos && a.find("=/dev/") == std::string::npos) return 0;
    }
    stopped = false;
    const int code = runCommandLine(args);
    if (code == 0 || code == 2 || (code == 1 && stopped)) return 0;
    std::string line;
    for (const std::string& a : args) line += " '" + a + "'";
    std::fprintf(stderr, "fuzz_cli: exit %d without a refused context for:%s\n", code, line.c_str());
    std::abort();
}
