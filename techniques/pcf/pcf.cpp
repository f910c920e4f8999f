// `pcf`: percentage-closer filtering with a fixed kernel (Reeves, Salesin and Cook 1987): the
// shadow map of `hard`, then the fraction of an n x n texel neighbourhood that passes the depth test.
#include "../hard/hard.h"

namespace shadowlab {

const TechniqueDesc& pcfTechnique() {
    static const TechniqueDesc desc = [] {
        TechniqueDesc d;
        d.id = "pcf";
        d.name = "Percentage-closer filtering";
        d.citation = "Reeves, Salesin, Cook 1987, Rendering antialiased shadows with depth maps; recap in buades2015 sec. 2";
        d.summary = "fixed n x n kernel of depth tests around the receiver's shadow-map texel: soft-looking edges "
                    "of constant width, whatever the light size and occluder distance";
        d.soft = true;
        d.params = shadowMapParams();
        d.params.push_back({"pcf_kernel", "n", ParamDesc::Type::Int, "texels", 5, 1, 63, 2,
                            "kernel width n (odd): n x n depth tests; 5 smooths a 1024^2 map's staircase without "
                            "blurring contact shadows much",
                            ""});
        d.passes = {
            shadowMapPass(),
            {"filter", {"shadow_map", "gbuffer", "param:bias_const", "param:bias_slope", "param:pcf_kernel"},
             {"visibility"}, "mean of n x n depth tests around the receiver's texel", true},
        };
        d.internals = {{"shadow_map", "image", "light-view depth of the nearest caster"},
                       {"visibility", "image", "this light's visibility"}};
        d.create = [] { return std::make_unique<HardShadowTechnique>("PCF"); };
        return d;
    }();
    return desc;
}

}  // namespace shadowlab
