// The frame as a graph of passes (DESIGN.md section 3; Filament's frame graph, Falcor's declared
// pass inputs and outputs). Passes declare the resources they read, create and modify. execute()
// runs only the passes that the requested outputs need, and skips a pass whose inputs have the same
// versions as when it last ran: its outputs are reused. A pass that modifies a resource makes a new
// version of it ("blur" after "hard_shadow" both writing "vbuffer": vbuffer#0, vbuffer#1), so a
// reader sees exactly the version written before it. Every decision is recorded with its reason
// for --stats, so a user can see that a static scene renders its shadow map once.
#pragma once
#include <cstdint>
#include <deque>
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
    static constexpr size_t kKeptFrames = 64;   // history entries kept (a window open all day stays bounded)
    static constexpr size_t kKeptTimes = 256;   // run times kept for the medians
    std::string name;
    std::string group;        // "frame", "L0", "L1", ...
    std::string technique;    // technique id, or "" for frame passes (fixed cost)
    int runs = 0;             // frames in which it ran
    int reuses = 0;           // frames in which its outputs were reused (inputs unchanged)
    int notNeeded = 0;        // frames in which nothing requested read its outputs
    std::string status;       // of the last frame: "ran" or "skipped"
    std::string reason;       // why it ran or was skipped, in the last frame
    std::deque<std::pair<int, double>> times;  // (frame, milliseconds) of the last runs
    std::deque<std::string> history;           // the last frames: "ran", "reused", "not needed", "skipped"
    // Median milliseconds of the runs in frames >= firstFrame (all kept runs when none).
    double medianMs(int firstFrame = 0) const;
};

class PassGraph {
public:
    using Timer = std::function<double(const std::function<void()>&)>;  // runs, returns milliseconds

    // A resource that no pass produces (scene transforms, camera, a light, a parameter value).
    void setSource(const std::string& resource, uint64_t version);
    // Adds a pass. `reads` must be sources or written by passes added before it; `creates` are new
    // resources; `modifies` are resources of earlier passes that this pass reads and rewrites.
    void addPass(const std::string& name, const std::string& group, const std::string& technique,
                 const std::vector<std::string>& reads, const std::vector<std::string>& creates,
                 const std::vector<std::string>& modifies, std::function<void()> run);
    // A pass of the chosen technique that will never run in this configuration, with the reason
    // ("point light (size 0): hard shadows replace soft-shadow passes"). Listed in --stats.
    void addStaticSkip(const std::string& name, const std::string& group, const std::string& technique,
                       const std::string& reason);
    // Starts a new graph; a pass added again with the same name, inputs and outputs keeps its cached
    // state (a technique switch on one light does not re-run the G-buffer). Sources are kept.
    void rebuild();

    // Runs frame `frame`: the passes needed by `requested` outputs whose input versions changed.
    void execute(const std::set<std::string>& requested, int frame, const Timer& timer);
    // Names of the passes `requested` needs, in execution order.
    std::vector<std::string> neededPasses(const std::set<std::string>& requested) const;
    // Runs the needed passes again, untimed and without touching versions or records (--check-reuse).
    void rerunNeeded(const std::set<std::string>& requested);
    // Runs every needed pass, timed, adding the times to the records (tagged with `frame`) without
    // counting a run or a reuse: what a frame costs when everything changes (cost_ms).
    void measureCost(const std::set<std::string>& requested, int frame, const Timer& timer);
    // Forgets every cached output: the next execute() runs everything needed (--no-reuse, to time
    // every pass of a static scene in every frame).
    void invalidate();

    bool produces(const std::string& resource) const;
    uint64_t version(const std::string& resource) const;  // the latest version of a resource
    const std::vector<PassRecord>& records() const { return records_; }

private:
    struct Node {
        std::string name;
        std::vector<std::string> inputs;   // versioned names ("L0/vbuffer#1")
        std::vector<std::string> outputs;  // versioned names
        std::function<void()> run;
        size_t record = 0;
        bool hasRun = false;
        uint64_t lastKey = 0;
        int lastRunFrame = -1;
    };
    std::string latest(const std::string& resource) const;  // "X" -> "X#k" (sources unchanged)
    std::vector<bool> needed(const std::set<std::string>& requested) const;

    std::vector<Node> nodes_;
    std::vector<PassRecord> records_;
    std::map<std::string, Node> previousNodes_;          // by name, from before rebuild()
    std::map<std::string, PassRecord> previousRecords_;  // by name
    std::map<std::string, uint64_t> versions_;   // current version of every (versioned) resource
    std::map<std::string, size_t> producer_;     // versioned resource -> node
    std::map<std::string, int> writes_;          // resource -> number of versions written
    std::set<std::string> sources_;
    bool invalidated_ = false;
};

}  // namespace shadowlab
