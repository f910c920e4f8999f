// TEMPLATE technique: copy this folder (and shaders/template/) to start a technique. It compiles
// and its descriptor is validated by tests/techniques/test_descriptors.cpp, but it is not registered: add
// `&<id>Technique()` to techniques/registry.cpp when yours is ready. docs/adding-a-technique.md
// walks through every part.
#include "visibility/shadow_map.h"

namespace shadowlab {

namespace {

// A pass is an object: it may keep what outlives one run (here a framebuffer); its resources
// belong to the pool and come from ctx, which checks each access against the pass's declaration.
// The pool may hand the pass other textures from one run to the next (a resize, sm_size changed):
// a FramebufferCache (gl/texture.h) rebuilds the framebuffer exactly then.
class TemplateVisibilityPass : public Pass {
public:
    void execute(PassContext& ctx) override {
        Texture& visibility = ctx.texture("visibility");
        const Framebuffer& fbo = fbo_.get({&visibility}, nullptr);
        const ShaderProgram& program = ctx.programs().get("common/fullscreen.vert", "template/visibility.frag");
        program.use();
        const Texture& map = ctx.texture(shadowTestMap(ctx));
        setShadowLookupUniforms(program, ctx.lightView(), map.width(), ctx.light());
        setLightFrontUniforms(program, ctx.light());
        program.set("biasConstTexels", float(ctx.param("bias_const")));
        program.set("biasSlopeTexels", float(ctx.param("bias_slope")));
        program.set("kernelTexels", ctx.paramInt("kernel"));
        ctx.bindGBuffer(program);  // units 0-2
        glBindTextureUnit(3, map.id());
        program.set("shadowMap", 3);
        fbo.bind(ctx.width(), ctx.height());
        drawFullscreenTriangle();
    }

private:
    FramebufferCache fbo_;
};

}  // namespace

const TechniqueDesc& templateTechnique() {
    static const TechniqueDesc desc = [] {
        TechniqueDesc d;
        d.id = "template";  // stable: the CLI, lessons and tests use it
        d.name = "Template technique";
        d.citation = "the paper, section and equations this technique implements";
        d.summary = "one line a student understands: what the technique computes and what it approximates";
        d.soft = true;
        // Parameters: one table row each (STYLE.md 3). The paper's symbol and default, a doc line
        // with the reason for the default; Int constraints (odd, power of two, step) and
        // `appliesWhen` conditions are enforced by --set, lessons and the window alike.
        d.params = shadowMapParams();
        ParamDesc kernel{"kernel", "n", ParamDesc::Type::Int, "texels", 3, 1, 31, 2,
                         "kernel width n (odd); 3 as the paper's smallest setting", ""};
        kernel.constraint = ParamDesc::Constraint::Odd;
        d.params.push_back(kernel);
        ParamDesc filter{"filter", "", ParamDesc::Type::Enum, "", 0, 0, 1, 1,
                         "weighting of the kernel's taps (an example enum: --set filter=mean)", ""};
        filter.choices = {"box", "mean"};
        d.params.push_back(filter);
        ParamDesc sigma{"sigma", "sigma", ParamDesc::Type::Float, "texels", 1.0, 0.1, 10, 0.1,
                        "an example of a parameter that applies only to one choice of another",
                        "filter == mean"};
        d.params.push_back(sigma);

        // Passes: what each reads, creates (allocated by the pool from the declaration) and
        // modifies; `soft` passes do not run for point lights (hard replaces the technique).
        PassDesc main;
        main.name = "visibility";
        main.doc = "the paper's step: n x n depth tests around the receiver's texel";
        main.reads = {"gbuffer", "light", "param:bias_const", "param:bias_slope", "param:kernel", "param:filter",
                      "param:sigma"};
        for (const std::string& r : shadowTestReads()) main.reads.push_back(r);
        main.creates = {visibilityResource()};
        main.soft = true;
        main.create = [] { return std::make_unique<TemplateVisibilityPass>(); };
        d.passes = {shadowMapPass(), main};

        // Internals: typed, each naming the resource it shows (views and --internals request them).
        d.internals = shadowMapInternals();
        return d;
    }();
    return desc;
}

}  // namespace shadowlab
