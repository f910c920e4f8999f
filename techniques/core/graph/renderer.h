// The renderer core: the G-buffer, the per-light techniques and the pass graph that runs them
// (DESIGN.md section 3), with live state: every setter bumps exactly the versions it changes, so
// the next frame re-runs exactly the passes that read them.
#pragma once
#include <algorithm>
#include <glm/glm.hpp>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "gl/util.h"
#include "graph/frame.h"
#include "graph/frame_stats.h"
#include "graph/internals.h"
#include "graph/pass_graph.h"
#include "graph/technique.h"
#include "image/image.h"
#include "scene/scene.h"

namespace shadowlab {

constexpr double kSecondsPerFrame = 1.0 / 30.0;
constexpr int kMaxLights = 8;

struct RenderOptions {
    int width = 512;
    int height = 512;
    std::string technique;  // "" = each light's default technique (its "technique" field, else hard)
    std::vector<std::pair<std::string, std::string>> sets;  // --set key=value, validated
    std::optional<float> lightSize;  // --light-size
    bool cpuClock = true;            // time passes on the CPU around glFinish (llvmpipe)
    bool reuse = true;               // false: every needed pass runs every frame (for timing)
    // true: a technique switch keeps the resources of the techniques used before (the window's
    // drag renderer: switching back allocates nothing; on llvmpipe a frame's textures cost ~0.1 s).
    bool keepResources = false;
    // What a resize replaced, kept up to this many bytes for a return to its size (ResourcePool::
    // setSpareBytes): the window's renderers, whose size follows the layout and the drag's divisor.
    size_t spareBytes = 0;
    // A choosing technique (`auto`) may render trials when it chooses (setMeasureChoices).
    bool measureChoices = true;
};

class Renderer {
public:
    // Validates the options against the scene and the technique tables (InputError) and builds
    // the pass graph. Needs a current GL context.
    Renderer(const Scene& scene, const RenderOptions& options);
    ~Renderer();

    // Renders frame `frame` at t = frame / 30 s, running only what `requested` needs: "image",
    // "visibility", "gbuffer", or a light's resource ("L0/shadow_map", see internalRequests()).
    // Afterwards each light's technique's reactive rule (TechniqueDesc::adapt) may change a
    // parameter for the next frame.
    void renderFrame(int frame, const std::set<std::string>& requested);
    // The same frame in slices that fit `budgetMs` each (the window's frame budget, issue 18): one
    // call runs what fits and returns the estimated fraction done; the next call resumes (or starts
    // over what a changed input invalidated). Passes that write only frame-size textures (the
    // G-buffer, the techniques' screen passes, shading) run in bands of rows under a scissor, pass
    // after pass, so a pass reading its inputs at other pixels (a screen-space blur) sees them
    // whole; the others run whole. At 1 the outputs equal renderFrame's (test: RefineFrame.*).
    // Reuse stays on whatever RenderOptions::reuse says.
    double refineFrame(int frame, const std::set<std::string>& requested, double budgetMs);
    // Shades frame `frame`'s G-buffer with `visibility[i]` (R32F at the frame's size, one per light)
    // as light i's visibility in place of its technique's (a light that casts no shadow keeps 1):
    // the window's progressive ray tracer re-shades each batch of rays with the shade pass's own
    // math. Runs the G-buffer when stale; image() and visibility() then hold this shading, and the
    // next frame that needs them runs the shade pass again. Only rows [y0, y1) (GL's order, row 0
    // at the bottom; y1 < 0: to the top) are shaded, so a batch can be shaded in bands over frames.
    void shadeWith(int frame, const std::vector<const Texture*>& visibility, int y0 = 0, int y1 = -1);
    // The passes refineFrame runs in bands (their names in the graph).
    const std::set<std::string>& bandedPasses() const { return banded_; }
    // refineFrame's pieces: tiles of kTileColumns columns by two rows, tileColumns() of them a row.
    static constexpr int kTileColumns = 128;
    int tileColumns() const { return std::max(1, (frame_.width + kTileColumns - 1) / kTileColumns); }

    // ---- live state: each setter bumps exactly the versions it changes (checked by tests).
    // Technique of one light (or of every light: light = -1); its parameters start at their defaults.
    void setTechnique(const std::string& id, int light = -1);
    // TechniqueDesc::adapt of every light whose passes ran at `frame` (renderFrame calls it).
    void adaptParameters(int frame);
    // One parameter, validated against the technique's table (InputError naming `where`).
    void setParam(const std::string& key, const std::string& value, int light = -1,
                  const std::string& where = "setParam");
    void setLight(size_t index, const Light& light);  // pose, size, shape, colour, intensity
    void setCamera(const Camera& camera);
    void setAmbient(float ambient);
    void setTime(double seconds);  // the next renderFrame(frame) sets it from the frame again
    void resize(int width, int height);
    // Whether a choosing technique (`auto`) may render trials of its own when it chooses (default
    // on): the window turns it off while the user drags, and on again at rest (a re-choice).
    void setMeasureChoices(bool on);

    Image visibility() const;  // 1 channel, combined over the lights (see shaders/common/shade.frag)
    Image positions() const;   // 3 channels, NaN on background
    Image normals() const;     // 3 channels, NaN on background
    Image ids() const;         // 1 channel, -1 on background
    Image image() const;       // 3 channels, sRGB-encoded shaded image in [0,1]

