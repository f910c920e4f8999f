#include "lesson/headless.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "error.h"
#include "lesson/html.h"
#include "graph/internals.h"
#include "lesson/player.h"

namespace fs = std::filesystem;

namespace shadowlab {

// ---- the host ---------------------------------------------------------------------------------------
RendererLessonHost::RendererLessonHost(int width, int height) : width_(width), height_(height) {
    if (width < 1 || height < 1 || width > 8192 || height > 8192)
        throw InputError("lesson: --size: expected each side in 1..8192");
}

RendererLessonHost::~RendererLessonHost() = default;

void RendererLessonHost::setScene(const std::string& name) {
    if (scene_ && name == sceneName_) return;
    main_.renderer.reset();
    reference_.renderer.reset();
    split_slot_.renderer.reset();
    scene_ = std::make_unique<Scene>(loadScene(name));
    sceneName_ = name;
    lights_ = scene_->lights;
    camera_ = scene_->camera;
}

void RendererLessonHost::setTechnique(const std::string& id) {
    main_.technique = requireTechnique(id, "lesson").id;
    main_.params.clear();
    if (main_.renderer) main_.renderer->setTechnique(id);
}

void RendererLessonHost::setParam(const std::string& key, const std::string& value) {
    for (auto& p : main_.params)
        if (p.first == key) p.second = value;
    if (std::none_of(main_.params.begin(), main_.params.end(), [&](const auto& p) { return p.first == key; }))
        main_.params.push_back({key, value});
    if (main_.renderer) main_.renderer->setParam(key, value, -1, "lesson");
}

void RendererLessonHost::setLight(size_t index, const Light& light) {
    lights_.at(index) = light;
    for (Slot* s : {&main_, &reference_, &split_slot_})
        if (s->renderer) s->renderer->setLight(index, light);
}

void RendererLessonHost::setCamera(const Camera& camera) {
    camera_ = camera;
    for (Slot* s : {&main_, &reference_, &split_slot_})
        if (s->renderer) s->renderer->setCamera(camera);
}

void RendererLessonHost::setReference(const std::string& technique,
                                      const std::vector<std::pair<std::string, std::string>>& params) {
    if (technique == reference_.technique && params == reference_.params) return;
    reference_.technique = technique;
    reference_.params = params;
    if (reference_.renderer) {
        reference_.renderer->setTechnique(technique);
        for (const auto& [k, v] : params) reference_.renderer->setParam(k, v, -1, "lesson reference");
    }
}

void RendererLessonHost::showView(const std::string& view, bool shown) {
    if (shown)
        views_.insert(view);
    else
        views_.erase(view);
}

void RendererLessonHost::pickPixel(const std::optional<LessonPick>& pick) { pick_ = pick; }

void RendererLessonHost::setSplit(const std::string& against) {
    split_ = against;
    if (!against.empty() && against != "reference" && against != split_slot_.technique) {
        split_slot_.technique = against;
        split_slot_.params.clear();
        if (split_slot_.renderer) split_slot_.renderer->setTechnique(against);
    }
}

std::optional<glm::ivec2> RendererLessonHost::pickedPixel() const {
    if (!pick_) return std::nullopt;
    auto p = pickPixelAt(*pick_, camera_, width_, height_);
    if (!p)
    {
        char what[200];
        std::snprintf(what, sizeof what, ": pick at %g %g %g is off-screen at %dx%d (behind the camera or outside the image)",
                      pick_->point.x, pick_->point.y, pick_->point.z, width_, height_);
        throw InputError(pick_->where.str() + what);
    }
    return p;
}

void RendererLessonHost::render(Renderer& renderer, const std::set<std::string>& requested) {
    // Lessons show the scene at t = 0: moving scenes hold still while a step is studied.
    renderer.setTime(0.0);
    renderer.renderFrame(0, requested);
}

RendererLessonHost::Slot& RendererLessonHost::ensure(Slot& slot, bool internals) {
    if (!scene_) throw InternalError("lesson host: no scene");
    if (!slot.renderer) {
        RenderOptions options;
        options.width = width_;
        options.height = height_;
        options.technique = slot.technique;
        slot.renderer = std::make_unique<Renderer>(*scene_, options);
        for (size_t i = 0; i < lights_.size(); ++i) slot.renderer->setLight(i, lights_[i]);
        slot.renderer->setCamera(camera_);
        for (const auto& [k, v] : slot.params) slot.renderer->setParam(k, v, -1, "lesson");
    }
    std::set<std::string> requested = {"image", "visibility"};
    if (&slot == &main_ && views_.count("shadow-map-texels"))
        for (const std::string& r : slot.renderer->internalRequests(false))
            if (r.find("/shadow_map") != std::string::npos) requested.insert(r);
    if (internals)
        for (const std::string& r : slot.renderer->internalRequests(false)) requested.insert(r);
    render(*slot.renderer, requested);
    return slot;
}

Renderer& RendererLessonHost::technique() { return *ensure(main_).renderer; }
Renderer& RendererLessonHost::reference() { return *ensure(reference_).renderer; }
Renderer& RendererLessonHost::splitRenderer() {
    return split_.empty() || split_ == "reference" ? reference() : *ensure(split_slot_).renderer;
}

TaskBuffers RendererLessonHost::readTaskBuffers(const TaskReads& reads) {
    TaskBuffers b;
    Renderer& t = *ensure(main_, !reads.internals.empty()).renderer;
    b.visibility = t.visibility();
    b.ids = t.ids();
    if (!reads.internals.empty()) b.internals = collectInternals(t, reads.internals);
    if (reads.positions) b.positions = t.positions();
    b.pick = pickedPixel();
    if (reads.reference) b.reference = reference().visibility();
    return b;
}

TaskBuffers RendererLessonHost::readVariantBuffers(const LessonState& variant, const TaskReads& reads) {
    // A host of its own at this size: its renderers are kept from one variant to the next (a scene
    // loads once), and what this host shows is untouched.
    if (!variant_) variant_ = std::make_unique<RendererLessonHost>(width_, height_);
    // The same variant again (another expectation of the step): its renderers are as they were,
    // and reuse the passes they ran.
    if (!variantState_ || *variantState_ != variant) applyLessonState(*variant_, variant);
    variantState_ = variant;
    return variant_->readTaskBuffers(reads);
}

namespace {

// The image internals a condition names, kept in memory as they are handed over (as viz/'s
// InternalCollector keeps every kind for the views): keyed by the light's prefix and the name.
class ConditionInternals : public InternalSink {
public:
    explicit ConditionInternals(const std::set<std::string>& names) : names_(names) {}
    void image(const std::string& name, const Image& image, const std::string&, const std::string&, int level) override {
        if (level <= 0 && names_.count(prefix_ + name)) images[prefix_ + name] = image;
    }
    void mesh(const std::string&, const MeshData&, const std::string&, const std::string&) override {}
    void json(const std::string&, const nlohmann::json&, const std::string&, const std::string&) override {}
    std::map<std::string, Image> images;

private:
    const std::set<std::string>& names_;
};

}  // namespace

std::map<std::string, Image> collectInternals(Renderer& renderer, const std::set<std::string>& names) {
    ConditionInternals sink(names);
    renderer.writeInternals(sink, std::nullopt);
    return sink.images;
}

// ---- the headless runner --------------------------------------------------------------------------------
namespace {

std::string stepFile(size_t step, const std::string& suffix) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "step-%02zu%s.png", step + 1, suffix.c_str());
    return buf;
}

