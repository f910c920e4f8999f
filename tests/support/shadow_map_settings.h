// The shadow-map settings a technique hands to the `hard` that replaces it for a point light
// (ParamValues::copySharedFrom): its defaults of sm_size, bias_const and bias_slope as --set pairs,
// so a test renders the `hard` that technique must equal at --light-size 0.
#pragma once
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "graph/technique.h"

namespace shadowlab::testing {

inline std::vector<std::pair<std::string, std::string>> shadowMapSettingsOf(const std::string& technique) {
    std::vector<std::pair<std::string, std::string>> sets;
    const TechniqueDesc& desc = requireTechnique(technique, "shadowMapSettingsOf");
    for (const char* key : {"sm_size", "bias_const", "bias_slope"}) {
        if (const ParamDesc* p = desc.findParam(key)) {
            std::ostringstream value;
            value << p->defaultValue;
            sets.emplace_back(key, value.str());
        }
    }
    return sets;
}

}  // namespace shadowlab::testing
