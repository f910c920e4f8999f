// Writes --internals files (DESIGN.md section 6) through an OutputSet, and index.json: images and
// pyramids as PFM (one file per level: <name>-<level>.pfm; one per channel beyond three), meshes
// and line sets as PLY with their per-primitive attributes, records and other data as JSON.
#pragma once
#include <nlohmann/json.hpp>
#include <string>

#include "image.h"
#include "resources.h"

namespace shadowlab {

class InternalWriter {
public:
    InternalWriter(const std::string& directory, OutputSet& outputs) : directory_(directory), outputs_(outputs) {}
    // `kind` is what index.json says ("image", "pyramid" level, ...); `level` >= 0 for pyramid levels.
    void image(const std::string& name, const Image& image, const std::string& doc, const std::string& kind = "image",
               int level = -1);
    void mesh(const std::string& name, const MeshData& mesh, const std::string& kind, const std::string& doc);
    void json(const std::string& name, const nlohmann::json& value, const std::string& doc,
              const std::string& kind = "json");
    void setPrefix(const std::string& prefix) { prefix_ = prefix; }  // "" or "light1/"
    // Every PFM written after this gets a JSON sidecar (techniques/core/provenance.h) with this
    // record, its "buffer" field naming the internal.
    void setProvenance(const nlohmann::json& provenance) { provenance_ = provenance; }
    void writeIndex();
    const nlohmann::json& entries() const { return entries_; }

private:
    std::string stage(const std::string& file);
    void writeFloatImage(const std::string& file, const Image& image, const std::string& name);
    std::string directory_;
    OutputSet& outputs_;
    std::string prefix_;
    nlohmann::json provenance_;
    nlohmann::json entries_ = nlohmann::json::array();
};

}  // namespace shadowlab