// A world pick must show its point: the surface under its pixel is within a few pixel footprints of
// it (4: the point may sit on a pixel's edge, on a surface seen at a slant), else another surface
// is in front of it, or it lies on the background. A lesson error naming the pick's line and size.
void checkPickVisible(RendererLessonHost& host, glm::ivec2 pixel) {
    const LessonPick& pick = *host.pick();
    if (!pick.world) return;
    const Image positions = host.technique().positions();
    const glm::vec3 shown(positions.at(pixel.x, pixel.y, 0), positions.at(pixel.x, pixel.y, 1),
                          positions.at(pixel.x, pixel.y, 2));
    const Camera& camera = host.camera();
    const float distance = glm::length(pick.point - camera.position);
    const float footprint = 2.0f * distance * std::tan(glm::radians(camera.fovYDegrees) * 0.5f) / float(host.height());
    const float off = glm::length(shown - pick.point);
    if (!(off <= 4.0f * footprint)) {
        char what[256];
        std::snprintf(what, sizeof what,
                      ": pick at %g %g %g is hidden at %dx%d: its pixel (%d, %d) shows %s %.3g away (%.1f pixel footprints)",
                      pick.point.x, pick.point.y, pick.point.z, host.width(), host.height(), pixel.x, pixel.y,
                      std::isfinite(off) ? "a surface" : "the background", double(off), double(off / footprint));
        throw InputError(pick.where.str() + what);
    }
}

