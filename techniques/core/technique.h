// A technique describes itself (STYLE.md 2-3): id, citation, parameter table, passes with named
// inputs and outputs, internals. The CLI (`list`, `--set`), the window, lessons and tests read this
// descriptor; nothing re-types it. Adding a technique touches its folder and one line of
// techniques/registry.cpp.
#pragma once
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace shadowlab {

// One row of a technique's parameter table (STYLE.md 3).
struct ParamDesc {
    enum class Type { Float, Int, Bool };
    std::string key;         // --set key, e.g. "sm_size"
    std::string symbol;      // the paper's symbol, e.g. "w_l", "t", "beta"; "" when the paper names none
    Type type = Type::Float;
    std::string unit;        // "texels", "world units", "" ...
    double defaultValue = 0;
    double minValue = 0;
    double maxValue = 1;
    double step = 1;
    std::string doc;         // one line, with the paper's symbol and the reason for the default
    std::string appliesWhen; // "" = always
};
const char* paramTypeName(ParamDesc::Type type);

// A pass declares what it reads and writes. Inputs name resources produced by other passes of the
// same light ("shadow_map"), frame resources ("gbuffer", "scene.casters", "light", "camera") or
// parameters ("param:sm_size"). soft passes do not run for point lights (hard shadows instead).
struct PassDesc {
    std::string name;
    std::vector<std::string> inputs;
    std::vector<std::string> outputs;
    std::string doc;
    bool soft = false;
};

struct InternalDesc {
    std::string name;  // file stem in --internals DIR
    std::string kind;  // "image", "geometry", "json"
    std::string doc;
};

class TechniqueInstance;
struct TechniqueDesc {
    std::string id;
    std::string name;
    std::string citation;  // paper and section, e.g. "Williams 1978; background in cournia2005 ch. 2"
    std::string summary;
    bool soft = false;     // a soft-shadow technique (converges to `hard` as the light shrinks)
    std::vector<ParamDesc> params;
    std::vector<PassDesc> passes;  // in execution order; the last one outputs "visibility"
    std::vector<InternalDesc> internals;
    std::function<std::unique_ptr<TechniqueInstance>()> create;

    const ParamDesc* findParam(const std::string& key) const;
};

// Parameter values of one technique instance: every key of the table, defaults filled in.
class ParamValues {
public:
    ParamValues() = default;
    explicit ParamValues(const TechniqueDesc& desc);
    double get(const std::string& key) const;
    int getInt(const std::string& key) const { return int(get(key)); }
    bool getBool(const std::string& key) const { return get(key) != 0.0; }
    // Validates against the table: unknown key, NaN/Inf, out of range, non-integer for Int/Bool.
    // `where` names the source for the message ("--set", "lesson.txt:12"). Throws InputError.
    void set(const TechniqueDesc& desc, const std::string& key, const std::string& text, const std::string& where);
    const std::map<std::string, double>& values() const { return values_; }
    // Copies the values of the keys both techniques declare (already validated by `from`'s table).
    void copySharedFrom(const ParamValues& from);

private:
    std::map<std::string, double> values_;
};

// Registry (techniques/registry.cpp): every technique, in the order `list` shows them.
const std::vector<const TechniqueDesc*>& allTechniques();
const TechniqueDesc* findTechnique(const std::string& id);                     // nullptr if unknown
const TechniqueDesc& requireTechnique(const std::string& id, const std::string& where);  // InputError

nlohmann::json describeTechnique(const TechniqueDesc& desc);

}  // namespace shadowlab
