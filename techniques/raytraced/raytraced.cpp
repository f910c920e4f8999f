// `raytraced`: visibility from M stratified rays per pixel to the light, traced with Embree against
// the real triangles (techniques/core/raytracer.h). Independent of any shadow map: the tests use it
// to validate `reference`. Runs on the CPU; its result is uploaded as the light's visibility.
#include <algorithm>
#include <chrono>
#include <cstdio>

#include "raytracer.h"
#include "renderer.h"

namespace shadowlab {

namespace {

class RaytracedTechnique : public TechniqueInstance {
public:
    void run(const std::string&, RenderContext& ctx, LightState& light) override {
        if (!visibility_ || visibility_.width() != ctx.width || visibility_.height() != ctx.height)
            visibility_ = Texture(ctx.width, ctx.height, GL_R32F);
        Image positions = readTexture(ctx.gbuffer.position, 4);
        Image normals = readTexture(ctx.gbuffer.normal, 4);
        for (size_t i = 0; i < positions.pixelCount(); ++i)
            if (positions.data[i * 4 + 3] == 0.0f) positions.data[i * 4] = NAN;  // background
        RayTracer tracer(ctx.scene, ctx.time);
        // Progress on stderr once a run takes more than two seconds, as `reference` does.
        auto start = std::chrono::steady_clock::now();
        int reported = 0;
        auto progress = [&](size_t done, size_t total) {
            double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            int percent = total ? int(done * 100 / total) : 100;
            if (seconds > 2.0 && percent >= reported + 10) {
                reported = percent - percent % 10;
                std::fprintf(stderr, "raytraced: %zu/%zu pixels (%d%%, %.1f s)\n", done, total, percent, seconds);
            }
        };
        Image v = tracer.visibility(positions, normals, light.light, light.params.getInt("rays"), progress);
        // Image row 0 is the top; GL row 0 is the bottom.
        std::vector<float> rows(v.data.size());
        for (int y = 0; y < v.height; ++y)
            std::copy_n(&v.data[size_t(v.height - 1 - y) * v.width], v.width, &rows[size_t(y) * v.width]);
        glTextureSubImage2D(visibility_.id(), 0, 0, 0, v.width, v.height, GL_RED, GL_FLOAT, rows.data());
        triangles_ = tracer.triangleCount();
    }
    const Texture& visibility() const override { return visibility_; }
    std::vector<std::pair<std::string, const Texture*>> buffers() const override { return {{"visibility", &visibility_}}; }
    void writeInternals(InternalWriter&, RenderContext&, LightState&) const override {}
    nlohmann::json pixelInfo(glm::ivec2, RenderContext&, LightState& light) const override {
        return {{"rays", light.params.getInt("rays")}, {"triangles", triangles_}};
    }

private:
    Texture visibility_;
    size_t triangles_ = 0;
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
        d.passes = {{"raytrace", {"scene.casters", "light", "gbuffer", "param:rays"}, {"visibility"},
                     "M shadow rays per pixel with Embree (CPU)", false}};
        d.internals = {{"visibility", "image", "this light's visibility"}};
        d.create = [] { return std::make_unique<RaytracedTechnique>(); };
        return d;
    }();
    return desc;
}

}  // namespace shadowlab
