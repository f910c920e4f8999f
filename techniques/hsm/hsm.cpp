// The HSM, the kernel and the classification of guennebaud2007 section 3, shared by ssm-gbp06 and
// ssm-contour, and their CPU mirror for the per-pixel records.
#include "hsm/hsm.h"

#include <cfloat>
#include <cmath>

#include "error.h"

namespace shadowlab {

using namespace shared;

namespace {

constexpr float kNoCaster = FLT_MAX;  // shadow_map.cpp's "no caster" marker (kernel.frag: 3.4e38)

// guennebaud2007 sec. 3: "a hierarchical version of the shadow map (HSM) is built from high to low
// resolution in a similar fashion to mipmapped textures. Each pixel stores both the minimum and
// maximum covered depth values." HSM level 0 is the map itself; the pyramid texture holds levels 1,
// 2, ... as its mip levels 0, 1, ...; one dispatch per level.
class HsmPass : public Pass {
public:
    void execute(PassContext& ctx) override {
        Texture& hsm = ctx.texture("hsm");
        const Texture& map = ctx.texture(shadowTestMap(ctx));
        const ShaderProgram& first = ctx.programs().compute("backprojection/hsm.comp", {"FIRST_LEVEL"});
        glBindTextureUnit(0, map.id());
        first.set("shadowMap", 0);
        bindImage(1, hsm, 0, GL_WRITE_ONLY);  // HSM level 1
        first.dispatch(GLuint((hsm.width() + 7) / 8), GLuint((hsm.height() + 7) / 8));
        memoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        const ShaderProgram& reduce = ctx.programs().compute("backprojection/hsm.comp");
        for (int k = 1; k < hsm.levels(); ++k) {
            bindImage(0, hsm, k - 1, GL_READ_ONLY);
            bindImage(1, hsm, k, GL_WRITE_ONLY);
            reduce.dispatch(GLuint((hsm.width(k) + 7) / 8), GLuint((hsm.height(k) + 7) / 8));
            memoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);  // level k is the next dispatch's source
        }
        memoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    }
};

// Kernel size (eq. 1 and refinement) and classification per pixel: shaders/backprojection/kernel.frag.
class KernelPass : public Pass {
public:
    void execute(PassContext& ctx) override {
        Texture& size = ctx.texture("kernel_size");
        Texture& iterations = ctx.texture("kernel_iterations");
        Texture& classes = ctx.texture("classification");
        Texture& occluder = ctx.texture("occluder_depth");
        if (fboTexture_ != size.id()) {
            fbo_ = Framebuffer({&size, &iterations, &classes, &occluder}, nullptr);
            fboTexture_ = size.id();
        }
        const ShaderProgram& program = ctx.programs().get("common/fullscreen.vert", "backprojection/kernel.frag");
        program.use();
        const Texture& hsm = ctx.texture("hsm");
        const Texture& map = ctx.texture(shadowTestMap(ctx));
        setReceiverUniforms(ctx, program, map.width());
        glBindTextureUnit(3, hsm.id());
        program.set("hsm", 3);
        glBindTextureUnit(4, map.id());
        program.set("shadowMap", 4);
        program.set("hsmTopLevel", hsm.levels());
        program.set("lightWidthWorld", bpLightWidth(bpLightShape(ctx.light()), ctx.light().size));
        fbo_.bind(ctx.width(), ctx.height());
        drawFullscreenTriangle();
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }

private:
    Framebuffer fbo_;
    GLuint fboTexture_ = 0;
};

}  // namespace

