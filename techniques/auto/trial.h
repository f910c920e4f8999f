// The measured half of `auto`'s choice (issue 25; techniques/auto/README.md, "Measured, not
// trusted"): a calibration setting rendered on this light, camera and time at a small trial size,
// its visibility compared with a ray-traced reference made the same way. The calibration's
// neighbours rank the settings and predict their time; the trial says whether a setting's error
// really meets the budget on this frame, before a light runs it.
#pragma once
#include <cstdint>
#include <vector>

#include "auto/auto.h"

namespace shadowlab {

// The trial's frame: the frame's own size when it has at most kTrialPixels pixels, else the same
// aspect scaled down to that many (errors of v are per-pixel averages: a smaller frame of the same
// view measures nearly the same RMSE, and the reference's cost grows with the pixels).
constexpr int kTrialPixels = 256 * 256;
// The reference's rays per pixel: as the bench's and the calibration's (raytraced's default, M =
// 256 stratified rays; its noise stays under 0.002 RMSE on the scenes in assets/).
constexpr int kTrialRays = 256;
// Rounds of the side-by-side timing: each renders every setting within the budget once, timed.
constexpr int kTimedRounds = 3;
struct TrialSize {
    int width = 1, height = 1;
};
TrialSize trialSize(int width, int height);

struct TrialInputs {
    const Scene* scene = nullptr;
    std::vector<Light> lights;  // every light as rendered
    int light = 0;              // the one measured: the others light the scene but cast nothing
    Camera camera;
    int width = 0, height = 0;  // the frame's size (the trial's is trialSize of it)
    double time = 0.0;
};

// What one choice's trials cost and did (for --stats).
struct TrialLog {
    int width = 0, height = 0;
    int measured = 0;          // settings rendered by this choice (not found in the cache)
    int timed = 0;             // settings timed by this choice
    int reused = 0;            // settings whose error, or whose time in the same list, the cache already held
    bool referenceMade = false;  // the reference was rendered by this choice (else cached)
    double ms = 0.0;           // wall time of this choice's renders (reference included)
    nlohmann::json toJson() const;
};

// The error of `setting` on this light and frame. Needs a current GL context; restores the bound
// framebuffers, viewport and program. Results are cached by the scene's content, the lights, the
// camera, the trial size and the time (the last few frames' keys), so a budget moved or the same
// view asked again renders nothing.
MeasuredError measureSettingError(const TrialInputs& in, const CalibrationSetting& setting, TrialLog& log);
// shadow_ms of each setting at the trial size, timed side by side: kTimedRounds rounds, each
// rendering every setting once (forward, then backward; after a switch, one untimed frame first,
// since it allocates), each setting's fastest round taken. The trial's renderer runs without reuse
// and times on the CPU, as the bench. Timed one after another, each alone, the settings met
// different loads of a shared machine (on three-lights at 1024x768, a quiet run times hard at 30 ms
// and pvm at 47; on a loaded CI run, auto at error_budget 0.3 took what it took at 0.02, whose times
// it had cached). Cached per view by the list of settings, so a budget moved back times nothing.
std::vector<double> timeSettingsSideBySide(const TrialInputs& in, const std::vector<CalibrationSetting>& settings,
                                           TrialLog& log);
// Frees the trial's renderers (their GL textures and the scene's GPU copy); the measured errors stay
// cached. The choice calls it when it is done.
void releaseTrialRenderers();

}  // namespace shadowlab
