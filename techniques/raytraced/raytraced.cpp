// `raytraced`: visibility from M stratified rays per pixel to the light, traced with Embree against
// the real triangles (techniques/core/visibility/raytracer.h). Independent of any shadow map: the tests use it
// to validate `reference`. Runs on the CPU; its result is uploaded as the light's visibility.
#include <algorithm>

#include "graph/frame.h"
#include "progress.h"
#include "visibility/raytracer.h"

namespace shadowlab {

namespace {

class RaytracePass : public Pass {
public:
    void execute(PassContext& ctx) override {
        const GBuffer& g = ctx.gbuffer();
        Image positions = readTexture(*g.position, 4);
        Image normals = readTexture(*g.normal, 4);
        for (size_t i = 0; i < positions.pixelCount(); ++i)
            if (positions.data[i * 4 + 3] == 0.0f) positions.data[i * 4] = NAN;  // background
        RayTracer tracer(ctx.scene(), ctx.sceneTime(true));  // the casters' triangles at this frame's time
        ProgressReporter progress("raytraced", "pixels");
        Image v = tracer.visibility(positions, normals, ctx.light(), ctx.paramInt("rays"),
                                    [&](size_t done, size_t total) { progress.update(done, total); });
        // Image row 0 is the top; GL row 0 is the bottom.
        std::vector<float> rows(v.data.size());
        for (int y = 0; y < v.height; ++y)
            std::copy_n(&v.data[size_t(v.height - 1 - y) * v.width], v.width, &rows[size_t(y) * v.width]);
        glTextureSubImage2D(ctx.texture("visibility").id(), 0, 0, 0, v.width, v.height, GL_RED, GL_FLOAT, rows.data());
    }
};

}  // namespace

const TechniqueDesc& raytracedTechnique() {
    static const TechniqueDesc desc = [] {
        TechniqueDesc d;
        d.id = "raytraced";
        d.name = "Reference: ray traced (Embree)";
        d.citation = "DESIGN.md sec. 3, reference (2): exact geometry, no shadow map";
        d.summary = "M stratified rays per pixel to points on the light, traced against the real triangles; "
                    "rays=1 with a point light gives exact hard shadows";
        d.soft = false;
        d.params = {{"rays", "M", ParamDesc::Type::Int, "", 256, 1, 65536, 1,
                     "M stratified rays per pixel; 256 keeps the noise's standard deviation under 0.03", ""}};
        PassDesc trace;
        trace.name = "raytrace";
        trace.doc = "M shadow rays per pixel with Embree (CPU)";
        trace.reads = {"scene.casters", "light", "gbuffer", "param:rays"};
        trace.creates = {visibilityResource()};
        trace.create = [] { return std::make_unique<RaytracePass>(); };
        d.passes = {trace};
        InternalDesc pixel;
        pixel.name = "pixel";
        pixel.kind = InternalDesc::Kind::Record;
        pixel.doc = "the picked pixel's ray-tracing settings";
        pixel.schema = {{"rays", "M, the shadow rays traced per pixel"},
                        {"triangles", "triangles of the shadow casters traced against"}};
        pixel.reads = {"param:rays", "scene.casters"};
        pixel.record = [](PassContext& ctx, glm::ivec2) {
            size_t triangles = 0;
            for (const Object& o : ctx.scene().objects)
                if (o.castsShadows) triangles += o.mesh.triangleCount();
            return nlohmann::json{{"rays", ctx.paramInt("rays")}, {"triangles", triangles}};
        };
        d.internals = {pixel};
        return d;
    }();
    return desc;
}

}  // namespace shadowlab
