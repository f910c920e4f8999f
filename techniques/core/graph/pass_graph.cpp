#include "graph/pass_graph.h"

#include <algorithm>

#include "error.h"

namespace shadowlab {

uint64_t hashBytes(const void* data, size_t size, uint64_t seed) {
    const unsigned char* bytes = static_cast<const unsigned char*>(data);
    uint64_t h = seed;
    for (size_t i = 0; i < size; ++i) {
        h ^= bytes[i];
        h *= 1099511628211ull;
    }
    return h;
}

double PassRecord::medianMs(int firstFrame) const {
    std::vector<double> v;
    for (const auto& [frame, ms] : times)
        if (frame >= firstFrame) v.push_back(ms);
    if (v.empty())
        for (const auto& [frame, ms] : times) v.push_back(ms);
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

template <class T>
static void pushBounded(std::deque<T>& d, T value, size_t keep) {
    d.push_back(std::move(value));
    while (d.size() > keep) d.pop_front();
}

void PassGraph::setSource(const std::string& resource, uint64_t version) {
    if (writes_.count(resource)) throw InternalError("resource '" + resource + "' is produced by a pass");
    sources_.insert(resource);
    versions_[resource] = version;
}

std::string PassGraph::latest(const std::string& resource) const {
    if (sources_.count(resource)) return resource;
    auto it = writes_.find(resource);
    if (it == writes_.end()) return "";
    return resource + "#" + std::to_string(it->second - 1);
}

void PassGraph::addPass(const std::string& name, const std::string& group, const std::string& technique,
                        const std::vector<std::string>& reads, const std::vector<std::string>& creates,
                        const std::vector<std::string>& modifies, std::function<void()> run) {
    Node node;
    node.name = name;
    for (const std::string& in : reads) {
        std::string v = latest(in);
        if (v.empty()) throw InternalError("pass '" + name + "' reads '" + in + "', which no earlier pass produces");
        node.inputs.push_back(v);
    }
    for (const std::string& m : modifies) {
        std::string v = latest(m);
        if (v.empty() || sources_.count(m))
            throw InternalError("pass '" + name + "' modifies '" + m + "', which no earlier pass produces");
        node.inputs.push_back(v);
    }
    for (const std::string& out : creates) {
        if (writes_.count(out) || sources_.count(out))
            throw InternalError("pass '" + name + "' creates '" + out + "', which is already produced");
    }
    for (const std::string& out : creates) {
        writes_[out] = 1;
        node.outputs.push_back(out + "#0");
    }
    for (const std::string& m : modifies) node.outputs.push_back(m + "#" + std::to_string(writes_[m]++));
    for (const std::string& out : node.outputs) producer_[out] = nodes_.size();
    node.run = std::move(run);
    node.record = records_.size();

    PassRecord record;
    auto prevNode = previousNodes_.find(name);
    auto prevRecord = previousRecords_.find(name);
    if (prevRecord != previousRecords_.end()) record = prevRecord->second;  // keeps its counts and times
    record.name = name;
    record.group = group;
    record.technique = technique;
    if (prevNode != previousNodes_.end() && prevNode->second.inputs == node.inputs &&
        prevNode->second.outputs == node.outputs) {
        node.hasRun = prevNode->second.hasRun;
        node.lastKey = prevNode->second.lastKey;
        node.lastRunFrame = prevNode->second.lastRunFrame;
    }
    records_.push_back(record);
    nodes_.push_back(std::move(node));
}

void PassGraph::addStaticSkip(const std::string& name, const std::string& group, const std::string& technique,
                              const std::string& reason) {
    PassRecord record;
    record.name = name;
    record.group = group;
    record.technique = technique;
    record.status = "skipped";
    record.reason = reason;
    records_.push_back(record);
}

void PassGraph::rebuild() {
    previousNodes_.clear();
    previousRecords_.clear();
    for (Node& n : nodes_) previousNodes_[n.name] = std::move(n);
    for (PassRecord& r : records_) previousRecords_[r.name] = std::move(r);
    nodes_.clear();
    records_.clear();
    producer_.clear();
    writes_.clear();
    // Versions of written resources stay: restored nodes compare keys built from them.
}

bool PassGraph::produces(const std::string& resource) const { return writes_.count(resource) > 0; }

uint64_t PassGraph::version(const std::string& resource) const {
    std::string v = latest(resource);
    auto it = versions_.find(v);
    return it == versions_.end() ? 0 : it->second;
}

void PassGraph::invalidate() {
    for (Node& n : nodes_) n.hasRun = false;
    invalidated_ = true;
}

std::vector<bool> PassGraph::needed(const std::set<std::string>& requested) const {
    // Walk back from the requested outputs (their latest versions) through the inputs.
    std::vector<bool> need(nodes_.size(), false);
    std::vector<std::string> stack;
    for (const std::string& r : requested) {
        std::string v = latest(r);
        if (v.empty()) throw InternalError("nothing produces requested output '" + r + "'");
        stack.push_back(v);
    }
    while (!stack.empty()) {
        std::string resource = stack.back();
        stack.pop_back();
        auto it = producer_.find(resource);
        if (it == producer_.end() || need[it->second]) continue;
        need[it->second] = true;
        for (const std::string& in : nodes_[it->second].inputs) stack.push_back(in);
    }
    return need;
}

std::vector<std::string> PassGraph::neededPasses(const std::set<std::string>& requested) const {
    std::vector<bool> need = needed(requested);
    std::vector<std::string> out;
    for (size_t i = 0; i < nodes_.size(); ++i)
        if (need[i]) out.push_back(nodes_[i].name);
    return out;
}

void PassGraph::rerunNeeded(const std::set<std::string>& requested) {
    std::vector<bool> need = needed(requested);
    for (size_t i = 0; i < nodes_.size(); ++i)
        if (need[i]) nodes_[i].run();
}

void PassGraph::measureCost(const std::set<std::string>& requested, int frame, const Timer& timer) {
    std::vector<bool> need = needed(requested);
    for (size_t i = 0; i < nodes_.size(); ++i) {
        if (!need[i]) continue;
        double ms = timer(nodes_[i].run);
        pushBounded(records_[nodes_[i].record].times, std::pair<int, double>(frame, ms), PassRecord::kKeptTimes);
    }
}

void PassGraph::execute(const std::set<std::string>& requested, int frame, const Timer& timer) {
    std::vector<bool> need = needed(requested);
    // In declaration order (a topological order, since inputs precede their readers): run the
    // needed passes whose input versions changed; reuse the outputs of the others.
    std::vector<bool> touched(records_.size(), false);
    for (size_t i = 0; i < nodes_.size(); ++i) {
        Node& node = nodes_[i];
        PassRecord& record = records_[node.record];
        touched[node.record] = true;
        if (!need[i]) {
            ++record.notNeeded;
            record.status = "skipped";
            record.reason = "not needed: no requested output reads it";
            pushBounded(record.history, std::string("not needed"), PassRecord::kKeptFrames);
            continue;
        }
        uint64_t key = 1469598103934665603ull;
        for (const std::string& in : node.inputs) {
            key = hashBytes(in.data(), in.size(), key);
            key = hashValue(versions_[in], key);
        }
        if (node.hasRun && key == node.lastKey) {
            ++record.reuses;
            record.status = "skipped";
            record.reason = "inputs unchanged since frame " + std::to_string(node.lastRunFrame) + ": outputs reused";
            pushBounded(record.history, std::string("reused"), PassRecord::kKeptFrames);
            continue;
        }
        record.reason = invalidated_ && frame > 0 ? "cached outputs dropped (reuse disabled)"
                        : !node.hasRun             ? "first frame that needs it"
                                                   : "an input changed";
        double ms = timer(node.run);
        pushBounded(record.times, std::pair<int, double>(frame, ms), PassRecord::kKeptTimes);
        ++record.runs;
        record.status = "ran";
        pushBounded(record.history, std::string("ran"), PassRecord::kKeptFrames);
        node.hasRun = true;
        node.lastKey = key;
        node.lastRunFrame = frame;
        for (const std::string& out : node.outputs) versions_[out] = hashBytes(out.data(), out.size(), key);
    }
    invalidated_ = false;
    for (size_t r = 0; r < records_.size(); ++r) {
        PassRecord& record = records_[r];
        if (!touched[r] && record.runs == 0 && record.reuses == 0 && record.notNeeded == 0 && !record.reason.empty())
            pushBounded(record.history, std::string("skipped"), PassRecord::kKeptFrames);  // a static reason
    }
}

}  // namespace shadowlab
