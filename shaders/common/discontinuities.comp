// The screen-space discontinuity buffer of guennebaud2007 sec. 5.2 (the paragraph after "Pull-push
// reconstruction"), step 1: a thresholded Sobel filter on the camera-space depth and on the
// G-buffer's normals; silhouettes against the background are marked on both sides. Writes 1
// (discontinuity) or 0 per pixel. Step 2 widens the lines: discontinuities_dilate.comp. Math:
// shaders/shared/discontinuity.glsl; host: DiscontinuityBuffer (techniques/core/visibility/
// discontinuities.cpp).
layout(local_size_x = 8, local_size_y = 8) in;
#include "../shared/discontinuity.glsl"

uniform sampler2D gPosition;  // world position xyz; w = 1 on geometry, 0 on background
uniform sampler2D gNormal;    // geometric normal xyz, turned towards the camera
uniform mat4 viewFromWorld;   // the camera's
uniform float depthThreshold;   // on |Sobel z| / z
uniform float normalThreshold;  // on the Sobel magnitude of the normal
layout(r32f, binding = 0) uniform writeonly image2D destination;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(destination);
    if (any(greaterThanEqual(p, size))) return;
    // The 3x3 neighbourhood, clamped to the image: rows[j][i] is pixel (p.x + i - 1, p.y + j - 1).
    float z[9];
    vec3 n[9];
    float c = 0.0;  // the largest cosine of incidence
    int covered = 0;
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
            ivec2 q = clamp(p + ivec2(i - 1, j - 1), ivec2(0), size - 1);
            vec4 position = texelFetch(gPosition, q, 0);
            covered += position.w != 0.0 ? 1 : 0;
            z[3 * j + i] = cameraDepth(viewFromWorld, position.xyz);
            n[3 * j + i] = texelFetch(gNormal, q, 0).xyz;
            if (position.w != 0.0) c = max(c, cosIncidence(viewFromWorld, position.xyz, n[3 * j + i]));
        }
    float mark = coverageDiscontinuity(covered);
    if (mark < 0.0) {
        vec2 gz = sobelGradient(vec3(z[0], z[1], z[2]), vec3(z[3], z[4], z[5]), vec3(z[6], z[7], z[8]));
        vec2 gx = sobelGradient(vec3(n[0].x, n[1].x, n[2].x), vec3(n[3].x, n[4].x, n[5].x), vec3(n[6].x, n[7].x, n[8].x));
        vec2 gy = sobelGradient(vec3(n[0].y, n[1].y, n[2].y), vec3(n[3].y, n[4].y, n[5].y), vec3(n[6].y, n[7].y, n[8].y));
        vec2 gn = sobelGradient(vec3(n[0].z, n[1].z, n[2].z), vec3(n[3].z, n[4].z, n[5].z), vec3(n[6].z, n[7].z, n[8].z));
        mark = discontinuityMark(relativeDepthEdge(gz, z[4], c), normalEdge(gx, gy, gn), depthThreshold, normalThreshold);
    }
    imageStore(destination, p, vec4(mark, 0.0, 0.0, 0.0));
}
