// Benchmark (not a test): the window's frame time while the user drags the light, under a virtual
// X server, on `plant` with `pcf`, with the reduced resolution while dragging (the default) and
// without (--no-reduce). It runs `xvfb-run shadowlab window --script` with a drag that starts on the
// light's centre (drag-light: the mouse code path a user's drag takes; plant's light is drawn just
// above its default view, and the script's press there is allowed), reads the per-frame report
// (--report) and prints, for the frames of the drag: median and 90th percentile of the whole frame
// (script step, render, present, UI, swap, glFinish), of the technique's render alone, the render
// size, and the first full-resolution frame after the drag (the refinement).
// Usage: LP_NUM_THREADS=2 shadowlab_bench_window_drag [scene] [technique] [WxH] [drag frames] [runs]
//        LP_NUM_THREADS=2 shadowlab_bench_window_drag plant all [WxH] [runs] [technique,...]
//        (issue 18's table: every technique, or those listed, the UI frame time p50 / p95 in the ten
//        frames after each of three switches to it, while dragging the light, after the drag (its
//        refinement, until the reference starts), and idle while the reference accumulates (for `raytraced`: its rays on the worker thread), over the frames
//        of every run pooled; the frame count of each phase in brackets, and with more than one run
//        the smallest and largest p95 of a single run)
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <unistd.h>
#include <vector>

namespace fs = std::filesystem;

namespace {

double percentile(std::vector<double> v, double p) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, size_t(p * double(v.size() - 1) + 0.5))];
}

struct Result {
    std::vector<double> frameMs, renderMs;
    int width = 0, height = 0;
    double refineMs = -1.0;  // none: the drag was never reduced
    double lightMoved = 0.0;
};

bool runOnce(const std::string& scene, const std::string& technique, const std::string& size, int frames,
             bool reduce, const fs::path& dir, Result& out) {
    fs::path script = dir / "drag.txt", report = dir / "report.json";
    std::ofstream(script) << "panel off\nbackground off\nwait 10\n"  // warm up: shaders, first frames
                          << "drag-light 160 60 " << frames << "\nwait 20\n";  // then the refinement
    std::string command = "xvfb-run -a -s '-screen 0 1920x1080x24' " + std::string(SHADOWLAB_BINARY) +
                          " window --scene " + scene + " --technique " + technique + " --size " + size +
                          " --script " + script.string() + " --report " + report.string() +
                          (reduce ? "" : " --no-reduce") + " > " + (dir / "log.txt").string() + " 2>&1";
    if (std::system(command.c_str()) != 0) {
        std::fprintf(stderr, "window_drag: the window failed, see %s\n", (dir / "log.txt").c_str());
        return false;
    }
    nlohmann::json frames_ = nlohmann::json::parse(std::ifstream(report))["frames"];
    // The drag's frames: those whose light moved; the refinement: the first full-resolution frame
    // after the last of them.
    size_t lastMoved = 0;
    for (size_t i = 1; i < frames_.size(); ++i) {
        const auto& f = frames_[i];
        if (f["light"] == frames_[i - 1]["light"]) continue;
        out.frameMs.push_back(f["frame_ms"]);
        out.renderMs.push_back(f["render_ms"]);
        out.width = f["render_size"][0];
        out.height = f["render_size"][1];
        lastMoved = i;
    }
    bool reduced = lastMoved > 0 && frames_[lastMoved]["reduced"].get<bool>();
    for (size_t i = lastMoved + 1; reduced && i < frames_.size(); ++i)
        if (!frames_[i]["reduced"].get<bool>()) {
            out.refineMs = frames_[i]["render_ms"];
            break;
        }
    auto a = frames_.front()["light"], b = frames_.back()["light"];
    for (int k = 0; k < 3; ++k) out.lightMoved += std::abs(b[k].get<double>() - a[k].get<double>());
    return !out.frameMs.empty();
}

// Issue 18's table: for one technique at its defaults, the UI frame time while it is switched to
// (from `hard`; `hard` from `pcf`), while the light is dragged, and while idle with the reference accumulating, as
// p50 and p95 of frame_ms over the frames of each phase (from --report).
struct Phases {
    std::vector<double> afterSwitch, drag, refine, idle;
};

