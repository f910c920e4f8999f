// Technique descriptors (STYLE.md 10): every default in range, every parameter documented, every
// pass input produced by an earlier pass, a frame resource or a declared parameter, and the last
// pass producing the light's visibility.
#include <gtest/gtest.h>

#include <set>

#include "error.h"
#include "graph/renderer.h"
#include "graph/technique.h"

namespace shadowlab {
const TechniqueDesc& templateTechnique();  // techniques/template: compiled, validated, not registered
namespace {

TEST(Descriptors, ParametersAreCompleteAndDefaultsInRange) {
    for (const TechniqueDesc* d : allTechniques()) {
        std::set<std::string> keys;
        EXPECT_FALSE(d->citation.empty()) << d->id;
        for (const PassDesc& pass : d->passes) EXPECT_TRUE(pass.create) << d->id << "/" << pass.name;
        EXPECT_EQ(validateTechnique(*d), std::vector<std::string>{}) << d->id;
        for (const ParamDesc& p : d->params) {
            EXPECT_TRUE(keys.insert(p.key).second) << d->id << ": duplicate " << p.key;
            EXPECT_LE(p.minValue, p.defaultValue) << d->id << "." << p.key;
            EXPECT_LE(p.defaultValue, p.maxValue) << d->id << "." << p.key;
            if (p.type != ParamDesc::Type::Enum) EXPECT_GT(p.step, 0.0) << d->id << "." << p.key;
            EXPECT_FALSE(p.doc.empty()) << d->id << "." << p.key;
            ParamValues values(*d);
            std::string text = p.type == ParamDesc::Type::Enum ? p.choices.at(size_t(p.defaultValue))
                               : p.type == ParamDesc::Type::Float ? std::to_string(p.defaultValue)
                                                                  : std::to_string((long long)p.defaultValue);
            EXPECT_NO_THROW(values.set(*d, p.key, text, "test"));
        }
    }
}

TEST(Descriptors, EveryInputIsProduced) {
    const std::set<std::string> frame = {"gbuffer", "scene.casters", "scene.objects", "camera", "light",
                                         "light.radiance", "ambient"};
    for (const TechniqueDesc* d : allTechniques()) {
        // A choosing technique (`auto`) runs the passes of what it picks, none of its own; its
        // parameters are read by the choice, made again when they change (AutoRender tests).
        if (d->choose) {
            EXPECT_TRUE(d->passes.empty()) << d->id;
            continue;
        }
        std::set<std::string> produced;
        ASSERT_FALSE(d->passes.empty()) << d->id;
        for (const PassDesc& pass : d->passes) {
            for (const std::string& in : pass.reads) {
                if (in.rfind("param:", 0) == 0) {
                    EXPECT_TRUE(d->findParam(in.substr(6))) << d->id << "/" << pass.name << " reads undeclared " << in;
                } else {
                    EXPECT_TRUE(frame.count(in) || produced.count(in)) << d->id << "/" << pass.name << " reads " << in;
                }
            }
            for (const std::string& m : pass.modifies) EXPECT_TRUE(produced.count(m)) << d->id << "/" << pass.name;
            for (const std::string& out : pass.writes()) produced.insert(out);
        }
        EXPECT_TRUE(produced.count("visibility")) << d->id;
        // Every parameter is read by some pass, so changing it re-runs what depends on it.
        for (const ParamDesc& p : d->params) {
            bool read = false;
            for (const PassDesc& pass : d->passes)
                for (const std::string& in : pass.reads) read |= in == "param:" + p.key;
            EXPECT_TRUE(read) << d->id << "." << p.key << " is read by no pass";
        }
    }
}

TEST(Descriptors, SoftTechniquesHaveSoftPassesAndShareShadowMapParameters) {
    for (const TechniqueDesc* d : allTechniques()) {
        bool softPass = false;
        for (const PassDesc& p : d->passes) softPass |= p.soft;
        if (d->choose) continue;  // `auto`: a point light's choice is `hard` itself (AutoRender tests)
        if (d->id == "raytraced") {
            EXPECT_FALSE(softPass);  // exact for point lights too
            continue;
        }
        if (d->id == "ssv") {
            // Geometry-based (ssv): its own passes are exact hard shadows under a point light (hard
            // shadow volumes), so nothing is replaced by `hard`, and it has no shadow map to size.
            EXPECT_FALSE(softPass) << d->id;
            EXPECT_FALSE(d->findParam("sm_size")) << d->id;
            continue;
        }
        EXPECT_EQ(softPass, d->soft) << d->id;
        EXPECT_TRUE(d->findParam("sm_size")) << d->id;
    }
}

TEST(Descriptors, TemplateFolderIsASoundDescriptor) {
    EXPECT_EQ(validateTechnique(templateTechnique()), std::vector<std::string>{});
    EXPECT_EQ(findTechnique("template"), nullptr);  // not registered: a folder to copy
    ParamValues v(templateTechnique());
    EXPECT_EQ(v.inapplicable(templateTechnique()).size(), 1u);  // sigma applies to filter=mean only
    v.set(templateTechnique(), "filter", "mean", "test");
    EXPECT_TRUE(v.inapplicable(templateTechnique()).empty());
}

TEST(Descriptors, ParameterValidation) {
    const TechniqueDesc& pcf = requireTechnique("pcf", "test");
    ParamValues v(pcf);
    EXPECT_THROW(v.set(pcf, "nope", "1", "--set"), InputError);
    EXPECT_THROW(v.set(pcf, "pcf_kernel", "nan", "--set"), InputError);
    EXPECT_THROW(v.set(pcf, "pcf_kernel", "inf", "--set"), InputError);
    EXPECT_THROW(v.set(pcf, "pcf_kernel", "3.5", "--set"), InputError);
    EXPECT_THROW(v.set(pcf, "pcf_kernel", "", "--set"), InputError);
    EXPECT_THROW(v.set(pcf, "pcf_kernel", "3x", "--set"), InputError);
    EXPECT_THROW(v.set(pcf, "second_depth", "2", "--set"), InputError);
    v.set(pcf, "second_depth", "true", "--set");
    EXPECT_TRUE(v.getBool("second_depth"));
    v.set(pcf, "pcf_kernel", "9", "--set");
    EXPECT_EQ(v.getInt("pcf_kernel"), 9);
    EXPECT_THROW(requireTechnique("nope", "--technique"), InputError);
}

}  // namespace
}  // namespace shadowlab
