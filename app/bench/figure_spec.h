// The figure specification of `shadowlab figure` (issue 8; format in assets/figures/README.md):
// reading and validating a spec, and writing it back with every default filled in (the sidecar
// that `figure --remake` reads with the same rules). Its own file so the reader can be fuzzed
// without the figure renderer (tests/fuzz/fuzz_figure.cpp, issue 11).
#pragma once
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bench/bench.h"
#include "scene/json_reader.h"
#include "scene/scene.h"

namespace shadowlab {

struct FigureRow {
    std::string scene;
    std::optional<float> lightSize;
    std::vector<std::pair<std::string, std::string>> sets;  // applied to every column whose technique has the key
    std::string label;
    std::optional<Camera> camera;
};
struct FigureColumn {
    Setting setting;
    std::string label;
};
struct Inset {
    int x = 0, y = 0, w = 0, h = 0;  // in cell pixels (the output size), y from the top
    std::optional<int> row;          // only this row; all rows when unset
};
struct FigureSpec {
    std::string title;
    int width = 256, height = 256;  // each cell's picture, output pixels
    int supersample = 1;
    int frames = 3, warmup = 1;
    std::string show = "image";  // "image" (shaded, sRGB) or "visibility" (grey)
    ReferenceSpec reference;
    std::vector<FigureRow> rows;
    std::vector<FigureColumn> columns;
    std::vector<Inset> insets;
    bool errorMaps = true;
    double errorMax = 0.0;  // 0: the largest error over all maps
    int textScale = 0;      // 0: from the cell width
};

// The spec, validated: file, line and field in every message (InputError).
FigureSpec parseFigureSpec(const JsonDocument& doc);
// The spec back as JSON, every default filled in: what the sidecar records and --remake reads.
// parseFigureSpec of its text gives the same spec again.
nlohmann::json specJson(const FigureSpec& s);

// What `figure --remake` reads back from a figure's sidecar, each field checked with its type and
// range (a tampered sidecar was read through nlohmann's unchecked const operator[]: "type must be
// number, but is number", exit 1, and undefined behaviour for a missing key).
struct FigureSidecar {
    std::string spec;      // the recorded spec, as JSON text (read with the spec's own rules)
    std::string specFile;  // the spec's file when it was made
    std::string out;
    std::string date;
    struct OldCell {
        double labelShadowMs = 0.0;
        double rmse = NAN;  // null when the original RMSE was not a number
    };
    std::vector<OldCell> cells;
    std::optional<float> errorMax;
};
FigureSidecar readFigureSidecar(const JsonDocument& doc);

}  // namespace shadowlab
