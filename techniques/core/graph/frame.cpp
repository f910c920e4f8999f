#include "graph/frame.h"

#include "error.h"

namespace shadowlab {

PassContext::PassContext(FrameState& frame, LightState* light, ResourcePool& pool, std::string passName,
                         std::set<std::string> declared)
    : frame_(frame), light_(light), pool_(pool), passName_(std::move(passName)), declared_(std::move(declared)) {}

void PassContext::need(const std::string& name) {
    if (!declared_.count(name))
        throw InternalError("pass '" + passName_ + "' uses '" + name +
                            "' without declaring it (add it to the pass's reads): the graph could reuse stale outputs");
}

std::string PassContext::qualified(const std::string& name) const {
    return light_ ? light_->group + "/" + name : "frame/" + name;
}

const GBuffer& PassContext::gbuffer() {
    need("gbuffer");
    return frame_.gbuffer;
}

void PassContext::bindGBuffer(const ShaderProgram& program, GLuint firstUnit) {
    const GBuffer& g = gbuffer();
    glBindTextureUnit(firstUnit + 0, g.position->id());
    glBindTextureUnit(firstUnit + 1, g.normal->id());
    glBindTextureUnit(firstUnit + 2, g.material->id());
    program.set("gPosition", int(firstUnit + 0));
    program.set("gNormal", int(firstUnit + 1));
    program.set("gMaterial", int(firstUnit + 2));
}

const Bounds& PassContext::sceneBounds() {
    need("light");
    return frame_.bounds;
}

void PassContext::drawScene(const ShaderProgram& program, bool castersOnly) {
    need(castersOnly ? "scene.casters" : "scene.objects");
    frame_.gpu->draw(program, frame_.time, castersOnly);
}

double PassContext::sceneTime(bool castersOnly) {
    need(castersOnly ? "scene.casters" : "scene.objects");
    return frame_.time;
}

float PassContext::pixelValue(const std::string& name, glm::ivec2 pixel) {
    float v = 0.0f;
    glGetTextureSubImage(texture(name).id(), 0, pixel.x, height() - 1 - pixel.y, 0, 1, 1, 1, GL_RED, GL_FLOAT, sizeof v,
                         &v);
    return v;
}

const Camera& PassContext::camera() {
    need("camera");
    return frame_.camera;
}

float PassContext::ambient() {
    need("ambient");
    return frame_.ambient;
}

const LightState& PassContext::lightState() {
    if (!light_) throw InternalError("frame pass '" + passName_ + "' asked for a light");
    need("light");
    return *light_;
}
const Light& PassContext::light() { return lightState().light; }
const LightView& PassContext::lightView() { return lightState().view; }
glm::vec3 PassContext::lightRadiance() {
    if (!light_) throw InternalError("frame pass '" + passName_ + "' asked for a light");
    need("light.radiance");
    return light_->light.color * light_->light.intensity;
}

double PassContext::param(const std::string& key) {
    if (!light_) throw InternalError("frame pass '" + passName_ + "' asked for parameter " + key);
    need("param:" + key);
    return light_->params.get(key);
}

std::string PassContext::paramChoice(const std::string& key) {
    if (!light_) throw InternalError("frame pass '" + passName_ + "' asked for parameter " + key);
    need("param:" + key);
    return light_->params.getChoice(key);
}

bool PassContext::applies(const std::string& condition) {
    if (condition.empty()) return true;
    if (!light_) throw InternalError("frame pass '" + passName_ + "' evaluated a parameter condition");
    Condition parsed(condition, *light_->desc, passName_);
    for (const std::string& key : parsed.keys()) need("param:" + key);
    return parsed.holds(light_->params);
}

Resource& PassContext::resource(const std::string& name) {
    need(name);
    Resource* r = pool_.find(qualified(name));
    if (!r) throw InternalError("pass '" + passName_ + "': resource '" + qualified(name) + "' is not allocated");
    return *r;
}

// ---- parameters shared by shadow-map techniques ------------------------------------------------------
std::vector<ParamDesc> shadowMapParams() {
    using T = ParamDesc::Type;
    ParamDesc size{"sm_size", "", T::Int, "texels", 1024, 1, 8192, 1,
                   "shadow-map resolution (width = height); 1024 resolves the test scenes' hard edges to under a pixel at 512x512",
                   ""};
    ParamDesc biasConst{"bias_const", "", T::Float, "texels", 1.0, 0, 100, 0.1,
                        "constant depth bias, in world-size texels of the shadow map at the receiver; one texel hides the depth "
                        "quantisation of a flat receiver",
                        ""};
    ParamDesc biasSlope{"bias_slope", "", T::Float, "texels", 1.0, 0, 100, 0.1,
                        "slope-scaled depth bias: texels times tan(theta), theta the angle between receiver normal and light "
                        "(clamped at tan 10)",
                        ""};
    ParamDesc second{"second_depth", "", T::Bool, "", 0, 0, 1, 1,
                     "store the second-nearest depth (Wang and Molnar 1994): closed occluders' back faces, so lit surfaces "
                     "need no bias",
                     ""};
    return {size, biasConst, biasSlope, second};
}

}  // namespace shadowlab
