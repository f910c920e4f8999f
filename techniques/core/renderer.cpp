#include "renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>

#include "error.h"

namespace shadowlab {

// ---- light frustum --------------------------------------------------------------------------------
LightView fitLightView(const Light& light, const glm::vec3& position, const Bounds& bounds) {
    LightView view;
    view.position = position;
    glm::vec3 up = light.up;
    if (std::abs(glm::dot(up, light.direction)) > 0.999f) up = std::abs(light.direction.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(0, 0, 1);
    view.viewFromWorld = glm::lookAt(position, position + light.direction, up);
    // Fit a symmetric frustum around the corners of the bounds in front of the light.
    float maxTan = 0.0f, minZ = 1e30f, maxZ = 0.0f;
    bool cornerBehind = bounds.empty();
    if (!bounds.empty()) {
        for (int i = 0; i < 8; ++i) {
            glm::vec3 corner((i & 1) ? bounds.hi.x : bounds.lo.x, (i & 2) ? bounds.hi.y : bounds.lo.y,
                             (i & 4) ? bounds.hi.z : bounds.lo.z);
            glm::vec3 v = glm::vec3(view.viewFromWorld * glm::vec4(corner, 1.0f));
            float z = -v.z;
            maxZ = std::max(maxZ, z);
            if (z <= 1e-6f * std::max(1.0f, std::abs(v.x) + std::abs(v.y))) {
                cornerBehind = true;
                continue;
            }
            minZ = std::min(minZ, z);
            maxTan = std::max({maxTan, std::abs(v.x) / z, std::abs(v.y) / z});
        }
    }
    // A corner beside or behind the light plane (the light inside the bounds, or at their edge)
    // needs the widest frustum, and a near plane close to the light: geometry may pass right by it.
    const float maxHalfAngleTan = std::tan(glm::radians(80.0f));
    view.tanHalfFov = cornerBehind ? maxHalfAngleTan : std::min(maxTan * 1.02f + 1e-4f, maxHalfAngleTan);
    if (maxZ <= 1e-6f) maxZ = 1.0f;
    view.farZ = maxZ * 1.01f;
    view.nearZ = cornerBehind ? view.farZ * 1e-6f : std::max(std::min(minZ * 0.9f, view.farZ * 0.5f), view.farZ * 1e-6f);
    // Reversed depth (near -> 1, far -> 0, with glClipControl GL_ZERO_TO_ONE in ShadowMap::render):
    // a float depth buffer then resolves surfaces equally well at every distance, so a near/far
    // ratio of 1e6 still orders nearby surfaces correctly. x and y do not depend on near and far.
    view.clipFromView = glm::perspectiveRH_ZO(2.0f * std::atan(view.tanHalfFov), 1.0f, view.farZ, view.nearZ);
    return view;
}

// ---- GPU scene --------------------------------------------------------------------------------------
GpuScene::GpuScene(const Scene& scene) : scene_(scene) {
    for (const Object& object : scene.objects) {
        GpuMesh m;
        std::vector<float> interleaved;
        interleaved.reserve(object.mesh.positions.size() * 6);
        for (size_t i = 0; i < object.mesh.positions.size(); ++i) {
            const glm::vec3& p = object.mesh.positions[i];
            glm::vec3 n = i < object.mesh.normals.size() ? object.mesh.normals[i] : glm::vec3(0, 1, 0);
            interleaved.insert(interleaved.end(), {p.x, p.y, p.z, n.x, n.y, n.z});
        }
        glCreateVertexArrays(1, &m.vao);
        glCreateBuffers(1, &m.vbo);
        glCreateBuffers(1, &m.ebo);
        glNamedBufferStorage(m.vbo, GLsizeiptr(std::max<size_t>(interleaved.size(), 1) * sizeof(float)),
                             interleaved.empty() ? nullptr : interleaved.data(), 0);
        glNamedBufferStorage(m.ebo, GLsizeiptr(std::max<size_t>(object.mesh.indices.size(), 1) * sizeof(uint32_t)),
                             object.mesh.indices.empty() ? nullptr : object.mesh.indices.data(), 0);
        glVertexArrayVertexBuffer(m.vao, 0, m.vbo, 0, 6 * sizeof(float));
        glVertexArrayElementBuffer(m.vao, m.ebo);
        glEnableVertexArrayAttrib(m.vao, 0);
        glEnableVertexArrayAttrib(m.vao, 1);
        glVertexArrayAttribFormat(m.vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
        glVertexArrayAttribFormat(m.vao, 1, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float));
        glVertexArrayAttribBinding(m.vao, 0, 0);
        glVertexArrayAttribBinding(m.vao, 1, 0);
        m.indexCount = GLsizei(object.mesh.indices.size());
        meshes_.push_back(m);
    }
}

GpuScene::~GpuScene() {
    for (GpuMesh& m : meshes_) {
        glDeleteVertexArrays(1, &m.vao);
        glDeleteBuffers(1, &m.vbo);
        glDeleteBuffers(1, &m.ebo);
    }
}

void GpuScene::draw(const ShaderProgram& program, double t, bool castersOnly) const {
    program.use();
    for (size_t i = 0; i < scene_.objects.size(); ++i) {
        const Object& object = scene_.objects[i];
        if (castersOnly && !object.castsShadows) continue;
        if (meshes_[i].indexCount == 0) continue;
        program.set("worldFromObject", object.worldFromObjectAt(t));
        program.set("albedo", object.albedo);
        program.set("objectId", float(object.id));
        program.set("receivesShadows", object.receivesShadows ? 1.0f : 0.0f);
        glBindVertexArray(meshes_[i].vao);
        glDrawElements(GL_TRIANGLES, meshes_[i].indexCount, GL_UNSIGNED_INT, nullptr);
    }
    glBindVertexArray(0);
}

// ---- internals ------------------------------------------------------------------------------------
static std::string joinPath(const std::string& dir, const std::string& name) {
    return (std::filesystem::path(dir) / name).string();
}

void InternalWriter::image(const std::string& name, const Image& img, const std::string& doc) {
    std::string file = prefix_ + name + ".pfm";
    std::filesystem::create_directories(std::filesystem::path(joinPath(directory_, file)).parent_path());
    writePFM(outputs_.stage(joinPath(directory_, file)), img);
    entries_.push_back({{"name", name}, {"file", file}, {"kind", "image"},
                        {"size", {img.width, img.height}}, {"channels", img.channels}, {"description", doc}});
}

void InternalWriter::geometry(const std::string& name, const std::string& objText, size_t primitives,
                              const std::string& doc) {
    std::string file = prefix_ + name + ".obj";
    std::filesystem::create_directories(std::filesystem::path(joinPath(directory_, file)).parent_path());
    std::ofstream(outputs_.stage(joinPath(directory_, file)), std::ios::binary) << objText;
    entries_.push_back({{"name", name}, {"file", file}, {"kind", "geometry"}, {"primitives", primitives},
                        {"description", doc}});
}

void InternalWriter::json(const std::string& name, const nlohmann::json& value, const std::string& doc) {
    std::string file = prefix_ + name + ".json";
    std::filesystem::create_directories(std::filesystem::path(joinPath(directory_, file)).parent_path());
    std::ofstream(outputs_.stage(joinPath(directory_, file)), std::ios::binary) << value.dump(2) << "\n";
    entries_.push_back({{"name", name}, {"file", file}, {"kind", "json"}, {"description", doc}});
}

void InternalWriter::writeIndex() {
    std::filesystem::create_directories(directory_);
    std::ofstream(outputs_.stage(joinPath(directory_, "index.json")), std::ios::binary)
        << nlohmann::json{{"files", entries_}}.dump(2) << "\n";
}

// ---- parameters shared by shadow-map techniques ------------------------------------------------------
std::vector<ParamDesc> shadowMapParams() {
    using T = ParamDesc::Type;
    return {
        {"sm_size", "", T::Int, "texels", 1024, 1, 8192, 1,
         "shadow-map resolution (width = height); 1024 resolves the test scenes' hard edges to under a pixel at 512x512", ""},
        {"bias_const", "", T::Float, "texels", 1.0, 0, 100, 0.1,
         "constant depth bias, in world-size texels of the shadow map at the receiver; one texel hides the depth quantisation of a flat receiver",
         ""},
        {"bias_slope", "", T::Float, "texels", 1.0, 0, 100, 0.1,
         "slope-scaled depth bias: texels times tan(theta), theta the angle between receiver normal and light (clamped at tan 10)",
         ""},
        {"second_depth", "", T::Bool, "", 0, 0, 1, 1,
         "store the second-nearest depth (Wang and Molnar 1994): closed occluders' back faces, so lit surfaces need no bias",
         ""},
    };
}

PassDesc shadowMapPass() {
    return {"shadow_map", {"scene.casters", "light", "param:sm_size", "param:second_depth"}, {"shadow_map"},
            "light-view depth of the casters from the light's centre (techniques/core/shadow_map.h)", false};
}

// ---- renderer -------------------------------------------------------------------------------------------
namespace {
constexpr double kSecondsPerFrame = 1.0 / 30.0;
constexpr int kMaxLights = 8;

uint64_t hashMat(const glm::mat4& m, uint64_t seed) { return hashBytes(&m[0][0], sizeof(float) * 16, seed); }

uint64_t hashLight(const Light& l, const LightView& v) {
    uint64_t h = hashValue(int(l.shape));
    h = hashBytes(&l.position, sizeof(glm::vec3), h);
    h = hashBytes(&l.direction, sizeof(glm::vec3), h);
    h = hashBytes(&l.up, sizeof(glm::vec3), h);
    h = hashValue(l.size, h);
    h = hashValue(l.castsShadows, h);
    h = hashMat(v.viewFromWorld, h);
    return hashMat(v.clipFromView, h);
}
}  // namespace

Renderer::Renderer(const Scene& scene, const RenderOptions& options) : scene_(scene), options_(options) {
    if (options.width < 1 || options.height < 1 || options.width > 8192 || options.height > 8192)
        throw InputError("--size: expected WxH with each side in 1..8192, got " + std::to_string(options.width) + "x" +
                         std::to_string(options.height));
    if (scene.lights.size() > size_t(kMaxLights))
        throw InputError(scene.path + ": lights: at most " + std::to_string(kMaxLights) + " lights are supported, got " +
                         std::to_string(scene.lights.size()));
    if (options.lightSize && (!std::isfinite(*options.lightSize) || *options.lightSize < 0.0f))
        throw InputError("--light-size: expected a finite number >= 0");

    // Resolve each light's technique and parameters before any GL work, so bad input writes nothing.
    std::set<std::string> usedKeys;
    for (size_t i = 0; i < scene.lights.size(); ++i) {
        auto state = std::make_unique<LightState>();
        state->index = int(i);
        state->group = "L" + std::to_string(i);
        state->light = scene.lights[i];
        if (options.lightSize) {
            state->light.size = *options.lightSize;
            if (*options.lightSize == 0.0f) state->light.shape = LightShape::Point;
        }
        std::string id = !options.technique.empty() ? options.technique
                         : !state->light.technique.empty() ? state->light.technique
                                                           : "hard";
        std::string where = !options.technique.empty() ? "--technique"
                                                       : scene.path + ": lights[" + std::to_string(i) + "].technique";
        state->requested = &requireTechnique(id, where);
        ParamValues requestedParams(*state->requested);
        for (const auto& [key, value] : options.sets) {
            if (state->requested->findParam(key)) {
                requestedParams.set(*state->requested, key, value, "--set " + key + "=" + value);
                usedKeys.insert(key);
            }
        }
        // A point light runs no soft-shadow pass: hard shadows, with the shadow-map settings.
        bool soft = std::any_of(state->requested->passes.begin(), state->requested->passes.end(),
                                [](const PassDesc& p) { return p.soft; });
        if (state->light.isPoint() && soft) {
            state->desc = &requireTechnique("hard", "internal");
            state->params = ParamValues(*state->desc);
            state->params.copySharedFrom(requestedParams);
        } else {
            state->desc = state->requested;
            state->params = requestedParams;
        }
        lights_.push_back(std::move(state));
    }
    for (const auto& [key, value] : options.sets) {
        if (usedKeys.count(key)) continue;
        std::string message = "--set " + key + "=" + value + ": unknown parameter '" + key + "'";
        std::set<std::string> ids;
        std::string known;
        for (const auto& l : lights_) {
            if (!ids.insert(l->requested->id).second) continue;
            for (const ParamDesc& p : l->requested->params) known += (known.empty() ? "" : ", ") + p.key;
        }
        message += std::string(ids.size() > 1 ? " (the techniques in use accept: " : " (the technique in use accepts: ") +
                   (known.empty() ? std::string("no parameters") : known) + ")";
        if (lights_.empty()) message = "--set " + key + ": the scene has no light, so no technique takes parameters";
        throw InputError(message);
    }

    // GL resources.
    gpu_ = std::make_unique<GpuScene>(scene);
    int w = options.width, h = options.height;
    gbuffer_.width = w;
    gbuffer_.height = h;
    gbuffer_.position = Texture(w, h, GL_RGBA32F);
    gbuffer_.normal = Texture(w, h, GL_RGBA32F);
    gbuffer_.material = Texture(w, h, GL_RGBA32F);
    gbuffer_.depth = Texture(w, h, GL_DEPTH_COMPONENT32F);
    gbuffer_.fbo = Framebuffer({&gbuffer_.position, &gbuffer_.normal, &gbuffer_.material}, &gbuffer_.depth);
    visibility_ = Texture(w, h, GL_R32F);
    image_ = Texture(w, h, GL_RGBA32F);
    visibilityFbo_ = Framebuffer({&visibility_}, nullptr);
    imageFbo_ = Framebuffer({&image_}, nullptr);
    white_ = Texture(1, 1, GL_R32F);
    const float one = 1.0f;
    glTextureSubImage2D(white_.id(), 0, 0, 0, 1, 1, GL_RED, GL_FLOAT, &one);
    for (auto& l : lights_) {
        if (l->light.castsShadows) l->instance = l->desc->create();
    }
    if (!options_.cpuClock) glCreateQueries(GL_TIME_ELAPSED, 1, &timerQuery_);
    buildGraph();
}

Renderer::~Renderer() {
    if (timerQuery_) glDeleteQueries(1, &timerQuery_);
}

double Renderer::timePass(const std::function<void()>& run) {
    if (options_.cpuClock) {
        glFinish();
        auto t0 = std::chrono::steady_clock::now();
        run();
        glFinish();
        auto t1 = std::chrono::steady_clock::now();
        return std::chrono::duration<double, std::milli>(t1 - t0).count();
    }
    glBeginQuery(GL_TIME_ELAPSED, timerQuery_);
    run();
    glEndQuery(GL_TIME_ELAPSED);
    GLuint64 ns = 0;
    glGetQueryObjectui64v(timerQuery_, GL_QUERY_RESULT, &ns);
    return double(ns) * 1e-6;
}

void Renderer::buildGraph() {
    // Frame resources: every pass reads named versions of these.
    graph_.setSource("scene.objects", 0);
    graph_.setSource("scene.casters", 0);
    graph_.setSource("camera", 0);

    graph_.addPass("gbuffer", "frame", "", {"scene.objects", "camera"}, {"gbuffer"}, [this] {
        const ShaderProgram& program = programs_.get("common/gbuffer.vert", "common/gbuffer.frag");
        float aspect = float(gbuffer_.width) / float(gbuffer_.height);
        program.use();
        program.set("viewFromWorld", scene_.camera.viewFromWorld());
        program.set("clipFromView", scene_.camera.clipFromView(aspect));
        gbuffer_.fbo.bind(gbuffer_.width, gbuffer_.height);
        const float zero[4] = {0, 0, 0, 0};
        const float background[4] = {0, 0, 0, -1};
        const float one = 1.0f;
        glClearNamedFramebufferfv(gbuffer_.fbo.id(), GL_COLOR, 0, zero);
        glClearNamedFramebufferfv(gbuffer_.fbo.id(), GL_COLOR, 1, zero);
        glClearNamedFramebufferfv(gbuffer_.fbo.id(), GL_COLOR, 2, background);
        glClearNamedFramebufferfv(gbuffer_.fbo.id(), GL_DEPTH, 0, &one);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glDisable(GL_CULL_FACE);
        glDisable(GL_BLEND);
        gpu_->draw(program, time_, false);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    });

    std::vector<std::string> visibilityInputs;
    for (auto& lp : lights_) {
        LightState& l = *lp;
        std::string g = l.group + "/";
        graph_.setSource(g + "light", 0);
        if (!l.light.castsShadows) {
            for (const PassDesc& p : l.requested->passes)
                graph_.addStaticSkip(g + l.requested->id + "/" + p.name, l.group, l.requested->id,
                                     "light casts no shadows: no shadow pass, visibility 1");
            continue;
        }
        if (l.desc != l.requested) {
            for (const PassDesc& p : l.requested->passes)
                graph_.addStaticSkip(g + l.requested->id + "/" + p.name, l.group, l.requested->id,
                                     "point light (size 0): soft-shadow passes do not run, `hard` passes replace them");
        }
        for (const auto& [key, value] : l.params.values()) graph_.setSource(g + "param:" + key, hashValue(value));
        for (const PassDesc& pass : l.desc->passes) {
            std::vector<std::string> inputs, outputs;
            for (const std::string& in : pass.inputs) {
                bool frameResource = in == "gbuffer" || in.rfind("scene.", 0) == 0 || in == "camera";
                inputs.push_back(frameResource ? in : g + in);
            }
            for (const std::string& out : pass.outputs) outputs.push_back(g + out);
            std::string passName = pass.name;
            graph_.addPass(g + l.desc->id + "/" + pass.name, l.group, l.desc->id, inputs, outputs, [this, &l, passName] {
                RenderContext ctx{scene_, *gpu_, programs_, gbuffer_, bounds_, time_, gbuffer_.width, gbuffer_.height};
                l.instance->run(passName, ctx, l);
            });
        }
        visibilityInputs.push_back(g + "visibility");
    }
    std::vector<std::string> combineInputs = visibilityInputs;
    combineInputs.insert(combineInputs.begin(), "gbuffer");
    for (auto& l : lights_) combineInputs.push_back(l->group + "/light");

    auto bindLights = [this](const ShaderProgram& program) {
        program.set("lightCount", int(lights_.size()));
        for (size_t i = 0; i < lights_.size(); ++i) {
            const LightState& l = *lights_[i];
            std::string idx = "[" + std::to_string(i) + "]";
            program.set(("lightPositions" + idx).c_str(), l.light.position);
            program.set(("lightRadiance" + idx).c_str(), l.light.color * l.light.intensity);
            glBindTextureUnit(GLuint(3 + i), l.instance ? l.instance->visibility().id() : white_.id());
            program.set(("lightVisibility" + idx).c_str(), int(3 + i));
        }
        glBindTextureUnit(0, gbuffer_.position.id());
        glBindTextureUnit(1, gbuffer_.normal.id());
        glBindTextureUnit(2, gbuffer_.material.id());
        program.set("gPosition", 0);
        program.set("gNormal", 1);
        program.set("gMaterial", 2);
    };

    graph_.addPass("visibility", "frame", "", combineInputs, {"visibility"}, [this, bindLights] {
        const ShaderProgram& program = programs_.get("common/fullscreen.vert", "common/combine.frag");
        visibilityFbo_.bind(gbuffer_.width, gbuffer_.height);
        glDisable(GL_DEPTH_TEST);
        glDisable(GL_BLEND);
        program.use();
        bindLights(program);
        drawFullscreenTriangle();
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    });
    graph_.addPass("shade", "frame", "", combineInputs, {"image"}, [this, bindLights] {
        const ShaderProgram& program = programs_.get("common/fullscreen.vert", "common/shade.frag");
        imageFbo_.bind(gbuffer_.width, gbuffer_.height);
        glDisable(GL_DEPTH_TEST);
        glDisable(GL_BLEND);
        program.use();
        bindLights(program);
        program.set("ambient", scene_.ambient);
        drawFullscreenTriangle();
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    });
}

void Renderer::updateSources(int frame) {
    time_ = frame * kSecondsPerFrame;
    bounds_ = scene_.bounds(time_);
    uint64_t objects = 1469598103934665603ull, casters = objects;
    for (size_t i = 0; i < scene_.objects.size(); ++i) {
        const Object& o = scene_.objects[i];
        glm::mat4 m = o.worldFromObjectAt(time_);
        objects = hashMat(m, hashValue(i, objects));
        if (o.castsShadows) casters = hashMat(m, hashValue(i, casters));
    }
    graph_.setSource("scene.objects", objects);
    graph_.setSource("scene.casters", casters);
    uint64_t camera = hashBytes(&scene_.camera, sizeof(Camera));
    camera = hashValue(gbuffer_.width, hashValue(gbuffer_.height, camera));
    graph_.setSource("camera", camera);
    for (auto& l : lights_) {
        l->view = fitLightView(l->light, l->light.position, bounds_);
        graph_.setSource(l->group + "/light", hashLight(l->light, l->view));
    }
}

void Renderer::renderFrame(int frame, const std::set<std::string>& requested) {
    updateSources(frame);
    if (!options_.reuse) graph_.invalidate();
    graph_.execute(requested, frame, [this](const std::function<void()>& run) { return timePass(run); });
}

Image Renderer::visibility() const { return readTexture(visibility_, 1); }

// xyz of a G-buffer texture, NaN on background pixels (position.w == 0).
static Image geometryChannels(const Texture& texture, const Texture& position) {
    Image t = readTexture(texture, 4);
    Image p = &texture == &position ? t : readTexture(position, 4);
    Image out(t.width, t.height, 3);
    for (size_t i = 0; i < t.pixelCount(); ++i)
        for (int c = 0; c < 3; ++c) out.data[i * 3 + c] = p.data[i * 4 + 3] == 0.0f ? NAN : t.data[i * 4 + c];
    return out;
}

Image Renderer::positions() const { return geometryChannels(gbuffer_.position, gbuffer_.position); }
Image Renderer::normals() const { return geometryChannels(gbuffer_.normal, gbuffer_.position); }

Image Renderer::ids() const {
    Image m = readTexture(gbuffer_.material, 4);
    Image out(m.width, m.height, 1);
    for (size_t i = 0; i < m.pixelCount(); ++i) out.data[i] = m.data[i * 4 + 3];
    return out;
}

Image Renderer::image() const {
    Image linear = readTexture(image_, 4);
    Image out(linear.width, linear.height, 3);
    for (size_t i = 0; i < linear.pixelCount(); ++i) {
        for (int c = 0; c < 3; ++c) {
            float v = std::clamp(linear.data[i * 4 + c], 0.0f, 1.0f);
            out.data[i * 3 + c] = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
        }
    }
    return out;
}

void Renderer::writeInternals(InternalWriter& out, std::optional<glm::ivec2> pixel) {
    RenderContext ctx{scene_, *gpu_, programs_, gbuffer_, bounds_, time_, gbuffer_.width, gbuffer_.height};
    nlohmann::json pixelData;
    for (auto& l : lights_) {
        out.setPrefix(l->index == 0 ? "" : "light" + std::to_string(l->index) + "/");
        if (!l->instance) continue;
        l->instance->writeInternals(out, ctx, *l);
        out.image("visibility", readTexture(l->instance->visibility(), 1),
                  "visibility v in [0,1] of this light alone (" + l->desc->id + ")");
        if (pixel) {
            nlohmann::json info = l->instance->pixelInfo(*pixel, ctx, *l);
            info["light"] = l->index;
            info["technique"] = l->desc->id;
            pixelData["lights"].push_back(info);
        }
    }
    out.setPrefix("");
    if (pixel) {
        Image pos = positions();
        Image vis = visibility();
        int x = pixel->x, y = pixel->y;
        pixelData["pixel"] = {x, y};
        if (std::isfinite(pos.at(x, y, 0)))
            pixelData["position"] = {pos.at(x, y, 0), pos.at(x, y, 1), pos.at(x, y, 2)};
        else
            pixelData["position"] = nullptr;
        pixelData["visibility"] = vis.at(x, y);
        out.json("pixel", pixelData, "per-pixel data of the picked pixel (--pixel x,y; y counted from the top)");
    }
    out.writeIndex();
}

static double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

nlohmann::json Renderer::stats(const std::vector<double>& frameMs, int warmupFrames) const {
    nlohmann::json j;
    j["scene"] = scene_.name;
    j["resolution"] = {gbuffer_.width, gbuffer_.height};
    j["clock"] = clockName();
    j["reuse"] = options_.reuse;
    j["warmup_frames"] = warmupFrames;
    j["frames"] = frameMs.size();
    j["total_ms"] = median(frameMs);
    j["frame_ms"] = frameMs;
    j["lights"] = nlohmann::json::array();
    for (const auto& l : lights_) {
        nlohmann::json lj{{"index", l->index},
                          {"name", l->light.name},
                          {"shape", lightShapeName(l->light.shape)},
                          {"size", l->light.size},
                          {"casts_shadows", l->light.castsShadows},
                          {"technique_requested", l->requested->id},
                          {"technique", l->light.castsShadows ? l->desc->id : "none (casts no shadows)"}};
        for (const auto& [key, value] : l->params.values()) lj["parameters"][key] = value;
        j["lights"].push_back(lj);
    }
    j["passes"] = nlohmann::json::array();
    for (const PassRecord& r : graph_.records()) {
        j["passes"].push_back({{"name", r.name},
                               {"group", r.group},
                               {"technique", r.technique},
                               {"status", r.status},
                               {"reason", r.reason},
                               {"runs", r.runs},
                               {"reuses", r.reuses},
                               {"not_needed", r.notNeeded},
                               {"median_ms", median(r.ms)},
                               {"history", r.history}});
    }
    size_t total = 0;
    j["buffers"] = nlohmann::json::array();
    auto addBuffer = [&](const std::string& name, const Texture& t) {
        if (!t) return;
        total += t.bytes();
        j["buffers"].push_back({{"name", name}, {"width", t.width()}, {"height", t.height()}, {"format", t.formatName()},
                                {"bytes", t.bytes()}});
    };
    addBuffer("gbuffer.position", gbuffer_.position);
    addBuffer("gbuffer.normal", gbuffer_.normal);
    addBuffer("gbuffer.material", gbuffer_.material);
    addBuffer("gbuffer.depth", gbuffer_.depth);
    addBuffer("visibility", visibility_);
    addBuffer("image", image_);
    for (const auto& l : lights_) {
        if (!l->instance) continue;
        for (const auto& [name, tex] : l->instance->buffers()) addBuffer(l->group + "/" + name, *tex);
    }
    j["memory_bytes"] = total;
    return j;
}

}  // namespace shadowlab