std::vector<ParamDesc> backprojectionParams() {
    std::vector<ParamDesc> params = shadowMapParams();
    ParamDesc cap{"max_kernel", "", ParamDesc::Type::Int, "texels", 256, 4, 8192, 1,
                  "cap on the kernel width w_k the visibility loop walks (not the paper's: its sec. 5 bounds the cost "
                  "with coarser HSM levels); wider kernels are clamped and lose their outer occluders. The test scenes "
                  "reach w_k = 108 at most at sm_size 1024",
                  ""};
    params.push_back(cap);
    ParamDesc multires{"light_multires", "", ParamDesc::Type::Bool, "", 0.0, 0, 1, 1,
                       "light-space multi-resolution (guennebaud2007 sec. 5.1): walk the finest HSM level whose kernel "
                       "is at most t_k of its texels instead of the shadow map itself, so the cost no longer grows "
                       "with the penumbra (off by default until the lessons' and figures' expectations are re-measured "
                       "with it on: techniques/ssm-contour/README.md)", ""};
    params.push_back(multires);
    ParamDesc tk{"t_k", "t_k", ParamDesc::Type::Float, "texels", 16.0, 2.0, 256.0, 1.0,
                 "kernel threshold t_k of eq. 2: the largest kernel, in texels of the level walked (2 t_k at most "
                 "outside the blending band); 16 keeps ssm-contour within 0.002 RMSE of the full-resolution walk on "
                 "every scene in assets/ (techniques/ssm-contour/README.md)",
                 "light_multires == true"};
    params.push_back(tk);
    return params;
}

PassDesc hsmPass() {
    PassDesc p;
    p.name = "hsm";
    p.doc = "hierarchical shadow map: min and max depth pyramid, every level (guennebaud2007 sec. 3)";
    p.reads = shadowTestReads();
    ResourceDesc hsm = ResourceDesc::texture("hsm", Format::RG32F, SizeRule::like("shadow_map", 2),
                                             "HSM levels 1, 2, ... (level 0 is the shadow map): (min, max) light-view "
                                             "depth over the map texels each texel covers");
    hsm.kind = ResourceKind::Pyramid;
    hsm.levels = 0;
    p.creates = {hsm};
    p.state = PipelineState::fullscreen();
    p.soft = true;
    p.create = [] { return std::make_unique<HsmPass>(); };
    return p;
}

PassDesc kernelPass() {
    PassDesc p;
    p.name = "kernel";
    p.doc = "kernel width from the top-level min (eq. 1), refined level by level until it converges; lit / umbra / "
            "penumbra from the kernel's depth bounds (guennebaud2007 sec. 3)";
    p.reads = {"gbuffer", "light", "hsm", "param:bias_const", "param:bias_slope"};
    for (const std::string& r : shadowTestReads()) p.reads.push_back(r);
    p.creates = {
        ResourceDesc::texture("kernel_size", Format::R32F, SizeRule::frame(),
                              "converged kernel width w_k per pixel, texels (0 when the top level already says lit)"),
        ResourceDesc::texture("kernel_iterations", Format::R32F, SizeRule::frame(),
                              "refinement steps per pixel (HSM levels read after the first estimate)"),
        ResourceDesc::texture("classification", Format::R32F, SizeRule::frame(),
                              "0 umbra, 0.5 penumbra, 1 lit (from the kernel's HSM depth bounds)"),
        ResourceDesc::texture("occluder_depth", Format::R32F, SizeRule::frame(),
                              "z_occ (guennebaud2007 sec. 5.1): the occluding min depths of the refinement level's "
                              "four texels around p', bilinearly weighted; a smooth hint for the level (eq. 3) and "
                              "the penumbra size (eq. 4); 0 when lit"),
    };
    p.soft = true;
    p.create = [] { return std::make_unique<KernelPass>(); };
    return p;
}

std::vector<InternalDesc> backprojectionInternals() {
    std::vector<InternalDesc> out = shadowMapInternals();
    InternalDesc hsm;
    hsm.name = "hsm";
    hsm.kind = InternalDesc::Kind::Pyramid;
    hsm.resource = "hsm";
    hsm.channels = {"min", "max"};
    hsm.doc = "hierarchical shadow map levels 1, 2, ... (file level k is HSM level k + 1; HSM level 0 is "
              "shadow_map): min and max light-view depth per texel (inf = no caster)";
    hsm.convert = farMarkerToInfinity;
    out.push_back(hsm);
    out.push_back({"kernel_size", InternalDesc::Kind::Image, "kernel_size", {"texels"},
                   "converged kernel width w_k per pixel (guennebaud2007 eq. 1 and refinement), texels", "", {}, {}, {}, {}});
    out.push_back({"kernel_iterations", InternalDesc::Kind::Image, "kernel_iterations", {"steps"},
                   "kernel refinement steps per pixel", "", {}, {}, {}, {}});
    out.push_back({"classification", InternalDesc::Kind::Image, "classification", {"class"},
                   "0 umbra, 0.5 penumbra, 1 lit", "", {}, {}, {}, {}});
    out.push_back({"occluder_depth", InternalDesc::Kind::Image, "occluder_depth", {"z_occ"},
                   "smooth occluder depth z_occ per pixel (guennebaud2007 sec. 5.1), light-view depth; 0 when lit", "",
                   {}, {}, {}, {}});
    return out;
}

