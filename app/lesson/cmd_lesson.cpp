// `shadowlab lesson L`: a lesson (lessons/L.md, lessons/README.md) checked, or rendered headless
// into an HTML handout with every step's pictures.
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "cli/cli.h"
#include "error.h"
#include "gl/context.h"
#include "lesson/cmd_lesson.h"
#include "lesson/headless.h"
#include "lesson/lesson.h"

namespace fs = std::filesystem;

namespace shadowlab {

nlohmann::json describeLessons() {
    nlohmann::json out = nlohmann::json::array();
    for (const std::string& id : listLessons()) {
        nlohmann::json j{{"name", id}, {"file", "lessons/" + id + ".md"}};
        try {
            Lesson lesson = loadLesson(id);
            size_t tasks = 0;
            for (const LessonStep& s : lesson.steps) tasks += s.task.has_value();
            j["title"] = lesson.title;
            j["steps"] = lesson.steps.size();
            j["tasks"] = tasks;
        } catch (const InputError& e) {
            j["error"] = e.what();
        }
        out.push_back(j);
    }
    return out;
}

int commandLesson(const std::vector<std::string>& args) {
    Options opts("lesson", args, 1, {"--out", "--size", "--gl"}, {"--headless", "--check"});
    if (opts.positional().size() != 1)
        throw InputError("lesson: expected one lesson name or .md path, e.g. 'shadowlab lesson intro --headless --out DIR'");
    const bool headless = opts.has("--headless");
    if (opts.has("--out") && !headless) throw InputError("lesson: --out is for --headless");
    int width = 320, height = 320;
    if (opts.has("--size")) parseSize(opts.get("--size"), width, height);
    std::string out = opts.get("--out");
    if (headless) {
        if (out.empty()) throw InputError("lesson: --headless needs --out DIR (the folder of the handout)");
        if (fs::exists(out) && !fs::is_directory(out)) throw InputError("lesson: --out: '" + out + "' is not a folder");
        fs::path parent = fs::path(out).parent_path();
        if (!parent.empty() && !fs::is_directory(parent))
            throw InputError("lesson: --out: folder '" + parent.string() + "' does not exist");
    }
    Lesson lesson = loadLesson(opts.positional()[0]);
    size_t tasks = 0;
    for (const LessonStep& s : lesson.steps) tasks += s.task.has_value();
    if (opts.has("--check") && !headless) {
        std::printf("%s: %s: %zu steps, %zu tasks, valid\n", lesson.file.c_str(), lesson.title.c_str(),
                    lesson.steps.size(), tasks);
        return 0;
    }
    if (!headless) {
        // The player in the window; without a display, runWindow says so (exit 2) and names --headless.
        std::vector<std::string> windowArgs = {"--lesson", opts.positional()[0]};
        if (opts.has("--size")) windowArgs.insert(windowArgs.end(), {"--size", opts.get("--size")});
        return runWindow(windowArgs);
    }
    auto context = createHeadlessContext(parseBackend(opts.get("--gl", "egl")));
    fs::create_directories(out);
    renderLessonHeadless(lesson, out, width, height);
    std::printf("%s\n", (fs::path(out) / "index.html").string().c_str());
    return 0;
}

}  // namespace shadowlab
