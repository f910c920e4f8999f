// `sssm`: separable soft shadow mapping (Buades, Gumbau and Chover 2015, all of it). The passes are
// the paper's steps (Table 1), so --stats times them as its Tables 2 and 3 do: DM (shadow_map),
// Step1 (hard shadow and horizontal blocker rows), Step2 (blocker average with alpha reuse,
// penumbra size, horizontal blur), Step3 (vertical blur with beta reuse).
#include <glm/gtc/matrix_access.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "hard/hard.h"
#include "pcss/pcss.h"

namespace shadowlab {

namespace {

// Uniforms every step reads: the shadow lookup, the light, the camera.
void setCommonUniforms(PassContext& ctx, const ShaderProgram& program, const Texture& map) {
    setShadowLookupUniforms(program, ctx.lightView(), map.width(), ctx.light());
    program.set("biasConstTexels", float(ctx.param("bias_const")));
    program.set("biasSlopeTexels", float(ctx.param("bias_slope")));
    program.set("lightWidthWorld", lightWidthWorld(ctx.light()));
    program.set("lightNearZ", ctx.lightView().nearZ);
    const Camera& camera = ctx.camera();
    float aspect = float(ctx.width()) / float(ctx.height());
    glm::mat4 viewFromWorld = camera.viewFromWorld();
    program.set("cameraViewFromWorld", viewFromWorld);
    program.set("cameraWorldFromView", glm::inverse(viewFromWorld));
    program.set("cameraTanHalfFovY", std::tan(glm::radians(camera.fovYDegrees) * 0.5f));
    program.set("cameraAspect", aspect);
    program.set("viewportSize", glm::vec2(ctx.width(), ctx.height()));
    const LightView& light = ctx.lightView();
    glm::mat4 lightViewFromCameraView = light.viewFromWorld * glm::inverse(viewFromWorld);
    program.set("lightClipFromCameraView", light.clipFromView * lightViewFromCameraView);
    program.set("lightDepthFromCameraView", -glm::row(lightViewFromCameraView, 2));
    ctx.bindGBuffer(program);  // units 0-2
    glBindTextureUnit(3, map.id());
    program.set("shadowMap", 3);
}

int filterKind(PassContext& ctx) { return ctx.paramChoice("filter") == "mean" ? 1 : 0; }

void setBlurUniforms(PassContext& ctx, const ShaderProgram& program) {
    program.set("beta", float(ctx.param("beta")));
    program.set("filterKind", filterKind(ctx));
    program.set("sigma", float(ctx.param("sigma")));
}

// The framebuffer of a full-screen draw into the textures it names (rebuilt when the pool
// reallocates them).
class Targets {
public:
    // Colour targets `names`, and the stencil marks of sssm_mask (pcss.h) as depth-stencil.
    void bind(PassContext& ctx, const std::vector<std::string>& names) {
        std::vector<const Texture*> targets;
        for (const std::string& n : names) targets.push_back(&ctx.texture(n));
        fbo_ = &cache_.get(targets, &ctx.texture("sssm_mask"));
        fbo_->bind(ctx.width(), ctx.height());
    }
    void clearStencil() { glClearNamedFramebufferfi(fbo_->id(), GL_DEPTH_STENCIL, 0, 1.0f, 0); }
    // Clears draw buffer `index` to `value`: what the pixels a shader discards keep.
    void clear(int index, glm::vec4 value) { glClearNamedFramebufferfv(fbo_->id(), GL_COLOR, index, &value.x); }

private:
    FramebufferCache cache_;
    const Framebuffer* fbo_ = nullptr;  // the cache's, as the last bind left it
};

// Step 1: hard shadows and horizontal blocker rows (partial_blocker_sum, partial_blocker_count).
class Step1Pass : public Pass {
public:
    void execute(PassContext& ctx) override {
        const ShaderProgram& program = ctx.programs().get("common/fullscreen.vert", "sssm/step1.frag");
        program.use();
        setCommonUniforms(ctx, program, ctx.texture(shadowTestMap(ctx)));
        program.set("blockerKernel", float(ctx.paramInt("blocker_kernel")));
        targets_.bind(ctx, {"hard_shadow", "blocker_rows"});
        targets_.clear(0, glm::vec4(1.0f, -1.0f, 0.0f, 0.0f));    // background: lit, no camera depth
        targets_.clear(1, glm::vec4(-1e30f, 0.0f, 0.0f, 0.0f));   // no receiver
        targets_.clearStencil();
        drawStencilMarks(ctx, -1);  // 1: geometry
        program.use();
        beginStencilTest(1);
        drawFullscreenTriangle();
        endStencilTest();
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }

private:
    Targets targets_;
};

// Step 2: blocker average (alpha reuse) and eq. 1 for every pixel; then, in a second draw over the
// pixels with a penumbra only, the kernel size and the horizontal blur.
class Step2Pass : public Pass {
public:
    void execute(PassContext& ctx) override {
        // Marks back to 1 on geometry first: when only alpha, beta or the filter changed, the pass
        // graph runs step 2 without step 1, and the mask still holds the last run's 2s.
        averageTargets_.bind(ctx, {"penumbra", "kernel_size", "horizontal_blur", "reuse_step2"});
        drawStencilMarks(ctx, -1);
        const Texture& map = ctx.texture(shadowTestMap(ctx));
        const ShaderProgram& average = ctx.programs().get("common/fullscreen.vert", "sssm/step2.frag");
        average.use();
        setCommonUniforms(ctx, average, map);
        const Camera& camera = ctx.camera();
        float aspect = float(ctx.width()) / float(ctx.height());
        average.set("cameraClipFromWorld", camera.clipFromView(aspect) * camera.viewFromWorld());
        glm::mat4 worldFromLight = glm::inverse(ctx.lightView().viewFromWorld);
        average.set("lightUpWorld", glm::normalize(glm::vec3(worldFromLight[1])));
        average.set("alpha", float(ctx.param("alpha")));
        glBindTextureUnit(4, ctx.texture("blocker_rows").id());
        average.set("blockerRows", 4);
        glBindTextureUnit(5, ctx.texture("hard_shadow").id());
        average.set("hardShadows", 5);
        averageTargets_.bind(ctx, {"penumbra", "kernel_size", "horizontal_blur", "reuse_step2"});
        averageTargets_.clear(0, glm::vec4(-1.0f, 0.0f, 0.0f, 0.0f));  // no blocker, no penumbra
        averageTargets_.clear(1, glm::vec4(1.0f));                       // kernel 1: none
        averageTargets_.clear(2, glm::vec4(1.0f));                       // lit
        averageTargets_.clear(3, glm::vec4(-1.0f));                      // no receiver
        beginStencilTest(1);
        drawFullscreenTriangle();
        endStencilTest();

        const ShaderProgram& blur = ctx.programs().get("common/fullscreen.vert", "sssm/step2_blur.frag");
        blur.use();
        setCommonUniforms(ctx, blur, map);
        setBlurUniforms(ctx, blur);
        blur.set("filterKernel", float(ctx.paramInt("filter_kernel")));
        glBindTextureUnit(4, ctx.texture("penumbra").id());
        blur.set("penumbras", 4);
        glBindTextureUnit(5, ctx.texture("hard_shadow").id());
        blur.set("hardShadows", 5);
        blurTargets_.bind(ctx, {"kernel_size", "horizontal_blur"});
        glBindTextureUnit(4, ctx.texture("penumbra").id());
        drawStencilMarks(ctx, 1, 1, 0.0f);  // 2: a penumbra (w_penumbra > 0)
        blur.use();
        beginStencilTest(2);
        drawFullscreenTriangle();
        endStencilTest();
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }

private:
    Targets averageTargets_, blurTargets_;
};

// Step 3: vertical blur (beta reuse): the visibility. A first draw gives every pixel its hard
// shadow; the second overwrites the pixels with a penumbra.
class Step3Pass : public Pass {
public:
    void execute(PassContext& ctx) override {
        targets_.bind(ctx, {"visibility", "reuse_step3"});
        const ShaderProgram& keep = ctx.programs().get("common/fullscreen.vert", "sssm/keep_hard.frag");
        keep.use();
        ctx.bindGBuffer(keep);  // units 0-2
        setLightFrontUniforms(keep, ctx.light());
        glBindTextureUnit(4, ctx.texture("hard_shadow").id());
        keep.set("hardShadows", 4);
        drawFullscreenTriangle();

        const ShaderProgram& program = ctx.programs().get("common/fullscreen.vert", "sssm/step3.frag");
        program.use();
        setCommonUniforms(ctx, program, ctx.texture(shadowTestMap(ctx)));
        setBlurUniforms(ctx, program);
        setLightFrontUniforms(program, ctx.light());
        program.set("hardShadows", 4);
        glBindTextureUnit(5, ctx.texture("penumbra").id());
        program.set("penumbras", 5);
        glBindTextureUnit(6, ctx.texture("horizontal_blur").id());
        program.set("horizontals", 6);
        glBindTextureUnit(7, ctx.texture("kernel_size").id());
        program.set("kernels", 7);
        beginStencilTest(2);
        drawFullscreenTriangle();
        endStencilTest();
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }

private:
    Targets targets_;
};

InternalDesc imageInternal(const std::string& name, const std::string& resource, std::vector<std::string> channels,
                           const std::string& doc) {
    InternalDesc i;
    i.name = name;
    i.kind = InternalDesc::Kind::Image;
    i.resource = resource;
    i.channels = std::move(channels);
    i.doc = doc;
    return i;
}

}  // namespace

namespace {
// SSSM's capped kernel: step 2's screen-space kernel m (pixels), per axis.
KernelCapDesc sssmFilterKernelCap() {
    KernelCapDesc k;
    k.name = "filter_kernel";
    k.doc = "penumbra pixels (step 2's w_penumbra > 0, the pixels step 3 filters); clamped when the kernel reached "
            "m = filter_kernel pixels along x or y";
    k.reads = {"penumbra", "kernel_size", "param:filter_kernel"};
    k.count = [](PassContext& ctx) {
        KernelCapCount c;
        c.cap = std::max(double(ctx.paramInt("filter_kernel")), 1.0);
        const Image p = readTexture(ctx.texture("penumbra"), 2);
        const Image k = readTexture(ctx.texture("kernel_size"), 2);
        for (size_t i = 0; i < p.pixelCount(); ++i) {
            if (!(p.data[i * 2 + 1] > 0.0f)) continue;
            const double kernel = std::max(k.data[i * 2], k.data[i * 2 + 1]);
            c.add(kernel, kernel >= c.cap * (1.0 - 1e-6));
        }
        return c;
    };
    return k;
}
}  // namespace

const TechniqueDesc& sssmTechnique() {
    static const TechniqueDesc desc = [] {
        TechniqueDesc d;
        d.id = "sssm";
        d.name = "Separable soft shadow mapping";
        d.citation = "Buades, Gumbau, Chover 2015, Separable soft shadow mapping (The Visual Computer), sec. 3-4, "
                     "Table 1, eq. 1";
        d.summary = "PCSS made separable: horizontal blocker rows reused vertically when their light depth is within "
                    "alpha, then a screen-space horizontal and vertical blur of the hard shadows whose rows are reused "
                    "when their camera depth is within beta";
        d.soft = true;
        using T = ParamDesc::Type;
        d.params = filteringShadowMapParams();
        d.params.push_back(blockerKernelParam());
        ParamDesc m = filterKernelParam("pixels");
        // The blur is in screen pixels, so the penumbra it must span grows with the image: at 512 x 512
        // square-occluder's is 95 px, plant's 68, sphere-light's 81 (kernel_caps' `largest`), which the
        // paper's 41 clamped (100%, 44%, 25% of their penumbra pixels). The default is the largest m
        // the blur's 128-bit set of shadow-map taps holds (sssm_blur.glsl), 127: the loops run to each
        // pixel's own kernel, so m costs only where a penumbra is that wide.
        m.defaultValue = 127;
        m.doc = "largest screen-space blur width m; each pixel blurs over its eq. 1 penumbra measured on its tangent "
                "plane, up to m (buades2015 uses 15, 21, 41; 127, the most the blur holds, by default: screen penumbrae grow with the image); wider penumbrae are clamped (kernel_caps in --stats)";
        d.params.push_back(m);
        d.params.push_back({"alpha", "alpha", T::Float, "world units", 0.10, 0.0, 100.0, 0.01,
                            "step-2 reuse threshold: a horizontal blocker row is reused when |d - d_t| < alpha (light "
                            "depths); 0.10 is buades2015's recommended value (Table 4), 0 reuses nothing",
                            ""});
        d.params.push_back({"beta", "beta", T::Float, "world units", 0.10, 0.0, 100.0, 0.01,
                            "step-3 reuse threshold: a horizontal blur row is reused when its camera depth is within beta "
                            "of this pixel's tangent plane; 0.10 as buades2015 (Table 4), 0 reuses nothing",
                            ""});
        ParamDesc filter{"filter", "", T::Enum, "", 0, 0, 1, 1,
                         "separable blur weights (buades2015 sec. 4.4): gaussian emulates a round light without the "
                         "screen-aligned squares of the mean (Fig. 5)",
                         ""};
        filter.choices = {"gaussian", "mean"};
        d.params.push_back(filter);
        d.params.push_back({"sigma", "sigma", T::Float, "kernel half-widths", 0.5, 0.05, 10.0, 0.05,
                            "standard deviation of the Gaussian over the kernel's half-width: the paper's N(0, 0.5) "
                            "(Fig. 1 caption)",
                            "filter == gaussian"});

        std::vector<std::string> common = {"gbuffer", "camera", "light", "param:bias_const", "param:bias_slope"};
        for (const std::string& r : shadowTestReads()) common.push_back(r);

        PassDesc step1;
        step1.name = "step1";
        step1.doc = "Step1 of Table 1: hard shadow per pixel and horizontal blocker rows (n x 1 texels)";
        step1.reads = common;
        step1.reads.push_back("param:blocker_kernel");
        step1.creates = {
            ResourceDesc::texture("hard_shadow", Format::RG32F, SizeRule::frame(),
                                  "hard shadow of each pixel (HardShadowMap) and its camera depth (-1: background)"),
            ResourceDesc::texture("blocker_rows", Format::RGBA32F, SizeRule::frame(),
                                  "horizontal blocker info: light depth d, partial_blocker_sum, partial_blocker_count, "
                                  "search width n (texels)"),
            markResource("sssm_mask", "stencil marks: 1 geometry, 2 with a penumbra (the pixels each draw shades)")};
        step1.soft = true;
        step1.create = [] { return std::make_unique<Step1Pass>(); };

        PassDesc step2;
        step2.name = "step2";
        step2.doc = "Step2 of Table 1: blocker average reusing rows within alpha, penumbra size (eq. 1), horizontal blur";
        step2.reads = common;
        for (const char* r : {"param:alpha", "param:beta", "param:filter_kernel", "param:filter", "param:sigma",
                              "hard_shadow", "blocker_rows"})
            step2.reads.push_back(r);
        step2.creates = {
            ResourceDesc::texture("penumbra", Format::RG32F, SizeRule::frame(),
                                  "average blocker depth z_avg (-1: none) and eq. 1 penumbra width (world)"),
            ResourceDesc::texture("kernel_size", Format::RG32F, SizeRule::frame(),
                                  "screen-space blur kernel width in x and y (pixels; 1 = no penumbra)"),
            ResourceDesc::texture("horizontal_blur", Format::R32F, SizeRule::frame(),
                                  "hard shadows blurred horizontally (partial_soft_shadow)"),
            ResourceDesc::texture("reuse_step2", Format::R32F, SizeRule::frame(),
                                  "fraction of blocker rows reused from step 1 (-1: no receiver)")};
        step2.modifies = {"sssm_mask"};
        step2.soft = true;
        step2.create = [] { return std::make_unique<Step2Pass>(); };

        PassDesc step3;
        step3.name = "step3";
        step3.doc = "Step3 of Table 1: vertical blur reusing horizontal rows within beta (normal-adjusted)";
        step3.reads = common;
        for (const char* r : {"param:beta", "param:filter", "param:sigma", "hard_shadow", "penumbra", "kernel_size",
                              "horizontal_blur", "sssm_mask"})
            step3.reads.push_back(r);
        step3.creates = {visibilityResource(),
                         ResourceDesc::texture("reuse_step3", Format::R32F, SizeRule::frame(),
                                               "fraction of blur rows reused from step 2 (-1: not filtered)")};
        step3.soft = true;
        step3.create = [] { return std::make_unique<Step3Pass>(); };
        d.passes = {shadowMapPass(), step1, step2, step3};
        d.kernelCaps = {sssmFilterKernelCap()};

        d.internals = shadowMapInternals();
        d.internals.push_back(imageInternal("hard_shadow", "hard_shadow", {"visibility", "camera_depth"},
                                            "hard shadow buffer of step 1 (0 shadowed, 1 lit) with the camera "
                                            "depth the beta test reads (-1: background)"));
        d.internals.push_back(imageInternal("blocker_rows", "blocker_rows",
                                            {"light_depth", "partial_sum", "partial_count", "search_width"},
                                            "step 1's horizontal blocker buffer; search_width is the blocker-search "
                                            "width n per pixel (texels)"));
        d.internals.push_back(imageInternal("penumbra", "penumbra", {"avg_blocker_depth", "penumbra_width"},
                                            "step 2: average blocker depth (-1: none) and eq. 1 penumbra width (world)"));
        d.internals.push_back(imageInternal("kernel_size", "kernel_size", {"kernel_x", "kernel_y"},
                                            "step 2: the screen-space kernel size per pixel (pixels; 1 = no penumbra)"));
        d.internals.push_back(imageInternal("horizontal_blur", "horizontal_blur", {"visibility"},
                                            "step 2's horizontal buffer: hard shadows blurred along x"));
        d.internals.push_back(imageInternal("reuse_step2", "reuse_step2", {"fraction"},
                                            "reuse map of step 2 (buades2015 Fig. 10): share of blocker rows taken "
                                            "from step 1 (1 = all, 0 = none, -1 = no receiver)"));
        d.internals.push_back(imageInternal("reuse_step3", "reuse_step3", {"fraction"},
                                            "reuse map of step 3: share of blur rows taken from step 2 (-1 = no "
                                            "penumbra, hard shadow kept)"));
        d.internals.push_back(shadowMapPixelRecord());
        return d;
    }();
    return desc;
}

}  // namespace shadowlab