ResourceDesc lightLevelsResource() {
    ResourceDesc r = ResourceDesc::texture("light_levels", Format::RGBA32F, SizeRule::frame(),
                                           "light-space multi-resolution per pixel (guennebaud2007 sec. 5.1): lambda "
                                           "(eq. 3; ssm-gbp06: eq. 2's level), the HSM level walked, the level blended "
                                           "in and its weight; -1 on lit and umbra pixels");
    r.appliesWhen = "light_multires == true";
    return r;
}

InternalDesc lightLevelsInternal() {
    InternalDesc i{"light_levels", InternalDesc::Kind::Image, "light_levels", {"lambda", "level", "blend_level", "blend_weight"},
                   "lambda (eq. 3), the HSM level walked, the level blended in and its weight (sec. 5.1); -1 where "
                   "nothing was back-projected (lit, umbra)", "", {}, {}, {}, {}};
    i.appliesWhen = "light_multires == true";
    return i;
}

std::vector<std::string> backprojectionVisibilityReads() {
    std::vector<std::string> reads = {"gbuffer", "light", "hsm", "kernel_size", "classification", "occluder_depth",
                                      "param:bias_const", "param:bias_slope", "param:max_kernel",
                                      "param:light_multires", "param:t_k"};
    for (const std::string& r : shadowTestReads()) reads.push_back(r);
    return reads;
}

int bpLightShape(const Light& light) {
    return light.shape == LightShape::Square ? BP_LIGHT_SQUARE : BP_LIGHT_DISK;
}

float bpLightHalfSize(const Light& light) {
    return light.shape == LightShape::Square ? 0.5f * light.size : light.size;
}

void setReceiverUniforms(PassContext& ctx, const ShaderProgram& program, int smSize) {
    const LightView& view = ctx.lightView();
    program.set("lightViewFromWorld", view.viewFromWorld);
    program.set("lightClipFromView", view.clipFromView);
    program.set("lightTanHalfFov", view.tanHalfFov);
    program.set("shadowMapSize", float(smSize));
    program.set("lightPosition", ctx.light().position);
    program.set("biasConstTexels", float(ctx.param("bias_const")));
    program.set("biasSlopeTexels", float(ctx.param("bias_slope")));
    ctx.bindGBuffer(program);  // units 0-2
}

// ---- CPU mirror -----------------------------------------------------------------------------------------

BackprojectionCpu BackprojectionCpu::read(PassContext& ctx) {
    BackprojectionCpu c;
    const Texture& hsm = ctx.texture("hsm");
    c.size = ctx.texture(shadowTestMap(ctx)).width();
    c.topLevel = hsm.levels();
    c.view = ctx.lightView();
    c.lightPosition = ctx.light().position;
    c.shape = bpLightShape(ctx.light());
    c.lightWidth = bpLightWidth(c.shape, ctx.light().size);
    c.lightHalfSize = bpLightHalfSize(ctx.light());
    c.biasConst = float(ctx.param("bias_const"));
    c.biasSlope = float(ctx.param("bias_slope"));
    c.maxKernel = float(ctx.param("max_kernel"));
    for (int k = 0; k < hsm.levels(); ++k) {
        c.hsm.push_back(readTextureLevel(hsm, k));
        if (c.hsm.back().width != hsmLevelSize(k + 1, c.size))
            throw InternalError("hsm level " + std::to_string(k + 1) + " is " + std::to_string(c.hsm.back().width) +
                                " texels across, hsmLevelSize says " + std::to_string(hsmLevelSize(k + 1, c.size)));
    }
    c.depth = readTextureLevel(ctx.texture(shadowTestMap(ctx)), 0);
    return c;
}

float BackprojectionCpu::depthAt(glm::ivec2 t) const {
    if (t.x < 0 || t.y < 0 || t.x >= size || t.y >= size) return kNoCaster;
    return depth.at(t.x, size - 1 - t.y);
}

