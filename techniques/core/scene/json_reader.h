// Validated JSON input: scene files, lessons, bench and figure specs, sidecars.
//
// Two steps. JsonDocument::fromFile/fromString parse the text; a syntax error names the file, line
// and column, and a number that overflows to infinity, a field given twice or nesting deeper than
// 64 levels name the field path instead ("objects[2].albedo[1]"). Then a JsonReader and JsonFields
// read the DOM into typed values, following pbrt's habit: every field an object contains is either
// read or reported as unknown, and every error names the file, the line (when the reader has it)
// and the field path, with what was expected and what was found:
//
//   spec.json:12: views[1].size: expected an integer in [1, 8192], got 0
//
// Every error is an InputError (exit code 2). A small schema reads like this:
//
//   const JsonDocument doc = JsonDocument::fromFile(path, "figure spec");
//   const JsonReader r(doc);
//   const JsonFields f(r, doc.root(), "", {"title", "scale", "mode"});
//   const std::string title = f.string("title");                          // required
//   const double scale = f.number("scale", 1.0, greaterThan(0.0));        // optional, default 1
//   const std::string mode = f.oneOf("mode", {"grid", "row"}, "grid");    // enum with a default
#pragma once
#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace shadowlab {

// Field paths: fieldPath("objects[2]", "albedo") == "objects[2].albedo", fieldPath("", "name") ==
// "name", elementPath("objects", 2) == "objects[2]". The empty path is the top level.
std::string fieldPath(const std::string& path, const std::string& key);
std::string elementPath(const std::string& path, size_t index);

// Numbers as messages print them: "%.9g", and "nan", "inf", "-inf".
std::string formatNumber(double x);
// What a JSON value is, for "got ..." in messages: "1.5", "true", "the string \"big\"", "an
// array of 2 elements", "an object", "null".
std::string describeJson(const nlohmann::json& v);

// nlohmann and tinygltf quote the text read before a JSON error ("last read: '<text>'"), which
// can be a whole base64 buffer: keeps only its end, where the error is.
std::string shortenLastRead(std::string detail);

// A parsed JSON file: the DOM and the line each value starts on (for an object's field, the line
// of its key).
class JsonDocument {
public:
    // `file` names the input in messages (a path, or "--set" or "<string>" for text from elsewhere).
    static JsonDocument fromString(const std::string& file, const std::string& text);
    // Reads and parses `path`; an unreadable file is "<path>: cannot read the <what>".
    static JsonDocument fromFile(const std::string& path, const std::string& what = "file");

    const std::string& file() const { return file_; }
    const nlohmann::json& root() const { return root_; }
    // The line of the value at `path`, or of its nearest enclosing value that has one (a missing
    // field: the object that lacks it); 0 when unknown.
    int lineOf(const std::string& path) const;

private:
    std::string file_;
    nlohmann::json root_;
    std::map<std::string, int> lines_;
};

// What a number must be: the words for messages and the test. The factories write the words
// ("a number > 0", "a number in [0, 1]") from the bounds.
struct NumberRule {
    std::string expected;
    std::function<bool(double)> valid;
};
NumberRule anyNumber();                            // "a number"
NumberRule greaterThan(double lo);                 // "a number > lo"
NumberRule atLeast(double lo);                     // "a number >= lo"
NumberRule inRange(double lo, double hi);          // "a number in [lo, hi]"
NumberRule inOpenRange(double lo, double hi);      // "a number in (lo, hi)"

// Reads JSON values into typed values, or throws an InputError naming the file, line and path.
// Numbers must also be finite and representable as floats (inputs are stored in floats).
class JsonReader {
public:
    enum class Lines { Named, Omitted };
    // A reader over a document: messages name the line of the value when `lines` is Named.
    explicit JsonReader(const JsonDocument& document, Lines lines = Lines::Named);
    // A reader over a DOM built elsewhere: messages name the file and the path only.
    explicit JsonReader(std::string file);

    const std::string& file() const { return file_; }
    // "<file>:<line>: <path>" (or "<file>: <path>" without a line); the top level is "(top level)".
    std::string place(const std::string& path) const;
    // Throws "<place>: expected <expected>, got <got>".
    [[noreturn]] void fail(const std::string& path, const std::string& expected,
                           const std::string& got) const;

