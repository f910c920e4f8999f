// A technique describes itself (STYLE.md 2-3): id, citation, parameter table, the passes it declares
// with the resources they read, create and modify (Falcor's RenderPass::reflect()), and the typed
// internals it can expose. The CLI (`list`, `--set`), the window, lessons, views and tests read this
// descriptor; nothing re-types it. Adding a technique touches its folder and one line of
// techniques/registry.cpp; techniques/template/ is the folder to copy.
#pragma once
#include <functional>
#include <optional>
#include <glm/glm.hpp>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "graph/resources.h"

namespace shadowlab {

// ---- parameters (one table: STYLE.md 3) ---------------------------------------------------------
struct ParamDesc {
    enum class Type { Float, Int, Bool, Enum };
    // Integer constraints beyond the range and the step.
    enum class Constraint { None, Odd, PowerOfTwo };
    std::string key;         // --set key, e.g. "sm_size"
    std::string symbol;      // the paper's symbol, e.g. "w_l", "t", "beta"; "" when the paper names none
    Type type = Type::Float;
    std::string unit;        // "texels", "world units", "" ...
    double defaultValue = 0; // Enum: index into `choices`
    double minValue = 0;
    double maxValue = 1;
    double step = 0;         // Int: values are min + k * step (0 or 1: any whole number); Float: UI step only
    std::string doc;         // one line, with the paper's symbol and the reason for the default
    std::string appliesWhen; // "" = always; else a condition on other parameters, e.g. "filter == gaussian"
    Constraint constraint = Constraint::None;
    std::vector<std::string> choices;  // Enum: the names, in order ("gaussian", "mean")
};
const char* paramTypeName(ParamDesc::Type type);

// A condition on parameter values: comparisons `key OP value` (OP one of == != < <= > >=; value a
// number, true/false, or an enum choice) joined by `&&`. Parsed against a parameter table, so a
// condition naming an unknown key or choice is a programming error caught by the descriptor tests.
class ParamValues;
struct TechniqueDesc;
class Condition {
public:
    Condition() = default;  // always true
    // Throws InternalError naming `where` when the text does not parse against `desc`.
    Condition(const std::string& text, const TechniqueDesc& desc, const std::string& where);
    bool holds(const ParamValues& values) const;
    bool always() const { return terms_.empty(); }
    std::vector<std::string> keys() const;  // the parameters it reads
    const std::string& text() const { return text_; }

private:
    struct Term {
        std::string key;
        std::string op;
        double value;
    };
    std::string text_;
    std::vector<Term> terms_;
};

// ---- passes ---------------------------------------------------------------------------------------
// What a pass sees when it runs: resources by name, parameters, the light, the frame. Every access
// is recorded and checked against the pass's declaration (an undeclared read is an error).
class PassContext;

// A pass is an object with its own execute(); it may keep objects that outlive one run (a
// framebuffer, a CPU-side acceleration structure). Resources themselves belong to the pool.
class Pass {
public:
    virtual ~Pass() = default;
    virtual void execute(PassContext& ctx) = 0;
};

// A pass declares what it reads and writes (Falcor's reflect(), Filament's frame graph).
//  reads:    resources of this light written by earlier passes ("shadow_map"); frame resources
//            ("gbuffer", "scene.casters" = transforms of shadow casters, "scene.objects", "camera");
//            "light" (the light's shape, pose and size; its colour is "light.radiance") and
//            parameters ("param:sm_size").
//  creates:  resources this pass writes first; the pool allocates them from their declaration.
//  modifies: resources an earlier pass wrote that this pass reads and rewrites (a ping-pong blur, a
//            stencil pass followed by add and subtract passes into one V-buffer): a new version.
// `state` is applied before execute(), so nothing one pass sets leaks into the next.
struct PassDesc {
    std::string name;
    std::string doc;
    std::vector<std::string> reads;
    std::vector<ResourceDesc> creates;
    std::vector<std::string> modifies;
    PipelineState state = PipelineState::fullscreen();
    bool soft = false;  // does not run for a point light (`hard` replaces the technique)
    // Never run in bands by Renderer::refineFrame, even when it writes only frame-size textures:
    // its cost is per draw call rather than per pixel (ssv's volumes and wedges: hundreds of draws,
    // each over much of the frame), so every band would pay for all of them again.
    bool wholeFrame = false;
    std::function<std::unique_ptr<Pass>()> create;

