#include "graph/renderer.h"

#include <algorithm>
#include <tuple>
#include <chrono>
#include <cmath>
#include <cstring>

#include "error.h"

namespace shadowlab {

namespace {

uint64_t hashMat(const glm::mat4& m, uint64_t seed) { return hashBytes(&m[0][0], sizeof(float) * 16, seed); }

// What shadows depend on: shape, pose, size, and the fitted light view. Colour and intensity are
// versioned apart ("light.radiance"): changing them re-shades without re-running shadow passes.
uint64_t hashLightGeometry(const Light& l, const LightView& v) {
    uint64_t h = hashValue(int(l.shape));
    h = hashBytes(&l.position, sizeof(glm::vec3), h);
    h = hashBytes(&l.direction, sizeof(glm::vec3), h);
    h = hashBytes(&l.up, sizeof(glm::vec3), h);
    h = hashValue(l.size, h);
    h = hashValue(l.castsShadows, h);
    h = hashMat(v.viewFromWorld, h);
    return hashMat(v.clipFromView, h);
}

uint64_t hashRadiance(const Light& l) {
    uint64_t h = hashBytes(&l.color, sizeof(glm::vec3));
    return hashValue(l.intensity, h);
}

uint64_t hashCamera(const Camera& c, int width, int height) {
    uint64_t h = hashBytes(&c.position, sizeof(glm::vec3));
    h = hashBytes(&c.target, sizeof(glm::vec3), h);
    h = hashBytes(&c.up, sizeof(glm::vec3), h);
    h = hashValue(c.fovYDegrees, h);
    h = hashValue(c.nearPlane, h);
    h = hashValue(c.farPlane, h);
    return hashValue(width, hashValue(height, h));
}

bool isFrameResource(const std::string& name) {
    return name == "gbuffer" || name == "camera" || name == "ambient" || name.rfind("scene.", 0) == 0;
}

// A resource of a technique that is a 2D texture of the frame's size (SizeRule::frame(), or like
// one); `desc` holds the declarations its size rule may point to.
bool isFrameTexture(const TechniqueDesc& desc, const std::string& name, int depth = 0) {
    if (name == "gbuffer") return true;
    if (depth > 16) return false;
    for (const PassDesc& p : desc.passes)
        for (const ResourceDesc& r : p.creates) {
            if (r.name != name) continue;
            if (r.kind != ResourceKind::Texture || r.size.scaleDown != 1) return false;
            if (r.size.kind == SizeRule::Kind::Frame) return true;
            return r.size.kind == SizeRule::Kind::Like && isFrameTexture(desc, r.size.from, depth + 1);
        }
    return false;
}

// A pass refineFrame may run in bands of rows: everything it writes is a frame-size texture (or its
// own scratch buffer, filled anew by every band), so a scissor bounds its work (clears and draws honour it; its fragments depend on their own pixel's
// inputs or on complete earlier passes).
bool writesOnlyFrameTextures(const TechniqueDesc& desc, const PassDesc& pass) {
    if (pass.wholeFrame || (pass.creates.empty() && pass.modifies.empty())) return false;
    for (const ResourceDesc& r : pass.creates)
        if (!r.scratch && !isFrameTexture(desc, r.name)) return false;
    for (const std::string& m : pass.modifies)
        if (!isFrameTexture(desc, m)) return false;
    return true;
}

// What light `s` runs: its requested technique, a choosing technique's pick (`auto`), and `hard`
// in place of a soft technique for a point light. Returns whether the technique or its parameters
// changed.
bool resolveLightTechnique(LightState& s, const Scene& scene, const Camera& camera, int width, int height,
                           double time, const std::vector<Light>& lights, bool measure) {
    const TechniqueDesc* before = s.desc;
    const std::map<std::string, double> beforeValues = s.params.values();
    const bool wasIdle = s.idle;
    if (s.requested->choose) {
        ChoiceInputs in;
        in.scene = &scene;
        in.light = &s.light;
        in.camera = &camera;
        in.width = width;
        in.height = height;
        in.params = &s.requestedParams;
        in.time = time;
        in.lights = lights;
        in.lightIndex = s.index;
        in.measure = measure;
        TechniqueChoice c = s.requested->choose(in);
        s.choice = c.report;
        s.idle = c.desc == nullptr;
        const TechniqueDesc& picked = c.desc ? *c.desc : requireTechnique("hard", "auto");
        const ParamValues values = c.desc ? *c.params : ParamValues(picked);
        std::tie(s.desc, s.params) = techniqueForLight(picked, values, s.light.isPoint());
    } else {
        s.choice = nullptr;
        s.idle = false;
        std::tie(s.desc, s.params) = techniqueForLight(*s.requested, s.requestedParams, s.light.isPoint());
    }
    return s.desc != before || s.params.values() != beforeValues || s.idle != wasIdle;
}

}  // namespace

std::vector<LightState> Renderer::resolveLights(const Scene& scene, const RenderOptions& options) {
    if (options.lightSize && (!std::isfinite(*options.lightSize) || *options.lightSize < 0.0f))
        throw InputError("--light-size: expected a finite number >= 0");
    // Resolve each light's technique and parameters before any GL work, so bad input writes nothing.
    std::set<std::string> usedKeys;
    std::vector<LightState> lights(scene.lights.size());
    for (size_t i = 0; i < scene.lights.size(); ++i) {
        LightState& state = lights[i];
        state.index = int(i);
        state.group = "L" + std::to_string(i);
        state.light = scene.lights[i];
        if (options.lightSize) {
            state.light.size = *options.lightSize;
            if (*options.lightSize == 0.0f) state.light.shape = LightShape::Point;
        }
        std::string id = !options.technique.empty() ? options.technique
                         : !state.light.technique.empty() ? state.light.technique
                                                          : "hard";
        std::string where = !options.technique.empty() ? "--technique"
                                                       : scene.path + ": lights[" + std::to_string(i) + "].technique";
        state.requested = &requireTechnique(id, where);
        state.requestedParams = ParamValues(*state.requested);
        for (const auto& [key, value] : options.sets) {
            if (state.requested->findParam(key)) {
                state.requestedParams.set(*state.requested, key, value, "--set " + key + "=" + value);
                usedKeys.insert(key);
            }
        }
    }
    std::vector<Light> all;
    for (const LightState& state : lights) all.push_back(state.light);
    for (LightState& state : lights) resolveLightTechnique(state, scene, scene.camera, options.width, options.height, 0.0, all, false);
    for (const auto& [key, value] : options.sets) {
        if (usedKeys.count(key)) continue;
        std::string message = "--set " + key + "=" + value + ": unknown parameter '" + key + "'";
        std::set<std::string> ids;
        std::string known;
        for (const LightState& l : lights) {
            if (!ids.insert(l.requested->id).second) continue;
            for (const ParamDesc& p : l.requested->params) known += (known.empty() ? "" : ", ") + p.key;
        }
        message += std::string(ids.size() > 1 ? " (the techniques in use accept: " : " (the technique in use accepts: ") +
                   (known.empty() ? std::string("no parameters") : known) + ")";
        if (lights.empty()) message = "--set " + key + ": the scene has no light, so no technique takes parameters";
        throw InputError(message);
    }

    return lights;
}

Renderer::Renderer(const Scene& scene, const RenderOptions& options)
    : scene_(scene), options_(options) {
    pool_.setSpareBytes(options.spareBytes);
    if (options.width < 1 || options.height < 1 || options.width > 8192 || options.height > 8192)
        throw InputError("--size: expected WxH with each side in 1..8192, got " + std::to_string(options.width) + "x" +
                         std::to_string(options.height));
    if (scene.lights.size() > size_t(kMaxLights))
        throw InputError(scene.path + ": lights: at most " + std::to_string(kMaxLights) + " lights are supported, got " +
                         std::to_string(scene.lights.size()));

    // Resolve each light's technique and parameters before any GL work, so bad input writes nothing.
    for (LightState& state : resolveLights(scene, options)) {
        auto slot = std::make_unique<LightSlot>();
        slot->state = std::move(state);
        lights_.push_back(std::move(slot));
    }

    // GL resources.
    gpu_ = std::make_unique<GpuScene>(scene);
    frame_.scene = &scene;
    frame_.gpu = gpu_.get();
    frame_.programs = &programs_;
    frame_.width = options.width;
    frame_.height = options.height;
    frame_.camera = scene.camera;
    frame_.ambient = scene.ambient;
    allocateFrameResources();
    white_ = Texture(1, 1, GL_R32F);
    const float one = 1.0f;
    glTextureSubImage2D(white_.id(), 0, 0, 0, 1, 1, GL_RED, GL_FLOAT, &one);
    for (auto& l : lights_) configureLight(*l);
    if (!options_.cpuClock) glCreateQueries(GL_TIME_ELAPSED, 1, &timerQuery_);
    buildGraph();
}

Renderer::~Renderer() {
    if (timerQuery_) glDeleteQueries(1, &timerQuery_);
}

// ---- configuration ------------------------------------------------------------------------------------
void Renderer::configureLight(LightSlot& slot) {
    LightState& s = slot.state;
    // A point light runs no soft-shadow pass: hard shadows, with the shadow-map settings; `auto`
    // runs what it picks for this light, camera and frame.
    resolveLightTechnique(s, scene_, frame_.camera, frame_.width, frame_.height, frame_.time, frameLights(), measureChoices_);
    slot.passes.clear();
    if (s.runs())
        for (const PassDesc& p : s.desc->passes) slot.passes.push_back(p.create());
}

void Renderer::allocateFrameResources() {
    int w = frame_.width, h = frame_.height;
    auto tex = [&](const std::string& name, Format f, const std::string& doc) -> const Texture* {
        return &pool_.ensure("frame/" + name, ResourceDesc::texture(name, f, SizeRule::frame(), doc), w, h).texture;
    };
    frame_.gbuffer.width = w;
    frame_.gbuffer.height = h;
    frame_.gbuffer.position = tex("gbuffer.position", Format::RGBA32F, "world position xyz; w = 1 on geometry, 0 on background");
    frame_.gbuffer.normal = tex("gbuffer.normal", Format::RGBA32F,
                                "unit geometric normal xyz (the triangle's plane: visibility's tangent plane); w = 1 when "
                                "the object receives shadows");
    frame_.gbuffer.material = tex("gbuffer.material", Format::RGBA32F, "albedo rgb; a = object id (-1 on background)");
    frame_.gbuffer.shadingNormal = tex("gbuffer.shading_normal", Format::RGBA16F,
                                       "unit interpolated vertex normal xyz, for the shading cosine only");
    frame_.gbuffer.depth = tex("gbuffer.depth", Format::DEPTH32F_STENCIL8,
                               "camera depth and an 8-bit stencil (cleared to 0; for shadow-volume counts)");
    const Texture* visibility = tex("visibility", Format::R32F, "the frame's visibility v, combined over the lights");
    const Texture* image = tex("image", Format::RGBA32F, "the shaded image, linear RGB");
    gbufferFbo_ = Framebuffer({frame_.gbuffer.position, frame_.gbuffer.normal, frame_.gbuffer.material,
                               frame_.gbuffer.shadingNormal},
                              frame_.gbuffer.depth);
    shadeFbo_ = Framebuffer({visibility, image}, nullptr);
}

std::vector<size_t> Renderer::lightIndices(int light) const {
    std::vector<size_t> out;
    if (light >= int(lights_.size())) throw InputError("light " + std::to_string(light) + ": the scene has " +
                                                       std::to_string(lights_.size()) + " light(s)");
    for (size_t i = 0; i < lights_.size(); ++i)
        if (light < 0 || size_t(light) == i) out.push_back(i);
    return out;
}

void Renderer::buildGraph() {
    graph_.rebuild();
    // Frame sources; their versions are set by updateSources() before every frame.
    for (const char* source : {"scene.objects", "scene.casters", "camera", "ambient"})
        if (!graph_.produces(source)) graph_.setSource(source, graph_.version(source));

    graph_.addPass("gbuffer", "frame", "", {"scene.objects", "camera"}, {"gbuffer"}, {}, [this] {
        PipelineState state = PipelineState::fullscreen();
        state.depthTest = true;
        state.depthFunc = GL_LESS;
        state.apply();
        PassContext ctx(frame_, nullptr, pool_, "gbuffer", {"scene.objects", "camera"});
        const ShaderProgram& program = programs_.get("common/gbuffer.vert", "common/gbuffer.frag");
        float aspect = float(frame_.width) / float(frame_.height);
        program.use();
        program.set("viewFromWorld", ctx.camera().viewFromWorld());
        program.set("clipFromView", ctx.camera().clipFromView(aspect));
        gbufferFbo_.bind(frame_.width, frame_.height);
        const float zero[4] = {0, 0, 0, 0};
        const float background[4] = {0, 0, 0, -1};
        const float one = 1.0f;
        glClearNamedFramebufferfv(gbufferFbo_.id(), GL_COLOR, 0, zero);
        glClearNamedFramebufferfv(gbufferFbo_.id(), GL_COLOR, 1, zero);
        glClearNamedFramebufferfv(gbufferFbo_.id(), GL_COLOR, 2, background);
        glClearNamedFramebufferfv(gbufferFbo_.id(), GL_COLOR, 3, zero);
        glClearNamedFramebufferfi(gbufferFbo_.id(), GL_DEPTH_STENCIL, 0, one, 0);
        ctx.drawScene(program, false);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    });

    banded_ = {"gbuffer", "shade"};
    passSlots_.clear();
    std::vector<std::string> shadeInputs = {"gbuffer", "ambient"};
    for (auto& lp : lights_) {
        LightSlot& slot = *lp;
        LightState& l = slot.state;
        std::string g = l.group + "/";
        for (const char* source : {"light", "light.radiance"})
            if (!graph_.produces(g + source)) graph_.setSource(g + source, graph_.version(g + source));
        shadeInputs.push_back(g + "light");
        shadeInputs.push_back(g + "light.radiance");
        if (!l.light.castsShadows) {
            for (const PassDesc& p : l.requested->passes)
                graph_.addStaticSkip(g + l.requested->id + "/" + p.name, l.group, l.requested->id,
                                     "light casts no shadows: no shadow pass, visibility 1");
            continue;
        }
        if (l.idle) {
            for (const PassDesc& p : l.desc->passes)
                graph_.addStaticSkip(g + l.desc->id + "/" + p.name, l.group, l.requested->id,
                                     "auto: this light's shadows fall on no visible pixel: no shadow pass, visibility 1");
            continue;
        }
        if (l.desc != l.requested) {
            for (const PassDesc& p : l.requested->passes)
                graph_.addStaticSkip(g + l.requested->id + "/" + p.name, l.group, l.requested->id,
                                     "point light (size 0): soft-shadow passes do not run, `hard` passes replace them");
        }
        for (const ParamDesc& p : l.desc->params) graph_.setSource(g + "param:" + p.key, hashValue(l.params.get(p.key)));
        for (size_t i = 0; i < l.desc->passes.size(); ++i) {
            const PassDesc& pass = l.desc->passes[i];
            auto qualify = [&](const std::vector<std::string>& names) {
                std::vector<std::string> out;
                for (const std::string& n : names) out.push_back(isFrameResource(n) ? n : g + n);
                return out;
            };
            std::vector<std::string> creates;
            for (const ResourceDesc& r : pass.creates) creates.push_back(g + r.name);
            if (writesOnlyFrameTextures(*l.desc, pass)) banded_.insert(g + l.desc->id + "/" + pass.name);
            passSlots_[g + l.desc->id + "/" + pass.name] = {&slot, i};
            graph_.addPass(g + l.desc->id + "/" + pass.name, l.group, l.desc->id, qualify(pass.reads), creates,
                           qualify(pass.modifies), [this, &slot, i] { runTechniquePass(slot, i); });
        }
        shadeInputs.push_back(g + "visibility");
    }

    // Shading and the combined visibility in one pass (DESIGN.md section 3):
    // v = sum_l v_l E_l / sum_l E_l, image = albedo * (ambient + sum_l v_l * direct_l).
    graph_.addPass("shade", "frame", "", shadeInputs, {"visibility", "image"}, {}, [this] {
        std::vector<const Texture*> visibility;
        for (const auto& slot : lights_) {
            const Resource* v = slot->state.runs() ? pool_.find(slot->state.group + "/visibility") : nullptr;
            visibility.push_back(v ? &v->texture : nullptr);
        }
        shade(visibility);
    });
    // A light's technique may have changed (auto's pick, setTechnique): the outputs the last frame
    // requested of the old one (its internals) are produced no more, and the stats and cost
    // measurements that replay that request must not ask for them.
    for (auto it = lastRequested_.begin(); it != lastRequested_.end();)
        it = graph_.produces(*it) ? std::next(it) : lastRequested_.erase(it);
}

void Renderer::shade(const std::vector<const Texture*>& visibility) {
    PipelineState::fullscreen().apply();
    std::vector<std::string> defines = {"LIGHT_COUNT " + std::to_string(lights_.size())};
    const ShaderProgram& program = programs_.get("common/fullscreen.vert", "common/shade.frag", defines);
    program.use();
    for (size_t i = 0; i < lights_.size(); ++i) {
        const Light& light = lights_[i]->state.light;
        std::string idx = "[" + std::to_string(i) + "]";
        program.set(("lightPositions" + idx).c_str(), light.position);
        program.set(("lightRadiance" + idx).c_str(), light.color * light.intensity);
        const Texture* v = i < visibility.size() ? visibility[i] : nullptr;
        glBindTextureUnit(GLuint(3 + i), v ? v->id() : white_.id());
        program.set(("lightVisibility" + idx).c_str(), int(3 + i));
    }
    PassContext ctx(frame_, nullptr, pool_, "shade", {"gbuffer", "ambient"});
    ctx.bindGBuffer(program);
    const GLuint shadingUnit = GLuint(3 + lights_.size());
    glBindTextureUnit(shadingUnit, ctx.gbuffer().shadingNormal->id());
    program.set("gShadingNormal", int(shadingUnit));
    program.set("ambient", ctx.ambient());
    shadeFbo_.bind(frame_.width, frame_.height);
    drawFullscreenTriangle();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void Renderer::shadeWith(int frame, const std::vector<const Texture*>& visibility, int y0, int y1) {
    if (visibility.size() != lights_.size()) {
        throw InternalError("Renderer::shadeWith: " + std::to_string(visibility.size()) + " visibility textures for " +
                            std::to_string(lights_.size()) + " lights");
    }
    for (const Texture* v : visibility) {
        if (v && (v->width() != frame_.width || v->height() != frame_.height)) {
            throw InternalError("Renderer::shadeWith: a visibility texture of " + std::to_string(v->width()) + "x" +
                                std::to_string(v->height()) + " for a frame of " + std::to_string(frame_.width) + "x" +
                                std::to_string(frame_.height));
        }
    }
    renderFrame(frame, {"gbuffer"});
    std::vector<const Texture*> own(visibility);
    for (size_t i = 0; i < lights_.size(); ++i)
        if (!lights_[i]->state.runs()) own[i] = nullptr;  // visibility 1, as the shade pass
    y0 = std::clamp(y0, 0, frame_.height);
    y1 = y1 < 0 ? frame_.height : std::clamp(y1, y0, frame_.height);
    const bool band = y0 > 0 || y1 < frame_.height;
    if (band) {
        glEnable(GL_SCISSOR_TEST);
        glScissor(0, y0, frame_.width, y1 - y0);
    }
    if (y1 > y0) shade(own);
    if (band) glDisable(GL_SCISSOR_TEST);
    graph_.invalidatePass("shade");  // image and visibility no longer hold the graph's shading
}

// Allocates the pass's resources from their declarations (reallocates what changed size or
// declaration, frees what does not apply); returns the textures it allocated anew.
std::vector<const Texture*> Renderer::ensurePassResources(LightSlot& slot, size_t index, size_t maxFresh, bool* more) {
    if (more) *more = false;
    LightState& l = slot.state;
    const PassDesc& pass = l.desc->passes[index];
    const std::string name = l.group + "/" + l.desc->id + "/" + pass.name;
    std::vector<const Texture*> fresh;
    for (const ResourceDesc& r : pass.creates) {
        if (fresh.size() >= maxFresh) {  // the rest on the next call
            if (more) *more = true;
            break;
        }
        std::string q = l.group + "/" + r.name;
        if (!r.appliesWhen.empty() && !Condition(r.appliesWhen, *l.desc, name).holds(l.params)) {
            pool_.release(q);
            continue;
        }
        const glm::ivec2 size = resolveResourceSize(
            r, {frame_.width, frame_.height}, l.params,
            [&](const std::string& other) -> std::optional<glm::ivec2> {
                const Resource* found = pool_.find(l.group + "/" + other);
                if (!found) return std::nullopt;
                return glm::ivec2(found->width, found->height);
            },
            name);
        const int w = size.x, h = size.y;
        const Resource* before = pool_.find(q);
        const GLuint oldId = before ? before->texture.id() : 0;
        Resource& now = pool_.ensure(q, r, w, h);
        if (now.texture.id() && now.texture.id() != oldId) fresh.push_back(&now.texture);
    }
    return fresh;
}

// Runs the pass through a context that checks every access against the declaration, after its
// resources and its pipeline state.
void Renderer::runTechniquePass(LightSlot& slot, size_t index) {
    LightState& l = slot.state;
    const PassDesc& pass = l.desc->passes[index];
    std::string name = l.group + "/" + l.desc->id + "/" + pass.name;
    std::set<std::string> declared(pass.reads.begin(), pass.reads.end());
    for (const std::string& w : pass.writes()) declared.insert(w);
    ensurePassResources(slot, index);
    pass.state.apply();
    PassContext ctx(frame_, &l, pool_, name, declared);
    slot.passes[index]->execute(ctx);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

int Renderer::preparePass(const std::string& pass) {
    auto it = passSlots_.find(pass);
    if (it == passSlots_.end()) return -1;
    // One new texture per call: on llvmpipe allocating a frame-size float texture costs ~20 ms.
    bool more = false;
    std::vector<const Texture*> fresh = ensurePassResources(*it->second.first, it->second.second, 1, &more);
    // A new texture's memory is first touched by whatever writes it first (on llvmpipe a frame-size
    // texture's first write costs tens of ms): cleared here, that cost is not in a band of rows.
    for (const Texture* t : fresh) {
        const std::optional<Format> known = formatFromGL(t->format());
        if (!known) continue;
        const Format f = *known;
        GLenum format = GL_RGBA, type = GL_FLOAT;
        if (formatHasStencil(f)) format = GL_DEPTH_STENCIL, type = GL_FLOAT_32_UNSIGNED_INT_24_8_REV;
        else if (formatIsDepth(f)) format = GL_DEPTH_COMPONENT;
        else if (formatIsInteger(f)) format = GL_RGBA_INTEGER, type = f == Format::R32I ? GL_INT : GL_UNSIGNED_INT;
        const GLenum channels[4] = {GL_RED, GL_RG, GL_RGB, GL_RGBA};
        const GLenum integerChannels[4] = {GL_RED_INTEGER, GL_RG_INTEGER, GL_RGB_INTEGER, GL_RGBA_INTEGER};
        if (!formatIsDepth(f)) {
            const int n = std::clamp(formatChannels(f), 1, 4) - 1;
            format = formatIsInteger(f) ? integerChannels[n] : channels[n];
        }
        for (int level = 0; level < t->levels(); ++level) glClearTexImage(t->id(), level, format, type, nullptr);
    }
    return fresh.empty() ? -1 : more ? 0 : 1;
}

// ---- live state -----------------------------------------------------------------------------------------
void Renderer::setTechnique(const std::string& id, int light) {
    const TechniqueDesc& desc = requireTechnique(id, "setTechnique");
    for (size_t i : lightIndices(light)) {
        LightSlot& slot = *lights_[i];
        slot.state.requested = &desc;
        slot.state.requestedParams = ParamValues(desc);
        configureLight(slot);
    }
    buildGraph();
    releaseUndeclaredResources();
}

void Renderer::releaseUndeclaredResources() {
    if (options_.keepResources) return;
    std::vector<std::string> keep;
    for (const auto& [name, r] : pool_.all())
        if (name.rfind("frame/", 0) == 0) keep.push_back(name);
    for (const auto& lp : lights_) {
        if (!lp->state.runs()) continue;
        for (const PassDesc& p : lp->state.desc->passes)
            for (const ResourceDesc& r : p.creates) keep.push_back(lp->state.group + "/" + r.name);
    }
    pool_.releaseAllBut(keep);
}

void Renderer::setParam(const std::string& key, const std::string& value, int light, const std::string& where) {
    bool any = false;
    for (size_t i : lightIndices(light)) {
        LightSlot& slot = *lights_[i];
        LightState& s = slot.state;
        if (!s.requested->findParam(key)) continue;
        s.requestedParams.set(*s.requested, key, value, where);
        any = true;
        if (s.desc->findParam(key)) {
            if (s.desc == s.requested)
                s.params = s.requestedParams;
            else
                s.params.copySharedFrom(s.requestedParams);
            graph_.setSource(s.group + "/param:" + key, hashValue(s.params.get(key)));
        }
    }
    if (any) rechoose();  // `auto`'s budgets decide what its lights run
    if (!any) {
        // Name the parameters the techniques in use accept.
        const TechniqueDesc& desc = *lights_.at(lightIndices(light).at(0))->state.requested;
        ParamValues probe(desc);
        probe.set(desc, key, value, where);  // throws: unknown parameter, with the accepted keys
    }
}

void Renderer::setLight(size_t index, const Light& light) {
    LightSlot& slot = *lights_.at(index);
    if (!std::isfinite(light.size) || light.size < 0.0f) throw InputError("setLight: size must be finite and >= 0");
    bool wasPoint = slot.state.light.isPoint(), casts = slot.state.light.castsShadows;
    slot.state.light = light;
    if (light.isPoint() != wasPoint || light.castsShadows != casts) {
        // What runs changes (a point light runs `hard`): the light's passes are rebuilt.
        configureLight(slot);
        buildGraph();
        releaseUndeclaredResources();  // e.g. reference's sample maps once the light is a point
    } else if (slot.state.requested->choose) {
        rechoose();  // `auto`'s choice follows the light's size and pose
    }
    // Versions are bumped by updateSources() at the next frame: "light" when the pose, shape or
    // size changed (through the fitted view too), "light.radiance" when colour or intensity did.
}

void Renderer::setCamera(const Camera& camera) {
    frame_.camera = camera;
    rechoose();  // `auto` measures the penumbra on screen from the camera
}
void Renderer::setAmbient(float ambient) {
    if (!std::isfinite(ambient) || ambient < 0.0f) throw InputError("setAmbient: expected a finite value >= 0");
    frame_.ambient = ambient;
}
void Renderer::setTime(double seconds) {
    frame_.time = seconds;
    timeSet_ = true;
}

void Renderer::resize(int width, int height) {
    if (width < 1 || height < 1 || width > 8192 || height > 8192)
        throw InputError("resize: expected each side in 1..8192, got " + std::to_string(width) + "x" + std::to_string(height));
    if (width == frame_.width && height == frame_.height) return;
    frame_.width = width;
    frame_.height = height;
    allocateFrameResources();  // the "camera" version includes the size: every frame-size pass re-runs
    // ... but a size and back (A -> B -> A with no frame at B: the window's paused ray tracer) gives
    // the versions of A again, while the textures allocated here (the G-buffer's, the shaded image
    // and visibility) are new: the passes writing them run again. (A technique's own frame-size
    // textures are reallocated when its pass next runs, so without a frame at B they still hold A.)
    graph_.invalidatePass("gbuffer");
    graph_.invalidatePass("shade");
    rechoose();  // `auto`'s estimate of the penumbra in pixels follows the frame's size
}

void Renderer::setMeasureChoices(bool on) {
    if (on == measureChoices_) return;
    measureChoices_ = on;
    if (on) rechoose();  // the choices made while it was off were predicted only
}

void Renderer::rechoose() {
    bool changed = false;
    for (auto& lp : lights_) {
        LightSlot& slot = *lp;
        if (!slot.state.requested->choose) continue;
        LightState probe = slot.state;
        if (resolveLightTechnique(probe, scene_, frame_.camera, frame_.width, frame_.height, frame_.time, frameLights(), measureChoices_)) {
            configureLight(slot);
            changed = true;
        } else {
            slot.state.choice = probe.choice;  // the same pick; its features and predictions may differ
        }
    }
    if (changed) {
        buildGraph();
        releaseUndeclaredResources();
    }
}

std::vector<Light> Renderer::frameLights() const {
    std::vector<Light> out;
    for (const auto& l : lights_) out.push_back(l->state.light);
    return out;
}

std::vector<const LightState*> Renderer::lights() const {
    std::vector<const LightState*> out;
    for (const auto& l : lights_) out.push_back(&l->state);
    return out;
}

// ---- frames ---------------------------------------------------------------------------------------------
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

void Renderer::updateLightSources(LightSlot& slot) {
    LightState& l = slot.state;
    l.view = fitLightView(l.light, l.light.position, frame_.bounds);
    graph_.setSource(l.group + "/light", hashLightGeometry(l.light, l.view));
    graph_.setSource(l.group + "/light.radiance", hashRadiance(l.light));
}

void Renderer::updateSources() {
    frame_.bounds = scene_.bounds(frame_.time);
    uint64_t objects = 1469598103934665603ull, casters = objects;
    for (size_t i = 0; i < scene_.objects.size(); ++i) {
        const Object& o = scene_.objects[i];
        glm::mat4 m = o.worldFromObjectAt(frame_.time);
        objects = hashMat(m, hashValue(i, objects));
        if (o.castsShadows) casters = hashMat(m, hashValue(i, casters));
    }
    graph_.setSource("scene.objects", objects);
    graph_.setSource("scene.casters", casters);
    graph_.setSource("camera", hashCamera(frame_.camera, frame_.width, frame_.height));
    graph_.setSource("ambient", hashValue(frame_.ambient));
    for (auto& l : lights_) updateLightSources(*l);
}

void Renderer::beginFrame(int frame, const std::set<std::string>& requested) {
    if (!timeSet_) frame_.time = frame * kSecondsPerFrame;
    timeSet_ = false;
    frameIndex_ = frame;
    updateSources();
    if (!options_.reuse) graph_.invalidate();
    lastRequested_ = requested;
}

void Renderer::renderFrame(int frame, const std::set<std::string>& requested) {
    beginFrame(frame, requested);
    graph_.execute(requested, frame, [this](const std::function<void()>& run) { return timePass(run); });
    adaptParameters(frame);
}

void Renderer::adaptParameters(int frame) {
    for (size_t i = 0; i < lights_.size(); ++i) {
        const LightState& l = lights_[i]->state;
        if (!l.desc || !l.desc->adapt) continue;
        // Once per new run of the light's passes (refineFrame calls this again while a finished
        // frame is reused): its runs counted against those at the last adaptation.
        double ms = 0.0;
        bool ran = false;
        int runs = 0;
        for (const PassRecord& r : graph_.records())
            if (r.group == l.group && r.technique == l.desc->id) {
                runs += r.runs;
                if (!r.times.empty() && r.times.back().first == frame) {
                    ms += r.times.back().second;
                    ran = true;
                }
            }
        int& seen = adaptedRuns_[l.group];
        if (!ran || runs == seen) continue;
        seen = runs;
        if (auto change = l.desc->adapt(l.params, ms)) setParam(change->first, change->second, int(i), "load balancing");
    }
}

double Renderer::refineFrame(int frame, const std::set<std::string>& requested, double budgetMs) {
    beginFrame(frame, requested);
    PassGraph::Slicing slicing;
    // Pieces are tiles of kTileColumns columns by two rows, in row-major order: a tile starts on an
    // even row and column, so the 2x2 quads the G-buffer's derivatives come from (its geometric
    // normal) are never split. Two whole rows of ssm-gbp06 under plant's foliage cost ~30 ms at
    // 1024 wide on llvmpipe, more than a frame's budget: a piece must be able to be smaller.
    const int columns = tileColumns();
    slicing.units = [this, columns](const std::string& pass) {
        return banded_.count(pass) ? columns * ((frame_.height + 1) / 2) : 0;
    };
    slicing.unitsPerRow = columns;
    slicing.prepare = [this](const std::string& pass) { return preparePass(pass); };  // one texture a call
    slicing.runUnits = [this, columns](const std::string&, int from, int to, const std::function<void()>& run) {
        // A run of tiles is at most three rectangles: the rest of its first row of tiles, whole
        // rows, the start of its last row.
        auto draw = [&](int row, int c0, int c1, int rows) {
            const int x0 = c0 * kTileColumns, x1 = std::min(frame_.width, c1 * kTileColumns);
            const int y0 = 2 * row, y1 = std::min(frame_.height, 2 * (row + rows));
            if (x1 <= x0 || y1 <= y0) return;
            glScissor(x0, y0, x1 - x0, y1 - y0);
            run();
        };
        glEnable(GL_SCISSOR_TEST);
        int row = from / columns, col = from % columns;
        const int lastRow = (to - 1) / columns, lastCol = (to - 1) % columns + 1;
        if (row == lastRow) {
            draw(row, col, lastCol, 1);
        } else {
            if (col > 0) draw(row++, col, columns, 1);
            const int whole = lastRow - row + (lastCol == columns ? 1 : 0);
            if (whole > 0) draw(row, 0, columns, whole);
            row += whole;
            if (row == lastRow) draw(row, 0, lastCol, 1);
        }
        glDisable(GL_SCISSOR_TEST);
    };
    const double progress = graph_.executeSliced(
        requested, frame, [this](const std::function<void()>& run) { return timePass(run); }, budgetMs, slicing);
    if (progress >= 1.0) adaptParameters(frame);  // a complete frame: the reactive rules see its cost
    return progress;
}

void Renderer::measureCost(int firstFrame, int frames) {
    for (int f = firstFrame; f < firstFrame + frames; ++f)
        graph_.measureCost(lastRequested_, f, [this](const std::function<void()>& run) { return timePass(run); });
}

std::vector<std::string> Renderer::checkReuse() {
    // Every texture level and buffer of the pool, as bytes.
    auto snapshot = [this] {
        std::map<std::string, std::vector<float>> out;
        for (const auto& [name, r] : pool_.all()) {
            if (r->desc.kind == ResourceKind::Mesh) {
                std::vector<float> v;
                for (const glm::vec3& p : r->mesh.positions) v.insert(v.end(), {p.x, p.y, p.z});
                for (uint32_t i : r->mesh.indices) v.push_back(float(i));
                out[name] = v;
            } else if (r->desc.kind == ResourceKind::StorageBuffer) {
                std::vector<float> v(r->bufferBytes / 4);
                glGetNamedBufferSubData(r->buffer, 0, GLsizeiptr(v.size() * 4), v.data());
                if (r->desc.unordered) {
                    std::vector<uint32_t> words(v.size());
                    std::memcpy(words.data(), v.data(), v.size() * 4);
                    std::sort(words.begin(), words.end());
                    std::memcpy(v.data(), words.data(), v.size() * 4);
                }
                out[name] = v;
            } else {
                for (int level = 0; level < r->texture.levels(); ++level) {
                    Image img = readTextureLevel(r->texture, level);
                    out[name].insert(out[name].end(), img.data.begin(), img.data.end());
                }
            }
        }
        return out;
    };
    auto before = snapshot();
    graph_.rerunNeeded(lastRequested_);
    auto after = snapshot();
    std::vector<std::string> differ;
    for (const auto& [name, data] : after) {
        auto it = before.find(name);
        if (it == before.end()) continue;
        if (it->second.size() != data.size() ||
            std::memcmp(it->second.data(), data.data(), data.size() * sizeof(float)) != 0)
            differ.push_back(name);
    }
    return differ;
}

// ---- read-back ------------------------------------------------------------------------------------------
const Texture& Renderer::imageTexture() const { return pool_.find("frame/image")->texture; }

Image Renderer::visibility() const { return readTexture(pool_.find("frame/visibility")->texture, 1); }

// xyz of a G-buffer texture, NaN on background pixels (position.w == 0).
static Image geometryChannels(const Texture& texture, const Texture& position) {
    Image t = readTexture(texture, 4);
    Image p = &texture == &position ? t : readTexture(position, 4);
    Image out(t.width, t.height, 3);
    for (size_t i = 0; i < t.pixelCount(); ++i)
        for (int c = 0; c < 3; ++c) out.data[i * 3 + c] = p.data[i * 4 + 3] == 0.0f ? NAN : t.data[i * 4 + c];
    return out;
}

Image Renderer::positions() const { return geometryChannels(*frame_.gbuffer.position, *frame_.gbuffer.position); }
Image Renderer::normals() const { return geometryChannels(*frame_.gbuffer.normal, *frame_.gbuffer.position); }

Image Renderer::ids() const {
    Image m = readTexture(*frame_.gbuffer.material, 4);
    Image out(m.width, m.height, 1);
    for (size_t i = 0; i < m.pixelCount(); ++i) out.data[i] = m.data[i * 4 + 3];
    return out;
}

Image Renderer::image() const {
    Image linear = readTexture(imageTexture(), 4);
    Image out(linear.width, linear.height, 3);
    for (size_t i = 0; i < linear.pixelCount(); ++i) {
        for (int c = 0; c < 3; ++c) {
            float v = std::clamp(linear.data[i * 4 + c], 0.0f, 1.0f);
            out.data[i * 3 + c] = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
        }
    }
    return out;
}

// ---- internals ------------------------------------------------------------------------------------------
static bool internalApplies(const InternalDesc& i, const LightState& l) {
    return i.appliesWhen.empty() || Condition(i.appliesWhen, *l.desc, l.desc->id + "." + i.name).holds(l.params);
}

std::set<std::string> Renderer::internalRequests(bool withPixelRecords) const {
    std::set<std::string> out = {"visibility"};
    for (const auto& lp : lights_) {
        const LightState& l = lp->state;
        if (!l.runs()) continue;
        out.insert(l.group + "/visibility");
        for (const InternalDesc& i : l.desc->internals) {
            if (!internalApplies(i, l)) continue;
            if (i.kind != InternalDesc::Kind::Record) {
                out.insert(l.group + "/" + i.resource);
            } else if (withPixelRecords) {
                for (const std::string& r : i.reads)
                    if (graph_.produces(l.group + "/" + r)) out.insert(l.group + "/" + r);
                    else if (r == "gbuffer") out.insert("gbuffer");
            }
        }
    }
    return out;
}

void Renderer::writeInternals(InternalSink& out, std::optional<glm::ivec2> pixel) {
    nlohmann::json pixelData;
    for (auto& lp : lights_) {
        LightState& l = lp->state;
        out.setPrefix(l.index == 0 ? "" : "light" + std::to_string(l.index) + "/");
        if (!l.runs()) continue;
        nlohmann::json lightRecord = {{"light", l.index}, {"technique", l.desc->id}};
        for (const InternalDesc& i : l.desc->internals) {
            if (!internalApplies(i, l)) continue;
            std::set<std::string> declared(i.reads.begin(), i.reads.end());
            declared.insert(i.resource);
            PassContext ctx(frame_, &l, pool_, "internal " + i.name, declared);
            switch (i.kind) {
                case InternalDesc::Kind::Image:
                case InternalDesc::Kind::Pyramid: {
                    const Resource& r = ctx.resource(i.resource);
                    for (int level = 0; level < r.levels(); ++level) {
                        Image img = readTextureLevel(r.texture, level);
                        if (i.convert) i.convert(img);
                        if (i.kind == InternalDesc::Kind::Pyramid)
                            out.image(i.name, img, i.doc + " (level " + std::to_string(level) + ")", "pyramid", level);
                        else
                            out.image(i.name, img, i.doc);
                    }
                    break;
                }
                case InternalDesc::Kind::Mesh:
                case InternalDesc::Kind::Lines:
                    out.mesh(i.name, ctx.mesh(i.resource), internalKindName(i.kind), i.doc);
                    break;
                case InternalDesc::Kind::Record:
                    if (pixel) {
                        nlohmann::json record = i.record(ctx, *pixel);
                        if (i.name == "pixel")
                            lightRecord.update(record);
                        else
                            lightRecord[i.name] = record;
                    }
                    break;
            }
        }
        out.image("visibility", readTexture(pool_.find(l.group + "/visibility")->texture, 1),
                  "visibility v in [0,1] of this light alone (" + l.desc->id + ")");
        if (pixel) pixelData["lights"].push_back(lightRecord);
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
        out.json("pixel", pixelData, "per-pixel records of the picked pixel (--pixel x,y; y counted from the top)", "record");
    }
    out.writeIndex();
}

}  // namespace shadowlab
