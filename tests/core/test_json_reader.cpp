// The validated JSON reader on its own (json_reader.h), on a small made-up schema: a "figure" with
// a title, a mode, a scale and panels. Every error must name the file, the line and the field
// path, and say what was expected and what was found.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>

#include "error.h"
#include "scene/json_reader.h"

namespace shadowlab {
namespace {

struct Panel {
    std::string technique;
    int samples = 16;
    glm::vec3 tint{1.0f};
};

struct Figure {
    std::string title;
    std::string mode;
    double scale = 1.0;
    std::vector<Panel> panels;
};

Figure readFigure(const JsonDocument& doc) {
    const JsonReader r(doc);
    const JsonFields f(r, doc.root(), "", {"title", "mode", "scale", "panels"});
    Figure figure;
    figure.title = f.string("title");
    figure.mode = f.oneOf("mode", {"grid", "row"}, "grid");
    figure.scale = f.number("scale", 1.0, inOpenRange(0.0, 10.0));
    const nlohmann::json& panels = f.require("panels", "an array of panels");
    if (!panels.is_array()) r.fail(f.path("panels"), "an array of panels", describeJson(panels));
    for (size_t i = 0; i < panels.size(); ++i) {
        const JsonFields p(r, panels[i], elementPath(f.path("panels"), i),
                           {"technique", "samples", "tint"});
        Panel panel;
        panel.technique = p.string("technique");
        panel.samples = static_cast<int>(p.integer("samples", panel.samples, 1, 1024));
        panel.tint = p.vec3("tint", panel.tint, inRange(0.0, 1.0));
        figure.panels.push_back(panel);
    }
    return figure;
}

std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    ADD_FAILURE() << "expected an InputError";
    return "";
}

std::string readError(const std::string& text) {
    return errorOf([&] { readFigure(JsonDocument::fromString("fig.json", text)); });
}

TEST(JsonReader, ReadsAValidDocumentWithDefaults) {
    const Figure figure = readFigure(JsonDocument::fromString("fig.json", R"({
  "title": "PCSS vs PCF",
  "panels": [{"technique": "pcss", "samples": 32.0}, {"technique": "pcf", "tint": [1, 0.5, 0]}]
})"));
    EXPECT_EQ(figure.title, "PCSS vs PCF");
    EXPECT_EQ(figure.mode, "grid");
    EXPECT_EQ(figure.scale, 1.0);
    ASSERT_EQ(figure.panels.size(), 2u);
    EXPECT_EQ(figure.panels[0].samples, 32);
    EXPECT_EQ(figure.panels[1].samples, 16);
    EXPECT_EQ(figure.panels[1].tint, glm::vec3(1.0f, 0.5f, 0.0f));
}

TEST(JsonReader, UnknownFieldNamesLineAndAllowedFields) {
    const std::string message = readError(
        "{\n  \"title\": \"t\",\n  \"panels\": [\n    {\"technique\": \"pcf\"},\n"
        "    {\"technique\": \"pcf\", \"colour\": [1, 0, 0]}\n  ]\n}\n");
    EXPECT_EQ(message,
              "fig.json:5: panels[1].colour: expected one of the fields technique, samples, tint, "
              "got an unknown field \"colour\"");
}

TEST(JsonReader, WrongType) {
    EXPECT_EQ(readError("{\"title\": 3, \"panels\": []}"),
              "fig.json:1: title: expected a string, got 3");
    EXPECT_EQ(readError("{\"title\": \"t\",\n\"panels\": {\"a\": 1}}"),
              "fig.json:2: panels: expected an array of panels, got an object");
    EXPECT_EQ(readError("{\"title\": \"t\", \"panels\": [{\"technique\": \"x\", \"tint\": 1}]}"),
              "fig.json:1: panels[0].tint: expected an array of 3 numbers (each a number in [0, "
              "1]), got 1");
}

TEST(JsonReader, OutOfRange) {
    EXPECT_EQ(readError("{\"title\": \"t\", \"scale\": 10, \"panels\": []}"),
              "fig.json:1: scale: expected a number in (0, 10), got 10");
    EXPECT_EQ(readError("{\"title\": \"t\", \"panels\": [{\"technique\": \"x\", \"samples\": 0}]}"),
              "fig.json:1: panels[0].samples: expected an integer in [1, 1024], got 0");
    EXPECT_EQ(
        readError("{\"title\": \"t\", \"panels\": [{\"technique\": \"x\", \"samples\": 2.5}]}"),
        "fig.json:1: panels[0].samples: expected an integer in [1, 1024], got 2.5");
    EXPECT_EQ(readError("{\"title\": \"t\", \"panels\": [\n{\"technique\": \"x\",\n"
                        "\"tint\": [0, 1.5, 0]}]}"),
              "fig.json:3: panels[0].tint[1]: expected a number in [0, 1], got 1.5");
}

TEST(JsonReader, NonFiniteNumbers) {
    // NaN is not JSON: a syntax error with line and column.
    const std::string nan = readError("{\n  \"scale\": NaN}");
    EXPECT_EQ(nan.rfind("fig.json:2:12: malformed JSON: ", 0), 0u) << nan;
    // 1e999 parses in nlohmann as infinity: reported by field path.
    EXPECT_EQ(readError("{\"title\": \"t\", \"panels\": [{\"technique\": \"x\", \"tint\": [0, "
                        "1e999, 0]}]}"),
              "fig.json: panels[0].tint[1]: expected a finite number, got 1e999");
    EXPECT_EQ(readError("{\"title\": \"t\", \"scale\": 1e300, \"panels\": []}"),
              "fig.json:1: scale: expected a number representable as a float (1.2e-38 <= |x| <= "
              "3.4e38, or 0), got 1e+300");
}

TEST(JsonReader, MissingRequiredField) {
    EXPECT_EQ(readError("{\n  \"panels\": []\n}"),
              "fig.json:1: title: expected a string, got nothing (the field is required)");
    EXPECT_EQ(readError("{\"title\": \"t\",\n \"panels\": [\n  {\"samples\": 3}]}"),
              "fig.json:3: panels[0].technique: expected a string, got nothing (the field is "
              "required)");
}

TEST(JsonReader, EnumListsTheAcceptedNames) {
    EXPECT_EQ(readError("{\"title\": \"t\", \"mode\": \"column\", \"panels\": []}"),
              "fig.json:1: mode: expected one of \"grid\", \"row\", got the string \"column\"");
    EXPECT_EQ(readError("{\"title\": \"t\", \"mode\": 2, \"panels\": []}"),
              "fig.json:1: mode: expected one of \"grid\", \"row\", got 2");
}

TEST(JsonReader, NestedPathsAndLines) {
    const JsonDocument doc = JsonDocument::fromString(
        "x.json", "{\n  \"a\": {\n    \"b\": [\n      1,\n      {\"c\": 2}\n    ]\n  }\n}");
    EXPECT_EQ(doc.lineOf(""), 1);
    EXPECT_EQ(doc.lineOf("a"), 2);
    EXPECT_EQ(doc.lineOf("a.b"), 3);
    EXPECT_EQ(doc.lineOf("a.b[0]"), 4);
    EXPECT_EQ(doc.lineOf("a.b[1]"), 5);
    EXPECT_EQ(doc.lineOf("a.b[1].c"), 5);
    EXPECT_EQ(doc.lineOf("a.b[1].missing"), 5);  // the object that lacks it
    const JsonReader r(doc);
    const JsonFields a = JsonFields(r, doc.root(), "", {"a"}).object("a", {"b"});
    EXPECT_EQ(a.path("b"), "a.b");
    const JsonFields c(r, doc.root()["a"]["b"][1], elementPath(a.path("b"), 1), {"c"});
    EXPECT_EQ(errorOf([&] { c.number("c", greaterThan(2.0)); }),
              "x.json:5: a.b[1].c: expected a number > 2, got 2");
    // Without lines (a DOM from elsewhere, or Lines::Omitted), the file and path only.
    EXPECT_EQ(errorOf([&] { JsonReader("y.json").boolean(doc.root()["a"], "a"); }),
              "y.json: a: expected true or false, got an object");
    const JsonReader noLines(doc, JsonReader::Lines::Omitted);
    EXPECT_EQ(noLines.place("a.b"), "x.json: a.b");
    EXPECT_EQ(r.place(""), "x.json:1: (top level)");
}

TEST(JsonReader, ParseErrors) {
    EXPECT_EQ(errorOf([] { JsonDocument::fromString("d.json", "{\"a\": 1, \"a\": 2}"); }),
              "d.json: a: expected each field at most once, got it a second time");
    const std::string syntax = errorOf([] { JsonDocument::fromString("s.json", "{\n\n  \"a\" 1}"); });
    EXPECT_EQ(syntax.rfind("s.json:3:7: malformed JSON: ", 0), 0u) << syntax;
    const std::string missing = (std::filesystem::path(SHADOWLAB_TEST_TMP) / "absent.json").string();
    EXPECT_EQ(errorOf([&] { JsonDocument::fromFile(missing, "figure spec"); }),
              missing + ": cannot read the figure spec: no such file");
}

}  // namespace
}  // namespace shadowlab
