#include "graph/internals.h"

#include <filesystem>
#include <fstream>

#include "error.h"
#include "image/provenance.h"

namespace fs = std::filesystem;

namespace shadowlab {

std::string InternalWriter::stage(const std::string& file) {
    fs::path full = fs::path(directory_) / file;
    fs::create_directories(full.parent_path());
    return outputs_.stage(full.string());
}

void InternalWriter::writeFloatImage(const std::string& file, const Image& image, const std::string& name) {
    fs::path full = fs::path(directory_) / file;
    fs::create_directories(full.parent_path());
    if (provenance_.is_null()) {
        writePFM(outputs_.stage(full.string()), image);
        return;
    }
    nlohmann::json record = provenance_;
    record["buffer"] = "internal " + prefix_ + name;
    writePfmWithSidecar(outputs_, full.string(), image, record);
}

void InternalWriter::image(const std::string& name, const Image& img, const std::string& doc, const std::string& kind,
                           int level) {
    std::string stem = prefix_ + name + (level >= 0 ? "-" + std::to_string(level) : "");
    // PFM holds 1 or 3 channels: 2-channel images (min/max, value/weight) are written channel by
    // channel, as are 4-channel ones.
    auto entry = [&](const std::string& file, int channels, int channel) {
        nlohmann::json e{{"name", name},        {"file", file},         {"kind", kind},
                         {"size", {img.width, img.height}}, {"channels", channels}, {"description", doc}};
        if (level >= 0) e["level"] = level;
        if (channel >= 0) e["channel"] = channel;
        entries_.push_back(e);
    };
    if (img.channels == 1 || img.channels == 3) {
        writeFloatImage(stem + ".pfm", img, name);
        entry(stem + ".pfm", img.channels, -1);
        return;
    }
    for (int c = 0; c < img.channels; ++c) {
        Image one(img.width, img.height, 1);
        for (size_t i = 0; i < one.pixelCount(); ++i) one.data[i] = img.data[i * size_t(img.channels) + size_t(c)];
        std::string file = stem + "-c" + std::to_string(c) + ".pfm";
        writeFloatImage(file, one, name);
        entry(file, 1, c);
    }
}

void InternalWriter::mesh(const std::string& name, const MeshData& mesh, const std::string& kind, const std::string& doc) {
    std::string file = prefix_ + name + ".ply";
    std::ofstream out(stage(file), std::ios::binary);
    out << meshToPLY(mesh);
    if (!out) throw InternalError("cannot write " + file);
    nlohmann::json attributes = nlohmann::json::array();
    for (const auto& [attr, values] : mesh.primitiveAttributes) attributes.push_back(attr);
    entries_.push_back({{"name", name}, {"file", file}, {"kind", kind}, {"primitives", mesh.primitiveCount()},
                        {"vertices", mesh.positions.size()}, {"attributes", attributes}, {"description", doc}});
}

void InternalWriter::json(const std::string& name, const nlohmann::json& value, const std::string& doc,
                          const std::string& kind) {
    std::string file = prefix_ + name + ".json";
    std::ofstream(stage(file), std::ios::binary) << value.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
    entries_.push_back({{"name", name}, {"file", file}, {"kind", kind}, {"description", doc}});
}

void InternalWriter::writeIndex() {
    fs::create_directories(directory_);
    std::ofstream(outputs_.stage((fs::path(directory_) / "index.json").string()), std::ios::binary)
        << nlohmann::json{{"files", entries_}}.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
}

}  // namespace shadowlab
