// The screen-space discontinuity buffer of guennebaud2007 sec. 5.2: a thresholded Sobel filter on
// depth and normals, then a separable max filter. GPU passes and their CPU mirror on
// shaders/shared/discontinuity.glsl; conventions in discontinuities.h.
#include "visibility/discontinuities.h"

#include <algorithm>

#include "error.h"
#include "shared/shared.h"

namespace shadowlab {

using namespace shared;

namespace {
GLuint groups(int n) { return GLuint((n + 7) / 8); }
}  // namespace

void DiscontinuityBuffer::run(PassContext& ctx, Texture& out, float depthThreshold, float normalThreshold, int radius) {
    const GBuffer& g = ctx.gbuffer();
    run(ctx.programs(), *g.position, *g.normal, ctx.camera().viewFromWorld(), out, depthThreshold, normalThreshold, radius);
}

void DiscontinuityBuffer::run(ProgramCache& programs, const Texture& position, const Texture& normal,
                              const glm::mat4& viewFromWorld, Texture& out, float depthThreshold, float normalThreshold,
                              int radius) {
    const int width = position.width(), height = position.height();
    if (out.format() != GL_R32F || out.width() != width || out.height() != height)
        throw InternalError("DiscontinuityBuffer::run: the output is " + out.formatName() + " " +
                            std::to_string(out.width()) + "x" + std::to_string(out.height()) + ", not R32F " +
                            std::to_string(width) + "x" + std::to_string(height) + " (the G-buffer's size)");
    if (radius < 0) throw InternalError("DiscontinuityBuffer::run: radius " + std::to_string(radius) + " < 0");
    const ShaderProgram& sobel = programs.compute("common/discontinuities.comp");
    glBindTextureUnit(0, position.id());
    sobel.set("gPosition", 0);
    glBindTextureUnit(1, normal.id());
    sobel.set("gNormal", 1);
    sobel.set("viewFromWorld", viewFromWorld);
    sobel.set("depthThreshold", depthThreshold);
    sobel.set("normalThreshold", normalThreshold);
    bindImage(0, out, 0, GL_WRITE_ONLY);
    sobel.dispatch(groups(width), groups(height));
    if (radius > 0) {
        if (!rows_ || rows_.width() != width || rows_.height() != height) rows_ = Texture::create2D(width, height, Format::R32F);
        memoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        const ShaderProgram& alongX = programs.compute("common/discontinuities_dilate.comp");
        alongX.set("radiusPixels", radius);
        bindImage(0, out, 0, GL_READ_ONLY);
        bindImage(1, rows_, 0, GL_WRITE_ONLY);
        alongX.dispatch(groups(width), groups(height));
        memoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        const ShaderProgram& alongY = programs.compute("common/discontinuities_dilate.comp", {"ALONG_Y"});
        alongY.set("radiusPixels", radius);
        bindImage(0, rows_, 0, GL_READ_ONLY);
        bindImage(1, out, 0, GL_WRITE_ONLY);
        alongY.dispatch(groups(width), groups(height));
    }
    memoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
}

int dilationRadiusForSpacing(int spacingPixels) { return std::max(0, spacingPixels / 2 + spacingPixels % 2); }

Image discontinuitiesCpu(const Image& position, const Image& normal, const glm::mat4& viewFromWorld,
                         float depthThreshold, float normalThreshold, int radius, Image* measures) {
    if (position.channels != 4 || normal.channels < 3 || normal.width != position.width || normal.height != position.height)
        throw InternalError("discontinuitiesCpu: expected a 4-channel position and a normal image of the same size");
    const int w = position.width, h = position.height;
    Image marks(w, h, 1);
    if (measures) *measures = Image(w, h, 2, -1.0f);
    for (int py = 0; py < h; ++py)
        for (int px = 0; px < w; ++px) {
            float z[9];
            vec3 n[9];
            float c = 0.0f;  // the largest cosine of incidence
            int covered = 0;
            for (int j = 0; j < 3; ++j)
                for (int i = 0; i < 3; ++i) {
                    int qx = std::clamp(px + i - 1, 0, w - 1), qy = std::clamp(py + j - 1, 0, h - 1);
                    const vec3 p(position.at(qx, qy, 0), position.at(qx, qy, 1), position.at(qx, qy, 2));
                    const bool geometry = position.at(qx, qy, 3) != 0.0f;
                    covered += geometry ? 1 : 0;
                    z[3 * j + i] = cameraDepth(viewFromWorld, p);
                    n[3 * j + i] = vec3(normal.at(qx, qy, 0), normal.at(qx, qy, 1), normal.at(qx, qy, 2));
                    if (geometry) c = std::max(c, cosIncidence(viewFromWorld, p, n[3 * j + i]));
                }
            float mark = coverageDiscontinuity(covered);
            if (mark < 0.0f) {
                vec2 gz = sobelGradient(vec3(z[0], z[1], z[2]), vec3(z[3], z[4], z[5]), vec3(z[6], z[7], z[8]));
                vec2 gx = sobelGradient(vec3(n[0].x, n[1].x, n[2].x), vec3(n[3].x, n[4].x, n[5].x), vec3(n[6].x, n[7].x, n[8].x));
                vec2 gy = sobelGradient(vec3(n[0].y, n[1].y, n[2].y), vec3(n[3].y, n[4].y, n[5].y), vec3(n[6].y, n[7].y, n[8].y));
                vec2 gn = sobelGradient(vec3(n[0].z, n[1].z, n[2].z), vec3(n[3].z, n[4].z, n[5].z), vec3(n[6].z, n[7].z, n[8].z));
                float depthMeasure = relativeDepthEdge(gz, z[4], c), normalMeasure = normalEdge(gx, gy, gn);
                mark = discontinuityMark(depthMeasure, normalMeasure, depthThreshold, normalThreshold);
                if (measures) {
                    measures->at(px, py, 0) = depthMeasure;
                    measures->at(px, py, 1) = normalMeasure;
                }
            }
            marks.at(px, py) = mark;
        }
    if (radius == 0) return marks;
    Image rows(w, h, 1), out(w, h, 1);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            ivec2 r = dilationRange(x, radius, w);
            float m = 0.0f;
            for (int t = r.x; t <= r.y; ++t) m = std::max(m, marks.at(t, y));
            rows.at(x, y) = m;
        }
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            ivec2 r = dilationRange(y, radius, h);
            float m = 0.0f;
            for (int t = r.x; t <= r.y; ++t) m = std::max(m, rows.at(x, t));
            out.at(x, y) = m;
        }
    return out;
}

}  // namespace shadowlab