int BackprojectionCpu::levelSize(int level) const {
    return hsmLevelSize(level, size);
}

glm::vec2 BackprojectionCpu::hsmAt(int level, glm::ivec2 t) const {
    if (level == 0) return glm::vec2(depthAt(t));
    const Image& l = hsm[size_t(level - 1)];
    return {l.at(t.x, l.height - 1 - t.y, 0), l.at(t.x, l.height - 1 - t.y, 1)};
}

BpReceiver BackprojectionCpu::receiver(const glm::vec3& worldPosition, const glm::vec3& worldNormal) const {
    return bpReceiver(view.viewFromWorld, view.clipFromView, worldPosition, worldNormal, lightPosition, view.tanHalfFov,
                      float(size), biasConst, biasSlope);
}

bool BackprojectionCpu::occludes(const BpReceiver& r, glm::ivec2 t, float z) const {
    return bpSampleOccludes(r, glm::vec2(t) + 0.5f, z, float(size), view.tanHalfFov);
}

float BackprojectionCpu::levelDepth(int level, glm::ivec2 t) const {
    int n = levelSize(level);
    if (t.x < 0 || t.y < 0 || t.x >= n || t.y >= n) return kNoCaster;
    return hsmAt(level, t).x;
}

bool BackprojectionCpu::levelOccludes(const BpReceiver& r, int level, glm::ivec2 t, float z) const {
    return bpLevelSampleOccludes(r, level, t, z, float(size), view.tanHalfFov);
}

glm::vec2 BackprojectionCpu::backprojectLevel(const BpReceiver& r, glm::vec2 u, int level, float z) const {
    return backprojectToLight(r.position, u * float(1 << level), z, float(size), view.tanHalfFov, lightHalfSize);
}

KernelResult computeKernel(const BackprojectionCpu& c, const BpReceiver& r) {
    KernelResult k;
    const float smSize = float(c.size);
    const float zp = r.position.z;
    k.globalMin = c.hsmAt(c.topLevel, {0, 0}).x;
    if (k.globalMin >= zp - r.bias) return k;
    float w = std::min(hsmKernelTexels(c.lightWidth, smSize, c.view.tanHalfFov, k.globalMin, zp), 2.0f * smSize);
    glm::vec2 bounds(k.globalMin, 3.4e38f);
    float planeMin = 0.0f;
    int lastLevel = 0;
    for (int step = 0; step < 32; ++step) {  // kernel.frag's kMaxRefinements
        int level = hsmRefinementLevel(w, c.topLevel);
        lastLevel = level;
        int levelSize = c.levelSize(level);
        glm::ivec4 rangeL = levelTexelRange(kernelTexelRange(r.centre, w, c.size), level, levelSize);
        bounds = glm::vec2(3.4e38f, -3.4e38f);
        for (int y = rangeL.y; y <= rangeL.w; ++y)
            for (int x = rangeL.x; x <= rangeL.z; ++x) {
                glm::vec2 t = c.hsmAt(level, {x, y});
                bounds = glm::vec2(std::min(bounds.x, t.x), std::max(bounds.y, t.y));
            }
        planeMin = regionPlaneDepthMin(r, levelRegionTexels(rangeL, level, levelSize, c.size), smSize, c.view.tanHalfFov);
        k.iterations += 1;
        KernelStep s;
        s.level = level;
        s.texels = rangeL;
        s.bounds = bounds;
        if (bounds.x >= zp - r.bias) {
            s.refinedTexels = 0.0f;
            k.steps.push_back(s);
            break;
        }
        float refined = hsmKernelTexels(c.lightWidth, smSize, c.view.tanHalfFov, bounds.x, zp);
        s.refinedTexels = refined;
        k.steps.push_back(s);
        if (refined >= w) break;
        w = refined;
    }
    k.texels = w;
    k.classification = bpClassify(r, bounds, planeMin);
    if (k.classification == BP_CLASS_LIT) return k;
    // z_occ, as kernel.frag.
    glm::vec2 u = r.centre / float(1 << lastLevel) - 0.5f;
    glm::ivec2 i0 = glm::ivec2(glm::floor(u));
    glm::vec4 d(c.levelDepth(lastLevel, i0), c.levelDepth(lastLevel, i0 + glm::ivec2(1, 0)),
                c.levelDepth(lastLevel, i0 + glm::ivec2(1, 1)), c.levelDepth(lastLevel, i0 + glm::ivec2(0, 1)));
    k.occluderDepth = occluderDepthHint(d, u - glm::floor(u), zp - r.bias, bounds.x);
    k.hintLevel = lastLevel;
    return k;
}

