// libFuzzer target: the lesson parser (app/lesson/lesson.cpp parseLesson: Markdown steps, commands, tasks,
// views checked against the technique registry and viz's listViews()). Bad input must be an
// InputError; any other exception or a crash is a finding (scripts/fuzz.sh).
#include <cstdint>
#include <string>

#include "error.h"
#include "lesson/lesson.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace shadowlab;
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        const Lesson lesson = parseLesson(text, "fuzz.md", "fuzz");
        (void)lesson;
    } catch (const InputError&) {
    }
    return 0;
}
