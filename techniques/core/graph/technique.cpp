#include "graph/technique.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "error.h"

namespace shadowlab {

const char* paramTypeName(ParamDesc::Type type) {
    switch (type) {
        case ParamDesc::Type::Float: return "float";
        case ParamDesc::Type::Int: return "int";
        case ParamDesc::Type::Bool: return "bool";
        case ParamDesc::Type::Enum: return "enum";
    }
    return "?";
}

const char* internalKindName(InternalDesc::Kind kind) {
    switch (kind) {
        case InternalDesc::Kind::Image: return "image";
        case InternalDesc::Kind::Pyramid: return "pyramid";
        case InternalDesc::Kind::Mesh: return "mesh";
        case InternalDesc::Kind::Lines: return "lines";
        case InternalDesc::Kind::Record: return "record";
    }
    return "?";
}

const ParamDesc* TechniqueDesc::findParam(const std::string& key) const {
    for (const ParamDesc& p : params)
        if (p.key == key) return &p;
    return nullptr;
}

const InternalDesc* TechniqueDesc::findInternal(const std::string& name) const {
    for (const InternalDesc& i : internals)
        if (i.name == name) return &i;
    return nullptr;
}

std::vector<std::string> PassDesc::writes() const {
    std::vector<std::string> out;
    for (const ResourceDesc& r : creates) out.push_back(r.name);
    out.insert(out.end(), modifies.begin(), modifies.end());
    return out;
}

static std::string formatNumber(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

static std::string joinChoices(const std::vector<std::string>& choices) {
    std::string out;
    for (const std::string& c : choices) out += (out.empty() ? "" : ", ") + c;
    return out;
}

// ---- conditions ------------------------------------------------------------------------------------
static std::string trim(const std::string& s) {
    size_t a = s.find_first_not_of(" \t"), b = s.find_last_not_of(" \t");
    return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

Condition::Condition(const std::string& text, const TechniqueDesc& desc, const std::string& where) : text_(text) {
    std::string rest = text;
    while (!trim(rest).empty()) {
        size_t amp = rest.find("&&");
        std::string part = trim(rest.substr(0, amp));
        rest = amp == std::string::npos ? "" : rest.substr(amp + 2);
        static const char* ops[] = {"==", "!=", "<=", ">=", "<", ">"};
        size_t at = std::string::npos;
        std::string op;
        for (const char* o : ops) {
            at = part.find(o);
            if (at != std::string::npos) {
                op = o;
                break;
            }
        }
        if (op.empty()) throw InternalError(where + ": condition '" + text + "': expected `key OP value` in '" + part + "'");
        Term term;
        term.key = trim(part.substr(0, at));
        term.op = op;
        std::string value = trim(part.substr(at + op.size()));
        const ParamDesc* p = desc.findParam(term.key);
        if (!p) throw InternalError(where + ": condition '" + text + "' names unknown parameter '" + term.key + "'");
        if (p->type == ParamDesc::Type::Enum) {
            auto it = std::find(p->choices.begin(), p->choices.end(), value);
            if (it == p->choices.end())
                throw InternalError(where + ": condition '" + text + "': '" + value + "' is not a choice of " + term.key +
                                    " (" + joinChoices(p->choices) + ")");
            term.value = double(it - p->choices.begin());
        } else if (value == "true" || value == "false") {
            term.value = value == "true" ? 1.0 : 0.0;
        } else {
            char* end = nullptr;
            term.value = std::strtod(value.c_str(), &end);
            if (value.empty() || *end != '\0')
                throw InternalError(where + ": condition '" + text + "': expected a number, got '" + value + "'");
        }
        terms_.push_back(term);
    }
}

std::vector<std::string> Condition::keys() const {
    std::vector<std::string> out;
    for (const Term& t : terms_) out.push_back(t.key);
    return out;
}

bool Condition::holds(const ParamValues& values) const {
    for (const Term& t : terms_) {
        double v = values.get(t.key);
        bool ok = t.op == "==" ? v == t.value
                  : t.op == "!=" ? v != t.value
                  : t.op == "<"  ? v < t.value
                  : t.op == "<=" ? v <= t.value
                  : t.op == ">"  ? v > t.value
                                 : v >= t.value;
        if (!ok) return false;
    }
    return true;
}

// ---- parameter values ------------------------------------------------------------------------------
ParamValues::ParamValues(const TechniqueDesc& desc) {
    for (const ParamDesc& p : desc.params) {
        values_[p.key] = p.defaultValue;
        if (p.type == ParamDesc::Type::Enum && !p.choices.empty())
            choices_[p.key] = p.choices[size_t(std::clamp(int(p.defaultValue), 0, int(p.choices.size()) - 1))];
    }
}

double ParamValues::get(const std::string& key) const {
    auto it = values_.find(key);
    if (it == values_.end()) throw InternalError("parameter '" + key + "' is not declared by this technique");
    return it->second;
}

std::string ParamValues::getChoice(const std::string& key) const {
    auto it = choices_.find(key);
    if (it == choices_.end()) throw InternalError("parameter '" + key + "' is not an enum of this technique");
    return it->second;
}

static std::string expectedText(const ParamDesc& p) {
    if (p.type == ParamDesc::Type::Enum) return "one of " + joinChoices(p.choices);
    if (p.type == ParamDesc::Type::Bool) return "0, 1, true or false";
    std::string s = std::string("a") + (p.type == ParamDesc::Type::Int ? " whole number" : " number") + " in [" +
                    formatNumber(p.minValue) + ", " + formatNumber(p.maxValue) + "]";
    if (p.constraint == ParamDesc::Constraint::Odd) s += ", odd";
    if (p.constraint == ParamDesc::Constraint::PowerOfTwo) s += ", a power of two";
    if (p.type == ParamDesc::Type::Int && p.step > 1) s += ", in steps of " + formatNumber(p.step) + " from " + formatNumber(p.minValue);
    return s;
}

void ParamValues::set(const TechniqueDesc& desc, const std::string& key, const std::string& text,
                      const std::string& where) {
    const ParamDesc* p = desc.findParam(key);
    if (!p) {
        std::string keys;
        for (const ParamDesc& q : desc.params) keys += (keys.empty() ? "" : ", ") + q.key;
        throw InputError(where + ": unknown parameter '" + key + "' for technique " + desc.id + " (expected one of: " +
                         (keys.empty() ? "none" : keys) + ")");
    }
    if (p->type == ParamDesc::Type::Enum) {
        auto it = std::find(p->choices.begin(), p->choices.end(), text);
        if (it == p->choices.end())
            throw InputError(where + ": " + key + ": expected one of " + joinChoices(p->choices) + ", got '" + text + "'");
        values_[key] = double(it - p->choices.begin());
        choices_[key] = text;
        return;
    }
    double value = 0;
    if (p->type == ParamDesc::Type::Bool && (text == "true" || text == "false")) {
        value = text == "true" ? 1.0 : 0.0;
    } else {
        char* end = nullptr;
        value = std::strtod(text.c_str(), &end);
        if (text.empty() || end != text.c_str() + text.size())
            throw InputError(where + ": " + key + ": expected a " + paramTypeName(p->type) + " in [" +
                             formatNumber(p->minValue) + ", " + formatNumber(p->maxValue) + "], got '" + text + "'");
    }
    if (!std::isfinite(value))
        throw InputError(where + ": " + key + ": expected a finite number, got '" + text + "'");
    if ((p->type != ParamDesc::Type::Float) && value != std::floor(value))
        throw InputError(where + ": " + key + ": expected a whole number (" + paramTypeName(p->type) + "), got '" +
                         text + "'");
    if (value < p->minValue || value > p->maxValue)
        throw InputError(where + ": " + key + ": expected a value in [" + formatNumber(p->minValue) + ", " +
                         formatNumber(p->maxValue) + "], got " + text);
    if (p->type == ParamDesc::Type::Int) {
        long long n = (long long)value;
        if (p->constraint == ParamDesc::Constraint::Odd && n % 2 == 0)
            throw InputError(where + ": " + key + ": expected " + expectedText(*p) + ", got " + text +
                             " (the kernel is centred on the receiver's texel, so its width is odd)");
        if (p->constraint == ParamDesc::Constraint::PowerOfTwo && (n <= 0 || (n & (n - 1)) != 0))
            throw InputError(where + ": " + key + ": expected " + expectedText(*p) + ", got " + text);
        if (p->step > 1 && std::fmod(value - p->minValue, p->step) != 0.0)
            throw InputError(where + ": " + key + ": expected " + expectedText(*p) + ", got " + text);
    }
    values_[key] = value;
}

void ParamValues::copySharedFrom(const ParamValues& from) {
    for (auto& [key, value] : values_) {
        auto it = from.values_.find(key);
        if (it != from.values_.end()) value = it->second;
    }
    for (auto& [key, choice] : choices_) {
        auto it = from.choices_.find(key);
        if (it != from.choices_.end()) choice = it->second;
    }
}

std::vector<std::pair<std::string, std::string>> ParamValues::inapplicable(const TechniqueDesc& desc) const {
    std::vector<std::pair<std::string, std::string>> out;
    for (const ParamDesc& p : desc.params) {
        if (p.appliesWhen.empty()) continue;
        Condition c(p.appliesWhen, desc, desc.id + "." + p.key);
        if (!c.holds(*this)) out.push_back({p.key, "applies only when " + p.appliesWhen});
    }
    return out;
}

nlohmann::json ParamValues::toJson(const TechniqueDesc& desc) const {
    nlohmann::json j = nlohmann::json::object();
    for (const ParamDesc& p : desc.params) {
        if (p.type == ParamDesc::Type::Enum)
            j[p.key] = getChoice(p.key);
        else
            j[p.key] = get(p.key);
    }
    return j;
}

const TechniqueDesc& requireTechnique(const std::string& id, const std::string& where) {
    if (const TechniqueDesc* d = findTechnique(id)) return *d;
    std::string ids;
    for (const TechniqueDesc* d : allTechniques()) ids += (ids.empty() ? "" : ", ") + d->id;
    throw InputError(where + ": unknown technique '" + id + "' (expected one of: " + ids + ")");
}

// ---- description and validation -------------------------------------------------------------------
static const char* constraintName(ParamDesc::Constraint c) {
    return c == ParamDesc::Constraint::Odd ? "odd" : c == ParamDesc::Constraint::PowerOfTwo ? "power of two" : "";
}

nlohmann::json describeTechnique(const TechniqueDesc& desc) {
    nlohmann::json j;
    j["id"] = desc.id;
    j["name"] = desc.name;
    j["citation"] = desc.citation;
    j["summary"] = desc.summary;
    j["soft"] = desc.soft;
    if (desc.choose) j["chooses"] = true;  // runs no pass of its own: picks a technique per light
    j["parameters"] = nlohmann::json::array();
    for (const ParamDesc& p : desc.params) {
        nlohmann::json pj{{"key", p.key},       {"symbol", p.symbol},           {"type", paramTypeName(p.type)},
                          {"unit", p.unit},     {"default", p.defaultValue},    {"min", p.minValue},
                          {"max", p.maxValue},  {"step", p.step},               {"doc", p.doc},
                          {"applies_when", p.appliesWhen}, {"constraint", constraintName(p.constraint)}};
        if (p.type == ParamDesc::Type::Enum) {
            pj["choices"] = p.choices;
            pj["default"] = p.choices.empty() ? "" : p.choices[size_t(p.defaultValue)];
        }
        j["parameters"].push_back(pj);
    }
    j["passes"] = nlohmann::json::array();
    for (const PassDesc& p : desc.passes) {
        nlohmann::json creates = nlohmann::json::array();
        for (const ResourceDesc& r : p.creates) {
            nlohmann::json rj{{"name", r.name}, {"kind", resourceKindName(r.kind)}, {"size", r.size.describe()},
                              {"doc", r.doc}};
            if (r.kind != ResourceKind::Mesh && r.kind != ResourceKind::StorageBuffer) rj["format"] = formatName(r.format);
            if (r.kind == ResourceKind::Pyramid) rj["levels"] = r.levels == 0 ? nlohmann::json("full chain") : nlohmann::json(r.levels);
            if (r.kind == ResourceKind::TextureArray) rj["layers"] = r.layers;
            if (r.kind == ResourceKind::StorageBuffer) rj["element_bytes"] = r.elementBytes;
            if (!r.appliesWhen.empty()) rj["applies_when"] = r.appliesWhen;
            creates.push_back(rj);
        }
        j["passes"].push_back({{"name", p.name},
                               {"reads", p.reads},
                               {"creates", creates},
                               {"modifies", p.modifies},
                               {"outputs", p.writes()},
                               {"doc", p.doc},
                               {"soft", p.soft},
                               {"state", p.state.describe()}});
    }
    j["internals"] = nlohmann::json::array();
    for (const InternalDesc& i : desc.internals) {
        nlohmann::json ij{{"name", i.name}, {"kind", internalKindName(i.kind)}, {"doc", i.doc}};
        if (!i.resource.empty()) ij["resource"] = i.resource;
        if (!i.channels.empty()) ij["channels"] = i.channels;
        if (i.signedValues) ij["signed"] = true;
        if (!i.appliesWhen.empty()) ij["applies_when"] = i.appliesWhen;
        if (!i.schema.empty()) {
            nlohmann::json schema = nlohmann::json::object();
            for (const auto& [field, doc] : i.schema) schema[field] = doc;
            ij["schema"] = schema;
        }
        j["internals"].push_back(ij);
    }
    return j;
}

// Frame and light resources every pass may read without a pass of its technique producing them.
static bool isExternalResource(const std::string& name) {
    return name == "gbuffer" || name == "camera" || name == "light" || name == "light.radiance" ||
           name.rfind("scene.", 0) == 0 || name.rfind("param:", 0) == 0;
}

std::vector<std::string> validateTechnique(const TechniqueDesc& desc) {
    std::vector<std::string> problems;
    auto problem = [&](const std::string& text) { problems.push_back(desc.id + ": " + text); };
    std::set<std::string> keys;
    for (const ParamDesc& p : desc.params) {
        if (!keys.insert(p.key).second) problem("parameter '" + p.key + "' declared twice");
        if (p.doc.empty()) problem("parameter '" + p.key + "' has no doc line");
        if (p.type == ParamDesc::Type::Enum) {
            if (p.choices.empty()) problem("enum '" + p.key + "' has no choices");
            if (p.defaultValue < 0 || p.defaultValue >= double(p.choices.size()) || p.defaultValue != std::floor(p.defaultValue))
                problem("enum '" + p.key + "': default is not a choice index");
            continue;
        }
        if (!(p.minValue <= p.defaultValue && p.defaultValue <= p.maxValue))
            problem("parameter '" + p.key + "': default " + formatNumber(p.defaultValue) + " outside its range");
        if (p.type != ParamDesc::Type::Float && p.defaultValue != std::floor(p.defaultValue))
            problem("parameter '" + p.key + "': default is not a whole number");
        long long n = (long long)p.defaultValue;
        if (p.constraint == ParamDesc::Constraint::Odd && n % 2 == 0) problem("parameter '" + p.key + "': even default");
        if (p.constraint == ParamDesc::Constraint::PowerOfTwo && (n <= 0 || (n & (n - 1)) != 0))
            problem("parameter '" + p.key + "': default is not a power of two");
        if (p.constraint == ParamDesc::Constraint::Odd && std::fmod(p.minValue, 2.0) == 0.0)
            problem("parameter '" + p.key + "': odd constraint but even minimum");
    }
    auto checkCondition = [&](const std::string& text, const std::string& where) {
        if (text.empty()) return;
        try {
            Condition(text, desc, where);
        } catch (const std::exception& e) {
            problem(e.what());
        }
    };
    for (const ParamDesc& p : desc.params) checkCondition(p.appliesWhen, "parameter " + p.key);
    std::set<std::string> produced, passNames;
    bool visibility = false;
    for (const PassDesc& pass : desc.passes) {
        if (!passNames.insert(pass.name).second) problem("pass '" + pass.name + "' declared twice");
        if (!pass.create) problem("pass '" + pass.name + "' has no create function");
        for (const std::string& in : pass.reads) {
            if (in.rfind("param:", 0) == 0 && !desc.findParam(in.substr(6)))
                problem("pass '" + pass.name + "' reads unknown parameter '" + in + "'");
            else if (!isExternalResource(in) && !produced.count(in))
                problem("pass '" + pass.name + "' reads '" + in + "', which no earlier pass writes");
        }
        for (const std::string& m : pass.modifies)
            if (!produced.count(m)) problem("pass '" + pass.name + "' modifies '" + m + "', which no earlier pass creates");
        for (const ResourceDesc& r : pass.creates) {
            if (!produced.insert(r.name).second) problem("resource '" + r.name + "' created twice");
            if (r.doc.empty()) problem("resource '" + r.name + "' has no doc line");
            checkCondition(r.appliesWhen, "resource " + r.name);
            if (r.size.kind == SizeRule::Kind::ShadowMap && !desc.findParam(r.size.from))
                problem("resource '" + r.name + "' is sized by unknown parameter '" + r.size.from + "'");
            if (r.size.kind == SizeRule::Kind::Like && !produced.count(r.size.from))
                problem("resource '" + r.name + "' is sized like '" + r.size.from + "', created by no earlier pass");
            if (r.name == "visibility") visibility = true;
        }
        checkCondition("", "");
    }
    if (!visibility && !desc.choose) problem("no pass creates 'visibility'");
    if (desc.choose && !desc.passes.empty()) problem("a choosing technique declares passes of its own");
    std::set<std::string> internalNames;
    for (const InternalDesc& i : desc.internals) {
        if (!internalNames.insert(i.name).second) problem("internal '" + i.name + "' declared twice");
        if (i.doc.empty()) problem("internal '" + i.name + "' has no doc line");
        checkCondition(i.appliesWhen, "internal " + i.name);
        if (i.kind == InternalDesc::Kind::Record) {
            if (!i.record) problem("record internal '" + i.name + "' has no record function");
            if (i.schema.empty()) problem("record internal '" + i.name + "' has no schema");
            for (const std::string& r : i.reads)
                if (!isExternalResource(r) && !produced.count(r)) problem("record '" + i.name + "' reads unknown '" + r + "'");
        } else if (!produced.count(i.resource)) {
            problem("internal '" + i.name + "' shows resource '" + i.resource + "', which no pass creates");
        }
    }
    return problems;
}

std::pair<const TechniqueDesc*, ParamValues> techniqueForLight(const TechniqueDesc& requested,
                                                               const ParamValues& requestedParams, bool pointLight) {
    const bool soft = std::any_of(requested.passes.begin(), requested.passes.end(), [](const PassDesc& p) { return p.soft; });
    if (!(pointLight && soft)) return {&requested, requestedParams};
    const TechniqueDesc* hard = &requireTechnique("hard", "internal");
    ParamValues params(*hard);
    params.copySharedFrom(requestedParams);
    return {hard, params};
}

glm::ivec2 resolveResourceSize(const ResourceDesc& r, glm::ivec2 frame, const ParamValues& params,
                               const std::function<std::optional<glm::ivec2>(const std::string&)>& like,
                               const std::string& where) {
    const int down = std::max(r.size.scaleDown, 1);
    switch (r.size.kind) {
        case SizeRule::Kind::Frame: return {(frame.x + down - 1) / down, (frame.y + down - 1) / down};
        case SizeRule::Kind::ShadowMap: {
            const int side = params.getInt(r.size.from);
            return {side, side};
        }
        case SizeRule::Kind::Fixed: return {r.size.width, r.size.height};
        case SizeRule::Kind::Like: {
            const std::optional<glm::ivec2> other = like(r.size.from);
            if (!other) throw InternalError(where + ": '" + r.name + "' is sized like '" + r.size.from + "', which is not allocated");
            return {(other->x + down - 1) / down, (other->y + down - 1) / down};
        }
    }
    return {1, 1};
}

double declaredResourceBytes(const ResourceDesc& r, glm::ivec2 size) {
    const double w = std::max(size.x, 1), h = std::max(size.y, 1);
    const double layers = std::max(r.layers, 1);
    switch (r.kind) {
        case ResourceKind::Mesh: return 0.0;
        case ResourceKind::StorageBuffer: return std::max(double(r.elementBytes) * w * h * layers, 4.0);
        case ResourceKind::Texture: return double(formatTexelBytes(r.format)) * w * h;
        case ResourceKind::Pyramid:
        case ResourceKind::TextureArray: {
            // A pyramid's levels 0: the full chain down to 1x1; an array has at least one level
            // (ResourcePool::ensure).
            int levels = r.kind == ResourceKind::TextureArray ? std::max(r.levels, 1) : r.levels;
            if (levels <= 0) levels = fullMipLevels(size.x, size.y);
            double texels = 0.0;
            for (int level = 0; level < levels; ++level)
                texels += std::max(1.0, std::floor(w / std::exp2(level))) * std::max(1.0, std::floor(h / std::exp2(level)));
            return double(formatTexelBytes(r.format)) * texels * layers;
        }
    }
    return 0.0;
}

double techniqueResourceBytes(const TechniqueDesc& desc, const ParamValues& params, glm::ivec2 frame) {
    std::map<std::string, glm::ivec2> sizes;
    double bytes = 0.0;
    for (const PassDesc& pass : desc.passes)
        for (const ResourceDesc& r : pass.creates) {
            const std::string where = desc.id + "/" + pass.name;
            if (!r.appliesWhen.empty() && !Condition(r.appliesWhen, desc, where).holds(params)) continue;
            const glm::ivec2 size = resolveResourceSize(
                r, frame, params,
                [&](const std::string& name) -> std::optional<glm::ivec2> {
                    const auto it = sizes.find(name);
                    if (it == sizes.end()) return std::nullopt;
                    return it->second;
                },
                where);
            sizes[r.name] = size;
            bytes += declaredResourceBytes(r, size);
        }
    return bytes;
}

}  // namespace shadowlab
