// `reference`: the papers' ground truth (guennebaud2007 sec. 7: the average of 1024 hard shadow
// maps rendered from points spread over the light; buades2015 sec. 5.3 uses 41 x 41 light sources).
// N stratified samples of the light (shaders/shared/light_sampling.glsl), one shadow map each, each
// pixel's hard visibility weighted by its sample's stratum area and summed with additive blending.
#include <chrono>
#include <cstdio>

#include "renderer.h"
#include "shadow_map.h"
#include "shared/shared.h"

namespace shadowlab {

namespace {

class ReferenceTechnique : public TechniqueInstance {
public:
    void run(const std::string&, RenderContext& ctx, LightState& light) override {
        if (!visibility_ || visibility_.width() != ctx.width || visibility_.height() != ctx.height) {
            visibility_ = Texture(ctx.width, ctx.height, GL_R32F);
            fbo_ = Framebuffer({&visibility_}, nullptr);
        }
        const float zero = 0.0f;
        glClearNamedFramebufferfv(fbo_.id(), GL_COLOR, 0, &zero);
        int samples = light.params.getInt("samples");
        int size = light.params.getInt("sm_size");
        bool secondDepth = light.params.getBool("second_depth");
        const Light& l = light.light;
        glm::vec3 right = l.right();
        auto start = std::chrono::steady_clock::now();
        int reported = 0;
        for (int s = 0; s < samples; ++s) {
            // Sample s of N: a jittered point in its stratum, weighted by the stratum's area.
            glm::vec3 sample = shared::stratifiedSample(uint32_t(s), uint32_t(samples), uint32_t(light.index + 1));
            glm::vec3 position = shared::lightSamplePosition(l.position, right, l.up, int(l.shape), l.size,
                                                             glm::vec2(sample.x, sample.y));
            LightView view = fitLightView(l, position, ctx.bounds);
            shadowMap_.render(ctx, view, size, secondDepth);

            const ShaderProgram& program = ctx.programs.get("common/fullscreen.vert", "reference/accumulate.frag");
            program.use();
            Light atSample = l;
            atSample.position = position;
            setShadowLookupUniforms(program, view, size, atSample);
            program.set("biasConstTexels", float(light.params.get("bias_const")));
            program.set("biasSlopeTexels", float(light.params.get("bias_slope")));
            program.set("sampleWeight", sample.z);
            glBindTextureUnit(0, ctx.gbuffer.position.id());
            glBindTextureUnit(1, ctx.gbuffer.normal.id());
            glBindTextureUnit(2, shadowMap_.depth().id());
            program.set("gPosition", 0);
            program.set("gNormal", 1);
            program.set("shadowMap", 2);
            fbo_.bind(ctx.width, ctx.height);
            glDisable(GL_DEPTH_TEST);
            glEnable(GL_BLEND);
            glBlendEquation(GL_FUNC_ADD);
            glBlendFunc(GL_ONE, GL_ONE);
            drawFullscreenTriangle();
            glDisable(GL_BLEND);
            glBindFramebuffer(GL_FRAMEBUFFER, 0);

            // Progress on stderr once a run takes more than two seconds.
            double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            int percent = (s + 1) * 100 / samples;
            if (seconds > 2.0 && percent >= reported + 10) {
                reported = percent - percent % 10;
                std::fprintf(stderr, "reference: %d/%d light samples (%d%%, %.1f s)\n", s + 1, samples, percent, seconds);
            }
        }
    }
    const Texture& visibility() const override { return visibility_; }
    std::vector<std::pair<std::string, const Texture*>> buffers() const override {
        std::vector<std::pair<std::string, const Texture*>> out;
        shadowMap_.appendBuffers(out, "sample_");
        out.push_back({"visibility", &visibility_});
        return out;
    }
    void writeInternals(InternalWriter& out, RenderContext&, LightState&) const override {
        Image last = readTexture(shadowMap_.firstDepth(), 1);
        for (float& z : last.data)
            if (z > 1e30f) z = INFINITY;
        out.image("sample_shadow_map", last, "shadow map of the last light sample (light-view depth; inf = no caster)");
    }
    nlohmann::json pixelInfo(glm::ivec2, RenderContext&, LightState& light) const override {
        return {{"samples", light.params.getInt("samples")}};
    }

private:
    ShadowMap shadowMap_;
    Texture visibility_;
    Framebuffer fbo_;
};

}  // namespace

const TechniqueDesc& referenceTechnique() {
    static const TechniqueDesc desc = [] {
        TechniqueDesc d;
        d.id = "reference";
        d.name = "Reference: averaged light-sample shadow maps";
        d.citation = "the papers' ground truth: guennebaud2007 sec. 7, Fig. 1 (1024 light samples); buades2015 sec. 5.3, Fig. 13";
        d.summary = "N stratified points on the light, one hard shadow map each, visibility = the weighted mean of "
                    "their depth tests; converges to the visibility integral as N grows";
        d.soft = true;
        d.params = shadowMapParams();
        d.params.push_back({"samples", "N", ParamDesc::Type::Int, "", 1024, 1, 65536, 1,
                            "N stratified light samples, one shadow map each; 1024 as in guennebaud2007 sec. 7",
                            ""});
        d.passes = {{"accumulate",
                     {"scene.casters", "light", "gbuffer", "param:samples", "param:sm_size", "param:second_depth",
                      "param:bias_const", "param:bias_slope"},
                     {"visibility"},
                     "for each light sample: render its shadow map, add weight x depth test per pixel",
                     true}};
        d.internals = {{"sample_shadow_map", "image", "shadow map of the last light sample"},
                       {"visibility", "image", "this light's visibility"}};
        d.create = [] { return std::make_unique<ReferenceTechnique>(); };
        return d;
    }();
    return desc;
}

}  // namespace shadowlab
