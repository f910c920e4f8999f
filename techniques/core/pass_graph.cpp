#include "pass_graph.h"

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

void PassGraph::setSource(const std::string& resource, uint64_t version) {
    if (producer_.count(resource)) throw InternalError("resource '" + resource + "' is produced by a pass");
    sources_.insert(resource);
    versions_[resource] = version;
}

void PassGraph::addPass(const std::string& name, const std::string& group, const std::string& technique,
                        const std::vector<std::string>& inputs, const std::vector<std::string>& outputs,
                        std::function<void()> run) {
    for (const std::string& in : inputs) {
        if (!sources_.count(in) && !producer_.count(in))
            throw InternalError("pass '" + name + "' reads '" + in + "', which no earlier pass produces");
    }
    Node node;
    node.inputs = inputs;
    node.outputs = outputs;
    node.run = std::move(run);
    node.record = records_.size();
    for (const std::string& out : outputs) {
        if (producer_.count(out) || sources_.count(out))
            throw InternalError("pass '" + name + "' writes '" + out + "', which is already produced");
        producer_[out] = nodes_.size();
    }
    PassRecord record;
    record.name = name;
    record.group = group;
    record.technique = technique;
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

bool PassGraph::produces(const std::string& resource) const { return producer_.count(resource) > 0; }

uint64_t PassGraph::version(const std::string& resource) const {
    auto it = versions_.find(resource);
    return it == versions_.end() ? 0 : it->second;
}

void PassGraph::invalidate() {
    for (Node& n : nodes_) n.hasRun = false;
    invalidated_ = true;
}

void PassGraph::execute(const std::set<std::string>& requested, int frame, const Timer& timer) {
    // 1. Which passes are needed: walk back from the requested outputs through the inputs.
    std::vector<bool> needed(nodes_.size(), false);
    std::vector<std::string> stack(requested.begin(), requested.end());
    for (const std::string& r : requested)
        if (!producer_.count(r) && !sources_.count(r)) throw InternalError("nothing produces requested output '" + r + "'");
    while (!stack.empty()) {
        std::string resource = stack.back();
        stack.pop_back();
        auto it = producer_.find(resource);
        if (it == producer_.end() || needed[it->second]) continue;
        needed[it->second] = true;
        for (const std::string& in : nodes_[it->second].inputs) stack.push_back(in);
    }
    // 2. In declaration order (a topological order, since inputs precede their readers): run the
    //    needed passes whose input versions changed; reuse the outputs of the others.
    for (size_t i = 0; i < nodes_.size(); ++i) {
        Node& node = nodes_[i];
        PassRecord& record = records_[node.record];
        if (!needed[i]) {
            ++record.notNeeded;
            record.status = "skipped";
            record.reason = "not needed: no requested output reads it";
            record.history.push_back("not needed");
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
            record.history.push_back("reused");
            continue;
        }
        record.reason = invalidated_ && frame > 0 ? "cached outputs dropped (reuse disabled)"
                        : !node.hasRun             ? "first frame that needs it"
                                                   : "an input changed";
        double ms = timer(node.run);
        record.ms.push_back(ms);
        ++record.runs;
        record.status = "ran";
        record.history.push_back("ran");
        node.hasRun = true;
        node.lastKey = key;
        node.lastRunFrame = frame;
        for (const std::string& out : node.outputs) versions_[out] = hashBytes(out.data(), out.size(), key);
    }
    invalidated_ = false;
    for (PassRecord& record : records_) {
        if (record.history.size() < size_t(frame + 1) && record.runs == 0 && record.reuses == 0 &&
            record.notNeeded == 0 && !record.reason.empty())
            record.history.push_back("skipped");  // a static reason, stated once in `reason`
    }
}

}  // namespace shadowlab