namespace {
const char* className(float c) {
    return c == BP_CLASS_LIT ? "lit" : c == BP_CLASS_UMBRA ? "umbra" : "penumbra";
}
nlohmann::json finite(float v) { return std::isfinite(v) && std::abs(v) < 1e30f ? nlohmann::json(v) : nlohmann::json(nullptr); }
}  // namespace

glm::vec3 chooseLightLevels(const BackprojectionCpu& c, const BpReceiver& r, float w, float zOcc, float tk, float beta,
                            float* lambda) {
    if (beta < 0.0f) {
        int lod = lightLevelForKernel(w, tk, c.topLevel);
        if (lambda) *lambda = float(lod);
        return glm::vec3(float(lod), 0.0f, 0.0f);
    }
    float smoothKernel = hsmKernelTexels(c.lightWidth, float(c.size), c.view.tanHalfFov, zOcc, r.position.z);
    float l = lightLevelContinuous(smoothKernel, w, tk, beta, c.topLevel);
    if (lambda) *lambda = l;
    return lightLevelBlend(l, beta, c.topLevel);
}

PixelRecordStart startPixelRecord(PassContext& ctx, glm::ivec2 pixel, float beta) {
    PixelRecordStart s;
    nlohmann::json& j = s.record;
    int row = ctx.height() - 1 - pixel.y;
    glm::vec4 position(0.0f), normal(0.0f);
    resetPackState();  // into client memory (gl/texture.h)
    glGetTextureSubImage(ctx.gbuffer().position->id(), 0, pixel.x, row, 0, 1, 1, 1, GL_RGBA, GL_FLOAT, sizeof position,
                         &position);
    glGetTextureSubImage(ctx.gbuffer().normal->id(), 0, pixel.x, row, 0, 1, 1, 1, GL_RGBA, GL_FLOAT, sizeof normal, &normal);
    if (position.w == 0.0f) {
        j["background"] = true;
        s.done = true;
        return s;
    }
    s.cpu = BackprojectionCpu::read(ctx);
    const BackprojectionCpu& c = s.cpu;
    const Light& light = ctx.light();
    s.front = lightFractionInFront(light.isPoint() ? LIGHT_SHAPE_POINT : int(light.shape), light.position,
                                   light.isPoint() ? glm::vec3(0.0f) : light.right(), light.up,
                                   light.isPoint() ? 0.0f : light.size, glm::vec3(position), glm::vec3(normal));
    s.receiver = c.receiver(glm::vec3(position), glm::vec3(normal));
    const BpReceiver& r = s.receiver;
    j["light_geometry"] = {{"shape", c.shape == BP_LIGHT_SQUARE ? "square" : "disk"},
                           {"area", bpLightArea(c.shape)},
                           {"unit_world", c.lightHalfSize},
                           {"coordinates", c.shape == BP_LIGHT_SQUARE ? "the light square is [-1,1]^2 (unit w_l / 2) on its right, up axes"
                                                                      : "the light disk is the unit disk (unit: its radius) on its right, up axes"}};
    j["receiver"] = {{"light_frame", {r.position.x, r.position.y, r.position.z}},
                     {"shadow_map_texel", {r.centre.x, r.centre.y}},
                     {"bias", r.bias},
                     {"in_light_frustum", r.inside != 0.0f}};
    float lightArea = bpLightArea(c.shape);
    if (r.inside == 0.0f) {
        j["classification"] = "lit";
        j["kernel"] = nullptr;  // outside the light's frustum: lit, as for `hard`
        s.done = true;
        return s;
    }
    s.kernel = computeKernel(c, r);
    nlohmann::json steps = nlohmann::json::array();
    for (const KernelStep& k : s.kernel.steps)
        steps.push_back({{"level", k.level},
                         {"texels", {k.texels.x, k.texels.y, k.texels.z, k.texels.w}},
                         {"min", finite(k.bounds.x)},
                         {"max", finite(k.bounds.y)},
                         {"refined_texels", k.refinedTexels}});
    float used = std::min(s.kernel.texels, c.maxKernel);
    s.range = kernelTexelRange(r.centre, used, c.size);
    j["kernel"] = {{"global_min", finite(s.kernel.globalMin)},
                   {"occluder_depth", finite(s.kernel.occluderDepth)},
                   {"texels", s.kernel.texels},
                   {"used_texels", used},
                   {"iterations", s.kernel.iterations},
                   {"steps", steps},
                   {"texel_range", {s.range.x, s.range.y, s.range.z, s.range.w}}};
    j["classification"] = className(s.kernel.classification);
    j["light_levels"] = nullptr;  // filled below for penumbra pixels when light_multires is on
    if (s.kernel.classification == BP_CLASS_UMBRA) s.initialArea = lightArea;
    s.done = s.kernel.classification != BP_CLASS_PENUMBRA;
    if (!s.done && ctx.param("light_multires") != 0.0) {
        float tk = float(ctx.param("t_k")), lambda = 0.0f;
        glm::vec3 levels = chooseLightLevels(c, r, used, s.kernel.occluderDepth, tk, beta, &lambda);
        s.level = int(levels.x);
        s.blendLevel = int(levels.y);
        s.blendWeight = levels.z;
        j["light_levels"] = {{"t_k", tk},
                             {"lod_eq2", lightLevelForKernel(used, tk, c.topLevel)},
                             {"lambda", lambda},
                             {"level", s.level},
                             {"blend_level", s.blendLevel},
                             {"blend_weight", s.blendWeight},
                             {"level_texel_range", [&] {
                                  int n = c.levelSize(s.level);
                                  glm::ivec4 l = levelTexelRange(s.range, s.level, n);
                                  return nlohmann::json::array({l.x, l.y, l.z, l.w});
                              }()}};
    } else if (!s.done) {
        j["light_levels"] = nullptr;  // light_multires off: the map itself
    }
    return s;
}

