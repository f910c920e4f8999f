// Validated JSON input (json_reader.h): parsing with places for every error, and typed reads.
#include "scene/json_reader.h"
#include "scene/input_file.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <set>
#include <sstream>

#include "error.h"

namespace shadowlab {

using json = nlohmann::json;

std::string fieldPath(const std::string& path, const std::string& key) {
    return path.empty() ? key : path + "." + key;
}

std::string elementPath(const std::string& path, size_t index) {
    return path + "[" + std::to_string(index) + "]";
}

std::string formatNumber(double x) {
    if (std::isnan(x)) return "nan";
    if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.9g", x);
    return buffer;
}

std::string describeJson(const json& v) {
    switch (v.type()) {
        case json::value_t::null: return "null";
        case json::value_t::boolean: return v.get<bool>() ? "true" : "false";
        case json::value_t::number_integer: return std::to_string(v.get<int64_t>());
        case json::value_t::number_unsigned: return std::to_string(v.get<uint64_t>());
        case json::value_t::number_float: return formatNumber(v.get<double>());
        case json::value_t::string: {
            std::string s = json(v).dump();
            if (s.size() > 60) s = s.substr(0, 56) + "...\"";
            return "the string " + s;
        }
        case json::value_t::array: return "an array of " + std::to_string(v.size()) + " elements";
        case json::value_t::object: return "an object";
        default: return "an unsupported value";
    }
}

std::string shortenLastRead(std::string detail) {
    const std::string marker = "last read: '";
    const size_t start = detail.find(marker);
    if (start == std::string::npos) return detail;
    const size_t from = start + marker.size();
    size_t end = detail.find("'; expected", from);
    if (end == std::string::npos) end = detail.rfind('\'');
    const size_t keep = 40;
    if (end != std::string::npos && end > from + keep + 3)
        detail.replace(from, end - keep - from, "...");
    return detail;
}

namespace {

std::string join(const std::vector<std::string>& parts, const std::string& separator) {
    std::string out;
    for (size_t i = 0; i < parts.size(); ++i) out += (i ? separator : "") + parts[i];
    return out;
}

std::string placeName(const std::string& path) { return path.empty() ? "(top level)" : path; }

// Walks the text for nlohmann's lexer and remembers the last character it read, so that the SAX
// events (which carry no position) can tell on which line they happened.
struct TrackingIterator {
    using iterator_category = std::forward_iterator_tag;
    using value_type = char;
    using difference_type = std::ptrdiff_t;
    using pointer = const char*;
    using reference = const char&;

    const char* at = nullptr;
    const char** lastRead = nullptr;

    reference operator*() const {
        *lastRead = at;
        return *at;
    }
    TrackingIterator& operator++() {
        ++at;
        return *this;
    }
    TrackingIterator operator++(int) {
        TrackingIterator before = *this;
        ++at;
        return before;
    }
    bool operator==(const TrackingIterator& o) const { return at == o.at; }
    bool operator!=(const TrackingIterator& o) const { return at != o.at; }
};

// Builds the DOM like nlohmann::json::parse, and also tracks the path of the value being read, so
// that a number that overflows to infinity (which nlohmann reports without a place) and a field
// given twice (which nlohmann silently collapses) are reported by field path, and so that every
// value's line is known (JsonDocument::lineOf).
class TrackingSax : public nlohmann::json_sax<json> {
public:
    enum class Failure { None, Syntax, NonFinite, Duplicate, TooDeep };
    Failure failure = Failure::None;
    size_t byte = 0;        // Syntax: 1-based offset of the last character read
    std::string detail;     // Syntax: nlohmann's explanation; NonFinite: the token
    std::string path;       // NonFinite, Duplicate, TooDeep: where
    static constexpr size_t kMaxDepth = 64;

    TrackingSax(json& result, const std::string& text, std::map<std::string, int>& lines)
        : dom_(result, false), scanned_(text.data()), lines_(lines) {}
    const char* lastRead = nullptr;  // written by TrackingIterator