    std::vector<std::string> writes() const;  // creates' names, then modifies
};

// ---- internals ------------------------------------------------------------------------------------
// What a technique computes inside (DESIGN.md section 4), typed, as outputs of the graph: views
// and --internals request them, so only what is asked is computed.
struct InternalDesc {
    enum class Kind { Image, Pyramid, Mesh, Lines, Record };
    std::string name;      // file stem in --internals DIR
    Kind kind = Kind::Image;
    std::string resource;  // Image/Pyramid: a texture resource; Mesh/Lines: a mesh resource; Record: ""
    std::vector<std::string> channels;  // names of the channels ("depth"; "min", "max"; "value", "weight")
    std::string doc;
    std::string appliesWhen;  // "" = always
    // Image/Pyramid: its negative values are data (a signed sum, ssv's wedge coverage), not the
    // "none" markers (-1: no receiver, no blocker) that statistics over internals skip.
    bool signedValues = false;
    // Image/Pyramid: turns raw texels into exported values (e.g. the far-plane marker into +inf).
    std::function<void(Image&)> convert;
    // Record: the per-pixel record of --pixel, a fixed schema (field -> one-line doc) and the function
    // computing it from the resources in `reads` (after the frame ran).
    std::vector<std::pair<std::string, std::string>> schema;
    std::vector<std::string> reads;
    std::function<nlohmann::json(PassContext&, glm::ivec2 pixel)> record;
};
const char* internalKindName(InternalDesc::Kind kind);

// A kernel width the technique caps by a parameter (a penumbra wider than the cap is truncated).
// After a frame, `count` reads the resources in `reads` and counts the pixels that computed this
// kernel and those of them whose kernel reached the cap; `--stats`, the bench CSV and the window
// report the fraction, and `render` warns when it is over 1% (docs/adding-a-technique.md).
struct KernelCapCount {
    size_t pixels = 0;   // pixels that computed the kernel (a penumbra, or a blocker found)
    size_t clamped = 0;  // of those, the ones whose kernel was cut at the cap
    double cap = 0.0;    // the cap in force, in the kernel's unit (texels or pixels)
    double largest = 0.0;  // the widest kernel asked for (before the cap where the technique keeps it)
    // One pixel that computed the kernel: its width, and whether the cap cut it.
    void add(double kernel, bool atCap) {
        ++pixels;
        clamped += atCap;
        largest = kernel > largest ? kernel : largest;
    }
};
struct KernelCapDesc {
    std::string name;  // the capping parameter, e.g. "filter_kernel"
    std::string doc;   // which pixels count, and when one is clamped
    std::vector<std::string> reads;
    std::function<KernelCapCount(PassContext&)> count;
};

// A count a technique reports after a frame, under `--stats` lights[i].counters[name] (an object of
// numbers, and strings naming what ran, e.g. spsm's "rasterization"): what its passes did that no image shows at a glance, e.g. how many pixels the
// screen-space selection of guennebaud2007 evaluated. `count` reads the resources in `reads` (after
// the frame ran); a counter whose appliesWhen does not hold, or whose resources are not allocated,
// is left out.
struct CounterDesc {
    std::string name;
    std::string doc;
    std::string appliesWhen;  // "" = always
    std::vector<std::string> reads;
    std::function<nlohmann::json(PassContext&)> count;
};

// ---- choosing techniques (`auto`) ---------------------------------------------------------------------
// What a choosing technique sees of one light when it picks what that light runs: the scene, the
// light (after --light-size), the camera, the frame size, its own parameters and the time.
struct Scene;
struct Light;
struct Camera;
struct ChoiceInputs {
    const Scene* scene = nullptr;
    const Light* light = nullptr;
    const Camera* camera = nullptr;
    int width = 0, height = 0;
    const ParamValues* params = nullptr;
    double time = 0.0;
    // Every light of the frame as rendered, this one among them: v mixes the lights (shade.frag), so
    // a choice may share its error budget between them.
    std::vector<Light> lights;
    int lightIndex = 0;  // this light's place in `lights`
    // A GL context is current and the renderer lets the choice render trials of its own (`auto`'s
    // measured errors): false when lights are resolved before any GL work (Renderer::resolveLights,
    // the memory estimate) and while the window's user drags (Renderer::setMeasureChoices).
    bool measure = false;
};
// What it picked: a registered technique with its parameters, or nothing to run (`desc` null: the
// light's shadow falls on no visible pixel, its visibility is 1), and why (for --stats and the HUD).
struct TechniqueChoice {
    const TechniqueDesc* desc = nullptr;
    std::shared_ptr<ParamValues> params;  // of desc (shared: ParamValues is declared below)
    nlohmann::json report;
};

// ---- the descriptor -------------------------------------------------------------------------------
struct TechniqueDesc {
    std::string id;
    std::string name;
    std::string citation;  // paper and section, e.g. "Williams 1978; background in cournia2005 ch. 2"
    std::string summary;
    bool soft = false;     // a soft-shadow technique (converges to `hard` as the light shrinks)
    std::vector<ParamDesc> params;
    std::vector<PassDesc> passes;  // in execution order; some pass writes "visibility" (R32F, frame size)
    std::vector<InternalDesc> internals;
    std::vector<KernelCapDesc> kernelCaps;  // the kernels it caps (empty: no capped kernel)
    std::vector<CounterDesc> counters;      // what --stats reports per light besides times (empty: none)
    // A reactive rule (assarsson2004's load balancing): after a frame in which the light's passes
    // ran, taking `lightMs` (their times summed, that frame), a parameter change for the next frame
    // ({key, value}), or nothing. Renderer::renderFrame applies it (setParam, so what depends on the
    // parameter runs again). Null: no rule.
    std::function<std::optional<std::pair<std::string, std::string>>(const ParamValues& params, double lightMs)> adapt;
    // A technique that runs none of its own passes but picks, per light, another technique and its
    // setting (`auto`, issue 25). Renderer::resolveLights and the memory estimate call it; the
    // renderer calls it again whenever one of its inputs changes (its parameters, the light, the
    // camera, the frame size) and rebuilds the light's passes when the choice changed. Null: the
    // technique runs its own passes.
    std::function<TechniqueChoice(const ChoiceInputs& inputs)> choose;

