// The screen-space discontinuity buffer of guennebaud2007 sec. 5.2 (the paragraph after
// "Pull-push reconstruction"): "a contour detection filter (e.g., a thresholded Sobel filter) on
// the depth and normal buffers of the scene seen from the camera", whose lines are then widened
// "such that their width is greater than the maximum allowed pixel spacing". The per-pixel math
// shared by shaders/common/discontinuities.comp, discontinuities_dilate.comp and the CPU mirror
// discontinuitiesCpu (techniques/core/visibility/discontinuities.cpp). Common GLSL/C++ subset: see
// shaders/shared/shared.h.
//
// Conventions:
//  - z is the camera-space depth in world units, positive in front of the camera:
//    z = -(viewFromWorld p).z;
//  - a 3x3 neighbourhood is passed as three rows (left, centre, right), `above` and `below` the
//    centre row; which way the rows run does not matter (only magnitudes are thresholded);
//  - the Sobel responses are divided by 4, so that a step of height h between two columns reads h
//    on the pixels beside it, and a ramp of slope s per pixel reads 2 s;
//  - neighbours outside the image repeat the border pixel (clamp to edge): the image border is no
//    discontinuity.
#ifndef SHADOWLAB_DISCONTINUITY_GLSL
#define SHADOWLAB_DISCONTINUITY_GLSL

#ifndef SHARED_FN
#define SHARED_FN
#endif

// Camera-space depth z of world point p, world units, positive in front of the camera.
SHARED_FN float cameraDepth(mat4 viewFromWorld, vec3 worldPosition) {
    vec4 view = viewFromWorld * vec4(worldPosition, 1.0f);
    return -view.z;
}

// The Sobel gradient (d/dx, d/dy) of a scalar over a 3x3 neighbourhood, divided by 4 (see above).
// x runs left to right along a row; y from `above` to `below`.
SHARED_FN vec2 sobelGradient(vec3 above, vec3 row, vec3 below) {
    float gx = (above.z - above.x) + 2.0f * (row.z - row.x) + (below.z - below.x);
    float gy = (below.x - above.x) + 2.0f * (below.y - above.y) + (below.z - above.z);
    return vec2(0.25f * gx, 0.25f * gy);
}

// The cosine of incidence |n . v| at the centre pixel: n its normal, v the direction from the camera
// to it, both in camera space (viewFromWorld applied; n need not be unit: it is normalised here).
SHARED_FN float cosIncidence(mat4 viewFromWorld, vec3 worldPosition, vec3 worldNormal) {
    vec4 view = viewFromWorld * vec4(worldPosition, 1.0f);
    vec3 n = normalize(mat3(viewFromWorld) * worldNormal);
    return abs(dot(n, normalize(vec3(view.x, view.y, view.z))));
}

// The depth test's measure: |Sobel z| / z at the centre pixel (zCentre > 0), a relative depth step,
// times the largest cosine of incidence |n . v| over the 3x3 neighbourhood (cosIncidenceMax). A
// plane seen at incidence alpha changes its depth by about tan(alpha) times the pixel's angle per
// pixel, relative to z: that grows without bound towards a grazing floor's horizon (without the
// cosine, a threshold of 0.1 marked 4.9% of the inside of the `grazing` scene's floor at 192 x 144),
// while times cos(alpha) it is at most the pixel's angle (reading 2 x 0.0055 at 144 pixels over 45
// degrees), on any plane. For two parallel surfaces h apart along their normal the measure is about
// h / z, whatever the view angle. At a silhouette the near side is seen at grazing incidence but the far side is not:
// the neighbourhood's largest cosine keeps the step's relative size times the far side's cosine.
SHARED_FN float relativeDepthEdge(vec2 depthGradient, float zCentre, float cosIncidenceMax) {
    return length(depthGradient) / zCentre * cosIncidenceMax;
}

// The normal test's measure: the Sobel magnitude over the three normal components,
// sqrt(|grad n_x|^2 + |grad n_y|^2 + |grad n_z|^2). A crease between unit normals n1, n2 reads
// |n2 - n1| = 2 sin(angle / 2) on the pixels beside it.
SHARED_FN float normalEdge(vec2 gradientX, vec2 gradientY, vec2 gradientZ) {
    return sqrt(dot(gradientX, gradientX) + dot(gradientY, gradientY) + dot(gradientZ, gradientZ));
}

// Background and silhouettes: given how many of the 3x3 pixels (the centre included) are covered by
// geometry (G-buffer position w = 1), 1 when the neighbourhood mixes geometry and background (both
// sides of a silhouette are marked), 0 when it is all background, -1 when it is all geometry (then
// the Sobel tests decide).
SHARED_FN float coverageDiscontinuity(int coveredPixels) {
    if (coveredPixels == 0) {
        return 0.0f;
    }
    return coveredPixels == 9 ? -1.0f : 1.0f;
}

// The thresholded filter: 1 (a discontinuity) when either measure exceeds its threshold, else 0.
SHARED_FN float discontinuityMark(float depthMeasure, float normalMeasure, float depthThreshold,
                                  float normalThreshold) {
    return depthMeasure > depthThreshold || normalMeasure > normalThreshold ? 1.0f : 0.0f;
}

// The widening (a max filter of `radiusPixels`, run separably: rows, then columns): the taps of
// pixel x along one axis are x - r .. x + r clamped to [0, size - 1].
SHARED_FN ivec2 dilationRange(int x, int radiusPixels, int size) {
    return ivec2(max(x - radiusPixels, 0), min(x + radiusPixels, size - 1));
}

#endif