    // Graph outputs the applicable internals of every light read (request them before writing).
    std::set<std::string> internalRequests(bool withPixelRecords) const;
    void writeInternals(InternalSink& out, std::optional<glm::ivec2> pixel);
    // frameMs: the frames as run; costFrom: the first frame whose pass times count for cost_ms.
    // (Defined in frame_stats.cpp.)
    // Reads back the kernel-cap resources (kernelCapReports), so it is not const.
    nlohmann::json stats(const std::vector<double>& frameMs, int warmupFrames, int costFrom = 1);
    // Every light's capped kernels after the last frame: how many pixels computed each and how
    // many were clamped (TechniqueDesc::kernelCaps). Reads textures back: call it after a frame,
    // not inside a timed loop.
    struct KernelCapReport {
        int light = 0;
        std::string technique, name;
        KernelCapCount count;
        double fraction() const { return count.pixels ? double(count.clamped) / double(count.pixels) : 0.0; }
    };
    std::vector<KernelCapReport> kernelCapReports();
    // shadow_ms / fixed_ms / per pass of the last request's needed passes (frame_stats.h).
    FrameCost cost(int costFrom = 1) const;
    // Passes needed by the last request with no run at a frame >= `frame` (their cost is unknown).
    bool costMeasuredSince(int frame) const;
    // Re-runs every pass the last request needed and returns the resources whose contents changed
    // although no declared input did (an undeclared read): empty when reuse is sound.
    std::vector<std::string> checkReuse();
    // Times every pass the last request needed, `frames` times, at frame numbers from `firstFrame`,
    // without changing what the graph reuses or its run counts (for cost_ms on a static scene).
    void measureCost(int firstFrame, int frames);
    // Forgets cached outputs: the next frame runs every needed pass.
    void invalidate() { graph_.invalidate(); }

    const PassGraph& graph() const { return graph_; }
    const ResourcePool& pool() const { return pool_; }
    ResourcePool& pool() { return pool_; }
    std::vector<const LightState*> lights() const;
    std::vector<Light> frameLights() const;  // every light as rendered, in order
    // Each light's technique and parameters (`hard` for a point light) as the constructor resolves
    // them, with no GL work: for checks made before there is a context (lesson --check's views).
    // Bad input is an InputError, as from the constructor.
    static std::vector<LightState> resolveLights(const Scene& scene, const RenderOptions& options);
    const Light& lightAt(size_t index) const { return lights_.at(index)->state.light; }
    const Camera& camera() const { return frame_.camera; }
    float ambient() const { return frame_.ambient; }
    const Texture& imageTexture() const;
    const char* clockName() const { return options_.cpuClock ? "cpu-finish" : "gpu-timer"; }
    double time() const { return frame_.time; }
    int width() const { return frame_.width; }
    int height() const { return frame_.height; }

private:
    struct LightSlot {
        LightState state;
        std::vector<std::unique_ptr<Pass>> passes;  // one per pass of state.desc
    };
    void configureLight(LightSlot& slot);  // picks what runs (hard for a point light) and its passes
    // Asks every light whose technique chooses (`auto`) again, and rebuilds the passes of those whose
    // pick changed (after a parameter, light, camera or size change).
    void rechoose();
    void buildGraph();
    void beginFrame(int frame, const std::set<std::string>& requested);  // time, sources, request
    void releaseUndeclaredResources();  // frees what no pass of the current graph creates
    void allocateFrameResources();
    void updateSources();
    void updateLightSources(LightSlot& slot);
    void runTechniquePass(LightSlot& slot, size_t pass);
    void shade(const std::vector<const Texture*>& visibility);  // the shade pass (null: visibility 1)
    // Allocates the pass's resources (at most `maxFresh` new textures; `more`: some are left).
    std::vector<const Texture*> ensurePassResources(LightSlot& slot, size_t pass, size_t maxFresh = ~size_t(0),
                                                    bool* more = nullptr);
    // refineFrame: a banded pass's resources allocated and cleared before its first band, one new
    // texture per call: -1 nothing to do, 0 allocated one and more are left, 1 allocated the last.
    int preparePass(const std::string& pass);
    std::map<std::string, std::pair<LightSlot*, size_t>> passSlots_;  // technique passes by graph name
    double timePass(const std::function<void()>& run);
    std::vector<size_t> lightIndices(int light) const;

    const Scene& scene_;
    RenderOptions options_;
    std::unique_ptr<GpuScene> gpu_;
    bool measureChoices_ = options_.measureChoices;
    ProgramCache& programs_ = programCache();  // the current GL context's: switching technique compiles nothing twice
    FrameState frame_;
    ResourcePool pool_;
    Texture white_;  // 1x1 visibility 1, for lights that cast no shadow
    Framebuffer gbufferFbo_, shadeFbo_;
    std::vector<std::unique_ptr<LightSlot>> lights_;
    std::map<std::string, int> adaptedRuns_;  // adaptParameters: by light group, its passes' runs when last adapted
    PassGraph graph_;
    std::set<std::string> lastRequested_;
    std::set<std::string> banded_;  // passes that write only frame-size textures (refineFrame)
    int frameIndex_ = 0;
    bool timeSet_ = false;
    GLuint timerQuery_ = 0;
};

}  // namespace shadowlab
