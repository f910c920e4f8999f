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
    // Forgets one pass's cached outputs (something outside the graph rewrote them): the next
    // execute() that needs them runs it again.
    void invalidatePass(const std::string& name);

    // ---- progressive execution (the window's frame budget) ----
    // A pass the graph may run a part at a time: `units(pass)` pieces of work (the renderer's
    // frame-size passes: tiles of two rows, row by row), `runUnits(pass, from, to, run)` runs pieces
    // [from, to) of it (`run` is the pass's own function, called with the pieces' scissor set). A
    // pass with 0 units runs whole. `unitsPerRow` says how units lie on the image (a row of tiles),
    // for the forecast of a unit from its neighbours' costs.
    struct Slicing {
        std::function<int(const std::string& pass)> units;
        std::function<void(const std::string& pass, int from, int to, const std::function<void()>& run)> runUnits;
        // Before a pass's first piece: gets it ready (allocates and first-touches its outputs) in
        // steps that are pieces of work of their own: returns -1 when there was nothing to do, 0
        // after a step with more to do, 1 after the last step. Optional.
        std::function<int(const std::string& pass)> prepare;
        int unitsPerRow = 1;
    };
    // Runs frame `frame` as execute() does, but stops once `budgetMs` is spent (after at least one
    // piece of work) and resumes where it stopped on the next call: a pass with units runs as many
    // as its measured cost per unit fits in what is left of the budget, the others whole. A pass
    // counts as run (its time the sum of its pieces, its outputs a new version) only when its last
    // piece ran; when an input changes between calls, what it invalidates runs again from the
    // start. Returns the estimated fraction of the frame's work done: 1 when every needed pass is
    // current, and then the outputs are those execute() would have made.
    double executeSliced(const std::set<std::string>& requested, int frame, const Timer& timer, double budgetMs,
                         const Slicing& slicing);

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
    // executeSliced: the pass it stopped inside, and the work of the frame it is refining.
    struct Partial {
        size_t node = ~size_t(0);
        uint64_t key = 0;  // the pass's input key when its first piece ran
        int done = 0, total = 0;
        double ms = 0.0;   // the pieces' time so far
        bool forecast = false;    // contiguous pieces sized by unitCost_; else scattered bands
        int band = 1, stride = 1; // scattered bands: units per band, the order's stride
        int next = 0;             // the next unit (forecast) or the next band in the order
        int bandsRun = 0;         // pieces run so far
        bool prepared = false;    // Slicing::prepare ran
        double lastMs = 0.0;      // the last piece's time
        std::vector<float> cost;  // ms per unit of the pieces run (-1: not run)
    };
    void keepUnitCosts();  // the partial's unit costs into unitCost_ (when it is abandoned)
    std::map<std::string, std::vector<float>> unitCost_;  // by pass: ms per unit of its last refinement (-1: unknown)
    Partial partial_;
    double slicedDoneMs_ = 0.0;        // work finished since the frame being refined started
    size_t slicedLastNode_ = 0;        // the last pass run in it (a pass at or before it running again: a restart)
    bool slicedComplete_ = true;       // the last call finished its frame
    uint64_t inputKey(const Node& node);
    // Records a pass that is not needed, or whose inputs are unchanged (reused): true for both.
    bool skipOrReuse(const Node& node, bool needed, uint64_t key);
    void recordRun(Node& node, uint64_t key, int frame, double ms, const char* reason);
};

}  // namespace shadowlab
