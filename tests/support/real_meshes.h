// The real-mesh test set in tests that walk every shipped scene (assets/models/README.md).
// Scene mesh-NAME draws the real mesh NAME, assets/models/real/NAME.gltf, which
// scripts/fetch-meshes.sh makes when the tests are built (CMake target shadowlab_real_meshes). Where
// it has not (SHADOWLAB_FETCH_MESHES=OFF, a copy of the tree without build/), such a scene cannot
// load, and the tests that walk every scene leave it out, saying so once.
#pragma once
#include <cstdio>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace shadowlab::testing {

// "mesh-bunny" -> "bunny"; "" for a scene that is not one of the real-mesh scenes.
inline std::string realMeshOfScene(const std::string& scene) {
    return scene.rfind("mesh-", 0) == 0 ? scene.substr(5) : std::string();
}

// Is the object one of the real meshes (its glTF under assets/models/real/)?
inline bool isRealMeshObject(const Object& object) {
    return object.source.rfind("gltf:", 0) == 0 && object.source.find("/models/real/") != std::string::npos;
}

// False, with a note on stdout the first time, for a real-mesh scene whose glTF is missing.
inline bool sceneCanLoad(const std::string& scene) {
    const std::string mesh = realMeshOfScene(scene);
    if (mesh.empty()) return true;
    std::error_code ec;
    if (std::filesystem::is_regular_file(realMeshPath(mesh), ec)) return true;
    static std::set<std::string> told;
    if (told.insert(scene).second)
        std::printf("[ note ] scene %s left out: %s is missing (scripts/fetch-meshes.sh makes it)\n", scene.c_str(),
                    realMeshPath(mesh).c_str());
    return false;
}

// listScenes() without the real-mesh scenes whose glTF is missing.
inline std::vector<std::string> loadableScenes() {
    std::vector<std::string> names;
    for (const std::string& name : listScenes())
        if (sceneCanLoad(name)) names.push_back(name);
    return names;
}

}  // namespace shadowlab::testing
