// Frame statistics: what each pass and the whole frame cost (frame_stats.h), and Renderer::stats,
// the JSON `--stats` writes (README "Command line").
#include <algorithm>

#include "graph/frame_stats.h"
#include "graph/renderer.h"

namespace shadowlab {

double medianMs(std::vector<double> times) {
    if (times.empty()) return 0.0;
    std::sort(times.begin(), times.end());
    size_t n = times.size();
    return n % 2 ? times[n / 2] : 0.5 * (times[n / 2 - 1] + times[n / 2]);
}

double FrameCost::passMs(const std::string& name) const {
    for (const PassCost& p : passes)
        if (p.name == name) return p.medianMs;
    return 0.0;
}

FrameCost frameCost(const PassGraph& graph, const std::vector<std::string>& needed, int costFrom) {
    FrameCost cost;
    for (const PassRecord& r : graph.records()) {
        PassCost c{r.name, r.group, r.technique, std::find(needed.begin(), needed.end(), r.name) != needed.end(),
                   r.medianMs(costFrom)};
        if (c.needed) (c.isShadow() ? cost.shadowMs : cost.fixedMs) += c.medianMs;
        cost.passes.push_back(std::move(c));
    }
    return cost;
}

// ---- Renderer::stats ----------------------------------------------------------------------------------------------
bool Renderer::costMeasuredSince(int frame) const {
    std::vector<std::string> needed = graph_.neededPasses(lastRequested_);
    for (const PassRecord& r : graph_.records()) {
        if (std::find(needed.begin(), needed.end(), r.name) == needed.end()) continue;
        bool measured = std::any_of(r.times.begin(), r.times.end(), [&](const auto& t) { return t.first >= frame; });
        if (!measured) return false;
    }
    return true;
}

FrameCost Renderer::cost(int costFrom) const {
    std::vector<std::string> needed = lastRequested_.empty() ? std::vector<std::string>{} : graph_.neededPasses(lastRequested_);
    return frameCost(graph_, needed, costFrom);
}

std::vector<Renderer::KernelCapReport> Renderer::kernelCapReports() {
    std::vector<KernelCapReport> out;
    for (auto& lp : lights_) {
        LightState& l = lp->state;
        if (!l.runs()) continue;
        for (const KernelCapDesc& k : l.desc->kernelCaps) {
            // Only once the passes that produce the kernel's resources have run.
            bool ready = true;
            for (const std::string& r : k.reads)
                if (!r.starts_with("param:") && r != "gbuffer" && r != "light" && !pool_.find(l.group + "/" + r)) ready = false;
            if (!ready) continue;
            std::set<std::string> declared(k.reads.begin(), k.reads.end());
            PassContext ctx(frame_, &l, pool_, "kernel cap " + k.name, declared);
            out.push_back({l.index, l.desc->id, k.name, k.count(ctx)});
        }
    }
    return out;
}

nlohmann::json Renderer::stats(const std::vector<double>& frameMs, int warmupFrames, int costFrom) {
    nlohmann::json j;
    j["scene"] = scene_.name;
    j["resolution"] = {frame_.width, frame_.height};
    j["clock"] = clockName();
    j["reuse"] = options_.reuse;
    j["warmup_frames"] = warmupFrames;
    j["frames"] = frameMs.size();
    // frame_ms: the frame as run (with reuse: a static scene costs almost nothing after its first
    // frame). cost_ms: what a frame costs when every needed pass runs (the median of each needed
    // pass's runs), split into shadow_ms (the techniques' passes, all lights: what speed claims
    // compare) and fixed_ms (G-buffer, shading: the same for every technique).
    j["frame_ms"] = medianMs(frameMs);
    j["frame_ms_all"] = frameMs;
    std::vector<std::string> needed = lastRequested_.empty() ? std::vector<std::string>{} : graph_.neededPasses(lastRequested_);
    const FrameCost cost = frameCost(graph_, needed, costFrom);
    j["passes"] = nlohmann::json::array();
    for (size_t i = 0; i < cost.passes.size(); ++i) {
        const PassCost& c = cost.passes[i];
        const PassRecord& r = graph_.records()[i];
        j["passes"].push_back({{"name", c.name},
                               {"group", c.group},
                               {"technique", c.technique},
                               {"cost", c.isShadow() ? "shadow" : "fixed"},
                               {"needed", c.needed},
                               {"status", r.status},
                               {"reason", r.reason},
                               {"runs", r.runs},
                               {"reuses", r.reuses},
                               {"not_needed", r.notNeeded},
                               {"median_ms", c.medianMs},
                               {"history", r.history}});
    }
    j["cost_ms"] = cost.costMs();
    j["shadow_ms"] = cost.shadowMs;
    j["fixed_ms"] = cost.fixedMs;
    j["lights"] = nlohmann::json::array();
    for (const auto& lp : lights_) {
        const LightState& l = lp->state;
        nlohmann::json lj{{"index", l.index},
                          {"name", l.light.name},
                          {"shape", lightShapeName(l.light.shape)},
                          {"size", l.light.size},
                          {"casts_shadows", l.light.castsShadows},
                          {"technique_requested", l.requested->id},
                          {"technique", !l.light.castsShadows ? std::string("none (casts no shadows)")
                                        : l.idle ? std::string("none (auto: no visible shadow)")
                                                 : l.desc->id}};
        if (!l.choice.is_null()) lj["auto"] = l.choice;
        lj["parameters"] = l.params.toJson(*l.desc);
        nlohmann::json inapplicable = nlohmann::json::object();
        for (const auto& [key, reason] : l.params.inapplicable(*l.desc)) inapplicable[key] = reason;
        if (!inapplicable.empty()) lj["parameters_not_applied"] = inapplicable;
        lj["kernel_caps"] = nlohmann::json::array();
        lj["counters"] = nlohmann::json::object();
        j["lights"].push_back(lj);
    }
    for (const KernelCapReport& k : kernelCapReports()) {
        for (auto& lj : j["lights"]) {
            if (lj["index"] != k.light) continue;
            lj["kernel_caps"].push_back({{"parameter", k.name},
                                         {"cap", k.count.cap},
                                         {"pixels", k.count.pixels},
                                         {"clamped_pixels", k.count.clamped},
                                         {"clamped_fraction", k.fraction()},
                                         {"largest", k.count.largest}});
        }
    }
    for (auto& lp : lights_) {
        LightState& l = lp->state;
        if (!l.runs()) continue;
        for (const CounterDesc& c : l.desc->counters) {
            if (!c.appliesWhen.empty() && !Condition(c.appliesWhen, *l.desc, l.desc->id + "." + c.name).holds(l.params))
                continue;
            bool ready = true;  // only once the passes that produce its resources have run
            for (const std::string& r : c.reads)
                if (!r.starts_with("param:") && r != "gbuffer" && r != "light" && !pool_.find(l.group + "/" + r)) ready = false;
            if (!ready) continue;
            std::set<std::string> declared(c.reads.begin(), c.reads.end());
            PassContext ctx(frame_, &l, pool_, "counter " + c.name, declared);
            for (auto& lj : j["lights"])
                if (lj["index"] == l.index) lj["counters"][c.name] = c.count(ctx);
        }
    }
    j["resources"] = pool_.describe();
    j["memory_bytes"] = pool_.totalBytes() + gpu_->bytes();
    j["scene_bytes"] = gpu_->bytes();
    return j;
}

}  // namespace shadowlab