bool runPhases(const std::string& scene, const std::string& technique, const std::string& size, const fs::path& dir,
               Phases& out) {
    fs::path script = dir / "phases.txt", report = dir / "phases.json";
    // Forty frames first: hiding the panel re-lays the window out (the full-size renderer and the
    // reference reallocate at the new size, ~0.3 s on llvmpipe); the switch is timed after that.
    // Three switches to the technique (and back), ten frames counted after each: a p95 of 30 frames.
    const std::string other = technique == "hard" ? "pcf" : "hard";
    std::ofstream(script) << "panel off\nwait 40\n"
                          << "technique " << technique << "\nwait 12\ntechnique " << other << "\nwait 12\n"
                          << "technique " << technique << "\nwait 12\ntechnique " << other << "\nwait 12\n"
                          << "technique " << technique << "\nwait 12\n"
                          << "drag-light 120 40 30\nwait 300\n";  // the refinement, then the reference (it starts 0.5 s after the input)
    std::string command = "xvfb-run -a -s '-screen 0 1920x1080x24' " + std::string(SHADOWLAB_BINARY) + " window --scene " +
                          scene + " --technique " + other + " --size " + size +
                          " --script " + script.string() + " --report " +
                          report.string() + " > " + (dir / "log.txt").string() + " 2>&1";
    if (std::system(command.c_str()) != 0) return false;
    const nlohmann::json frames = nlohmann::json::parse(std::ifstream(report))["frames"];
    std::vector<size_t> switches;
    size_t dragEnd = frames.size(), dragStart = frames.size();
    for (size_t i = 1; i < frames.size(); ++i) {
        if (frames[i]["technique"] == technique && frames[i - 1]["technique"] != technique) switches.push_back(i);
        if (!switches.empty() && frames[i]["light"] != frames[i - 1]["light"]) {
            out.drag.push_back(frames[i]["frame_ms"]);
            dragStart = std::min(dragStart, i);
            dragEnd = i;
        }
    }
    for (size_t s : switches)
        for (size_t i = s; i < std::min({frames.size(), s + 10, dragStart}); ++i)
            if (frames[i]["technique"] == technique) out.afterSwitch.push_back(frames[i]["frame_ms"]);
    // After the drag: its refinement at full size, to its complete frame, and five frames after.
    size_t refined = dragEnd + 1;
    while (refined < frames.size() && !(frames[refined]["complete"].get<bool>() && !frames[refined]["reduced"].get<bool>()))
        ++refined;
    for (size_t i = dragEnd + 1; i < std::min(frames.size(), refined + 6); ++i) out.refine.push_back(frames[i]["frame_ms"]);
    // Idle: after the drag's last frame and its refinement, while the reference accumulates (or
    // shows a new batch).
    for (size_t i = dragEnd + 3; i < frames.size(); ++i)
        if (frames[i]["reference_samples"].get<int>() > frames[i - 1]["reference_samples"].get<int>() ||
            (frames[i]["reference_samples"].get<int>() > 0 &&
             frames[i]["reference_samples"].get<int>() < frames[i]["reference_total"].get<int>()))
            out.idle.push_back(frames[i]["frame_ms"]);
    return !out.afterSwitch.empty() && !out.drag.empty();
}

}  // namespace