    const ParamDesc* findParam(const std::string& key) const;
    const InternalDesc* findInternal(const std::string& name) const;
};

// Parameter values of one technique instance: every key of the table, defaults filled in.
class ParamValues {
public:
    ParamValues() = default;
    explicit ParamValues(const TechniqueDesc& desc);
    double get(const std::string& key) const;
    int getInt(const std::string& key) const { return int(get(key)); }
    bool getBool(const std::string& key) const { return get(key) != 0.0; }
    std::string getChoice(const std::string& key) const;  // Enum: the chosen name
    // Validates against the table: unknown key, NaN/Inf, out of range, non-integer for Int/Bool,
    // step, odd / power-of-two, unknown enum choice (the choices are listed). `where` names the
    // source for the message ("--set", "lessons/intro.md:12"). Throws InputError.
    void set(const TechniqueDesc& desc, const std::string& key, const std::string& text, const std::string& where);
    const std::map<std::string, double>& values() const { return values_; }
    // Copies the values of the keys both techniques declare (already validated by `from`'s table).
    void copySharedFrom(const ParamValues& from);
    // Parameters whose appliesWhen does not hold for these values, with the reason.
    std::vector<std::pair<std::string, std::string>> inapplicable(const TechniqueDesc& desc) const;
    // {key: value} with enum values by name, for stats and sidecars.
    nlohmann::json toJson(const TechniqueDesc& desc) const;

private:
    std::map<std::string, double> values_;
    std::map<std::string, std::string> choices_;  // enum key -> chosen name
};

// The technique a light runs, and its parameters: `requested` with its values, or `hard` (with the
// shadow-map settings both declare) for a point light when `requested` has soft passes (they do not
// run for a point; Renderer::configureLight and the memory estimate both ask here).
std::pair<const TechniqueDesc*, ParamValues> techniqueForLight(const TechniqueDesc& requested,
                                                               const ParamValues& requestedParams, bool pointLight);

// The side of a resource from its size rule (Renderer::ensurePassResources allocates at it): Frame
// and Fixed directly, ShadowMap from its parameter, Like from `like(name)`, the size of the named
// resource of the same light (nullopt when it is not allocated: InternalError naming `where`).
glm::ivec2 resolveResourceSize(const ResourceDesc& r, glm::ivec2 frame, const ParamValues& params,
                               const std::function<std::optional<glm::ivec2>(const std::string&)>& like,
                               const std::string& where);
// The bytes a declaration takes once allocated at `size` (what Resource::bytes() reports): texels x
// levels x layers, a storage buffer's elements; 0 for a Mesh (CPU-side, its size follows the scene).
double declaredResourceBytes(const ResourceDesc& r, glm::ivec2 size);
// The bytes of every resource one light's passes declare and whose appliesWhen holds, at a frame
// size: what the pool allocates for that light. The memory estimate (`--max-memory-mb`) counts it
// before anything is allocated (issue 24: ssm-gbp06 at sm_size 8192 was estimated at half of what
// it took).
double techniqueResourceBytes(const TechniqueDesc& desc, const ParamValues& params, glm::ivec2 frame);

// Registry (techniques/registry.cpp): every technique, in the order `list` shows them.
const std::vector<const TechniqueDesc*>& allTechniques();
const TechniqueDesc* findTechnique(const std::string& id);                     // nullptr if unknown
const TechniqueDesc& requireTechnique(const std::string& id, const std::string& where);  // InputError

nlohmann::json describeTechnique(const TechniqueDesc& desc);

// Checks a descriptor's consistency (every read produced earlier or a known frame/light/param
// resource, names unique, defaults valid, conditions parse, internals name real resources); returns
// the problems found, empty when it is sound. The descriptor tests run it on every technique.
std::vector<std::string> validateTechnique(const TechniqueDesc& desc);

}  // namespace shadowlab