nlohmann::json outcomeJson(const TaskCondition::Outcome& o) {
    nlohmann::json values = nlohmann::json::array();
    for (double v : o.values) values.push_back(std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr));
    return {{"passed", o.passed}, {"message", o.message}, {"values", values}};
}

}  // namespace

nlohmann::json renderLessonHeadless(const Lesson& lesson, const std::string& directory, int width, int height) {
    const bool writing = !directory.empty();
    OutputSet outputs;
    auto png = [&](const std::string& name, const std::string& label, const Image& image) {
        if (writing) writePNG(outputs.stage((fs::path(directory) / name).string()), image);
        return HandoutPicture{name, label, image.width, image.height};
    };
    RendererLessonHost host(width, height);
    LessonPlayer player(lesson, host);
    const std::string size = std::to_string(width) + "x" + std::to_string(height);
    nlohmann::json summary{{"lesson", lesson.id}, {"title", lesson.title}, {"file", lesson.file},
                           {"size", {width, height}}, {"steps", nlohmann::json::array()}};
    std::vector<HandoutStep> handout;
    std::vector<std::string> failures;  // every failing expectation of the lesson, reported together
    for (size_t k = 0; k < lesson.steps.size(); ++k) {
        player.goTo(k);
        const LessonStep& step = lesson.steps[k];
        HandoutStep h;
        h.title = step.title;
        h.narration = step.narration;
        nlohmann::json js{{"title", step.title}, {"line", step.where.line}, {"state", step.state.describe()}};
        // The claims first, on the step's own state (the pictures below render the same state).
        player.checkExpects();
        js["expects"] = nlohmann::json::array();
        for (size_t e = 0; e < step.expects.size(); ++e) {
            const LessonExpect& expect = step.expects[e];
            const LessonPlayer::ExpectResult& r = player.expectResults().at(e);
            nlohmann::json values = nlohmann::json::array();
            for (double v : r.outcome.values) values.push_back(std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr));
            js["expects"].push_back({{"line", expect.where.line}, {"expect", expect.condition.text()}, {"passed", r.passed},
                                     {"values", values}, {"message", r.message}});
            h.expects.push_back({expect.condition.text(), r.outcome.values.empty() ? r.message : expect.condition.measured(r.outcome),
                                 r.passed});
            if (!r.passed)
                failures.push_back(expect.where.str() + " at " + size + ": expect " + expect.condition.text() + ": " + r.failure);
        }
        h.picture = png(stepFile(k, ""), step.state.technique + (step.state.split.empty() ? "" : " | " + step.state.split),
                        renderLessonView(host, "technique"));
        js["images"] = {h.picture.file};
        for (const std::string& view : step.state.views) {
            // A view that does not apply to the step's technique (`show hsm` under `hard`) is the
            // lesson's error: named by the step's file and line, not only by the view.
            Image picture;
            try {
                picture = renderLessonView(host, view);
            } catch (const LessonCheckError&) {
                throw;
            } catch (const InputError& e) {
                throw InputError(step.where.str() + ": show " + view + " (technique " + step.state.technique + "): " + e.what());
            }
            h.views.push_back(png(stepFile(k, "-" + view), view, picture));
            js["images"].push_back(h.views.back().file);
        }
        if (auto p = host.pickedPixel()) {
            checkPickVisible(host, *p);
            float v = host.technique().visibility().at(p->x, p->y);
            float r = host.reference().visibility().at(p->x, p->y);
            char line[160];
            std::snprintf(line, sizeof line, "picked pixel (%d, %d): visibility %.3f, reference %.3f", p->x, p->y, v, r);
            h.notes.push_back(line);
            const Image positions = host.technique().positions();
            js["pick"] = {{"pixel", {p->x, p->y}},
                          {"point", {positions.at(p->x, p->y, 0), positions.at(p->x, p->y, 1), positions.at(p->x, p->y, 2)}},
                          {"visibility", v},
                          {"reference", r}};
        }
        if (step.animate) {
            const LessonAnimation& a = *step.animate;
            for (int f = 0; f < 3; ++f) {
                double fraction = f * 0.5;
                applyLessonState(host, animatedState(step, fraction));
                h.animation.push_back(png(stepFile(k, "-anim-" + std::to_string(f)), a.target + " = " + animatedValueText(step, fraction),
                                          renderLessonView(host, "technique")));
                js["images"].push_back(h.animation.back().file);
            }
            player.restore();
        }
        if (step.task) {
            const LessonTask& task = *step.task;
            TaskCondition::Outcome own = evaluateOnHost(task.check, host);
            player.showMe();
            TaskCondition::Outcome answer = evaluateOnHost(task.check, host);
            if (own.passed)
                throw InputError(task.where.str() + ": the task is already solved in the step's own state (" +
                                 own.message + "); the student would have nothing to do");
            if (!answer.passed)
                throw InputError(task.where.str() + ": the task's answer does not pass its check (" + answer.message + ")");
            h.task = task.prompt;
            h.check = task.check.text();
            h.ownOutcome = own.message;
            h.answerOutcome = answer.message;
            h.answerCommands = "";
            for (const LessonCommand& c : task.answer) {
                std::string line = c.name;
                for (const std::string& a : c.args) line += " " + a;
                h.answerCommands += line + "\n";
            }
            h.answer = png(stepFile(k, "-answer"), "the answer's state", renderLessonView(host, "technique"));
            js["task"] = {{"prompt", task.prompt}, {"check", task.check.text()}, {"line", task.where.line},
                          {"own", outcomeJson(own)}, {"answer", outcomeJson(answer)}, {"image", h.answer.file}};
            player.restore();
        }
        summary["steps"].push_back(js);
        handout.push_back(h);
    }
    if (!failures.empty()) {
        std::string message;
        for (const std::string& f : failures) message += (message.empty() ? "" : "\n") + f;
        throw LessonCheckError(message);
    }
    if (!writing) return summary;
    std::ofstream html(outputs.stage((fs::path(directory) / "index.html").string()), std::ios::binary);
    html << lessonHandoutHtml(lesson, handout);
    html.close();
    std::ofstream json(outputs.stage((fs::path(directory) / "lesson.json").string()), std::ios::binary);
    json << summary.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
    json.close();
    if (!html || !json) throw InternalError("cannot write the handout into " + directory);
    outputs.commit();
    // Pictures of an earlier run that this run did not write would mislead: remove them.
    std::set<std::string> written;
    for (const auto& s : summary["steps"])
        for (const auto& f : s["images"]) written.insert(f.get<std::string>());
    for (const auto& s : summary["steps"])
        if (s.contains("task")) written.insert(s["task"]["image"].get<std::string>());
    for (const auto& e : fs::directory_iterator(directory)) {
        std::string name = e.path().filename().string();
        if (name.rfind("step-", 0) == 0 && e.path().extension() == ".png" && !written.count(name)) fs::remove(e.path());
    }
    return summary;
}

}  // namespace shadowlab
