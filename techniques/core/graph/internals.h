// Writes --internals files (DESIGN.md section 6) through an OutputSet, and index.json: images and
// pyramids as PFM (one file per level: <name>-<level>.pfm; one per channel beyond three), meshes
// and line sets as PLY with their per-primitive attributes, records and other data as JSON.
#pragma once
#include <nlohmann/json.hpp>
#include <string>

#include "graph/resources.h"
#include "image/image.h"

namespace shadowlab {

// Where Renderer::writeInternals puts what it reads: files (InternalWriter) or memory (the views
// of viz/ collect the typed internals without writing a file).
class InternalSink {
public:
    virtual ~InternalSink() = default;
    // `kind` is what index.json says ("image", "pyramid" level, ...); `level` >= 0 for pyramid levels.
    virtual void image(const std::string& name, const Image& image, const std::string& doc,
                       const std::string& kind = "image", int level = -1) = 0;
    virtual void mesh(const std::string& name, const MeshData& mesh, const std::string& kind, const std::string& doc) = 0;
    virtual void json(const std::string& name, const nlohmann::json& value, const std::string& doc,
                      const std::string& kind = "json") = 0;
    virtual void setPrefix(const std::string& prefix) { prefix_ = prefix; }  // "" or "light1/"
    virtual void setProvenance(const nlohmann::json&) {}
    virtual void writeIndex() {}

protected:
    std::string prefix_;
};

class InternalWriter : public InternalSink {
public:
    InternalWriter(const std::string& directory, OutputSet& outputs) : directory_(directory), outputs_(outputs) {}
    void image(const std::string& name, const Image& image, const std::string& doc, const std::string& kind = "image",
               int level = -1) override;
    void mesh(const std::string& name, const MeshData& mesh, const std::string& kind, const std::string& doc) override;
    void json(const std::string& name, const nlohmann::json& value, const std::string& doc,
              const std::string& kind = "json") override;
    // Every PFM written after this gets a JSON sidecar (techniques/core/image/provenance.h) with this
    // record, its "buffer" field naming the internal.
    void setProvenance(const nlohmann::json& provenance) override { provenance_ = provenance; }
    void writeIndex() override;
    const nlohmann::json& entries() const { return entries_; }

private:
    std::string stage(const std::string& file);
    void writeFloatImage(const std::string& file, const Image& image, const std::string& name);
    std::string directory_;
    OutputSet& outputs_;
    nlohmann::json provenance_;
    nlohmann::json entries_ = nlohmann::json::array();
};

}  // namespace shadowlab
