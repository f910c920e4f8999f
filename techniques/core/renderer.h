// The renderer core: GPU scene, G-buffer, shadow maps, the per-light technique instances and the
// pass graph that runs them (DESIGN.md section 3).
#pragma once
#include <glm/glm.hpp>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "gl_program.h"  // ProgramCache, one per GL context
#include "gl_util.h"
#include "image.h"
#include "pass_graph.h"
#include "scene.h"
#include "technique.h"

namespace shadowlab {

// The frustum of a shadow map rendered from `position` with the light's orientation, fitted to the
// world bounds of the scene: symmetric, half-angle atan(tanHalfFov) at most 80 degrees, depth range
// [nearZ, farZ] in world units along the light's axis.
struct LightView {
    glm::vec3 position{0.0f};
    glm::mat4 viewFromWorld{1.0f};
    glm::mat4 clipFromView{1.0f};
    float tanHalfFov = 1.0f;
    float nearZ = 0.1f;
    float farZ = 100.0f;
};
LightView fitLightView(const Light& light, const glm::vec3& position, const Bounds& bounds);

// Meshes uploaded once; draw() binds each object's transform at time t.
class GpuScene {
public:
    explicit GpuScene(const Scene& scene);
    ~GpuScene();
    GpuScene(const GpuScene&) = delete;
    GpuScene& operator=(const GpuScene&) = delete;
    // Sets uniforms worldFromObject, albedo, objectId, receivesShadows on `program` per object.
    void draw(const ShaderProgram& program, double t, bool castersOnly) const;

private:
    const Scene& scene_;
    struct GpuMesh {
        GLuint vao = 0, vbo = 0, ebo = 0;
        GLsizei indexCount = 0;
    };
    std::vector<GpuMesh> meshes_;
};

// G-buffer from the camera (DESIGN.md section 3). position: xyz world, w = 1 on geometry and 0 on
// background; normal: xyz unit world normal, w = 1 when the object receives shadows; material:
// albedo rgb, object id in a (-1 on background).
struct GBuffer {
    int width = 0, height = 0;
    Texture position, normal, material, depth;
    Framebuffer fbo;
};

// What a pass sees of the frame.
struct RenderContext {
    const Scene& scene;
    GpuScene& gpu;
    ProgramCache& programs;
    const GBuffer& gbuffer;
    const Bounds& bounds;  // world bounds of all objects at `time`
    double time = 0.0;
    int width = 0, height = 0;
};

class TechniqueInstance;
// One shadow-casting light with its technique.
struct LightState {
    int index = 0;
    std::string group;              // "L0", "L1", ...
    Light light;                    // after --light-size
    const TechniqueDesc* requested = nullptr;  // what the user asked for
    const TechniqueDesc* desc = nullptr;       // what runs: `hard` for a point light and a soft technique
    ParamValues params;             // of desc
    LightView view;                 // light-centre frustum at the current time
    std::unique_ptr<TechniqueInstance> instance;
};

// Writes --internals files through an OutputSet and keeps index.json's entries.
class InternalWriter {
public:
    InternalWriter(const std::string& directory, OutputSet& outputs) : directory_(directory), outputs_(outputs) {}
    void image(const std::string& name, const Image& image, const std::string& doc);
    void geometry(const std::string& name, const std::string& objText, size_t primitives, const std::string& doc);
    void json(const std::string& name, const nlohmann::json& value, const std::string& doc);
    void setPrefix(const std::string& prefix) { prefix_ = prefix; }  // "" or "light1/"
    void writeIndex();

private:
    std::string directory_;
    OutputSet& outputs_;
    std::string prefix_;
    nlohmann::json entries_ = nlohmann::json::array();
};

class TechniqueInstance {
public:
    virtual ~TechniqueInstance() = default;
    // Runs one pass of the descriptor for this light.
    virtual void run(const std::string& pass, RenderContext& ctx, LightState& light) = 0;
    // The light's visibility buffer (R32F, frame size), valid once the last pass ran.
    virtual const Texture& visibility() const = 0;
    // GPU buffers the technique owns, for the memory figures of --stats.
    virtual std::vector<std::pair<std::string, const Texture*>> buffers() const = 0;
    // Exposes internals (DESIGN.md section 4) and, for a picked pixel, its per-pixel data.
    virtual void writeInternals(InternalWriter& out, RenderContext& ctx, LightState& light) const = 0;
    virtual nlohmann::json pixelInfo(glm::ivec2 pixel, RenderContext& ctx, LightState& light) const = 0;
};

struct RenderOptions {
    int width = 512;
    int height = 512;
    std::string technique;  // "" = each light's default technique (its "technique" field, else hard)
    std::vector<std::pair<std::string, std::string>> sets;  // --set key=value, validated
    std::optional<float> lightSize;  // --light-size
    bool cpuClock = true;            // time passes on the CPU around glFinish (llvmpipe)
    bool reuse = true;               // false: every needed pass runs every frame (for timing)
};

class Renderer {
public:
    // Validates the options against the scene and the technique tables (InputError) and builds
    // the pass graph. Needs a current GL context.
    Renderer(const Scene& scene, const RenderOptions& options);
    ~Renderer();

    // Renders frame `frame` at t = frame / 30 s, running only what `requested` needs
    // ("image", "visibility", "gbuffer").
    void renderFrame(int frame, const std::set<std::string>& requested);

    Image visibility() const;  // 1 channel, combined over the lights (see shaders/common/combine.frag)
    Image positions() const;   // 3 channels, NaN on background
    Image normals() const;     // 3 channels, NaN on background
    Image ids() const;         // 1 channel, -1 on background
    Image image() const;       // 3 channels, sRGB-encoded shaded image in [0,1]

    void writeInternals(InternalWriter& out, std::optional<glm::ivec2> pixel);
    nlohmann::json stats(const std::vector<double>& frameMs, int warmupFrames) const;

    const PassGraph& graph() const { return graph_; }
    const std::vector<std::unique_ptr<LightState>>& lights() const { return lights_; }
    const Texture& imageTexture() const { return image_; }
    const char* clockName() const { return options_.cpuClock ? "cpu-finish" : "gpu-timer"; }
    double time() const { return time_; }

private:
    void buildGraph();
    void updateSources(int frame);
    double timePass(const std::function<void()>& run);

    const Scene& scene_;
    RenderOptions options_;
    double time_ = 0.0;
    Bounds bounds_;
    std::unique_ptr<GpuScene> gpu_;
    ProgramCache& programs_ = programCache();  // the current GL context's
    GBuffer gbuffer_;
    Texture visibility_;  // combined
    Texture image_;       // shaded, linear RGBA32F
    Texture white_;       // 1x1 visibility 1, for lights that cast no shadow
    Framebuffer visibilityFbo_, imageFbo_;
    std::vector<std::unique_ptr<LightState>> lights_;
    PassGraph graph_;
    GLuint timerQuery_ = 0;
};

// Shadow-map parameters shared by every shadow-map technique (one table, STYLE.md 3).
std::vector<ParamDesc> shadowMapParams();
// The pass that renders the light-centre shadow map, as hard and pcf declare it.
PassDesc shadowMapPass();

}  // namespace shadowlab
