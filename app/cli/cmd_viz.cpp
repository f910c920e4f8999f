// `shadowlab viz`: a view of what a technique computes (viz/views.h), headless, to PNG, with its
// data for ParaView (--export .vtp/.vti). The caption (what the picture says in numbers) is printed
// to stdout, or with --json the caption and the numbers behind it.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "scene/input_file.h"
#include "cli/cli.h"
#include "cli/resource_limits.h"
#include "error.h"
#include "gl/context.h"
#include "graph/renderer.h"
#include "graph/technique.h"
#include "image/image.h"
#include "scene/scene.h"
#include "views.h"
#include "vtk_offscreen.h"

namespace fs = std::filesystem;

namespace shadowlab {

namespace {

std::optional<glm::ivec2> parseVizPixel(const std::string& text) {
    int x = 0, y = 0;
    char comma = 0, extra = 0;
    if (std::sscanf(text.c_str(), "%d%c%d%c", &x, &comma, &y, &extra) != 3 || comma != ',')
        throw InputError("--pixel: expected x,y (whole numbers, y counted from the top), got '" + text + "'");
    return glm::ivec2(x, y);
}

void checkOutput(const std::string& flag, const std::string& path, const std::string& ext) {
    if (path.empty()) throw InputError(flag + ": expected a file path");
    checkPathName(flag, path);
    fs::path parent = fs::path(path).parent_path();
    std::error_code ec;
    if (!parent.empty() && !fs::is_directory(parent, ec))
        throw InputError(flag + ": folder '" + parent.string() + "' does not exist");
    if (fs::is_directory(path, ec)) throw InputError(flag + ": '" + path + "' is a folder, expected a file path");
    if (!ext.empty() && fs::path(path).extension() != ext)
        throw InputError(flag + ": expected a " + ext + " file, got '" + path + "'");
}

}  // namespace

int commandViz(const std::vector<std::string>& args) {
    Options opts("viz", args, 1,
                 {"--view", "--scene", "--technique", "--set", "--pixel", "--internal", "--light", "--size",
                  "--view-size", "--out", "--export", "--reference", "--reference-samples", "--rays", "--azimuth", "--elevation", "--zoom",
                  "--light-size", "--max-memory-mb", "--max-triangles"},
                 {"--json"});
    if (!opts.positional().empty()) throw InputError("viz: unexpected argument '" + opts.positional()[0] + "'");
    std::string views;
    for (const ViewInfo& v : listViews()) views += (views.empty() ? "" : ", ") + v.name;
    if (!opts.has("--view")) throw InputError("viz: --view is required (one of: " + views + ")");
    if (!opts.has("--scene")) throw InputError("viz: --scene is required (a scene name or a .json path)");
    if (!opts.has("--out")) throw InputError("viz: --out view.png is required");

    ViewRequest request;
    request.view = opts.get("--view");
    const ViewInfo* info = nullptr;
    std::vector<ViewInfo> all = listViews();
    for (const ViewInfo& v : all)
        if (v.name == request.view) info = &v;
    if (!info) throw InputError("viz: --view: unknown view '" + request.view + "' (expected one of: " + views + ")");

    RenderOptions options;
    options.technique = opts.get("--technique");
    if (!options.technique.empty()) requireTechnique(options.technique, "--technique");
    for (const std::string& s : opts.all("--set")) {
        size_t eq = s.find('=');
        if (eq == std::string::npos || eq == 0) throw InputError("--set: expected key=value, got '" + s + "'");
        options.sets.push_back({s.substr(0, eq), s.substr(eq + 1)});
    }
    if (opts.has("--size")) parseSize(opts.get("--size"), options.width, options.height);
    if (opts.has("--light-size")) options.lightSize = opts.getFloat("--light-size", 0.0f, 0.0f, 1e6f);
    if (opts.has("--view-size")) {
        try {
            parseSize(opts.get("--view-size"), request.width, request.height);
        } catch (const InputError&) {
            throw InputError("--view-size: expected WxH with W and H whole numbers in 1..8192, got '" +
                             opts.get("--view-size") + "'");
        }
    }
    if (opts.has("--pixel")) request.pixel = parseVizPixel(opts.get("--pixel"));
    request.internal = opts.get("--internal");
    request.light = opts.getInt("--light", 0, 0, 1000);
    request.rays = opts.getInt("--rays", 64, 1, 4096);
    request.azimuth = opts.getFloat("--azimuth", 0.0f, -360.0f, 360.0f);
    request.elevation = opts.getFloat("--elevation", 0.0f, -89.0f, 89.0f);
    request.zoom = opts.getFloat("--zoom", 1.0f, 0.05f, 50.0f);

    const std::string out = opts.get("--out");
    checkOutput("--out", out, ".png");
    const std::string exportPath = opts.get("--export");
    if (!exportPath.empty()) {
        checkOutput("--export", exportPath, "");
        if (fs::path(exportPath).extension() != info->exportExtension)
            throw InputError("--export: view " + info->name + " exports " + info->exportExtension + " data, got '" +
                             exportPath + "'");
    }
    // The view's picture and its export, checked together (one file named twice, a folder, a
    // folder that cannot take them) before anything is rendered.
    OutputPlan plan;
    plan.file("--out", out);
    plan.file("--export", exportPath);
    plan.check();
    Image reference;
    if (opts.has("--reference")) {
        if (request.view != "error") throw InputError("--reference: only the error view compares with a reference");
        reference = readPFM(opts.get("--reference"));
        request.reference = &reference;
    }

    if (opts.has("--reference-samples")) {
        if (request.view != "error") throw InputError("--reference-samples: only the error view computes a reference");
        if (opts.has("--reference")) throw InputError("viz: give --reference FILE or --reference-samples N, not both");
        request.referenceSamples = opts.getInt("--reference-samples", 0, 1, 65536);
    }
    Scene scene = loadScene(opts.get("--scene"), sceneLimitsFrom(opts));
    // The memory estimate `render` applies, before the context and the renderer exist.
    checkRenderMemory(scene, options, opts);
    // VTK needs EGL (or the window's context): it does not mix with OSMesa in one process.
    auto context = createHeadlessContext(GLBackend::Egl);
    options.cpuClock = context->isSoftwareRasterizer();
    Renderer renderer(scene, options);
    if (std::string why = viewRefusal(renderer, request); !why.empty())
        throw InputError("view " + request.view + ": " + why);

    OutputSet outputs;
    request.exportPath = exportPath;
    request.outputs = &outputs;
    ViewResult result = renderView(renderer, scene, request);
    writePNG(outputs.stage(out), result.image);
    if (glDebugState().errors > 0)
        throw InternalError(std::to_string(glDebugState().errors) + " OpenGL error(s), the last: " +
                            glDebugState().lastError);
    if (vtkMessages().errors > 0)
        throw InternalError(std::to_string(vtkMessages().errors) + " VTK error(s), the last: " + vtkMessages().last);
    outputs.commit();
    if (opts.has("--json")) {
        std::cout << nlohmann::json{{"view", request.view}, {"caption", result.caption}, {"data", result.data}}.dump(2, ' ', false, nlohmann::json::error_handler_t::replace)
                  << "\n";
    } else {
        std::cout << result.caption << "\n";
    }
    return 0;
}

}  // namespace shadowlab