    bool null() override { return value() && dom_.null(); }
    bool boolean(bool v) override { return value() && dom_.boolean(v); }
    bool number_integer(number_integer_t v) override { return value() && dom_.number_integer(v); }
    bool number_unsigned(number_unsigned_t v) override {
        return value() && dom_.number_unsigned(v);
    }
    bool number_float(number_float_t v, const string_t& s) override {
        return value() && dom_.number_float(v, s);
    }
    bool string(string_t& v) override { return value() && dom_.string(v); }
    bool binary(binary_t& v) override { return value() && dom_.binary(v); }
    bool start_object(std::size_t n) override {
        if (!value() || !push(false)) return false;
        return dom_.start_object(n);
    }
    bool key(string_t& k) override {
        Frame& frame = stack_.back();
        frame.key = k;
        if (!frame.keys.insert(k).second) {
            failure = Failure::Duplicate;
            path = currentPath(false);
            return false;
        }
        lines_[currentPath(false)] = line();
        return dom_.key(k);
    }
    bool end_object() override {
        stack_.pop_back();
        return dom_.end_object();
    }
    bool start_array(std::size_t n) override {
        if (!value() || !push(true)) return false;
        return dom_.start_array(n);
    }
    bool end_array() override {
        stack_.pop_back();
        return dom_.end_array();
    }
    bool parse_error(std::size_t position, const std::string& lastToken,
                     const nlohmann::detail::exception& ex) override {
        if (ex.id == 406) {  // out_of_range.406: "number overflow", i.e. the value is +-inf
            failure = Failure::NonFinite;
            detail = lastToken;
            path = currentPath(true);
        } else {
            failure = Failure::Syntax;
            byte = position;
            detail = ex.what();
            // Drop nlohmann's "[json.exception.parse_error.101] parse error at line 2, column 8: "
            // prefix: the caller prints its own place.
            if (const size_t column = detail.find("column "); column != std::string::npos) {
                if (const size_t colon = detail.find(": ", column); colon != std::string::npos) {
                    detail = detail.substr(colon + 2);
                }
            } else if (const size_t bracket = detail.find("] "); bracket != std::string::npos) {
                detail = detail.substr(bracket + 2);
            }
        }
        return false;
    }

private:
    struct Frame {
        bool isArray = false;
        long index = -1;  // arrays: index of the current element
        std::string key;  // objects: key of the current field
        std::set<std::string> keys;
    };

    // A value starts: an array element (or the top-level value) is placed on the current line;
    // an object's field was placed by its key.
    bool value() {
        if (!stack_.empty() && stack_.back().isArray) ++stack_.back().index;
        if (stack_.empty() || stack_.back().isArray) lines_[currentPath(false)] = line();
        return true;
    }
    bool push(bool isArray) {
        if (stack_.size() >= kMaxDepth) {
            failure = Failure::TooDeep;
            path = currentPath(false);
            return false;
        }
        stack_.push_back(Frame{isArray, -1, {}, {}});
        return true;
    }
    // The line of the last character the lexer read (a lookahead newline after a number is not
    // counted: only the newlines before it are). Events arrive in text order, so one pass counts.
    int line() {
        if (lastRead != nullptr) {
            for (; scanned_ < lastRead; ++scanned_) lineCount_ += *scanned_ == '\n';
        }
        return lineCount_;
    }
    // The path of the value being read; `pending` when its value event has not arrived yet (an
    // array's next element then has index + 1).
    std::string currentPath(bool pending) const {
        std::string out;
        for (size_t i = 0; i < stack_.size(); ++i) {
            const Frame& f = stack_[i];
            if (f.isArray) {
                const long index = f.index + ((pending && i + 1 == stack_.size()) ? 1 : 0);
                out += "[" + std::to_string(index) + "]";
            } else {
                out += (out.empty() ? "" : ".") + f.key;
            }
        }
        return out;
    }

