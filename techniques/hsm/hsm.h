// The part of soft shadow mapping by back-projection that `ssm-gbp06` and `ssm-contour` share
// (guennebaud2007 section 3, after GBP06): the hierarchical shadow map (HSM, a min/max depth
// pyramid of the shadow map), the kernel size per pixel (eq. 1, then iterative refinement) and the
// lit / umbra / penumbra classification; and the CPU mirror of all of it that the per-pixel records
// (--pixel) run on the same shared functions as the shaders (shaders/shared/backprojection.glsl).
#pragma once
#include <functional>
#include <nlohmann/json.hpp>

#include "shared/shared.h"
#include "visibility/shadow_map.h"

namespace shadowlab {

// Parameters both techniques add to shadowMapParams(): `max_kernel`.
std::vector<ParamDesc> backprojectionParams();

// Pass "hsm": creates the RG32F pyramid "hsm" from the shadow map, on the GPU: HSM levels 1, 2, ...
// down to 1x1 as its mip levels 0, 1, ... (HSM level 0 is the shadow map itself).
PassDesc hsmPass();
// Pass "kernel": creates "kernel_size", "kernel_iterations" and "classification" (frame size).
PassDesc kernelPass();
// Internals of both: the shadow map, every HSM level (min, max), kernel size, iterations, classes.
std::vector<InternalDesc> backprojectionInternals();
// The visibility pass's second output where light_multires is on, and its internal.
ResourceDesc lightLevelsResource();
InternalDesc lightLevelsInternal();
// What a visibility pass of either technique reads besides its own parameters, and what it
// modifies: the sparse v-buffer where screen_adaptive is on.
std::vector<std::string> backprojectionVisibilityReads();
std::vector<std::string> backprojectionVisibilityModifies();

// The screen-space multi-resolution (guennebaud2007 sec. 5.2 and 6), where `screen_adaptive` is on
// (every pass does nothing where it is off):
//  - "discontinuities": the discontinuity buffer (thresholded Sobel on camera depth and normals,
//    widened past the pattern's largest pixel spacing), where `discontinuities` is on too;
//  - "selection": per pixel the code (screen_selection.glsl) and the sparse v-buffer (v, w);
//  - "pack": the block classification (whole, compacted, skipped) and the compacted pixel list;
//  - then the technique's visibility pass evaluates the listed pixels into the sparse v-buffer;
//  - "pull_push": the pull-push reconstruction of the sparse v-buffer into "visibility".
std::vector<PassDesc> screenSelectionPasses();
PassDesc screenPullPushPass();
std::vector<InternalDesc> screenAdaptiveInternals();
// `--stats` counter "screen_selection": pixels evaluated and skipped, blocks by class.
CounterDesc screenSelectionCounter();

// The shared light-shape code of the shaders (BP_LIGHT_SQUARE, BP_LIGHT_DISK for disk and sphere)
// and the unit of light coordinates (w_l / 2, or the radius).
int bpLightShape(const Light& light);
float bpLightHalfSize(const Light& light);
// Uniforms of shaders/backprojection/receiver.glsl, and the G-buffer on units 0-2.
void setReceiverUniforms(PassContext& ctx, const ShaderProgram& program, int smSize);

// The visibility pass of both techniques over the receiver, the shadow map, the kernel and the
// classification: with screen_adaptive off a full-screen `shader` (backprojection/gbp06.frag or
// contour.frag) writing "visibility"; with it on the compute `sparseShader` (gbp06_sparse.comp,
// contour_sparse.comp) over the whole blocks and the compacted pixels of "pack", writing the sparse
// v-buffer. `extra` sets a technique's own uniforms (contour's t).
class BackprojectionVisibilityPass : public Pass {
public:
    using Uniforms = std::function<void(PassContext&, const ShaderProgram&)>;
    BackprojectionVisibilityPass(std::string shader, std::string sparseShader, Uniforms extra = {})
        : shader_(std::move(shader)), sparseShader_(std::move(sparseShader)), extra_(std::move(extra)) {}
    void execute(PassContext& ctx) override;

private:
    void setUniforms(PassContext& ctx, const ShaderProgram& program);
    void executeSparse(PassContext& ctx);
    std::string shader_, sparseShader_;
    Uniforms extra_;
    FramebufferCache fbo_;
};

// ---- the CPU mirror (per-pixel records) ----------------------------------------------------------

// The GPU resources a record needs, read back once: the depth map and every HSM level, plus the
// light and parameters, so the shared functions can run on the CPU.
struct BackprojectionCpu {
    int size = 0;  // r
    int topLevel = 0;
    LightView view;
    glm::vec3 lightPosition{0.0f};
    int shape = shared::BP_LIGHT_SQUARE;
    float lightWidth = 0.0f;     // bounding width in world units (eq. 1's w_l)
    float lightHalfSize = 0.0f;  // unit of light coordinates
    float biasConst = 0.0f, biasSlope = 0.0f, maxKernel = 0.0f;
    std::vector<Image> hsm;  // HSM level k + 1: RG, row 0 at the top (readTextureLevel); level 0 is `depth`
    Image depth;             // the shadow map the depth tests read, row 0 at the top

