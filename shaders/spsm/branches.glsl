// Which step of the spsm look-up decided a pixel (the `branches` internal; techniques/spsm/spsm.cpp
// names them for --stats and the views).
#ifndef SHADOWLAB_SPSM_BRANCHES_GLSL
#define SHADOWLAB_SPSM_BRANCHES_GLSL
#define SPSM_BRANCH_NONE 0.0            // background
#define SPSM_BRANCH_ON_TRIANGLE 1.0     // the texel's triangle covers x at or behind p: lit
#define SPSM_BRANCH_HIT 2.0             // the ray meets the texel's triangle: shadowed
#define SPSM_BRANCH_NEIGHBOUR_HIT 3.0   // the ray meets a neighbour's triangle: shadowed
#define SPSM_BRANCH_NEIGHBOUR_COVER 4.0 // a neighbour's triangle covers x at or behind p (none hit): lit
#define SPSM_BRANCH_EDGE 5.0            // no stored triangle covers x: the reconstructed edge decides
#define SPSM_BRANCH_FALLBACK 6.0        // no edge to reconstruct: the depth comparison with p's texel
#define SPSM_BRANCH_EMPTY 7.0           // no caster touches p's texel (or p is outside the frustum): lit
#define SPSM_BRANCH_FACING_AWAY 8.0     // p faces away from the light centre: 0 (tangent-plane convention)
#define SPSM_BRANCH_UNDECIDED 9.0       // between the two draws only
#endif