    nlohmann::detail::json_sax_dom_parser<json> dom_;
    std::vector<Frame> stack_;
    const char* scanned_;
    int lineCount_ = 1;
    std::map<std::string, int>& lines_;
};

}  // namespace

// --- JsonDocument
// --------------------------------------------------------------------------------

JsonDocument JsonDocument::fromString(const std::string& file, const std::string& text) {
    JsonDocument document;
    document.file_ = file;
    TrackingSax sax(document.root_, text, document.lines_);
    const TrackingIterator first{text.data(), &sax.lastRead};
    const TrackingIterator last{text.data() + text.size(), &sax.lastRead};
    bool ok = false;
    try {
        ok = json::sax_parse(first, last, &sax, json::input_format_t::json, true);
    } catch (const std::exception& e) {
        throw InputError(file + ": malformed JSON: " + e.what());
    }
    if (ok) return document;
    switch (sax.failure) {
        case TrackingSax::Failure::NonFinite:
            throw InputError(file + ": " + placeName(sax.path) +
                             ": expected a finite number, got " + sax.detail);
        case TrackingSax::Failure::Duplicate:
            throw InputError(file + ": " + placeName(sax.path) +
                             ": expected each field at most once, got it a second time");
        case TrackingSax::Failure::TooDeep:
            throw InputError(file + ": " + placeName(sax.path) + ": expected at most " +
                             std::to_string(TrackingSax::kMaxDepth) +
                             " levels of nesting, got more");
        default: {
            // nlohmann's byte is the 1-based offset of the last character it read (one past the
            // end at end of input); the error is at that character.
            const size_t index = std::min(sax.byte > 0 ? sax.byte - 1 : 0, text.size());
            size_t line = 1, lineStart = 0;
            for (size_t i = 0; i < index; ++i) {
                if (text[i] == '\n') {
                    ++line;
                    lineStart = i + 1;
                }
            }
            const size_t column = index - lineStart + 1;
            throw InputError(file + ":" + std::to_string(line) + ":" + std::to_string(column) +
                             ": malformed JSON: " + shortenLastRead(sax.detail));
        }
    }
}

JsonDocument JsonDocument::fromFile(const std::string& path, const std::string& what) {
    return fromString(path, readInputFile(path, what, kMaxTextInputBytes));
}

int JsonDocument::lineOf(const std::string& path) const {
    std::string p = path;
    while (true) {
        if (const auto it = lines_.find(p); it != lines_.end()) return it->second;
        if (p.empty()) return 0;
        // Drop the last step: ".key" or "[index]".
        const size_t cut = p.find_last_of(".[");
        p = cut == std::string::npos ? std::string() : p.substr(0, cut);
    }
}

// --- Number rules
// --------------------------------------------------------------------------------

NumberRule anyNumber() {
    return {"a number", [](double) { return true; }};
}
NumberRule greaterThan(double lo) {
    return {"a number > " + formatNumber(lo), [lo](double x) { return x > lo; }};
}
NumberRule atLeast(double lo) {
    return {"a number >= " + formatNumber(lo), [lo](double x) { return x >= lo; }};
}
NumberRule inRange(double lo, double hi) {
    return {"a number in [" + formatNumber(lo) + ", " + formatNumber(hi) + "]",
            [lo, hi](double x) { return x >= lo && x <= hi; }};
}
NumberRule inOpenRange(double lo, double hi) {
    return {"a number in (" + formatNumber(lo) + ", " + formatNumber(hi) + ")",
            [lo, hi](double x) { return x > lo && x < hi; }};
}

// --- JsonReader
// ----------------------------------------------------------------------------------

JsonReader::JsonReader(const JsonDocument& document, Lines lines)
    : file_(document.file()), document_(lines == Lines::Named ? &document : nullptr) {}

JsonReader::JsonReader(std::string file) : file_(std::move(file)) {}

std::string JsonReader::place(const std::string& path) const {
    const int line = document_ != nullptr ? document_->lineOf(path) : 0;
    return file_ + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " +
           placeName(path);
}

void JsonReader::fail(const std::string& path, const std::string& expected,
                      const std::string& got) const {
    throw InputError(place(path) + ": expected " + expected + ", got " + got);
}

void JsonReader::requireObject(const json& v, const std::string& path) const {
    if (!v.is_object()) fail(path, "an object", describeJson(v));
}

double JsonReader::number(const json& v, const std::string& path, const NumberRule& rule) const {
    if (!v.is_number()) fail(path, rule.expected, describeJson(v));
    const double x = v.get<double>();
    if (!std::isfinite(x)) fail(path, "a finite number", formatNumber(x));
    // Inputs are stored in floats: a number that overflows or flushes to zero there is wrong.
    const float f = static_cast<float>(x);
    if (!std::isfinite(f) || (x != 0.0 && std::abs(f) < std::numeric_limits<float>::min())) {
        fail(path, "a number representable as a float (1.2e-38 <= |x| <= 3.4e38, or 0)",
             formatNumber(x));
    }
    if (!rule.valid(x)) fail(path, rule.expected, formatNumber(x));
    return x;
}

int64_t JsonReader::integer(const json& v, const std::string& path, int64_t lo, int64_t hi) const {
    const std::string expected =
        "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
    if (v.is_number_integer()) {
        if (v.is_number_unsigned() && v.get<uint64_t>() > static_cast<uint64_t>(hi)) {
            fail(path, expected, describeJson(v));
        }
        const int64_t x = v.get<int64_t>();
        if (x < lo || x > hi) fail(path, expected, describeJson(v));
        return x;
    }
    // 32.0 is an integer too; 32.5 is not.
    const double x = number(v, path, expected, [&](double d) {
        return d == std::floor(d) && d >= static_cast<double>(lo) && d <= static_cast<double>(hi);
    });
    return static_cast<int64_t>(x);
}

glm::vec3 JsonReader::vec3(const json& v, const std::string& path, const NumberRule& each) const {
    if (!v.is_array() || v.size() != 3) {
        fail(path, "an array of 3 numbers (each " + each.expected + ")", describeJson(v));
    }
    glm::vec3 out;
    for (size_t i = 0; i < 3; ++i) {
        out[static_cast<int>(i)] = static_cast<float>(number(v[i], elementPath(path, i), each));
    }
    return out;
}

glm::vec3 JsonReader::nonZeroVec3(const json& v, const std::string& path) const {
    const glm::vec3 x = vec3(v, path);
    if (!(glm::length(x) > 1e-12f)) fail(path, "a non-zero vector", describeVec(x));
    return x;
}

std::string JsonReader::string(const json& v, const std::string& path,
                               const std::string& expected) const {
    if (!v.is_string()) fail(path, expected, describeJson(v));
    return v.get<std::string>();
}

bool JsonReader::boolean(const json& v, const std::string& path) const {
    if (!v.is_boolean()) fail(path, "true or false", describeJson(v));
    return v.get<bool>();
}

namespace {
std::string oneOfExpected(const std::vector<std::string>& names) {
    std::vector<std::string> quoted;
    for (const std::string& n : names) quoted.push_back("\"" + n + "\"");
    return "one of " + join(quoted, ", ");
}
}  // namespace

std::string JsonReader::oneOf(const json& v, const std::string& path,
                              const std::vector<std::string>& names) const {
    const std::string expected = oneOfExpected(names);
    const std::string name = string(v, path, expected);
    if (std::find(names.begin(), names.end(), name) == names.end())
        fail(path, expected, describeJson(v));
    return name;
}

std::string JsonReader::peekOneOf(const json& v, const std::string& path, const std::string& key,
                                  const std::vector<std::string>& names) const {
    requireObject(v, path);
    const auto it = v.find(key);
    if (it == v.end())
        fail(fieldPath(path, key), oneOfExpected(names), "nothing (the field is required)");
    return oneOf(*it, fieldPath(path, key), names);
}

std::string JsonReader::describeVec(const glm::vec3& x) {
    return "[" + formatNumber(x.x) + ", " + formatNumber(x.y) + ", " + formatNumber(x.z) + "]";
}

// --- JsonFields
// ----------------------------------------------------------------------------------

JsonFields::JsonFields(const JsonReader& reader, const json& v, std::string path,
                       std::vector<std::string> allowed)
    : reader_(reader), v_(v), path_(std::move(path)), allowed_(std::move(allowed)) {
    reader_.requireObject(v_, path_);
    for (const auto& item : v_.items()) {
        if (std::find(allowed_.begin(), allowed_.end(), item.key()) == allowed_.end()) {
            reader_.fail(fieldPath(path_, item.key()), "one of the fields " + join(allowed_, ", "),
                         "an unknown field \"" + item.key() + "\"");
        }
    }
}

const json* JsonFields::find(const std::string& key) const {
    const auto it = v_.find(key);
    return it == v_.end() ? nullptr : &*it;
}

const json& JsonFields::require(const std::string& key, const std::string& expected) const {
    const json* v = find(key);
    if (v == nullptr) reader_.fail(path(key), expected, "nothing (the field is required)");
    return *v;
}

double JsonFields::number(const std::string& key, const NumberRule& rule) const {
    return reader_.number(require(key, rule.expected), path(key), rule);
}
int64_t JsonFields::integer(const std::string& key, int64_t lo, int64_t hi) const {
    const std::string expected =
        "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
    return reader_.integer(require(key, expected), path(key), lo, hi);
}
glm::vec3 JsonFields::vec3(const std::string& key, const NumberRule& each) const {
    return reader_.vec3(require(key, "an array of 3 numbers (each " + each.expected + ")"),
                        path(key), each);
}
std::string JsonFields::string(const std::string& key) const {
    return reader_.string(require(key, "a string"), path(key));
}
bool JsonFields::boolean(const std::string& key) const {
    return reader_.boolean(require(key, "true or false"), path(key));
}
std::string JsonFields::oneOf(const std::string& key, const std::vector<std::string>& names) const {
    return reader_.peekOneOf(v_, path_, key, names);
}
JsonFields JsonFields::object(const std::string& key, std::vector<std::string> allowed) const {
    return JsonFields(reader_, require(key, "an object"), path(key), std::move(allowed));
}

double JsonFields::number(const std::string& key, double fallback, const NumberRule& rule) const {
    const json* v = find(key);
    return v ? reader_.number(*v, path(key), rule) : fallback;
}
int64_t JsonFields::integer(const std::string& key, int64_t fallback, int64_t lo,
                            int64_t hi) const {
    const json* v = find(key);
    return v ? reader_.integer(*v, path(key), lo, hi) : fallback;
}
glm::vec3 JsonFields::vec3(const std::string& key, const glm::vec3& fallback,
                           const NumberRule& each) const {
    const json* v = find(key);
    return v ? reader_.vec3(*v, path(key), each) : fallback;
}
std::string JsonFields::string(const std::string& key, const std::string& fallback) const {
    const json* v = find(key);
    return v ? reader_.string(*v, path(key)) : fallback;
}
bool JsonFields::boolean(const std::string& key, bool fallback) const {
    const json* v = find(key);
    return v ? reader_.boolean(*v, path(key)) : fallback;
}
std::string JsonFields::oneOf(const std::string& key, const std::vector<std::string>& names,
                              const std::string& fallback) const {
    const json* v = find(key);
    return v ? reader_.oneOf(*v, path(key), names) : fallback;
}

}  // namespace shadowlab
