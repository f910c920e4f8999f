// guennebaud2007 sec. 6, pass one ("classifies each pixel as occluded, lit or in penumbra, and, in
// the latter case, applies view dependent selection; the result is written in the v-buffer"): per
// pixel the selection code (screen_selection.glsl) and the sparse v-buffer (v, w) the pull-push
// reconstructs: lit pixels (light-front fraction, 1), umbra (0, 1), background (1, 1), penumbra
// (0, 0) until the visibility pass computes the evaluated ones. Penumbra pixels are selected by
// eq. 4-6 from z_occ, or forced by the discontinuity buffer.
// A full-screen draw whose two results are render targets: llvmpipe writes a fragment shader's
// outputs a block of pixels at a time and a compute shader's imageStore lane by lane (as a compute
// pass this took 6.7-7.3 ms on plant at 384x384, of which 2.2 ms the sparse buffer's store alone).
#include "receiver.glsl"
#include "../common/light_front.glsl"
#include "../shared/screen_selection.glsl"

uniform sampler2D classification;   // kernel.frag: BP_CLASS_*
uniform sampler2D occluderDepth;    // kernel.frag: z_occ
uniform sampler2D discontinuities;  // 1 on a (widened) discontinuity
uniform bool useDiscontinuities;
uniform float lightWidthWorld;      // w_l of eq. 4
uniform float sMin;                 // s_min of eq. 6, pixels
uniform int patternSize;            // h
uniform float eta;                  // eq. 5: pixels per world unit at unit camera depth
uniform vec3 cameraPosition;
uniform mat4 cameraViewFromWorld;
layout(location = 0) out float selection;  // SEL_* code
layout(location = 1) out vec2 sparse;      // (v, weight) for pull-push

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    int code = SEL_BACKGROUND;
    vec2 vw = vec2(1.0, 1.0);
    if (!isBackground(p)) {
        float cls = texelFetch(classification, p, 0).r;
        vec3 position = worldPosition(p), normal = worldNormal(p);
        if (cls == BP_CLASS_LIT) {
            code = SEL_LIT;
            vw = vec2(lightFrontFraction(position, normal), 1.0);
        } else if (cls == BP_CLASS_UMBRA) {
            code = SEL_UMBRA;
            vw = vec2(0.0, 1.0);
        } else {
            BpReceiver r = prepareReceiver(p);
            float sObj = penumbraObjectSize(lightWidthWorld, r.position.z, texelFetch(occluderDepth, p, 0).r);
            float zCamera = -(cameraViewFromWorld * vec4(position, 1.0)).z;
            float cosView = abs(dot(normalize(normal), normalize(cameraPosition - position)));
            float sScr = penumbraScreenSize(sObj, eta, zCamera, cosView);
            bool selected = screenSelected(sScr, sMin, ditherRank(p.x, p.y, patternSize), patternSize);
            bool forced = useDiscontinuities && texelFetch(discontinuities, p, 0).r > 0.5;
            code = penumbraSelectionCode(selected, forced);
            vw = vec2(0.0, 0.0);
        }
    }
    selection = float(code);
    sparse = vw;
}
