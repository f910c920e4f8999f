#pragma once
#include "renderer.h"
#include "shadow_map.h"

namespace shadowlab {

// Shadow map + per-pixel depth test. pcf reuses it with the PCF define (a kernel of tests).
class HardShadowTechnique : public TechniqueInstance {
public:
    explicit HardShadowTechnique(std::string shaderDefine);
    void run(const std::string& pass, RenderContext& ctx, LightState& light) override;
    const Texture& visibility() const override { return visibility_; }
    std::vector<std::pair<std::string, const Texture*>> buffers() const override;
    void writeInternals(InternalWriter& out, RenderContext& ctx, LightState& light) const override;
    nlohmann::json pixelInfo(glm::ivec2 pixel, RenderContext& ctx, LightState& light) const override;

private:
    std::string define_;
    ShadowMap shadowMap_;
    Texture visibility_;
    Framebuffer fbo_;
};

const TechniqueDesc& hardTechnique();

}  // namespace shadowlab
