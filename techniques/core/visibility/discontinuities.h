// The screen-space discontinuity buffer of guennebaud2007 sec. 5.2 (the paragraph after "Pull-push
// reconstruction"): pull-push would blend penumbrae across two different surfaces, so pixels near
// a depth or normal discontinuity of the receivers are always sampled. "A contour detection filter
// (e.g., a thresholded Sobel filter) on the depth and normal buffers of the scene seen from the
// camera", whose lines are then widened "such that their width is greater than the maximum allowed
// pixel spacing". GPU passes (shaders/common/discontinuities.comp, discontinuities_dilate.comp) and
// a CPU mirror on the same shared functions (shaders/shared/discontinuity.glsl).
//
// Measures (see discontinuity.glsl; Sobel responses divided by 4, so a step of h reads h):
//  - depth:  |Sobel z| / z times the largest cosine of incidence |n . v| over the 3x3 (z the
//            camera-space depth, world units, positive in front; v the view direction): a relative
//            depth step, corrected for the view angle so that a grazing plane is no step (a plane of
//            relative depth slope s per pixel seen at incidence a reads 2 s cos a = 2 sin a x the
//            pixel's angle, at most twice the pixel's angle in radians);
//  - normal: the Sobel magnitude over the normal's three components: a crease of angle a reads
//            2 sin(a / 2).
// A pixel whose 3x3 neighbourhood mixes geometry and background (G-buffer position w = 0) is a
// discontinuity (both sides of a silhouette); all-background pixels are not.
#pragma once
#include <glm/glm.hpp>

#include "graph/frame.h"

namespace shadowlab {

class DiscontinuityBuffer {
public:
    // Defaults, chosen on the scenes of assets/scenes at 192 x 144
    // (DiscontinuityGpu.DefaultsOnTheScenes: every object outline found within a pixel on 98.5-100%
    // of its pixels, none of the inside of floors and spheres marked):
    //  - depth 0.03: two parallel surfaces 3% of the depth apart along their normal (the measure times
    //    the cosine of incidence is about h / z for surfaces h apart, whatever the view angle): the
    //    0.3-unit steps of depth-discontinuities at 6.5 units read 0.046, a plate over its floor far
    //    more; any plane reads at most twice the pixel's angle (0.011 at 144 pixels over 45 degrees),
    //    so planes, even the grazing scene's 60-unit floor to its horizon, stay unmarked while a pixel
    //    spans less than 0.015 rad (45 degrees over 52 pixels; the plain |Sobel z| / z, without the
    //    cosine, marked 4.9% of that floor's inside even at a threshold of 0.1);
    //  - normal 0.5: creases sharper than 29 degrees (2 sin(a / 2) > 0.5): a box's 90-degree edges,
    //    a box on the floor, while the facets of a 32-segment sphere (11.25 degrees, 0.196) and of
    //    the torus are smooth;
    //  - radius: the caller's (dilationRadiusForSpacing of its pixel spacing).
    static constexpr float kDefaultDepthThreshold = 0.03f;
    static constexpr float kDefaultNormalThreshold = 0.5f;

    // From the frame's G-buffer and camera (the pass must read "gbuffer" and "camera"): `out` is
    // R32F at the G-buffer's size, 1 on a discontinuity (widened by `radius` pixels on each side,
    // a (2 radius + 1)^2 max filter), 0 elsewhere. Leaves `out` visible to fetches and read-backs.
    // Compute dispatches over the whole frame: a pass that runs it should set PassDesc::wholeFrame.
    void run(PassContext& ctx, Texture& out, float depthThreshold = kDefaultDepthThreshold,
             float normalThreshold = kDefaultNormalThreshold, int radius = 0);
    // The same from explicit inputs: `position` and `normal` RGBA32F G-buffer textures.
    void run(ProgramCache& programs, const Texture& position, const Texture& normal, const glm::mat4& viewFromWorld,
             Texture& out, float depthThreshold, float normalThreshold, int radius);

private:
    Texture rows_;  // the widening along the rows, before the columns
};

// The radius that widens a line of one pixel to more than `spacingPixels` (2 r + 1 > spacing).
int dilationRadiusForSpacing(int spacingPixels);

// CPU mirror: `position` and `normal` are the G-buffer's (4 channels, position w = coverage; any row
// order, every step is symmetric), `viewFromWorld` the camera's. Returns the 1-channel buffer of
// DiscontinuityBuffer::run in the same row order. `measures`, when given, receives per pixel the
// depth and normal measures (2 channels; -1, -1 where coverage decided: background or silhouette).
Image discontinuitiesCpu(const Image& position, const Image& normal, const glm::mat4& viewFromWorld,
                         float depthThreshold, float normalThreshold, int radius, Image* measures = nullptr);

}  // namespace shadowlab