    static BackprojectionCpu read(PassContext& ctx);
    // Texel (x, y) counted from the bottom, as texelFetch: the no-caster marker outside the map.
    float depthAt(glm::ivec2 t) const;
    glm::vec2 hsmAt(int level, glm::ivec2 t) const;  // HSM level `level` (0: the map, min = max)
    int levelSize(int level) const;
    shared::BpReceiver receiver(const glm::vec3& worldPosition, const glm::vec3& worldNormal) const;
    bool occludes(const shared::BpReceiver& r, glm::ivec2 t, float z) const;
    // The light-space multi-resolution's access (sec. 5.1; visibility_common.glsl): the min depth of
    // level `level` at its texel t (no caster outside it), its occlusion test, and level
    // coordinates u at depth z back-projected onto the light.
    float levelDepth(int level, glm::ivec2 t) const;
    bool levelOccludes(const shared::BpReceiver& r, int level, glm::ivec2 t, float z) const;
    glm::vec2 backprojectLevel(const shared::BpReceiver& r, glm::vec2 u, int level, float z) const;
};

// One refinement step of the kernel: the HSM level read, its texels (x0, y0, x1, y1) and their
// (min, max) depth, and the kernel width that step's min gave.
struct KernelStep {
    int level = 0;
    glm::ivec4 texels{0};
    glm::vec2 bounds{0.0f};
    float refinedTexels = 0.0f;
};
struct KernelResult {
    float texels = 0.0f;  // converged w_k (what kernel.frag writes)
    int iterations = 0;
    float classification = shared::BP_CLASS_LIT;
    float globalMin = 0.0f;  // the top level's min (first estimate)
    float occluderDepth = 0.0f;  // z_occ (sec. 5.1), 0 when lit
    int hintLevel = 0;           // the level z_occ was read at (the last refinement step's)
    std::vector<KernelStep> steps;
};
// The same steps as shaders/backprojection/kernel.frag.
KernelResult computeKernel(const BackprojectionCpu& cpu, const shared::BpReceiver& r);

// The start of both techniques' per-pixel records: the receiver, the kernel with its refinement
// steps, the classification and the light. `done` is true when nothing more is integrated
// (background, outside the light's frustum, lit or umbra); then `record` is complete apart from
// the technique's list and the totals finishRecord() adds.
struct PixelRecordStart {
    bool done = false;
    nlohmann::json record;
    BackprojectionCpu cpu;
    shared::BpReceiver receiver{};
    KernelResult kernel;
    glm::ivec4 range{0};  // level-0 texels the visibility loop walks (kernel clamped by max_kernel)
    float initialArea = 0.0f;
    float front = 1.0f;  // fraction of the light in front of the receiver's tangent plane
    // The light-space multi-resolution (sec. 5.1, visibility_levels.glsl): the level walked, the
    // other level blended in and its weight (0: none); all 0 when light_multires is off.
    int level = 0, blendLevel = 0;
    float blendWeight = 0.0f;
};
// `beta` is the blending band of ssm-contour (eq. 3 and the pseudo-code); a negative beta picks
// GBP06's level of eq. 2 without blending.
PixelRecordStart startPixelRecord(PassContext& ctx, glm::ivec2 pixel, float beta);
// The occluded area of the level blended in (initial area and the items' sum), when there is one.
struct BlendedLevelArea {
    float initialArea = 0.0f, itemsArea = 0.0f;
};
// Adds "initial_area", "occluded_area" = initial + sum of the items' areas (the level walked),
// "front_fraction", "visibility_recomputed" (the back-projected visibility, blended with the other
// level's when there is one, times front_fraction, as the shader) and the image's "visibility".
void finishPixelRecord(PassContext& ctx, glm::ivec2 pixel, PixelRecordStart& start, float itemsArea,
                       const BlendedLevelArea* blended = nullptr);
// The levels of visibility_levels.glsl's chooseLevels: (lod, other, weight), and lambda (eq. 3;
// for GBP06, eq. 2's level) through `lambda`.
glm::vec3 chooseLightLevels(const BackprojectionCpu& c, const shared::BpReceiver& r, float w, float zOcc, float tk,
                            float beta, float* lambda);
// The record's fields shared by both techniques (each adds its list: "samples" or "edges").
std::vector<std::pair<std::string, std::string>> backprojectionRecordSchema();
// The capped kernel of both back-projection techniques: w_k against max_kernel.
KernelCapDesc backprojectionKernelCap();
// The resources a record reads.
std::vector<std::string> backprojectionRecordReads();

}  // namespace shadowlab
