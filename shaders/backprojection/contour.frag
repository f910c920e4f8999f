// ssm-contour (guennebaud2007 sec. 4): the contour edges of the occluding samples in the kernel,
// found 2x2 block by 2x2 block with the rule table (sec. 4.1, Fig. 3-4, parameter t), are
// back-projected from p onto the light, clipped to it and radially integrated from the light centre
// with signed areas (sec. 4.2, Fig. 5a). The integration starts from the full light when the light
// centre is occluded and from zero otherwise, decided by the contour inside test on the block of
// four samples around p' (Fig. 5b), not by a plain shadow-map test. The C++ mirror for --pixel is
// techniques/ssm-contour/contour.cpp.
#include "receiver.glsl"
#include "../common/light_front.glsl"
uniform sampler2D shadowMap;       // light-view depth z (R32F), level 0
uniform sampler2D kernelSize;      // from kernel.frag
uniform sampler2D classification;  // from kernel.frag
uniform int lightShape;            // BP_LIGHT_SQUARE or BP_LIGHT_DISK
uniform float lightHalfSize;       // w_l / 2 or r: the unit of light coordinates
uniform float maxKernelTexels;     // the `max_kernel` cap
uniform float contourT;            // t in [-1, 1]
layout(location = 0) out float visibility;

BpReceiver receiver;

float depthAt(ivec2 t) {
    int last = int(shadowMapSize) - 1;
    if (t.x < 0 || t.y < 0 || t.x > last || t.y > last) return 3.4e38;  // off the map: no caster
    return texelFetch(shadowMap, t, 0).r;
}

bool occludes(ivec2 t, float z) {
    return bpSampleOccludes(receiver, vec2(t) + 0.5, z, shadowMapSize, lightTanHalfFov);
}

// Edge `which` of the block whose lower-left sample is `corner`, back-projected: (a, b) on the light.
vec4 blockEdge(ivec2 corner, int mask, int which, vec4 depths) {
    vec4 e = contourEdge(mask, contourT, which);
    ivec2 holders = contourEdgeHolders(mask, which);
    vec2 centre = vec2(corner) + 1.0;  // the block's centre: the samples' shared corner
    vec2 a = backprojectToLight(receiver.position, centre + vec2(e.x, e.y), depths[holders.x], shadowMapSize,
                                lightTanHalfFov, lightHalfSize);
    vec2 b = backprojectToLight(receiver.position, centre + vec2(e.z, e.w), depths[holders.y], shadowMapSize,
                                lightTanHalfFov, lightHalfSize);
    return vec4(a, b);
}

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    visibility = 1.0;
    if (isBackground(pixel)) return;
    float cls = texelFetch(classification, pixel, 0).r;
    // The visibility convention (common/light_front.glsl): only the light in front of the
    // receiver's tangent plane counts, as a factor on the back-projected visibility.
    float front = lightFrontFraction(worldPosition(pixel), worldNormal(pixel));
    if (cls == BP_CLASS_LIT) {
        visibility = front;
        return;
    }
    if (cls == BP_CLASS_UMBRA) {
        visibility = 0.0;
        return;
    }
    receiver = prepareReceiver(pixel);
    int size = int(shadowMapSize);
    float w = min(texelFetch(kernelSize, pixel, 0).r, maxKernelTexels);
    ivec4 range = kernelTexelRange(receiver.centre, w, size);
    float occluded = 0.0;

    // Initialisation (Fig. 5b): the block of the four samples around p'.
    {
        ivec2 corner = ivec2(floor(receiver.centre - 0.5));
        vec4 z = vec4(depthAt(corner), depthAt(corner + ivec2(1, 0)), depthAt(corner + ivec2(1, 1)), depthAt(corner + ivec2(0, 1)));
        int mask = (occludes(corner, z.x) ? 1 : 0) | (occludes(corner + ivec2(1, 0), z.y) ? 2 : 0) |
                   (occludes(corner + ivec2(1, 1), z.z) ? 4 : 0) | (occludes(corner + ivec2(0, 1), z.w) ? 8 : 0);
        int count = contourRule(mask).x;
        float turn0 = 0.0, turn1 = 0.0;
        if (count >= 1) {
            vec4 e = blockEdge(corner, mask, 0, z);
            turn0 = edgeTurn(e.xy, e.zw);
        }
        if (count == 2) {
            vec4 e = blockEdge(corner, mask, 1, z);
            turn1 = edgeTurn(e.xy, e.zw);
        }
        if (contourCentreOccluded(mask, contourT, turn0, turn1)) occluded = bpLightArea(lightShape);
    }

    // Every 2x2 block with a sample in the kernel, walked row by row; the left column's two samples
    // are the previous block's right column.
    for (int by = range.y - 1; by <= range.w; ++by) {
        ivec2 left = ivec2(range.x - 1, by);
        float z0 = depthAt(left), z3 = depthAt(left + ivec2(0, 1));
        bool o0 = occludes(left, z0), o3 = occludes(left + ivec2(0, 1), z3);
        for (int bx = range.x - 1; bx <= range.z; ++bx) {
            ivec2 corner = ivec2(bx, by);
            float z1 = depthAt(corner + ivec2(1, 0)), z2 = depthAt(corner + ivec2(1, 1));
            bool o1 = occludes(corner + ivec2(1, 0), z1), o2 = occludes(corner + ivec2(1, 1), z2);
            int mask = (o0 ? 1 : 0) | (o1 ? 2 : 0) | (o2 ? 4 : 0) | (o3 ? 8 : 0);
            if (mask != 0 && mask != 15) {
                vec4 depths = vec4(z0, z1, z2, z3);
                int count = contourRule(mask).x;
                for (int which = 0; which < count; ++which) {
                    vec4 e = blockEdge(corner, mask, which, depths);
                    occluded += edgeOccludedArea(lightShape, e.xy, e.zw);
                }
            }
            z0 = z1;
            z3 = z2;
            o0 = o1;
            o3 = o2;
        }
    }
    visibility = bpVisibility(occluded, lightShape) * front;
}