void finishPixelRecord(PassContext& ctx, glm::ivec2 pixel, PixelRecordStart& s, float itemsArea,
                       const BlendedLevelArea* blended) {
    nlohmann::json& j = s.record;
    if (j.contains("background")) return;
    float occluded = s.initialArea + itemsArea;
    j["initial_area"] = s.initialArea;
    j["occluded_area"] = occluded;
    j["front_fraction"] = s.front;
    float v = bpVisibility(occluded, s.cpu.shape);
    j["blend_initial_area"] = nullptr;  // no level blended in
    j["blend_occluded_area"] = nullptr;
    if (blended && s.blendWeight > 0.0f) {
        float other = blended->initialArea + blended->itemsArea;
        j["blend_initial_area"] = blended->initialArea;
        j["blend_occluded_area"] = other;
        v = v + (bpVisibility(other, s.cpu.shape) - v) * s.blendWeight;  // GLSL mix
    }
    j["visibility_recomputed"] = v * s.front;
    j["visibility"] = ctx.pixelValue("visibility", pixel);
}

KernelCapDesc backprojectionKernelCap() {
    KernelCapDesc k;
    k.name = "max_kernel";
    k.doc = "penumbra pixels (the kernel pass's classification); clamped when the converged kernel w_k (eq. 1) "
            "was wider than max_kernel texels, so the visibility pass walked only max_kernel of it";
    k.reads = {"classification", "kernel_size", "param:max_kernel"};
    k.count = [](PassContext& ctx) {
        KernelCapCount c;
        c.cap = ctx.param("max_kernel");
        const Image cls = readTexture(ctx.texture("classification"), 1);
        const Image w = readTexture(ctx.texture("kernel_size"), 1);
        for (size_t i = 0; i < cls.pixelCount(); ++i) {
            if (cls.data[i] != BP_CLASS_PENUMBRA) continue;
            c.add(w.data[i], w.data[i] > c.cap);
        }
        return c;
    };
    return k;
}

