// `pcf`: percentage-closer filtering with a fixed kernel (Reeves, Salesin and Cook 1987): the
// shadow map of `hard`, then the fraction of an n x n texel neighbourhood that passes the depth test.
#include "hard/hard.h"

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
        ParamDesc kernel{"pcf_kernel", "n", ParamDesc::Type::Int, "texels", 5, 1, 63, 2,
                         "kernel width n (odd, centred on the receiver's texel): n x n depth tests; 5 smooths a 1024^2 "
                         "map's staircase without blurring contact shadows much",
                         ""};
        kernel.constraint = ParamDesc::Constraint::Odd;
        d.params.push_back(kernel);
        d.passes = {shadowMapPass(), depthTestPass(true)};
        d.internals = shadowMapInternals();
        d.internals.push_back(shadowMapPixelRecord(true));
        return d;
    }();
    return desc;
}

}  // namespace shadowlab
