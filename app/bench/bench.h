// `shadowlab bench` and `shadowlab figure` (issue 8; DESIGN.md sections 1 and 6): what accuracy
// costs in time. The pieces shared by the two commands: the reference cache, timed renders with
// their error against the reference, the bench specification (assets/bench/README.md) and the
// rows of the CSV.
#pragma once
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "image/image.h"
#include "image/metrics.h"
#include "scene/scene.h"

namespace shadowlab {

class GLContext;

// ---- references ----------------------------------------------------------------------------------
// The ground truth a setting is compared with: `raytraced` with M rays (default) or `reference`
// with N light samples (the papers' averaged shadow maps).
struct ReferenceSpec {
    std::string technique = "raytraced";
    int count = 256;  // rays (raytraced) or samples (reference)
    std::string countKey() const { return technique == "raytraced" ? "rays" : "samples"; }
    std::string describe() const { return technique + " " + countKey() + "=" + std::to_string(count); }
};
// "raytraced", "raytraced:256", "reference:1024" (InputError naming `where` otherwise).
ReferenceSpec parseReferenceSpec(const std::string& text, const std::string& where);

class JsonReader;
// A parameter value in a bench or figure spec as --set text: numbers as "%.9g", booleans
// true/false, enum names as written; anything else fails naming `path` (InputError).
std::string specValueText(const JsonReader& r, const nlohmann::json& v, const std::string& path);

// A reference visibility buffer, computed once and cached on disk in `cacheDir` by a key over
// everything that decides it: the scene (name and file contents), the size, the light (after
// --light-size) and the reference settings. The key and its fields are in the cached PFM's
// sidecar; a cached file whose recorded fields differ from the request is recomputed.
struct CachedReference {
    Image visibility;
    std::string key;         // 16 hex digits
    nlohmann::json fields;   // what the key hashes
    std::string path;        // the cached PFM
    bool hit = false;        // read from the cache
    double computeMs = 0.0;  // time to compute it (0 on a hit)
};
// $SHADOWLAB_CACHE, else $XDG_CACHE_HOME/shadowlab, else ~/.cache/shadowlab; plus "/references".
std::string defaultReferenceCacheDir();
CachedReference cachedReference(const Scene& scene, int width, int height, std::optional<float> lightSize,
                                const ReferenceSpec& reference, const std::string& cacheDir,
                                const std::string& glRenderer);

// ---- one timed, measured render --------------------------------------------------------------------
struct Setting {
    std::string technique;
    std::vector<std::pair<std::string, std::string>> sets;  // validated key=value pairs
    // "pcf_kernel=9 sm_size=1024", or "defaults".
    std::string describe() const;
};

struct Measurement {
    std::string scene;
    double lightSize = 0.0;  // light 0's size as rendered (after --light-size)
    Setting setting;
    nlohmann::json parameters;  // light 0's parameters as rendered (every key, defaults filled in)
    std::string techniqueRan;   // light 0's technique as run (a point light runs `hard`)
    nlohmann::json lights;      // every light as rendered: shape, pose, size, technique, parameters
    int width = 0, height = 0;
    int frames = 0, warmup = 0;
    std::string clock;
    double shadowMs = 0.0, fixedMs = 0.0, totalMs = 0.0;
    std::map<std::string, double> passMs;  // "<technique>/<pass>" and "gbuffer", "shade"; summed over lights
    // Light 0's counters (`render --stats`' lights[0].counters), "<counter>.<field>" for each number:
    // what the technique restricted its work to (pvmf's mask.masked_fraction, ...).
    std::map<std::string, double> counters;
    Metrics all, penumbra;
    size_t techniqueBytes = 0;  // GPU memory of the technique's resources (all lights)
    size_t memoryBytes = 0;     // all GPU memory of the render (frame buffers and scene too)
    // Of the pixels that computed a capped kernel, the fraction whose kernel was clamped (the
    // largest over the lights and capped kernels; NaN, an empty CSV cell, when none is capped).
    double kernelClampedFraction = NAN;
    std::string referenceKey;   // the cache key of the reference it was compared with
    std::string referenceDesc;  // "raytraced rays=256"
    Image visibility;  // the render's visibility buffer
    Image image;       // the shaded image (sRGB)
    Image ids;         // object ids per pixel, -1 on background (no geometry)
};

// Renders `setting` on `scene` with every pass timed every frame (no reuse): `warmup` frames, then
// `frames` timed frames; times are medians over the timed frames. The errors are measured against
// `reference` (when it is not empty). Needs a current GL context.
Measurement measureSetting(const Scene& scene, const std::string& sceneName, int width, int height,
                           std::optional<float> lightSize, const Setting& setting, int frames, int warmup,
                           const Image* reference, bool cpuClock);

// ---- the specification -----------------------------------------------------------------------------
// One technique of a run list with the values its parameters sweep.
struct RunSpec {
    std::string technique;
    std::vector<std::pair<std::string, std::vector<std::string>>> sweep;  // key -> values, in order
    std::vector<std::pair<std::string, std::string>> fixed;               // key=value for every setting
    std::vector<Setting> settings() const;  // the cartesian product, the first key slowest
    // How many settings() would make, counted without making them (saturates at 1e300).
    double settingCount() const;
};

// The paper's numbers a spec reproduces (assets/bench/README.md).
struct PaperRow {
    std::string label;
    std::string scene;                      // "" = any scene of the spec
    std::optional<double> lightSize;        // unset = any
    std::string technique;
    std::map<std::string, double> params;  // must equal the setting's values
    std::vector<std::pair<std::string, double>> values;  // paper column -> value
    std::string place;                      // "spec.json:40: paper.rows[2]" for messages
};
struct PaperSpec {
    std::string citation, what, machine, note;
    std::string compare = "ratio";  // "ratio": each value over the baseline row's; "absolute"
    std::string baseline;           // label of the baseline row (compare = ratio)
    std::vector<std::pair<std::string, std::string>> columns;  // paper column -> CSV column
    std::vector<PaperRow> rows;
    bool present = false;
};

// A scene as a bench measures it: its camera moved along the line of sight to `distance` times its
// distance from the target (the far plane moved out with it), and its label in the rows: the name,
// with " camera Dx" when the spec has distances other than 1.
Scene benchScene(const Scene& scene, double distance);
std::string benchSceneLabel(const std::string& name, double distance, const std::vector<double>& distances);

struct BenchSpec {
    std::string file;  // "" when built from flags
    std::string name, title, reproduces;
    std::vector<std::string> scenes;
    std::vector<std::optional<float>> lightSizes = {std::nullopt};  // nullopt = the scene's own
    // Each scene's camera moved along its line of sight to this many times its distance from the
    // target (1: as in the scene); one row per scene x distance x light size x setting.
    std::vector<double> cameraDistances = {1.0};
    int width = 256, height = 256;
    int frames = 5, warmup = 2;
    ReferenceSpec reference;
    std::vector<RunSpec> runs;
    std::string errorMetric = "rmse";  // the chart's y axis: "rmse" or "1-ssim"
    PaperSpec paper;
};

// Reads and validates a spec: every scene loads, every technique, key and value is valid, every
// paper row matches a setting; errors name the file, line and field (InputError).
// The settings a bench may measure unless --max-settings raises it: each costs a render of
// `frames` + `warmup` frames, so 10,000 is hours already; three 1000-value sweeps made 10^9 in
// memory (std::bad_alloc) before this was counted.
constexpr double kDefaultMaxSettings = 10000;
// scenes x light sizes x the runs' settings, counted before any is built.
double benchSettingCount(const BenchSpec& spec);
// InputError "<where>: the bench would measure N settings (...), over the limit of M (--max-settings
// N raises it)" when over `maxSettings`, or "... no setting" when the count is 0.
void checkBenchSettingCount(const BenchSpec& spec, double maxSettings, const std::string& where);
BenchSpec loadBenchSpec(const std::string& path, double maxSettings = kDefaultMaxSettings);
// "a:b:n": n values from a to b inclusive (rounded for integer parameters, duplicates dropped).
std::vector<std::string> expandRange(const std::string& text, const std::string& where, bool integer);
// Does a paper row name this setting? (scene, light size, technique, and each of the row's
// parameters equal to the setting's value)
bool paperRowMatches(const PaperRow& row, const std::string& scene, double lightSize, const std::string& technique,
                     const nlohmann::json& parameters);

// The known technique ids: the registry's, plus the stable ids of DESIGN.md section 4 that have not
// landed yet (paper rows may name them; runs may not).
bool isPlannedTechnique(const std::string& id);

// ---- rows, CSV, report -----------------------------------------------------------------------------
// The CSV's columns, in order: fixed columns, then one "ms.<technique>/<pass>" per pass seen.
std::vector<std::string> csvColumns(const std::vector<Measurement>& rows);
// A column's value in a row as the CSV writes it ("" when the row has no such column).
std::string csvValue(const Measurement& row, const std::string& column);
// A numeric column's value (nullopt when missing or not a number).
std::optional<double> numericValue(const Measurement& row, const std::string& column);
std::string toCsv(const std::vector<Measurement>& rows);
// The fixed columns' names (to validate spec column mappings).
const std::vector<std::string>& fixedCsvColumns();

struct RunInfo {
    std::string glRenderer, cpu, lpNumThreads, version, date;
    std::string loadAverage;  // /proc/loadavg's 1, 5 and 15 minute loads when the run started (other processes share the cores)
    double seconds = 0.0;
    std::vector<std::string> commandLine;
};
std::string benchReportMarkdown(const BenchSpec& spec, const std::vector<Measurement>& rows, const RunInfo& info,
                                const std::string& chartPath);
std::string benchLatexTable(const BenchSpec& spec, const std::vector<Measurement>& rows);

// "1-ssim" or "rmse" of a row.
double errorOf(const Measurement& row, const std::string& metric);

// What `figure` and `bench` write about the machine.
RunInfo currentRunInfo(const std::string& glRenderer);

}  // namespace shadowlab
