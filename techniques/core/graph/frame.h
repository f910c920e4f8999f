// What a pass sees of the frame: the scene, its GPU meshes, the G-buffer, the light with its
// technique and parameters, and the resources of the pool, all through a PassContext that checks
// every access against the pass's declaration (an undeclared read is an error, caught in tests and
// by --check-reuse).
#pragma once
#include <glm/glm.hpp>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "gl/util.h"
#include "graph/resources.h"
#include "graph/technique.h"
#include "scene/gpu_scene.h"
#include "scene/light_view.h"
#include "scene/scene.h"

namespace shadowlab {

// G-buffer from the camera (DESIGN.md section 3). position: xyz world, w = 1 on geometry and 0 on
// background; normal: xyz unit world normal, w = 1 when the object receives shadows; material:
// albedo rgb, object id in a (-1 on background); depth: camera depth and stencil (DEPTH32F_STENCIL8).
struct GBuffer {
    int width = 0, height = 0;
    const Texture* position = nullptr;
    const Texture* normal = nullptr;         // geometric (the triangle's plane): what visibility uses
    const Texture* shadingNormal = nullptr;  // interpolated vertex normal: the shading cosine only
    const Texture* material = nullptr;
    const Texture* depth = nullptr;
};

// The frame as every pass of it sees it.
struct FrameState {
    const Scene* scene = nullptr;
    GpuScene* gpu = nullptr;
    ProgramCache* programs = nullptr;
    GBuffer gbuffer;
    Bounds bounds;  // world bounds of all objects at `time`
    double time = 0.0;
    int width = 0, height = 0;
    Camera camera;
    float ambient = 0.0f;
};

// One shadow-casting light with its technique.
struct LightState {
    int index = 0;
    std::string group;              // "L0", "L1", ...
    Light light;                    // after --light-size and setLight
    const TechniqueDesc* requested = nullptr;  // what the user asked for
    const TechniqueDesc* desc = nullptr;       // what runs: `hard` for a point light and a soft technique
    ParamValues requestedParams;    // of requested
    ParamValues params;             // of desc
    LightView view;                 // light-centre frustum at the current time
    // A choosing technique's (`auto`'s) pick and why (TechniqueChoice::report); null otherwise.
    nlohmann::json choice;
    bool idle = false;              // the choice runs nothing: no pass, visibility 1
    bool runs() const { return light.castsShadows && !idle; }  // the light's passes run
};

class PassContext {
public:
    // `declared`: the unqualified names the pass (or record) declared it reads or writes; `light` is
    // null for frame passes.
    PassContext(FrameState& frame, LightState* light, ResourcePool& pool, std::string passName,
                std::set<std::string> declared);

    // ---- the frame
    const Scene& scene() const { return *frame_.scene; }
    ProgramCache& programs() { return *frame_.programs; }
    int width() const { return frame_.width; }
    int height() const { return frame_.height; }
    const GBuffer& gbuffer();              // declares nothing: needs "gbuffer"
    void bindGBuffer(const ShaderProgram& program, GLuint firstUnit = 0);  // gPosition, gNormal, gMaterial
    const Bounds& sceneBounds();           // needs "light" (the light view is fitted to it)
    // Draws the scene's objects (all: "scene.objects"; casters only: "scene.casters").
    void drawScene(const ShaderProgram& program, bool castersOnly);
    // The time at which the objects ("scene.objects") or the casters ("scene.casters") are posed.
    double sceneTime(bool castersOnly);
    const Camera& camera();                // needs "camera"
    float ambient();                       // needs "ambient"

    // ---- the light (needs "light"; its colour and intensity need "light.radiance")
    const LightState& lightState();
    const Light& light();
    const LightView& lightView();
    glm::vec3 lightRadiance();

    // ---- parameters (needs "param:<key>")
    double param(const std::string& key);
    int paramInt(const std::string& key) { return int(param(key)); }
    bool paramBool(const std::string& key) { return param(key) != 0.0; }
    std::string paramChoice(const std::string& key);
    bool applies(const std::string& condition);  // a condition on parameters (reads those it names)

    // ---- resources of this light's group (or frame resources for frame passes)
    Resource& resource(const std::string& name);
    Texture& texture(const std::string& name) { return resource(name).texture; }
    MeshData& mesh(const std::string& name) { return resource(name).mesh; }
    GLuint buffer(const std::string& name) { return resource(name).buffer; }
    std::string qualified(const std::string& name) const;
    // One texel of a float resource at a picked pixel (x, y from the top), channel 0.
    float pixelValue(const std::string& name, glm::ivec2 pixel);

    const std::string& passName() const { return passName_; }

private:
    void need(const std::string& name);
    FrameState& frame_;
    LightState* light_;
    ResourcePool& pool_;
    std::string passName_;
    std::set<std::string> declared_;
};

// Shadow-map parameters shared by every shadow-map technique (one table, STYLE.md 3).
std::vector<ParamDesc> shadowMapParams();

}  // namespace shadowlab