std::vector<std::pair<std::string, std::string>> backprojectionRecordSchema() {
    return {{"background", "true when no geometry covers the pixel (then no other field)"},
            {"light_geometry", "shape, area (4 for the square, pi for the disk, in light coordinates), unit and axes"},
            {"receiver", "p in the light frame (x, y, depth z_p), p' in shadow-map texels, depth bias (world)"},
            {"kernel", "global_min (top HSM level), texels (converged w_k, eq. 1), used_texels (after max_kernel), "
                       "iterations, steps [{level, texels [x0,y0,x1,y1] of that level, min, max, refined_texels}], "
                       "texel_range (level-0 texels walked)"},
            {"classification", "lit, umbra or penumbra (from the kernel's depth bounds)"},
            {"light_levels", "light-space multi-resolution (sec. 5.1; null when light_multires is off): t_k, "
                             "lod_eq2 (eq. 2), lambda (eq. 3 from kernel.occluder_depth; GBP06: eq. 2's level), "
                             "level walked, blend_level and blend_weight (sec. 5.1's pseudo-code), "
                             "level_texel_range [x0,y0,x1,y1] of the level walked"},
            {"initial_area", "occluded area before the list: the full light for umbra (and, for ssm-contour, when "
                             "the contour inside test occludes the light centre), else 0"},
            {"occluded_area", "initial_area + the list's areas (the level walked)"},
            {"blend_initial_area", "when blend_weight > 0: the blended level's initial area"},
            {"blend_occluded_area", "when blend_weight > 0: the blended level's occluded area (its list is not "
                                    "recorded)"},
            {"front_fraction", "the fraction of the light in front of the receiver's tangent plane (the visibility "
                               "convention, shaders/shared/tangent_plane.glsl)"},
            {"visibility_recomputed", "clamp(1 - occluded_area / light area, 0, 1), mixed with the blended level's by "
                                      "blend_weight, x front_fraction, on the CPU"},
            {"visibility", "this light's visibility in the image (GPU)"}};
}

std::vector<std::string> backprojectionRecordReads() {
    std::vector<std::string> reads = {"gbuffer", "light", "hsm", "visibility", "param:bias_const", "param:bias_slope",
                                      "param:max_kernel", "param:light_multires", "param:t_k"};
    for (const std::string& r : shadowTestReads()) reads.push_back(r);
    return reads;
}

void BackprojectionVisibilityPass::execute(PassContext& ctx) {
    Texture& visibility = ctx.texture("visibility");
    // Two variants (visibility_common.glsl): the level arithmetic only where light_multires is on.
    const bool multires = ctx.param("light_multires") != 0.0;
    Texture* levels = multires ? &ctx.texture("light_levels") : nullptr;
    GLuint key = visibility.id() ^ (levels ? levels->id() << 16 : 0u);
    if (fboTexture_ != key) {
        if (levels) fbo_ = Framebuffer({&visibility, levels}, nullptr);
        else fbo_ = Framebuffer({&visibility}, nullptr);
        fboTexture_ = key;
    }
    std::vector<std::string> defines;
    if (multires) defines.push_back("LIGHT_MULTIRES");
    const ShaderProgram& program = ctx.programs().get("common/fullscreen.vert", shader_, defines);
    program.use();
    const Texture& map = ctx.texture(shadowTestMap(ctx));
    setReceiverUniforms(ctx, program, map.width());
    glBindTextureUnit(3, map.id());
    program.set("shadowMap", 3);
    glBindTextureUnit(4, ctx.texture("kernel_size").id());
    program.set("kernelSize", 4);
    glBindTextureUnit(5, ctx.texture("classification").id());
    program.set("classification", 5);
    const Texture& hsm = ctx.texture("hsm");
    glBindTextureUnit(6, hsm.id());
    program.set("hsm", 6);
    program.set("hsmTopLevel", hsm.levels());
    glBindTextureUnit(7, ctx.texture("occluder_depth").id());
    program.set("occluderDepth", 7);
    program.set("lightWidthWorld", bpLightWidth(bpLightShape(ctx.light()), ctx.light().size));
    program.set("kernelThreshold", float(ctx.param("t_k")));
    program.set("lightShape", bpLightShape(ctx.light()));
    program.set("lightHalfSize", bpLightHalfSize(ctx.light()));
    program.set("maxKernelTexels", float(ctx.param("max_kernel")));
    setLightFrontUniforms(program, ctx.light());
    if (extra_) extra_(ctx, program);
    fbo_.bind(ctx.width(), ctx.height());
    drawFullscreenTriangle();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

}  // namespace shadowlab
