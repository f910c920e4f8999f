#include "graph/pass_graph.h"

#include <algorithm>
#include <numeric>
#include <cmath>

#include "error.h"

namespace shadowlab {

namespace {
// executeSliced: without a forecast, a pass runs in this many scattered bands (rows differ 40-80x
// in cost, so the first bands sample the whole frame); with one, a unit's forecast is the dearest
// unit within this many rows of units of it.
constexpr int kScatteredBands = 512;
constexpr int kForecastRows = 8;
constexpr double kForecastCoverage = 0.9;  // the fraction of units whose cost must be known
}  // namespace

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
    partial_ = Partial();  // node indices change
    slicedComplete_ = true;
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
    partial_ = Partial();
    invalidated_ = true;
}

void PassGraph::invalidatePass(const std::string& name) {
    for (size_t i = 0; i < nodes_.size(); ++i) {
        if (nodes_[i].name != name) continue;
        nodes_[i].hasRun = false;
        if (partial_.node == i) partial_ = Partial();
    }
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

uint64_t PassGraph::inputKey(const Node& node) {
    uint64_t key = 1469598103934665603ull;
    for (const std::string& in : node.inputs) {
        key = hashBytes(in.data(), in.size(), key);
        key = hashValue(versions_[in], key);
    }
    return key;
}

void PassGraph::recordRun(Node& node, uint64_t key, int frame, double ms, const char* reason) {
    PassRecord& record = records_[node.record];
    record.reason = reason;
    pushBounded(record.times, std::pair<int, double>(frame, ms), PassRecord::kKeptTimes);
    ++record.runs;
    record.status = "ran";
    pushBounded(record.history, std::string("ran"), PassRecord::kKeptFrames);
    node.hasRun = true;
    node.lastKey = key;
    node.lastRunFrame = frame;
    for (const std::string& out : node.outputs) versions_[out] = hashBytes(out.data(), out.size(), key);
}

bool PassGraph::skipOrReuse(const Node& node, bool needed, uint64_t key) {
    PassRecord& record = records_[node.record];
    if (!needed) {
        ++record.notNeeded;
        record.status = "skipped";
        record.reason = "not needed: no requested output reads it";
        pushBounded(record.history, std::string("not needed"), PassRecord::kKeptFrames);
        return true;
    }
    if (node.hasRun && key == node.lastKey) {
        ++record.reuses;
        record.status = "skipped";
        record.reason = "inputs unchanged since frame " + std::to_string(node.lastRunFrame) + ": outputs reused";
        pushBounded(record.history, std::string("reused"), PassRecord::kKeptFrames);
        return true;
    }
    return false;
}

static const char* runReason(bool invalidated, int frame, bool hasRun) {
    return invalidated && frame > 0 ? "cached outputs dropped (reuse disabled)"
           : !hasRun                 ? "first frame that needs it"
                                     : "an input changed";
}

void PassGraph::execute(const std::set<std::string>& requested, int frame, const Timer& timer) {
    std::vector<bool> need = needed(requested);
    partial_ = Partial();  // a frame run whole drops what executeSliced left half done
    slicedComplete_ = true;
    // In declaration order (a topological order, since inputs precede their readers): run the
    // needed passes whose input versions changed; reuse the outputs of the others.
    std::vector<bool> touched(records_.size(), false);
    for (size_t i = 0; i < nodes_.size(); ++i) {
        Node& node = nodes_[i];
        touched[node.record] = true;
        const uint64_t key = inputKey(node);
        if (skipOrReuse(node, need[i], key)) continue;
        const char* reason = runReason(invalidated_, frame, node.hasRun);
        double ms = timer(node.run);
        recordRun(node, key, frame, ms, reason);
    }
    invalidated_ = false;
    for (size_t r = 0; r < records_.size(); ++r) {
        PassRecord& record = records_[r];
        if (!touched[r] && record.runs == 0 && record.reuses == 0 && record.notNeeded == 0 && !record.reason.empty())
            pushBounded(record.history, std::string("skipped"), PassRecord::kKeptFrames);  // a static reason
    }
}

void PassGraph::keepUnitCosts() {
    if (partial_.node >= nodes_.size() || partial_.cost.empty()) return;
    std::vector<float>& h = unitCost_[nodes_[partial_.node].name];
    if (h.size() != partial_.cost.size()) h.assign(partial_.cost.size(), -1.0f);
    for (size_t k = 0; k < h.size(); ++k)
        if (partial_.cost[k] >= 0.0f) h[k] = partial_.cost[k];
}

double PassGraph::executeSliced(const std::set<std::string>& requested, int frame, const Timer& timer,
                                double budgetMs, const Slicing& slicing) {
    std::vector<bool> need = needed(requested);
    if (slicedComplete_) {  // a new frame to refine
        slicedDoneMs_ = 0.0;
        slicedLastNode_ = 0;
    }
    double spent = 0.0;
    bool ranSomething = false, stopped = false;
    size_t stopAt = nodes_.size();
    for (size_t i = 0; i < nodes_.size() && !stopped; ++i) {
        Node& node = nodes_[i];
        PassRecord& record = records_[node.record];
        const uint64_t key = inputKey(node);
        if (skipOrReuse(node, need[i], key)) continue;
        if (ranSomething && spent >= budgetMs) {  // the budget is spent: the rest on the next call
            stopped = true;
            stopAt = i;
            break;
        }
        // A pass at or before the last one this frame ran must run again: an input changed since,
        // the refinement starts over.
        if (!slicedComplete_ && slicedDoneMs_ > 0.0 && i <= slicedLastNode_ && partial_.node != i) slicedDoneMs_ = 0.0;
        const char* reason = runReason(invalidated_, frame, node.hasRun);
        const int units = slicing.units ? slicing.units(node.name) : 0;
        if (units <= 0) {
            // A whole pass whose last run cost more than what is left waits for the next call,
            // where it runs first (a light-space pass after a frame's bands overshot the budget).
            const double expected = record.times.empty() ? 0.0 : record.times.back().second;
            if (ranSomething && expected > budgetMs - spent) {
                stopped = true;
                stopAt = i;
                break;
            }
            double ms = timer(node.run);
            recordRun(node, key, frame, ms, reason);
            spent += ms;
            slicedDoneMs_ += ms;
            ranSomething = true;
            slicedLastNode_ = i;
            if (partial_.node == i) partial_ = Partial();
            continue;
        }
        if (partial_.node != i || partial_.key != key || partial_.total != units) {
            keepUnitCosts();  // an abandoned refinement still says what its rows cost
            partial_ = Partial();
            partial_.node = i;
            partial_.key = key;
            partial_.total = units;
            partial_.cost.assign(size_t(units), -1.0f);
            const std::vector<float>& h = unitCost_[node.name];
            // A forecast needs what (nearly) every unit cost: an abandoned refinement in scattered
            // bands (a drag started mid-way) knows a few bands, and the mean of those under-forecasts
            // a penumbra by 10x.
            const auto known = std::count_if(h.begin(), h.end(), [](float c) { return c >= 0.0f; });
            partial_.forecast = h.size() == size_t(units) && double(known) >= kForecastCoverage * double(units);
            if (!partial_.forecast) {
                // No forecast: bands of 1/kScatteredBands of the pass in a scattered order (stride coprime to the
                // band count, near its golden section), so the first bands sample the whole frame
                // and their mean cost predicts the next band's (rows differ a lot: sky is cheap,
                // a penumbra under foliage dear).
                partial_.band = std::max(1, units / kScatteredBands);
                const int bands = (units + partial_.band - 1) / partial_.band;
                partial_.stride = std::max(1, int(double(bands) * 0.6180339887));
                while (std::gcd(partial_.stride, bands) != 1) ++partial_.stride;
            }
            node.hasRun = false;  // its outputs are being rewritten: never reused half done
        }
        // Its outputs made ready first (allocation and first touch cost what a band of rows may
        // not), as work of its own: on the next call when over half the budget is spent.
        while (!partial_.prepared && slicing.prepare) {
            if (ranSomething && spent >= 0.5 * budgetMs) break;
            int step = -1;
            const double ms = timer([&] { step = slicing.prepare(node.name); });
            if (step != 0) partial_.prepared = true;
            if (step >= 0) {
                spent += ms;
                slicedDoneMs_ += ms;
                ranSomething = true;
                slicedLastNode_ = i;
            }
        }
        if (!partial_.prepared && slicing.prepare) {
            record.status = "refining";
            record.reason = "allocating its outputs (the frame budget)";
            stopped = true;
            stopAt = i;
            break;
        }
        // Pieces that fit what is left of the budget. With a forecast (what each unit cost in the
        // pass's last refinement at this many units, scaled by how this frame's pieces compare with
        // it) the pieces are contiguous runs of units; without one, scattered bands at the mean
        // cost of the bands run so far. (The pass's times of other sizes, e.g. a reduced frame while
        // dragging, say nothing about a piece now.)
        const std::vector<float>& history = unitCost_[node.name];
        double known = 0.0;
        int knownCount = 0;
        for (float c : history)
            if (c >= 0.0f) known += c, ++knownCount;
        const double meanUnit = knownCount ? known / knownCount : 0.0;
        // What a unit is expected to cost: the dearest of its neighbours in that refinement (a tile
        // either side, kForecastRows rows of tiles above and below), so a penumbra that moved a
        // little since (a dragged light) does not land in a piece sized for the sky.
        std::vector<double> expected;
        if (partial_.forecast) {
            const int perRow = std::max(1, slicing.unitsPerRow), n = int(history.size());
            std::vector<double> across(history.size());
            for (int k = 0; k < n; ++k) {
                const int row = k / perRow, col = k % perRow;
                double m = 0.0;
                for (int c = std::max(0, col - 1); c <= std::min(perRow - 1, col + 1); ++c) {
                    const int j = row * perRow + c;
                    if (j < n) m = std::max(m, history[size_t(j)] >= 0.0f ? double(history[size_t(j)]) : meanUnit);
                }
                across[size_t(k)] = m;
            }
            expected.assign(history.size(), 0.0);
            for (int k = 0; k < n; ++k)
                for (int d = -kForecastRows; d <= kForecastRows; ++d) {
                    const int j = k + d * perRow;
                    if (j >= 0 && j < n) expected[size_t(k)] = std::max(expected[size_t(k)], across[size_t(j)]);
                }
        }
        auto forecastOf = [&](int k) { return expected[size_t(k)]; };
        while (partial_.done < partial_.total) {
            const double left = std::max(budgetMs - spent, 0.0);
            if (ranSomething && left <= 0.0) break;
            int from = 0, to = 0;
            if (partial_.forecast) {
                from = partial_.next;
                const int rest = partial_.total - from;
                double before = 0.0;
                for (int k = 0; k < from; ++k) before += forecastOf(k);
                const double scale = from > 0 && before > 0.0 ? std::clamp(partial_.ms / before, 0.5, 4.0) : 1.0;
                double predicted = 0.0;
                int count = 0;
                while (count < rest && (predicted + forecastOf(from + count)) * scale <= left) predicted += forecastOf(from + count++);
                if (count == 0 && ranSomething) break;  // the next unit is forecast over what is left: the next call
                to = from + std::clamp(count, 1, rest);
            } else {
                const int bands = (partial_.total + partial_.band - 1) / partial_.band;
                // Before the first band, the pass's last whole run spread over its bands (when it ran
                // before): an unknown band does not start in the last few ms of a budget.
                const double lastRun = record.times.empty() ? 0.0 : record.times.back().second;
                const double meanBand = partial_.bandsRun > 0 ? partial_.ms / partial_.bandsRun : lastRun / bands;
                if (ranSomething && std::max(meanBand, partial_.lastMs) > left) break;
                const int b = int((int64_t(partial_.next) * partial_.stride) % bands);
                from = b * partial_.band;
                to = std::min(partial_.total, from + partial_.band);
            }
            double ms = timer([&] { slicing.runUnits(node.name, from, to, node.run); });
            for (int k = from; k < to; ++k) partial_.cost[size_t(k)] = float(ms / (to - from));
            partial_.done += to - from;
            partial_.lastMs = ms;
            partial_.next = partial_.forecast ? to : partial_.next + 1;
            ++partial_.bandsRun;
            partial_.ms += ms;
            spent += ms;
            slicedDoneMs_ += ms;
            ranSomething = true;
            slicedLastNode_ = i;
        }
        if (partial_.done < partial_.total) {
            record.status = "refining";
            record.reason = std::to_string(partial_.done) + " of " + std::to_string(partial_.total) +
                            " pieces run (the frame budget)";
            stopped = true;
            stopAt = i;
            break;
        }
        recordRun(node, key, frame, partial_.ms, reason);
        unitCost_[node.name] = std::move(partial_.cost);  // what each unit cost: the next refinement's forecast
        partial_ = Partial();
    }
    invalidated_ = false;
    if (!stopped) {
        slicedComplete_ = true;
        return 1.0;
    }
    slicedComplete_ = false;
    // What is left: the rest of the pass it stopped in, and every needed pass after it that is
    // stale now or reads what a stale pass writes, at their last whole times.
    double remaining = 0.0;
    std::set<std::string> dirty;
    for (size_t i = stopAt; i < nodes_.size(); ++i) {
        const Node& node = nodes_[i];
        if (!need[i]) continue;
        bool stale = !node.hasRun || inputKey(const_cast<Node&>(node)) != node.lastKey || i == stopAt;
        for (const std::string& in : node.inputs) stale = stale || dirty.count(in) > 0;
        if (!stale) continue;
        for (const std::string& out : node.outputs) dirty.insert(out);
        const PassRecord& record = records_[node.record];
        double whole = record.times.empty() ? 0.0 : record.medianMs();
        if (partial_.node == i && partial_.done > 0)
            remaining += partial_.ms / partial_.done * double(partial_.total - partial_.done);
        else
            remaining += whole;
    }
    const double total = slicedDoneMs_ + remaining;
    return total > 0.0 ? std::clamp(slicedDoneMs_ / total, 0.0, 0.99) : 0.0;
}

}  // namespace shadowlab