    void requireObject(const nlohmann::json& v, const std::string& path) const;
    double number(const nlohmann::json& v, const std::string& path,
                  const NumberRule& rule = anyNumber()) const;
    double number(const nlohmann::json& v, const std::string& path, const std::string& expected,
                  const std::function<bool(double)>& valid) const {
        return number(v, path, NumberRule{expected, valid});
    }
    // Whole numbers (32.0 counts, 32.5 does not): "an integer in [lo, hi]".
    int64_t integer(const nlohmann::json& v, const std::string& path, int64_t lo, int64_t hi) const;
    // An array of 3 numbers, each obeying `each`.
    glm::vec3 vec3(const nlohmann::json& v, const std::string& path,
                   const NumberRule& each = anyNumber()) const;
    glm::vec3 vec3(const nlohmann::json& v, const std::string& path, const std::string& expectedEach,
                   const std::function<bool(double)>& valid) const {
        return vec3(v, path, NumberRule{expectedEach, valid});
    }
    glm::vec3 nonZeroVec3(const nlohmann::json& v, const std::string& path) const;
    std::string string(const nlohmann::json& v, const std::string& path,
                       const std::string& expected = "a string") const;
    bool boolean(const nlohmann::json& v, const std::string& path) const;
    // One of `names`: "expected one of \"a\", \"b\", got ...".
    std::string oneOf(const nlohmann::json& v, const std::string& path,
                      const std::vector<std::string>& names) const;
    // The field `key` of the object `v`, one of `names`, read before the object's other fields
    // because it decides which are allowed (a "type" tag). Missing: "nothing (the field is
    // required)".
    std::string peekOneOf(const nlohmann::json& v, const std::string& path, const std::string& key,
                          const std::vector<std::string>& names) const;

    static std::string describeVec(const glm::vec3& x);

private:
    std::string file_;
    const JsonDocument* document_ = nullptr;
};

// A JSON object whose fields are all known: constructing it reports the first unknown field
// ("expected one of the fields a, b, c, got an unknown field \"d\""). Then each field is read
// required (missing: "got nothing (the field is required)") or optional with a default.
class JsonFields {
public:
    JsonFields(const JsonReader& reader, const nlohmann::json& v, std::string path,
               std::vector<std::string> allowed);

    const JsonReader& reader() const { return reader_; }
    const std::string& path() const { return path_; }
    std::string path(const std::string& key) const { return fieldPath(path_, key); }
    const nlohmann::json* find(const std::string& key) const;
    // The field's value; missing: "<path.key>: expected <expected>, got nothing (...)".
    const nlohmann::json& require(const std::string& key, const std::string& expected) const;

    // Required fields.
    double number(const std::string& key, const NumberRule& rule = anyNumber()) const;
    int64_t integer(const std::string& key, int64_t lo, int64_t hi) const;
    glm::vec3 vec3(const std::string& key, const NumberRule& each = anyNumber()) const;
    std::string string(const std::string& key) const;
    bool boolean(const std::string& key) const;
    std::string oneOf(const std::string& key, const std::vector<std::string>& names) const;
    // A nested object with its own allowed fields.
    JsonFields object(const std::string& key, std::vector<std::string> allowed) const;

    // Optional fields: `fallback` when absent; a present field must be valid.
    double number(const std::string& key, double fallback,
                  const NumberRule& rule = anyNumber()) const;
    int64_t integer(const std::string& key, int64_t fallback, int64_t lo, int64_t hi) const;
    glm::vec3 vec3(const std::string& key, const glm::vec3& fallback,
                   const NumberRule& each = anyNumber()) const;
    std::string string(const std::string& key, const std::string& fallback) const;
    bool boolean(const std::string& key, bool fallback) const;
    std::string oneOf(const std::string& key, const std::vector<std::string>& names,
                      const std::string& fallback) const;

private:
    const JsonReader& reader_;
    const nlohmann::json& v_;
    std::string path_;
    std::vector<std::string> allowed_;
};

}  // namespace shadowlab
