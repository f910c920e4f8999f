// libFuzzer target: the window's --script parser (app/window/input.cpp parseScript: verbs and their
// arity, numbers with their ranges: frames, pixels, ui-scale, sizes). Bad input must be an
// InputError naming the script's line; anything else is a finding (a `ui-scale nan` that passed
// here reached ImGui's assertion; `wait 99999999999` escaped as std::out_of_range, exit 1). An
// accepted script must give every command its line, and every number must read back with the
// conversion the runner uses (Window::runScriptStep: stoi for whole numbers, stof or stod) to the
// value that was checked (`split-at 1e-50` passed the check and then threw from stof).
#include <cstdio>
#include <cstdlib>
#include <map>
#include <vector>

#include "fuzz_common.h"
#include "window/window.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace shadowlab;
    const std::string path = fuzz::writeInput("script.txt", data, size);
    try {
        const std::deque<ScriptCommand> script = parseScript(path);
        int last = 0;
        for (const ScriptCommand& c : script) {
            if (c.line <= last || c.verb.empty()) {
                std::fprintf(stderr, "fuzz_window_script: command '%s' at line %d after line %d\n", c.verb.c_str(), c.line,
                             last);
                std::abort();
            }
            last = c.line;
            // Per verb, the runner's conversion of each numeric argument: 'i' stoi, 'f' stof, 'd' stod.
            static const std::map<std::string, std::string> kinds = {
                {"scroll", "d"},      {"pick", "ii"},    {"split-at", "f"}, {"ui-scale", "f"},     {"reference-samples", "i"},
                {"reference-rays", "i"}, {"resize", "ii"}, {"wait", "i"},     {"wait-reference", "i"}, {"drag-light", "ffi"},
                {"drag", "__ffffi"}};
            const auto it = kinds.find(c.verb);
            if (it == kinds.end()) continue;
            for (size_t i = 0; i < c.args.size() && i < it->second.size(); ++i) {
                const char kind = it->second[i];
                if (kind == '_') continue;
                const double checked = std::stod(c.args[i]);
                double read = 0.0;
                try {
                    read = kind == 'i' ? double(std::stoi(c.args[i])) : kind == 'f' ? double(std::stof(c.args[i])) : std::stod(c.args[i]);
                } catch (const std::exception& e) {
                    std::fprintf(stderr, "fuzz_window_script: line %d: %s '%s': the runner's conversion throws %s\n", c.line,
                                 c.verb.c_str(), c.args[i].c_str(), e.what());
                    std::abort();
                }
                if (kind == 'f' ? float(checked) != float(read) : checked != read) {
                    std::fprintf(stderr, "fuzz_window_script: line %d: %s '%s' was checked as %.17g and runs as %.17g\n", c.line,
                                 c.verb.c_str(), c.args[i].c_str(), checked, read);
                    std::abort();
                }
            }
        }
    } catch (const InputError&) {
    }
    return 0;
}
