// Pull-push reconstruction of a sparse screen-space visibility buffer (guennebaud2007 sec. 5.2,
// "Pull-push reconstruction", after Gortler et al. 1996): the gaps of a frame-size (v, w) buffer
// (w = 1 on computed pixels, 0 on gaps, any value in [0, 1] accepted) are filled from coarser and
// coarser averages, computed pixels (w = 1) are kept exactly. GPU passes and a CPU mirror on the
// same shared functions (shaders/shared/pull_push.glsl).
//
// Pyramid level convention. Pull-push level 0 is the frame (the input); level k >= 1 has
// pullPushLevelSize(k, n) texels across: ceil(n / 2) at level 1, then halved and rounded down (at
// least 1) down to 1x1 -- the GL mip chain of a texture of ceil(width / 2) x ceil(height / 2), which
// is what a ResourceKind::Pyramid of SizeRule::frame(2) with levels = 0 allocates. The pyramids
// hold levels 1, 2, ... only: mip level m of `pull` and `push` is pull-push level m + 1.
//  - pull mip m: the reduced (v, w) of level m + 1 (weighted mean visibility, min(1, sum of weights));
//  - push mip m: (completed v, the pull weight w) of level m + 1 after the push;
//  - the output: the completed level 0 (R32F).
#pragma once
#include <string>
#include <vector>

#include "graph/frame.h"

namespace shadowlab {

class PullPush {
public:
    // Runs the pull (levels 1 .. top) and the push (top .. 0). `input` is RG32F (v, w) at the frame
    // size; `pull` and `push` RG32F with the full mip chain of ceil(w / 2) x ceil(h / 2) (the
    // convention above; InternalError otherwise); `output` R32F at the frame size. Leaves every
    // write visible to texture fetches, image loads and read-backs.
    void run(ProgramCache& programs, const Texture& input, Texture& pull, Texture& push, Texture& output);
};

// Pass "pull_push": reads `input` (RG32F (v, w), frame size), creates the pyramids
// "pull_push.pull" and "pull_push.push" and `output` (R32F, frame size). Every created resource
// carries `appliesWhen` (a condition on the technique's parameters; "" = always). A soft pass, like
// the rest of a back-projection technique's, and a wholeFrame one (never run in bands).
PassDesc pullPushPass(const std::string& input, const std::string& output, const std::string& appliesWhen);
// The two pyramids' declarations, "pull_push.pull" and "pull_push.push" (frame(2), the full mip
// chain), for a pass that reconstructs `input` and writes its output its own way (pullPushPass
// creates it; the back-projection techniques' pull_push pass modifies their "visibility").
std::vector<ResourceDesc> pullPushPyramids(const std::string& input, const std::string& appliesWhen);
// The two pyramids as Pyramid internals with channels {"visibility", "weight"}: "pull_push.pull"
// and "pull_push.push" (file level m is pull-push level m + 1).
std::vector<InternalDesc> pullPushInternals(const std::string& appliesWhen = "");

// CPU mirror: the same steps as the passes on the same shared functions. `vw` has 2 channels
// (v, w) and, like every Image, row 0 at the top (readTextureLevel's order). The odd-size rules
// (the last row takes the left-over one, the clamped bilinear) are not symmetric, so the mirror runs
// them in GL's row order (row 0 at the bottom) as the shaders do, flipping on the way in and out.
// Returns the completed visibility (1 channel, top first); `pull` and `push`, when given, receive
// pull-push levels 1 .. top (2 channels each, top first: readTextureLevel of the pyramids' mips).
Image pullPushCpu(const Image& vw, std::vector<Image>* pull = nullptr, std::vector<Image>* push = nullptr);

}  // namespace shadowlab
