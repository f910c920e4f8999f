// `shadowlab lesson L`: a lesson (lessons/L.md, lessons/README.md) checked, or rendered headless
// into an HTML handout with every step's pictures.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>

#include "scene/input_file.h"
#include "cli/cli.h"
#include "cli/resource_limits.h"
#include "error.h"
#include "image/image.h"
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
    Options opts("lesson", args, 1,
                 {"--out", "--size", "--gl", "--sizes", "--screenshot", "--frames", "--script", "--report", "--ui-scale",
                  "--max-memory-mb"},
                 {"--headless", "--check", "--present"});
    if (opts.positional().size() != 1)
        throw InputError("lesson: expected one lesson name or .md path, e.g. 'shadowlab lesson intro --headless --out DIR'");
    const bool headless = opts.has("--headless");
    if (opts.has("--out") && !headless) throw InputError("lesson: --out is for --headless");
    if (opts.has("--sizes") && !opts.has("--check")) throw InputError("lesson: --sizes is for --check");
    if (headless || opts.has("--check"))
        for (const char* windowOnly : {"--screenshot", "--frames", "--script", "--report", "--ui-scale", "--present"})
            if (opts.has(windowOnly))
                throw InputError(std::string("lesson: ") + windowOnly + " is for the window (`shadowlab lesson L` without "
                                 "--headless or --check)");
    int width = 320, height = 320;
    if (opts.has("--size")) parseSize(opts.get("--size"), width, height);
    std::string out = opts.get("--out");
    if (headless) {
        if (out.empty()) throw InputError("lesson: --headless needs --out DIR (the folder of the handout)");
        checkPathName("lesson: --out", out);
        std::error_code ec;
        if (fs::exists(out, ec) && !fs::is_directory(out, ec)) throw InputError("lesson: --out: '" + out + "' is not a folder");
        // "handout/" names the folder handout: its parent is the one that must exist.
        fs::path path = fs::path(out);
        while (path.has_filename() == false && path.has_parent_path() && path != path.root_path()) path = path.parent_path();
        fs::path parent = path.parent_path();
        if (!parent.empty() && !fs::is_directory(parent, ec))
            throw InputError("lesson: --out: folder '" + parent.string() + "' does not exist");
    }
    Lesson lesson = loadLesson(opts.positional()[0]);
    // The memory estimate `render` applies, for each step's technique and reference at the
    // handout's size (and each --check size), before the first render.
    auto checkLessonMemory = [&](int width, int height) {
        std::map<std::string, Scene> scenes;
        for (const LessonStep& step : lesson.steps)
            for (const LessonState* state : {&step.state, step.answerState ? &*step.answerState : nullptr}) {
                if (!state) continue;
                auto it = scenes.find(state->scene);
                if (it == scenes.end()) it = scenes.emplace(state->scene, loadScene(state->scene)).first;
                Scene scene = it->second;
                scene.lights = state->lights;
                for (const bool reference : {false, true}) {
                    RenderOptions o;
                    o.width = width;
                    o.height = height;
                    o.technique = reference ? state->referenceTechnique : state->technique;
                    o.sets = reference ? state->referenceParamTexts() : state->paramTexts();
                    try {
                        checkRenderMemory(scene, o, opts);
                    } catch (const InputError& e) {
                        throw InputError(step.where.str() + ": " + o.technique + " at " + std::to_string(width) + "x" +
                                         std::to_string(height) + ": " + e.what());
                    }
                }
            }
    };
    size_t tasks = 0;
    for (const LessonStep& s : lesson.steps) tasks += s.task.has_value();
    if (opts.has("--check") && !headless) {
        checkLessonViews(lesson);  // a view its technique cannot give, named by line (no rendering)
        std::printf("%s: %s: %zu steps, %zu tasks, valid\n", lesson.file.c_str(), lesson.title.c_str(),
                    lesson.steps.size(), tasks);
        if (!opts.has("--sizes")) return 0;
        // Checked where it is shown: every step rendered at each size, every expectation holding,
        // every task failing in its own state and passing with its answer, every pick on its point
        // (a lesson error names the line and the size). Nothing is written.
        std::vector<std::pair<int, int>> sizes;
        const std::string list = opts.get("--sizes");
        size_t start = 0;
        while (start <= list.size()) {
            const size_t comma = list.find(',', start);
            const std::string one = list.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
            int w = 0, h = 0;
            parseSize(one, w, h);
            checkLessonMemory(w, h);
            sizes.push_back({w, h});
            if (comma == std::string::npos) break;
            start = comma + 1;
        }
        auto context = createHeadlessContext(parseBackend(opts.get("--gl", "egl")));
        size_t expects = 0;
        for (const LessonStep& s : lesson.steps) expects += s.expects.size();
        for (const auto& [w, h] : sizes) {
            try {
                renderLessonHeadless(lesson, "", w, h);  // renders and checks, writes nothing
            } catch (const LessonCheckError&) {
                throw;  // each failing expectation already names its line and the size
            } catch (const InputError& e) {
                throw InputError(std::string(e.what()) + " (at " + std::to_string(w) + "x" + std::to_string(h) + ")");
            }
            std::printf("  %dx%d: %zu steps rendered, %zu expectation(s) holding, %zu task(s) failing in their own state "
                        "and passing with their answer, picks on their points\n",
                        w, h, lesson.steps.size(), expects, tasks);
            std::fflush(stdout);
        }
        return 0;
    }
    if (!headless) {
        // The player in the window (`shadowlab lesson L` is `shadowlab window --lesson L`, with the
        // window's options); without a display, runWindow says so (exit 2) and names --headless.
        std::vector<std::string> windowArgs = {"--lesson", opts.positional()[0]};
        for (const char* flag : {"--size", "--screenshot", "--frames", "--script", "--report", "--ui-scale", "--max-memory-mb"})
            if (opts.has(flag)) windowArgs.insert(windowArgs.end(), {flag, opts.get(flag)});
        if (opts.has("--present")) windowArgs.push_back("--present");
        return runWindow(windowArgs);
    }
    checkLessonMemory(width, height);
    // The handout's folder takes files (tried, before any step is rendered); a folder this run
    // creates is removed again when the run fails (a failed handout left an empty folder).
    const bool existed = fs::exists(out);
    checkOutputWritable(existed ? (fs::path(out) / "index.html").string() : (fs::path(out).lexically_normal() / "").parent_path().string());
    auto context = createHeadlessContext(parseBackend(opts.get("--gl", "egl")));
    fs::create_directories(out);
    try {
        renderLessonHeadless(lesson, out, width, height);
    } catch (...) {
        std::error_code ignored;
        if (!existed) fs::remove(out, ignored);  // only when empty: nothing of the user's is touched
        throw;
    }
    std::printf("%s\n", (fs::path(out) / "index.html").string().c_str());
    return 0;
}

}  // namespace shadowlab
