#include "technique.h"

#include <cmath>
#include <sstream>

#include "error.h"

namespace shadowlab {

const char* paramTypeName(ParamDesc::Type type) {
    switch (type) {
        case ParamDesc::Type::Float: return "float";
        case ParamDesc::Type::Int: return "int";
        case ParamDesc::Type::Bool: return "bool";
    }
    return "?";
}

const ParamDesc* TechniqueDesc::findParam(const std::string& key) const {
    for (const ParamDesc& p : params)
        if (p.key == key) return &p;
    return nullptr;
}

ParamValues::ParamValues(const TechniqueDesc& desc) {
    for (const ParamDesc& p : desc.params) values_[p.key] = p.defaultValue;
}

double ParamValues::get(const std::string& key) const {
    auto it = values_.find(key);
    if (it == values_.end()) throw InternalError("parameter '" + key + "' is not declared by this technique");
    return it->second;
}

static std::string formatNumber(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
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
    values_[key] = value;
}

void ParamValues::copySharedFrom(const ParamValues& from) {
    for (auto& [key, value] : values_) {
        auto it = from.values_.find(key);
        if (it != from.values_.end()) value = it->second;
    }
}

const TechniqueDesc& requireTechnique(const std::string& id, const std::string& where) {
    if (const TechniqueDesc* d = findTechnique(id)) return *d;
    std::string ids;
    for (const TechniqueDesc* d : allTechniques()) ids += (ids.empty() ? "" : ", ") + d->id;
    throw InputError(where + ": unknown technique '" + id + "' (expected one of: " + ids + ")");
}

nlohmann::json describeTechnique(const TechniqueDesc& desc) {
    nlohmann::json j;
    j["id"] = desc.id;
    j["name"] = desc.name;
    j["citation"] = desc.citation;
    j["summary"] = desc.summary;
    j["soft"] = desc.soft;
    j["parameters"] = nlohmann::json::array();
    for (const ParamDesc& p : desc.params) {
        j["parameters"].push_back({{"key", p.key}, {"symbol", p.symbol}, {"type", paramTypeName(p.type)},
                                   {"unit", p.unit}, {"default", p.defaultValue}, {"min", p.minValue},
                                   {"max", p.maxValue}, {"step", p.step}, {"doc", p.doc},
                                   {"applies_when", p.appliesWhen}});
    }
    j["passes"] = nlohmann::json::array();
    for (const PassDesc& p : desc.passes)
        j["passes"].push_back({{"name", p.name}, {"inputs", p.inputs}, {"outputs", p.outputs}, {"doc", p.doc},
                               {"soft", p.soft}});
    j["internals"] = nlohmann::json::array();
    for (const InternalDesc& i : desc.internals)
        j["internals"].push_back({{"name", i.name}, {"kind", i.kind}, {"doc", i.doc}});
    return j;
}

}  // namespace shadowlab
