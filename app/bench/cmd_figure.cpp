// `shadowlab figure` (issue 8): a comparison grid for a paper. Rows are scenes (or parameter
// values), columns techniques, the reference first; each cell labelled with technique, setting,
// time and error; zoom insets marked on the full image; error heat maps under each row with one
// shared colour bar; supersampling; a JSON sidecar from which `figure --remake` makes the same
// figure again. Spec format: assets/figures/README.md.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <thread>

#include "scene/input_file.h"
#include "bench/bench.h"
#include "bench/figure_draw.h"
#include "bench/figure_spec.h"
#include "cli/cli.h"
#include "cli/provenance.h"
#include "cli/resource_limits.h"
#include "error.h"
#include "gl/context.h"
#include "graph/technique.h"
#include "scene/json_reader.h"

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace shadowlab {

namespace {

using figure::Rgb;

std::string fmt(const char* format, double v) {
    char text[64];
    std::snprintf(text, sizeof text, format, v);
    return text;
}

const Rgb kBackground{1.0f, 1.0f, 1.0f};
const Rgb kInk{0.08f, 0.08f, 0.08f};
const Rgb kGreyInk{0.35f, 0.35f, 0.35f};
const Rgb kInsetColours[] = {{1.0f, 0.78f, 0.0f}, {0.0f, 0.75f, 1.0f}, {1.0f, 0.2f, 0.6f}, {0.3f, 0.9f, 0.3f}};

struct Cell {
    Measurement m;
    Image picture;  // output size, RGB or grey
    Image error;    // |v - ref| at output size (1 channel), empty without a reference
    double labelShadowMs = 0.0;
};

// One label as drawn: its lines and box in the picture (the sidecar's "layout", which the tests read).
struct LabelBox {
    std::string what;  // "title", "row 0 header", "cell 0,1 label", "error bar caption", ...
    std::vector<std::string> lines;
    int x = 0, y = 0, w = 0, h = 0;
};

// Lays the figure out and draws it. Text follows the views' standard (viz/README.md): an em of at
// least 14 px and 1/30 of a cell's height (stb_easy_font's em is about 10 units, its capitals 7, so
// the scale is at least 2: 14 px capitals); labels wrap and their cell grows, never cut.
Image composeFigure(const FigureSpec& spec, const std::vector<std::vector<Cell>>& cells, float errorMax,
                    std::vector<LabelBox>& layout) {
    const int W = spec.width, H = spec.height;
    const int ts = spec.textScale > 0 ? spec.textScale : std::max(2, (std::max(14, int(std::lround(H / 30.0))) + 9) / 10);
    const int pad = 4 * ts, lineH = figure::textHeight(ts) - 2 * ts;
    const int rowsCount = int(spec.rows.size()), colsCount = int(spec.columns.size());
    const bool insetsOn = !spec.insets.empty();
    const int figureW = pad + colsCount * (W + pad);
    auto insetsOf = [&](int r) {
        std::vector<std::pair<int, Inset>> out;
        for (size_t i = 0; i < spec.insets.size(); ++i)
            if (!spec.insets[i].row || *spec.insets[i].row == r) out.push_back({int(i), spec.insets[i]});
        return out;
    };
    // Each inset strip: the insets side by side, each W / max(2, count) wide (centred), keeping its aspect.
    auto insetWidth = [&](int r) { return W / std::max<int>(2, int(insetsOf(r).size())); };
    auto insetHeight = [&](int r) {
        auto list = insetsOf(r);
        int h = 0;
        for (const auto& [i, in] : list) h = std::max(h, int(std::lround(double(insetWidth(r)) * in.h / in.w)));
        return list.empty() ? 0 : h + pad;
    };
    auto wrap = [&](const std::string& text, int width, const std::string& what) {
        return figure::wrapText(text, ts, width, what);
    };

    // Every label's lines first: a row's label block is as tall as its tallest cell's.
    struct CellText {
        std::vector<std::pair<std::vector<std::string>, Rgb>> parts;
        int lines = 0;
    };
    std::vector<std::vector<CellText>> cellText(static_cast<size_t>(rowsCount));
    std::vector<std::vector<std::string>> headers(static_cast<size_t>(rowsCount));
    std::vector<int> labelH(static_cast<size_t>(rowsCount), 0);
    for (int r = 0; r < rowsCount; ++r) {
        const FigureRow& row = spec.rows[size_t(r)];
        const Measurement& first = cells[size_t(r)][0].m;
        std::string header = row.label.empty() ? row.scene : row.label;
        header += "  (light size " + fmt("%g", first.lightSize) + ", " + std::to_string(W * spec.supersample) + "x" +
                  std::to_string(H * spec.supersample) +
                  (spec.supersample > 1 ? " rendered, shown at " + std::to_string(W) + "x" + std::to_string(H) : "") + ")";
        headers[size_t(r)] = wrap(header, figureW - 2 * pad, "row " + std::to_string(r) + " header");
        int most = 0;
        for (int c = 0; c < colsCount; ++c) {
            const Cell& cell = cells[size_t(r)][size_t(c)];
            const FigureColumn& col = spec.columns[size_t(c)];
            std::string name = col.label.empty() ? cell.m.setting.technique : col.label;
            if (!cell.m.techniqueRan.empty() && cell.m.techniqueRan != cell.m.setting.technique)
                name += " (ran " + cell.m.techniqueRan + ")";
            const std::string what = "label of cell " + std::to_string(r) + "," + std::to_string(c);
            CellText t;
            t.parts.push_back({wrap(name, W, what), kInk});
            t.parts.push_back({wrap(Setting{cell.m.setting.technique, cell.m.setting.sets}.describe(), W, what), kGreyInk});
            t.parts.push_back({wrap("shadow " + fmt("%.2f", cell.labelShadowMs) + " ms", W, what), kGreyInk});
            if (cell.error.width)
                t.parts.push_back({wrap("RMSE " + fmt("%.4f", cell.m.all.rmse) + "  SSIM " + fmt("%.3f", cell.m.all.ssim), W, what),
                                   kGreyInk});
            for (const auto& [lines, colour] : t.parts) t.lines += int(lines.size());
            most = std::max(most, t.lines);
            cellText[size_t(r)].push_back(t);
        }
        labelH[size_t(r)] = most * lineH + pad;
    }
    const std::vector<std::string> title = spec.title.empty() ? std::vector<std::string>{} : wrap(spec.title, figureW - 2 * pad, "title");
    const int titleH = title.empty() ? pad : int(title.size()) * lineH + 2 * pad;
    std::vector<int> rowTop;
    int total = titleH;
    for (int r = 0; r < rowsCount; ++r) {
        rowTop.push_back(total);
        const int headerH = int(headers[size_t(r)].size()) * lineH + pad;
        total += headerH + H + insetHeight(r) + labelH[size_t(r)] + (spec.errorMaps ? H + pad : 0) + pad;
    }
    const std::string barCaption = "|v - v_ref|: visibility error against " + spec.reference.describe() +
                                   " (grey: no data, the background)";
    const std::vector<std::string> caption = spec.errorMaps ? wrap(barCaption, figureW - 2 * pad, "error bar caption")
                                                            : std::vector<std::string>{};
    const int barH = spec.errorMaps ? 10 * ts + lineH * (1 + int(caption.size())) + 3 * pad : 0;
    Image out(figureW, total + barH, 3);
    figure::fill(out, 0, 0, out.width, out.height, kBackground);
    auto drawLines = [&](const std::vector<std::string>& lines, int left, int top, Rgb colour, const std::string& what,
                         bool centred = false, int span = 0) {
        LabelBox box{what, lines, left, top, 0, int(lines.size()) * lineH};
        for (size_t i = 0; i < lines.size(); ++i) {
            const int w = figure::textWidth(lines[i], ts);
            const int x = centred ? left + (span - w) / 2 : left;
            figure::text(out, lines[i], x, top + int(i) * lineH, ts, colour);
            box.x = i == 0 ? x : std::min(box.x, x);
            box.w = std::max(box.w, x + w - box.x);
        }
        layout.push_back(box);
    };
    if (!title.empty()) drawLines(title, pad, pad, kInk, "title");

    for (int r = 0; r < rowsCount; ++r) {
        drawLines(headers[size_t(r)], pad, rowTop[size_t(r)] + pad / 2, kInk, "row " + std::to_string(r) + " header");
        const int imageTop = rowTop[size_t(r)] + int(headers[size_t(r)].size()) * lineH + pad;
        const auto insets = insetsOf(r);
        for (int c = 0; c < colsCount; ++c) {
            const Cell& cell = cells[size_t(r)][size_t(c)];
            const int left = pad + c * (W + pad);
            figure::blit(out, cell.picture, left, imageTop);
            // Insets: the rectangle marked on the full picture, the zoom beneath it.
            int y = imageTop + H;
            if (!insets.empty()) {
                const int each = insetWidth(r);
                const int stripLeft = left + (W - each * int(insets.size())) / 2;
                for (size_t k = 0; k < insets.size(); ++k) {
                    const Inset& in = insets[k].second;
                    const Rgb colour = kInsetColours[insets[k].first % 4];
                    figure::outline(out, left + in.x, imageTop + in.y, left + in.x + in.w, imageTop + in.y + in.h,
                                    std::max(1, ts), colour);
                    const int zh = int(std::lround(double(each) * in.h / in.w));
                    // The zoom samples the supersampled render, so it shows detail the cell cannot.
                    const int s = spec.supersample;
                    Image zoomed = figure::zoom(cell.m.image.width ? (spec.show == "image" ? cell.m.image : cell.m.visibility) : cell.picture,
                                                in.x * s, in.y * s, in.w * s, in.h * s, each - (k + 1 < insets.size() ? ts : 0), zh);
                    const int zx = stripLeft + int(k) * each;
                    figure::blit(out, zoomed, zx, y + pad / 2);
                    figure::outline(out, zx, y + pad / 2, zx + zoomed.width, y + pad / 2 + zh, std::max(1, ts), colour);
                }
                y += insetHeight(r);
            } else if (insetsOn) {
                y += insetHeight(r);
            }
            // Labels: technique and setting; time; error; each part wrapped to the cell's width.
            int ly = y + pad / 2;
            const std::string what = "cell " + std::to_string(r) + "," + std::to_string(c) + " label";
            for (const auto& [lines, colour] : cellText[size_t(r)][size_t(c)].parts) {
                drawLines(lines, left, ly, colour, what);
                ly += int(lines.size()) * lineH;
            }
            y += labelH[size_t(r)];
            if (spec.errorMaps) {
                if (cell.error.width) {
                    figure::blit(out, figure::colourError(cell.error, errorMax), left, y);
                } else {
                    figure::fill(out, left, y, left + W, y + H, {0.9f, 0.9f, 0.9f});
                }
            }
        }
    }
    if (spec.errorMaps) {
        // One colour bar for every error map of the figure.
        const int top = total + pad;
        const int barW = std::min(figureW - 2 * pad, std::max(W, figureW / 2));
        const int left = (figureW - barW) / 2;
        Image ramp(barW, 1, 1);
        for (int x = 0; x < barW; ++x) ramp.data[size_t(x)] = errorMax * float(x) / float(std::max(1, barW - 1));
        Image bar = figure::colourError(figure::zoom(ramp, 0, 0, barW, 1, barW, 10 * ts), errorMax);
        figure::blit(out, bar, left, top);
        figure::outline(out, left - 1, top - 1, left + barW + 1, top + 10 * ts + 1, 1, kInk);
        const int ty = top + 10 * ts + pad / 2;
        drawLines({"0"}, left, ty, kInk, "error bar 0");
        const std::string maxText = fmt("%.3g", errorMax);
        drawLines({maxText}, left + barW - figure::textWidth(maxText, ts), ty, kInk, "error bar maximum");
        drawLines(caption, pad, ty + lineH, kInk, "error bar caption", true, figureW - 2 * pad);
    }
    return out;
}

int runFigure(const FigureSpec& spec, const std::string& specFile, const std::string& out, const std::string& cacheDir,
              const FigureSidecar* remakeFrom, const std::string& gl) {
    if (!std::getenv("LP_NUM_THREADS"))
        setenv("LP_NUM_THREADS", std::to_string(std::max(1u, std::thread::hardware_concurrency())).c_str(), 1);
    auto context = createHeadlessContext(parseBackend(gl));
    const int s = spec.supersample;
    const int rw = spec.width * s, rh = spec.height * s;
    std::vector<std::vector<Cell>> cells(spec.rows.size());
    json cellsJson = json::array();
    float errorMax = float(spec.errorMax);
    bool autoMax = !(spec.errorMax > 0.0);
    if (autoMax) errorMax = 0.0f;
    for (size_t r = 0; r < spec.rows.size(); ++r) {
        const FigureRow& row = spec.rows[r];
        Scene scene = loadScene(row.scene);
        if (row.camera) scene.camera = *row.camera;
        CachedReference ref = cachedReference(scene, rw, rh, row.lightSize, spec.reference, cacheDir, context->renderer());
        for (size_t c = 0; c < spec.columns.size(); ++c) {
            Setting setting = spec.columns[c].setting;
            const TechniqueDesc& d = requireTechnique(setting.technique, "columns");
            for (const auto& kv : row.sets)
                if (d.findParam(kv.first)) {
                    setting.sets.erase(std::remove_if(setting.sets.begin(), setting.sets.end(),
                                                      [&](const auto& p) { return p.first == kv.first; }),
                                       setting.sets.end());
                    setting.sets.push_back(kv);
                }
            std::fprintf(stderr, "figure: [%zu/%zu] %s %s %s\n", r * spec.columns.size() + c + 1,
                         spec.rows.size() * spec.columns.size(), row.scene.c_str(), setting.technique.c_str(),
                         setting.describe().c_str());
            Cell cell;
            cell.m = measureSetting(scene, row.scene, rw, rh, row.lightSize, setting, spec.frames, spec.warmup,
                                    &ref.visibility, context->isSoftwareRasterizer());
            cell.m.referenceKey = ref.key;
            cell.m.referenceDesc = spec.reference.describe();
            cell.picture = figure::downsample(spec.show == "image" ? cell.m.image : cell.m.visibility, s);
            // The error map: no data (NaN, shown grey) where the pixel sees no geometry, so the background
            // is never mistaken for zero error.
            Image error = figure::absoluteError(cell.m.visibility, ref.visibility);
            if (cell.m.ids.pixelCount() == error.pixelCount())
                for (size_t i = 0; i < error.pixelCount(); ++i)
                    if (cell.m.ids.data[i] < 0.0f) error.data[i] = NAN;
            cell.error = figure::downsample(error, s);
            cell.labelShadowMs = cell.m.shadowMs;
            if (autoMax)
                for (float e : cell.error.data)
                    if (std::isfinite(e)) errorMax = std::max(errorMax, e);
            if (remakeFrom) {
                // Labels show the times of the original run, so the picture is the same; the new
                // times go to the new sidecar beside them.
                const size_t index = r * spec.columns.size() + c;
                const FigureSidecar::OldCell& old = remakeFrom->cells[index];
                cell.labelShadowMs = old.labelShadowMs;
                if (!(old.rmse == cell.m.all.rmse))
                    std::fprintf(stderr, "figure: warning: row %zu column %zu: RMSE %.9g, the original had %.9g\n", r, c,
                                 cell.m.all.rmse, old.rmse);
            }
            json cj{{"row", r},
                    {"column", c},
                    {"scene", row.scene},
                    {"scene_file", scene.path},
                    {"camera",
                     {{"position", {scene.camera.position.x, scene.camera.position.y, scene.camera.position.z}},
                      {"target", {scene.camera.target.x, scene.camera.target.y, scene.camera.target.z}},
                      {"up", {scene.camera.up.x, scene.camera.up.y, scene.camera.up.z}},
                      {"fov_deg", scene.camera.fovYDegrees}}},
                    {"light_size", cell.m.lightSize},
                    {"lights", cell.m.lights},
                    {"technique", setting.technique},
                    {"technique_ran", cell.m.techniqueRan},
                    {"set", setting.describe()},
                    {"parameters", cell.m.parameters},
                    {"render_size", {rw, rh}},
                    {"shadow_ms", cell.m.shadowMs},
                    {"fixed_ms", cell.m.fixedMs},
                    {"total_ms", cell.m.totalMs},
                    {"passes_ms", cell.m.passMs},
                    {"clock", cell.m.clock},
                    {"label_shadow_ms", cell.labelShadowMs},
                    {"rmse", cell.m.all.rmse},
                    {"max_abs", cell.m.all.maxAbs},
                    {"ssim", cell.m.all.ssim},
                    {"penumbra_rmse", cell.m.penumbra.rmse},
                    {"reference", spec.reference.describe()},
                    {"reference_key", ref.key}};
            cellsJson.push_back(cj);
            cells[r].push_back(std::move(cell));
            if (glDebugState().errors > 0)
                throw InternalError(std::to_string(glDebugState().errors) + " OpenGL error(s), the last: " + glDebugState().lastError);
        }
    }
    if (remakeFrom && remakeFrom->errorMax) errorMax = *remakeFrom->errorMax;
    if (!(errorMax > 0.0f)) errorMax = 1.0f;  // every cell equals the reference: a scale of 1
    std::vector<LabelBox> layout;
    Image picture = composeFigure(spec, cells, errorMax, layout);
    json layoutJson = json::array();
    for (const LabelBox& b : layout)
        layoutJson.push_back({{"what", b.what}, {"lines", b.lines}, {"box", {b.x, b.y, b.w, b.h}}});

    RunInfo info = currentRunInfo(context->renderer());
    json side{{"shadowlab_figure", 1},
              {"spec", specJson(spec)},
              {"spec_file", specFile},
              {"out", out},
              {"error_max", errorMax},
              {"cells", cellsJson},
              {"program", {{"name", "shadowlab"}, {"version", info.version}}},
              {"gl_renderer", info.glRenderer},
              {"machine", {{"cpu", info.cpu}, {"lp_num_threads", info.lpNumThreads}, {"load_average", info.loadAverage}}},
              {"date", info.date},
              {"picture_size", {picture.width, picture.height}},
              {"layout", layoutJson}};
    if (remakeFrom) side["remade_from"] = {{"date", remakeFrom->date}, {"out", remakeFrom->out}};
    OutputSet outputs;
    if (fs::path(out).extension() == ".pdf")
        figure::writeRasterPdf(outputs.stage(out), picture, 150.0, spec.title.empty() ? "shadowlab figure" : spec.title);
    else
        writePNG(outputs.stage(out), picture);
    std::ofstream sidecar(outputs.stage(out + ".json"), std::ios::binary);
    sidecar << side.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
    sidecar.close();
    if (!sidecar) throw InternalError("cannot write " + out + ".json");
    outputs.commit();
    std::fprintf(stderr, "figure: %s (%dx%d) and its sidecar %s.json\n", out.c_str(), picture.width, picture.height, out.c_str());
    return 0;
}

// The memory estimate `render` applies, for every cell and row reference at the rendered size
// (size x supersample), before the first render.
void checkFigureMemory(const FigureSpec& spec, const Options& opts) {
    for (size_t r = 0; r < spec.rows.size(); ++r) {
        const FigureRow& row = spec.rows[r];
        const Scene scene = loadScene(row.scene);
        RenderOptions reference;
        reference.width = spec.width * spec.supersample;
        reference.height = spec.height * spec.supersample;
        reference.technique = spec.reference.technique;
        std::vector<std::pair<std::string, RenderOptions>> renders = {{"the reference " + spec.reference.describe(), reference}};
        for (size_t c = 0; c < spec.columns.size(); ++c) {
            RenderOptions o = reference;
            o.technique = spec.columns[c].setting.technique;
            o.sets = spec.columns[c].setting.sets;
            o.sets.insert(o.sets.end(), row.sets.begin(), row.sets.end());
            renders.push_back({"columns[" + std::to_string(c) + "] " + o.technique, o});
        }
        for (const auto& [what, options] : renders) {
            try {
                checkRenderMemory(scene, options, opts);
            } catch (const InputError& e) {
                throw InputError("figure: rows[" + std::to_string(r) + "] " + row.scene + ", " + what + ": " + e.what());
            }
        }
    }
}

void checkFigureOut(const std::string& out) {
    checkPathName("figure: --out", out);
    fs::path parent = fs::path(out).parent_path();
    std::error_code ec;
    if (!parent.empty() && !fs::is_directory(parent, ec))
        throw InputError("figure: --out: folder '" + parent.string() + "' does not exist");
    std::string ext = fs::path(out).extension().string();
    if (ext != ".png" && ext != ".pdf") throw InputError("figure: --out: expected a .png or .pdf file, got '" + out + "'");
    // The figure and its sidecar, checked before any cell is rendered.
    OutputPlan plan;
    plan.fileWithSidecar("figure: --out", out);
    plan.check();
}

}  // namespace

int commandFigure(const std::vector<std::string>& args) {
    Options opts("figure", args, 1, {"--spec", "--out", "--remake", "--cache", "--gl", "--max-memory-mb"}, {});
    if (!opts.positional().empty()) throw InputError("figure: unexpected argument '" + opts.positional()[0] + "'");
    const std::string cacheDir = opts.has("--cache") ? opts.get("--cache") : defaultReferenceCacheDir();
    if (opts.has("--remake")) {
        if (opts.has("--spec")) throw InputError("figure: give --spec fig.json or --remake fig.png.json, not both");
        const std::string path = opts.get("--remake");
        const JsonDocument doc = JsonDocument::fromFile(path, "figure sidecar");
        const FigureSidecar side = readFigureSidecar(doc);
        // The recorded spec is read with the spec's own rules (messages name the sidecar and "spec.<field>").
        const JsonDocument specDoc = JsonDocument::fromString(path + " (field spec)", side.spec);
        FigureSpec spec = parseFigureSpec(specDoc);
        if (side.cells.size() != spec.rows.size() * spec.columns.size())
            JsonReader(doc).fail("cells", std::to_string(spec.rows.size() * spec.columns.size()) +
                                              " cells (the spec's rows x columns)",
                                 "an array of " + std::to_string(side.cells.size()));
        std::string out = opts.get("--out", side.out);
        checkFigureOut(out);
        checkFigureMemory(spec, opts);
        return runFigure(spec, side.specFile, out, cacheDir, &side, opts.get("--gl", "egl"));
    }
    if (!opts.has("--spec")) throw InputError("figure: --spec fig.json (or --remake fig.png.json) is required");
    if (!opts.has("--out")) throw InputError("figure: --out fig.png|fig.pdf is required");
    const std::string out = opts.get("--out");
    checkFigureOut(out);
    const JsonDocument doc = JsonDocument::fromFile(opts.get("--spec"), "figure spec");
    FigureSpec spec = parseFigureSpec(doc);
    checkFigureMemory(spec, opts);
    return runFigure(spec, opts.get("--spec"), out, cacheDir, nullptr, opts.get("--gl", "egl"));
}

}  // namespace shadowlab
