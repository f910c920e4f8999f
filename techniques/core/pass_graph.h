// The frame as a graph of passes (DESIGN.md section 3; Filament's frame graph, Falcor's declared
// pass inputs and outputs). Passes declare the resources they read and write. execute() runs only
// the passes that the requested outputs need, and skips a pass whose inputs have the same versions
// as when it last ran: its outputs are reused. Every decision is recorded with its reason for
// --stats, so a user can see that a static scene renders its shadow map once.
#pragma once
#include <cstdint>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace shadowlab {

// FNV-1a, for versions of resources (scene transforms, light, parameters).
uint64_t hashBytes(const void* data, size_t size, uint64_t seed = 1469598103934665603ull);
template <class T>
uint64_t hashValue(const T& value, uint64_t seed = 1469598103934665603ull) {
    return hashBytes(&value, sizeof(T), seed);
}

struct PassRecord {
    std::string name;
    std::string group;        // "frame", "L0", "L1", ...
    std::string technique;    // technique id, or "" for frame passes
    int runs = 0;             // frames in which it ran
    int reuses = 0;           // frames in which its outputs were reused (inputs unchanged)
    int notNeeded = 0;        // frames in which nothing requested read its outputs
    std::string status;       // of the last frame: "ran" or "skipped"
    std::string reason;       // why it ran or was skipped, in the last frame
    std::vector<double> ms;   // time of every run
    std::vector<std::string> history;  // one entry per frame: "ran", "reused", "not needed", or "skipped"
                                       // (a pass that never runs here; `reason` says why)
};

class PassGraph {
public:
    using Timer = std::function<double(const std::function<void()>&)>;  // runs, returns milliseconds

    // A resource that no pass produces (scene transforms, camera, a light, a parameter value).
    void setSource(const std::string& resource, uint64_t version);
    // Adds a pass; all its inputs must be sources or outputs of passes added before it.
    void addPass(const std::string& name, const std::string& group, const std::string& technique,
                 const std::vector<std::string>& inputs, const std::vector<std::string>& outputs,
                 std::function<void()> run);
    // A pass of the chosen technique that will never run in this configuration, with the reason
    // ("point light (size 0): hard shadows replace soft-shadow passes"). Listed in --stats.
    void addStaticSkip(const std::string& name, const std::string& group, const std::string& technique,
                       const std::string& reason);

    // Runs frame `frame`: the passes needed by `requested` outputs whose input versions changed.
    void execute(const std::set<std::string>& requested, int frame, const Timer& timer);
    // Forgets every cached output: the next execute() runs everything needed (--no-reuse, to time
    // every pass of a static scene in every frame).
    void invalidate();

    bool produces(const std::string& resource) const;
    uint64_t version(const std::string& resource) const;
    const std::vector<PassRecord>& records() const { return records_; }
    std::vector<PassRecord>& records() { return records_; }

private:
    struct Node {
        std::vector<std::string> inputs;
        std::vector<std::string> outputs;
        std::function<void()> run;
        size_t record = 0;
        bool hasRun = false;
        uint64_t lastKey = 0;
        int lastRunFrame = -1;
    };
    std::vector<Node> nodes_;
    std::vector<PassRecord> records_;
    std::map<std::string, uint64_t> versions_;   // current version of every resource
    std::map<std::string, size_t> producer_;     // resource -> node
    std::set<std::string> sources_;
    bool invalidated_ = false;
};

}  // namespace shadowlab
