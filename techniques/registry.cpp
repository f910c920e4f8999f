// Every technique, one line each, in the order `shadowlab list` shows them.
#include "graph/technique.h"

namespace shadowlab {

const TechniqueDesc& hardTechnique();
const TechniqueDesc& pcfTechnique();
const TechniqueDesc& pcssTechnique();
const TechniqueDesc& sssmTechnique();
const TechniqueDesc& ssmGbp06Technique();
const TechniqueDesc& ssmContourTechnique();
const TechniqueDesc& referenceTechnique();
const TechniqueDesc& raytracedTechnique();
const TechniqueDesc& ssvTechnique();
const TechniqueDesc& spsmTechnique();
const TechniqueDesc& pvmTechnique();
const TechniqueDesc& pvmfTechnique();
const TechniqueDesc& autoTechnique();

const std::vector<const TechniqueDesc*>& allTechniques() {
    static const std::vector<const TechniqueDesc*> all = {
        &hardTechnique(),
        &pcfTechnique(),
        &pcssTechnique(),
        &sssmTechnique(),
        &ssmGbp06Technique(),
        &ssmContourTechnique(),
        &ssvTechnique(),
        &pvmTechnique(),
        &pvmfTechnique(),
        &spsmTechnique(),
        &autoTechnique(),
        &referenceTechnique(),
        &raytracedTechnique(),
    };
    return all;
}

const TechniqueDesc* findTechnique(const std::string& id) {
    for (const TechniqueDesc* d : allTechniques())
        if (d->id == id) return d;
    return nullptr;
}

}  // namespace shadowlab
