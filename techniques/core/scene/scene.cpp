// Scenes: the small amount of math the rest of the renderer asks of a scene (transforms over time,
// bounds), finding scene files, and exporting triangles. Reading a scene file is scene_file.cpp
// (the schema) on top of json_reader.cpp (validated JSON).
#include "scene/scene.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>

#include "error.h"

namespace shadowlab {

namespace fs = std::filesystem;

// --- Scene math
// -----------------------------------------------------------------------------------

glm::mat4 Object::worldFromObjectAt(double t) const {
    switch (motion.type) {
        case Motion::Type::None:
            return worldFromObject;
        case Motion::Type::Rotate: {
            // Reduce the angle in double so that long runs keep float precision.
            const double degrees =
                std::fmod(static_cast<double>(motion.degreesPerSecond) * t, 360.0);
            const float angle = glm::radians(static_cast<float>(degrees));
            const glm::mat4 pivotFromObject = glm::translate(glm::mat4(1.0f), -motion.pivot);
            const glm::mat4 rotated = glm::rotate(glm::mat4(1.0f), angle, motion.axis);
            const glm::mat4 worldFromPivot = glm::translate(glm::mat4(1.0f), motion.pivot);
            return worldFromPivot * rotated * pivotFromObject * worldFromObject;
        }
        case Motion::Type::Keyframes: {
            if (motion.keys.empty()) return worldFromObject;
            const auto& keys = motion.keys;
            glm::vec3 offset = keys.front().translate;
            const double period = keys.back().time;
            if (keys.size() > 1 && period > 0.0) {
                // Loop over [0, period): the last key's time is the loop length.
                double local = std::fmod(t, period);
                if (local < 0.0) local += period;
                if (local > keys.front().time) {
                    for (size_t i = 0; i + 1 < keys.size(); ++i) {
                        if (local < keys[i + 1].time) {
                            const double span = keys[i + 1].time - keys[i].time;
                            const float s = static_cast<float>((local - keys[i].time) / span);
                            offset = glm::mix(keys[i].translate, keys[i + 1].translate, s);
                            break;
                        }
                    }
                }
            }
            return glm::translate(glm::mat4(1.0f), offset) * worldFromObject;
        }
    }
    return worldFromObject;
}

const char* lightShapeName(LightShape shape) {
    switch (shape) {
        case LightShape::Point: return "point";
        case LightShape::Square: return "square";
        case LightShape::Disk: return "disk";
        case LightShape::Sphere: return "sphere";
    }
    return "unknown";
}

glm::vec3 Light::right() const { return glm::normalize(glm::cross(direction, up)); }

glm::mat4 Camera::viewFromWorld() const { return glm::lookAt(position, target, up); }

glm::mat4 Camera::clipFromView(float aspect) const {
    return glm::perspective(glm::radians(fovYDegrees), aspect, nearPlane, farPlane);
}

bool Scene::hasMotion() const {
    return std::any_of(objects.begin(), objects.end(), [](const Object& o) { return o.moves(); });
}

Bounds Scene::bounds(double t, bool castersOnly) const {
    Bounds b;
    for (const Object& object : objects) {
        if (castersOnly && !object.castsShadows) continue;
        const glm::mat4 worldFromObject = object.worldFromObjectAt(t);
        for (const glm::vec3& p : object.mesh.positions) {
            b.extend(glm::vec3(worldFromObject * glm::vec4(p, 1.0f)));
        }
    }
    return b;
}

// --- Finding scene files
// ----------------------------------------------------------------------------

std::string projectRoot() {
    if (const char* root = std::getenv("SHADOWLAB_ROOT"); root != nullptr && root[0] != '\0') {
        return root;
    }
#ifdef SHADOWLAB_SOURCE_DIR
    return SHADOWLAB_SOURCE_DIR;
#else
    return ".";
#endif
}

std::vector<std::string> listScenes() {
    std::vector<std::string> names;
    std::error_code ec;
    const fs::path dir = fs::path(projectRoot()) / "assets" / "scenes";
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        if (it->path().extension() == ".json" && it->is_regular_file(ec)) {
            names.push_back(it->path().stem().string());
        }
    }
    std::sort(names.begin(), names.end());
    return names;
}

namespace {

std::string join(const std::vector<std::string>& parts, const std::string& separator) {
    std::string out;
    for (size_t i = 0; i < parts.size(); ++i) out += (i ? separator : "") + parts[i];
    return out;
}

bool endsWith(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() &&
           s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

std::string resolveScenePath(const std::string& nameOrPath) {
    const bool isPath = nameOrPath.find('/') != std::string::npos || endsWith(nameOrPath, ".json");
    const std::string path =
        isPath ? nameOrPath
               : (fs::path(projectRoot()) / "assets" / "scenes" / (nameOrPath + ".json")).string();
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    if (fs::is_directory(status)) throw InputError(path + ": is a directory, expected a scene file (.json)");
    if (fs::exists(status) && !fs::is_regular_file(status)) {
        throw InputError(path + ": is not a regular file (a device, pipe or socket), expected a scene file (.json)");
    }
    if (!fs::is_regular_file(status)) {
        const std::vector<std::string> known = listScenes();
        throw InputError(path + ": no such scene file (known scenes: " +
                         (known.empty() ? std::string("none") : join(known, ", ")) + ")");
    }
    return path;
}

// --- Parsing: JSON text to a DOM, with field paths for the errors nlohmann reports
// --------------------

// --- Export
// -------------------------------------------------------------------------------------------

void writeTrianglesOBJ(const Scene& scene, double t, const std::string& path) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path + ": cannot open for writing");
    char line[128];
    std::snprintf(line, sizeof line, "%.9g", t);
    out << "# shadowlab scene " << scene.name << ", world-space triangles at t = " << line << "\n";
    size_t base = 1;  // OBJ indices are 1-based and global over the file
    for (const Object& object : scene.objects) {
        std::string name = object.name;
        std::replace_if(
            name.begin(), name.end(), [](unsigned char c) { return std::isspace(c); }, '_');
        out << "o " << (name.empty() ? "object" : name) << "\n";
        const glm::mat4 worldFromObject = object.worldFromObjectAt(t);
        for (const glm::vec3& p : object.mesh.positions) {
            const glm::vec3 w = glm::vec3(worldFromObject * glm::vec4(p, 1.0f));
            std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", w.x, w.y, w.z);
            out << line;
        }
        for (size_t i = 0; i + 2 < object.mesh.indices.size(); i += 3) {
            out << "f " << base + object.mesh.indices[i] << ' ' << base + object.mesh.indices[i + 1]
                << ' ' << base + object.mesh.indices[i + 2] << '\n';
        }
        base += object.mesh.positions.size();
    }
    out.flush();
    if (!out) throw InputError(path + ": write failed");
}

}  // namespace shadowlab
