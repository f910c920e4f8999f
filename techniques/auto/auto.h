// `auto` (issue 25): per light, the cheapest registered technique and setting whose predicted error
// meets `error_budget`, from facts of the light and the scene and from a measured calibration; it
// says why. The pieces, each testable without a GL context:
//  - LightFeatures: what the choice rests on, measured on the CPU from the scene's geometry, the
//    light and the camera (a conservative bound on the largest penumbra, guennebaud2007 eq. 4-5);
//  - Calibration: error and shadow_ms per technique setting on measured cases (the JSON file that
//    `shadowlab bench --calibrate` writes, assets/calibration/default.json);
//  - chooseTechnique: the facts first (a point light or a penumbra under a pixel takes `hard`; a
//    shadow on no visible pixel runs nothing), then the calibration's prediction.
#pragma once
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "graph/technique.h"
#include "scene/scene.h"

namespace shadowlab {

const TechniqueDesc& autoTechnique();

// ---- features -----------------------------------------------------------------------------------------
struct LightFeatures {
    bool point = false;
    double lightExtent = 0.0;     // the light's largest width (square: its diagonal; disk, sphere: 2r)
    double casterNear = 0.0;      // the nearest caster's depth along the light's axis (z_o of eq. 4)
    double receiverFar = 0.0;     // the farthest receiver's depth along the light's axis (z_r)
    double penumbraWorld = 0.0;   // eq. 4 at those depths: w_l (z_r - z_o) / z_o, world units
    double penumbraPixels = 0.0;  // eq. 5 (without the normal term): at the nearest depth from the camera
                                  // at which a shadow can fall, in pixels of the frame
    double penumbraTexels = 0.0;  // the same penumbra seen from the light's centre, in texels of a
                                  // 1024^2 shadow map fitted to the scene
    double casterTriangles = 0.0;
    // The share of the frame's pixels in this light's penumbra, estimated by ray-tracing the light
    // (16 stratified rays) from points spread over the receivers where its shadows can fall, each
    // weighted by the pixels its patch covers on screen (occlusion from the camera ignored: an upper
    // estimate). What scales a technique's whole-image RMSE from its penumbra error. Taken at the
    // scene's first pose (t = 0) whatever t: one cached ray-traced set per scene and light.
    double penumbraFraction = 0.0;
    bool shadowOnScreen = true;   // false: the region where this light's shadows can fall is outside
                                  // the camera's frustum (conservative: true when unsure)
    // This light's weight in v over its penumbra, with `others` lights beside it (shade.frag: v =
    // sum_l v_l E_l / sum_l E_l): the root mean square of E_l / sum_k E_k over the sampled points in
    // its penumbra; 1 alone. Not a calibration feature: it shares the budget between lights.
    double share = 1.0;
    nlohmann::json toJson() const;
};
// Conservative by construction: the nearest caster with the farthest receiver, and the shadow
// region's nearest point to the camera, so the estimate is never smaller than the true largest
// penumbra (up to the scene's bounds' looseness). At time t (objects posed as at t).
LightFeatures measureLightFeatures(const Scene& scene, const Light& light, const Camera& camera, int width,
                                   int height, double t = 0.0, const std::vector<Light>& all = {});

// Keys of the caches (the ray-traced samples, the trials): the scene's content at time t (each
// object's triangle and vertex counts, its first, middle and last vertex, transform and flags; not
// its address), and a light's pose, shape, size, colour and intensity mixed into a key.
uint64_t sceneContentKey(const Scene& scene, double t);
uint64_t mixLightKey(uint64_t key, const Light& light);
// One value mixed into such a key (FNV-style: xor, then multiply by the FNV prime); a float by its bits.
uint64_t mixKey(uint64_t key, uint64_t value);
uint64_t mixKey(uint64_t key, float value);

// Each light's part of a frame's error budget (a light decided by the facts takes its whole budget,
// it errs only by aliasing): with n lights left to the calibration, light l may err by
// budget / (n share_l), so that sum_l share_l e_l <= budget bounds the RMSE of v (Minkowski's
// inequality, with the shares over each light's penumbra standing in for the per-pixel weights).
// At most 1.
double lightBudget(double frameBudget, const LightFeatures& light, int lightsByCalibration);

// ---- calibration -----------------------------------------------------------------------------------------
struct CalibrationSetting {
    std::string technique;
    std::vector<std::pair<std::string, std::string>> sets;  // key=value as --set text
    std::string describe() const;                          // "pcss defaults", "pcf pcf_kernel=9"
};
struct CalibrationResult {
    double rmse = 0.0;          // of v against the reference, whole image
    double rmsePenumbra = 0.0;  // over the reference's penumbra (0 < v < 1)
    double fixedMs = 0.0;       // shadow passes whose work does not scale with the frame (shadow maps)
    double frameMs = 0.0;       // shadow passes over frame-size textures (scale with the pixel count)
};
struct CalibrationCase {
    std::string scene;  // the scene's name, or "random:SEED"
    double lightSize = 0.0;
    int width = 0, height = 0;
    LightFeatures features;
    std::vector<CalibrationResult> results;  // one per Calibration::settings, in order
};
struct Calibration {
    static constexpr int kVersion = 1;
    std::string file;  // where it was read from ("" when built in memory)
    std::string program, date, glRenderer, cpu, lpNumThreads, reference;
    double probeMs = 0.0;  // machineProbeMs() on the machine that made it
    std::vector<CalibrationSetting> settings;
    std::vector<CalibrationCase> cases;
    nlohmann::json toJson() const;
};
// Reads and validates a calibration file (InputError naming the file, line and field).
Calibration loadCalibration(const std::string& path);
// $SHADOWLAB_CALIBRATION, else <root>/assets/calibration/default.json; read once per process.
std::string defaultCalibrationPath();
const Calibration& defaultCalibration();
// A fixed CPU workload timed on this machine (best of three, milliseconds): times of a calibration
// made elsewhere are scaled by probe-now over probe-then (on llvmpipe the GPU is the CPU).
double machineProbeMs();

// ---- prediction and choice ---------------------------------------------------------------------------------
// A setting's predicted error is the largest over this many nearest calibrated cases (chosen by
// leaving each scene of a 147-case calibration out in turn: techniques/auto/README.md).
constexpr size_t kNeighbours = 3;
struct Prediction {
    double error = 0.0;  // conservative: the largest error of the nearest calibrated cases, each scaled
                         // by sqrt(penumbra fraction here / there)
    double ms = 0.0;     // shadow_ms at this frame size on this machine
    double distance = 0.0;  // to the nearest calibrated case in feature space
    std::vector<std::string> nearest;  // the cases it rests on ("plant light 2")
};
// Distance in the feature space the prediction uses (log2 of the penumbra in pixels and in texels,
// log10 of the caster triangles): the calibration's neighbourhoods.
double featureDistance(const LightFeatures& a, const LightFeatures& b);
Prediction predictSetting(const Calibration& calibration, size_t setting, const LightFeatures& features,
                          bool penumbraBudget, int pixels, double machineScale);
// The calibration cannot speak for a light whose features lie this far from every case (or whose
// penumbra is over twice the widest calibrated one).
constexpr double kOutsideCalibration = 1.5;

struct AutoBudget {
    double error = 0.02;       // this light's part (lightBudget)
    double frameError = 0.0;   // the frame's budget it was shared from (0: the same as error)
    int sharedBy = 1;          // the lights left to the calibration that share it
    // Measured choices with several lights: the measured errors of the lights the facts give `hard`
    // (their root sum of squares), taken off frameError in quadrature before the rest is shared
    // (< 0: shared by the lights' shares instead).
    double byFacts = -1.0;
    bool penumbra = false;  // budget_on = penumbra
    double timeMs = 0.0;    // 0: none
};
// A setting's error measured on this light and frame (trial.h: rendered at the trial size against a
// ray-traced reference); nullopt when it could not be measured.
struct MeasuredError {
    double rmse = 0.0;          // whole image
    double rmsePenumbra = 0.0;  // over the reference's penumbra (0 < v < 1)
};
// What a measured choice asks of its trials: one setting's error, and the shadow_ms of the settings
// within the budget timed side by side (in alternated rounds, put at the frame's size; < 0: not timed),
// so the load of a shared machine falls on all of them alike and no time is compared with one
// measured at another moment.
struct SettingTrials {
    std::function<std::optional<MeasuredError>(size_t setting)> error;
    std::function<std::vector<double>(const std::vector<size_t>& settings)> time;
};
// The facts first, then the calibration. With `trials` (the parameter `measure` on, and a GL
// context to render in), every setting within the time budget is measured (its error), in the order
// of its predicted time, and those within the error budget are timed side by side: the fastest
// measured within the budget is taken. The calibration's times miss by up to 17x (ssv on
// random:2013: 113 ms predicted, 7 measured), so a prediction only orders what is then checked and
// puts a trial's time at the frame's size (techniques/auto/README.md, "Measured, not trusted").
TechniqueChoice chooseTechnique(const Calibration& calibration, const LightFeatures& features,
                                const AutoBudget& budget, int pixels, double machineScale,
                                const SettingTrials* trials = nullptr);

}  // namespace shadowlab