int main(int argc, char** argv) {
    std::string scene = argc > 1 ? argv[1] : "plant";
    std::string technique = argc > 2 ? argv[2] : "pcf";
    if (technique == "all") {  // every technique the window runs, the three phases
        std::string size = argc > 3 ? argv[3] : "1024x768";
        const int runs = argc > 4 ? std::max(1, std::atoi(argv[4])) : 1;
        std::vector<std::string> techniques = {"hard", "pcf", "pcss", "sssm", "ssm-gbp06", "ssm-contour", "reference", "raytraced"};
        if (argc > 5) {
            techniques.clear();
            std::string list = argv[5];
            for (size_t a = 0; a <= list.size();) {
                size_t b = std::min(list.find(',', a), list.size());
                if (b > a) techniques.push_back(list.substr(a, b - a));
                a = b + 1;
            }
        }
        fs::path dir = fs::temp_directory_path() / ("shadowlab-window-phases-" + std::to_string(getpid()));
        fs::create_directories(dir);
        std::printf("window UI frame time by phase: %s at %s, each technique at its defaults, %d run(s) pooled, LP_NUM_THREADS=%s\n",
                    scene.c_str(), size.c_str(), runs, std::getenv("LP_NUM_THREADS") ? std::getenv("LP_NUM_THREADS") : "(unset)");
        std::printf("%-12s %30s %30s %30s %30s\n", "technique", "after switch p50/p95", "drag p50/p95", "after drag p50/p95",
                    "idle+ref p50/p95");
        int status = 0;
        for (const std::string& t : techniques) {
            Phases all;
            std::vector<Phases> each;
            for (int run = 0; run < runs; ++run) {
                Phases p;
                if (!runPhases(scene, t, size, dir, p)) {
                    std::fprintf(stderr, "window_drag: %s: the window failed or a phase had no frames (see %s)\n", t.c_str(),
                                 (dir / "log.txt").c_str());
                    status = 1;
                    continue;
                }
                for (auto [to, from] : {std::pair{&all.afterSwitch, &p.afterSwitch}, {&all.drag, &p.drag}, {&all.refine, &p.refine},
                                        {&all.idle, &p.idle}})
                    to->insert(to->end(), from->begin(), from->end());
                each.push_back(p);
            }
            if (each.empty()) continue;
            auto cell = [&](std::vector<double> Phases::*phase) {
                const std::vector<double>& v = all.*phase;
                char text[64];
                if (v.empty()) return std::string("-");
                std::snprintf(text, sizeof text, "%.0f / %.0f ms (%zu)", percentile(v, 0.5), percentile(v, 0.95), v.size());
                std::string out = text;
                if (each.size() > 1) {
                    double lo = 1e30, hi = 0.0;
                    for (const Phases& p : each) {
                        lo = std::min(lo, percentile(p.*phase, 0.95));
                        hi = std::max(hi, percentile(p.*phase, 0.95));
                    }
                    std::snprintf(text, sizeof text, " [%.0f-%.0f]", lo, hi);
                    out += text;
                }
                return out;
            };
            std::printf("%-12s %30s %30s %30s %30s\n", t.c_str(), cell(&Phases::afterSwitch).c_str(), cell(&Phases::drag).c_str(),
                        cell(&Phases::refine).c_str(), cell(&Phases::idle).c_str());
            std::fflush(stdout);
        }
        fs::remove_all(dir);
        return status;
    }
    std::string size = argc > 3 ? argv[3] : "1024x768";
    int frames = argc > 4 ? std::atoi(argv[4]) : 60;
    int runs = argc > 5 ? std::atoi(argv[5]) : 2;
    fs::path dir = fs::temp_directory_path() / ("shadowlab-window-drag-" + std::to_string(getpid()));
    fs::create_directories(dir);
    std::printf("window drag: %s, %s, window %s, %d drag frames, %d run(s) per mode, LP_NUM_THREADS=%s\n",
                scene.c_str(), technique.c_str(), size.c_str(), frames, runs,
                std::getenv("LP_NUM_THREADS") ? std::getenv("LP_NUM_THREADS") : "(unset)");
    std::printf("%-22s %10s %10s %11s %11s %10s %12s\n", "mode", "frame p50", "frame p90", "render p50",
                "render p90", "size", "refine (ms)");
    int status = 0;
    for (int run = 0; run < runs; ++run) {
        for (bool reduce : {true, false}) {
            Result r;
            if (!runOnce(scene, technique, size, frames, reduce, dir, r)) {
                status = 1;
                continue;
            }
            if (r.lightMoved <= 0.0) {
                std::fprintf(stderr, "window_drag: the light did not move\n");
                status = 1;
            }
            char dims[32];
            std::snprintf(dims, sizeof dims, "%dx%d", r.width, r.height);
            char refine[32] = "-";
            if (r.refineMs >= 0) std::snprintf(refine, sizeof refine, "%.1f", r.refineMs);
            std::printf("%-22s %10.1f %10.1f %11.1f %11.1f %10s %12s\n",
                        reduce ? "reduced while dragging" : "full resolution", percentile(r.frameMs, 0.5),
                        percentile(r.frameMs, 0.9), percentile(r.renderMs, 0.5), percentile(r.renderMs, 0.9), dims,
                        refine);
        }
    }
    fs::remove_all(dir);
    return status;
}
