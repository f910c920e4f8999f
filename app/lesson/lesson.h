// Lessons (DESIGN.md section 8): a Markdown file of narration with a small command language per
// step, parsed and validated against the technique descriptors and the scenes, and the complete
// state of every step computed from the lesson's start, so that going to step k restores exactly
// that state whatever the user changed. The format is documented in lessons/README.md.
#pragma once
#include <glm/glm.hpp>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "graph/technique.h"
#include "image/image.h"
#include "scene/scene.h"

namespace shadowlab {

// "lessons/intro.md:12": where a command or a task came from, for error messages.
struct SourceLocation {
    std::string file;
    int line = 0;
    std::string str() const { return file + ":" + std::to_string(line); }
};

// One line of a ```shadowlab block: a command word and its arguments (quotes group words).
struct LessonCommand {
    std::string name;
    std::vector<std::string> args;
    SourceLocation where;
};

// A step's picked pixel: a world point, projected through the step's camera at whatever size is
// rendered (`pick at X Y Z`), or, where the lesson says so explicitly, a fraction of the image from
// the top left (`pick fraction U V`). `where` is the command's file and line, for a pick that is
// hidden or off-screen at some size.
struct LessonPick {
    bool world = true;
    glm::vec3 point{0.0f};
    glm::vec2 fraction{0.0f};
    SourceLocation where;
    bool operator==(const LessonPick& o) const {
        return world == o.world && (world ? point == o.point : fraction == o.fraction);
    }
};

// The pixel (x right, y down from the top) a pick lands on in a width x height image seen through
// `camera`; nullopt when a world point is behind the camera or outside the image.
std::optional<glm::ivec2> pickPixelAt(const LessonPick& pick, const Camera& camera, int width, int height);

// Everything a step shows: applied in full to a host, so nothing the user changed survives.
struct LessonState {
    std::string scene;                 // a scene name (assets/scenes/<name>.json)
    std::string technique;             // id; every light runs it
    ParamValues params;                // every key of the technique's table
    std::vector<Light> lights;         // every light of the scene, after `light` commands
    Camera camera;
    std::set<std::string> views;       // views shown beside the technique view (lessonViews())
    std::optional<LessonPick> pick;    // the picked pixel (LessonPick)
    std::string split;                 // "" (no split), "reference", or a technique id
    std::string referenceTechnique = "reference";  // what "reference" means in tasks, error and split
    ParamValues referenceParams;

    // Parameter values as text the technique's table accepts (enum choices by name).
    std::vector<std::pair<std::string, std::string>> paramTexts() const;
    std::vector<std::pair<std::string, std::string>> referenceParamTexts() const;
    bool operator==(const LessonState& other) const;
    bool operator!=(const LessonState& other) const { return !(*this == other); }
    std::string describe() const;  // one line per field, for test failures and the handout
};

// The views a lesson can show (validated names). Rendered in one place: app/lesson/step_views.cpp.
const std::vector<std::string>& lessonViews();

// A parameter or the light moving between two values while the step plays (the handout shows
// its first, middle and last frame). target: a parameter key, or light.size / light.x / light.y /
// light.z (light 0).
struct LessonAnimation {
    std::string target;
    double from = 0.0, to = 0.0;
    double seconds = 2.0;
    SourceLocation where;
};

// ---- conditions: a task's check and a step's expectations ------------------------------------------
// What one render of a condition reads besides the technique's visibility and the object ids: the
// reference (for the reference and error buffers and the lit / umbra / penumbra masks) and
// internals of the technique by the names Renderer::writeInternals gives them ("kernel_size", and
// "light1/kernel_size" for light 1).
struct TaskReads {
    bool reference = false;
    bool positions = false;            // the near(...) mask: the world point of every pixel
    std::set<std::string> internals;
    bool operator==(const TaskReads& o) const {
        return reference == o.reference && positions == o.positions && internals == o.internals;
    }
};

// What a condition reads from one render, all of the image's size but the internals that live in
// light space (a shadow map): the technique's visibility, the reference's, the object ids (-1 on
// background), and the internals asked for (every channel; a pyramid's level 0). An internal the
// technique did not write is absent.
struct TaskBuffers {
    Image visibility;
    Image reference;
    Image ids;
    Image positions;                   // world position per pixel (3 channels; not finite on background)
    std::optional<glm::ivec2> pick;    // the picked pixel, when the host has one (the pick mask)
    std::map<std::string, Image> internals;
};

// The step rendered with a few changes (an expectation's `visibility[filter=gaussian]`): the
// changes as written, the state they make, and what its render must provide.
struct TaskVariant {
    std::string key;                   // the changes as one canonical text: "filter=gaussian"
    std::vector<std::pair<std::string, std::string>> changes;
    LessonState state;
    TaskReads reads;
    bool sharesReference = false;      // its lights are the step's: its reference is the step's own
};

// A condition over the buffers of the step's render and of its variants (grammar in
// lessons/README.md), e.g.
//   min(reference) >= 0.01
//   fraction(visibility < 0.5 in lit & object:0) < 0.01
//   mean(visibility in penumbra & object:0) < mean(reference in penumbra & object:0) - 0.02
//   mean(internal:reuse_step2) > 0.9
//   mean(diff(visibility, visibility[filter=gaussian]) in penumbra) > 0.02
class TaskCondition {
public:
    TaskCondition() = default;
    // Throws InputError naming `where` when the text does not parse; `command` is the word the
    // lesson wrote ("check", "expect") for messages. Variants ([...]) only where `variants` allows.
    TaskCondition(const std::string& text, const SourceLocation& where, const std::string& command = "check",
                  bool variants = false);
    // Validates the internals and the variants against the step's state (the technique's
    // descriptor: its internals, their channels and when they apply; the variants' keys and
    // values) and computes each variant's state. InputError naming the condition's line.
    void bind(const LessonState& step);
    struct Outcome {
        bool passed = false;
        std::string message;           // one line per term: its value and what it needs
        std::vector<double> values;    // each term's value (NaN when its mask is empty)
        std::vector<double> needs;     // what each term's value was compared with (NaN when unknown)
        std::vector<bool> termPassed;
        std::vector<std::string> problems;  // each term's: "" or why it has no value ("no pixel in the mask")
    };
    // `variants[k]` are the buffers of variants()[k]. InputError (naming the line) for what the
    // buffers cannot answer: an internal of another size under a mask, two buffers of different
    // sizes in a diff.
    Outcome evaluate(const TaskBuffers& step, const std::vector<TaskBuffers>& variants = {}) const;
    const std::string& text() const { return text_; }
    const SourceLocation& where() const { return where_; }
    const TaskReads& reads() const { return reads_; }
    const std::vector<TaskVariant>& variants() const { return variants_; }
    bool readsReference() const;   // the step's render or any variant's
    // The term texts that failed in `o`, each with its value: "mean(visibility) > 0.3: 0.21".
    std::string failures(const Outcome& o) const;
    // Every term's value and what it needed: "0.21 (needs > 0.3)"; several terms each named.
    std::string measured(const Outcome& o) const;

    struct Buffer {
        std::string name;              // visibility, reference, error, internal
        std::string internal;          // internal: the collector's key ("kernel_size", "light1/kernel_size")
        std::string channel;           // internal: "" = every channel
        int channelIndex = -1;         // bound: the channel's index (-1 = every channel)
        bool signedValues = false;     // bound: the internal's negative values count (InternalDesc::signedValues)
        int variant = -1;              // index into variants(), -1 = the step's own render
        std::string variantKey;
        std::vector<std::pair<std::string, std::string>> changes;
        std::string text;
    };
    struct Stat {
        std::string stat;              // min, max, mean, fraction
        std::vector<Buffer> buffers;   // one, or two for diff(a, b) = |a - b|
        std::string compare;           // fraction only: < <= > >=
        double threshold = 0.0;
        std::vector<std::string> masks;  // all, lit, umbra, penumbra, object:N, pick, near
        std::vector<glm::vec4> near;     // per near mask: the world point and the radius
        std::string text;
    };

private:
    struct Term {
        Stat lhs;
        std::string op;                // < <= > >=
        std::optional<Stat> rhs;       // compared with rhs + value, or with value alone
        double value = 0.0;
        std::string text;
    };
    std::string termValues(const Outcome& o, bool failingOnly) const;
    double statistic(const Stat& s, const TaskBuffers& step, const std::vector<TaskBuffers>& variants,
                     std::string& problem) const;
    std::string text_;
    SourceLocation where_;
    std::string command_ = "check";
    std::vector<Term> terms_;
    TaskReads reads_;
    std::vector<TaskVariant> variants_;
};

// A claim of the narration that the step's pictures show (`expect CONDITION`): checked in every
// render of the lesson (the handout, --check --sizes, the window's player).
struct LessonExpect {
    TaskCondition condition;
    SourceLocation where;
};

struct LessonTask {
    std::string prompt;                // what the student is asked to do
    TaskCondition check;
    std::vector<LessonCommand> answer; // applied on top of the step's state by "show me"
    SourceLocation where;
};

struct LessonStep {
    std::string title;
    std::string narration;             // Markdown
    std::vector<int> narrationLines;   // the source line of each line of `narration`
    std::vector<LessonCommand> commands;
    std::optional<LessonAnimation> animate;
    std::optional<LessonTask> task;
    std::vector<LessonExpect> expects;  // the narration's claims, in order
    LessonState state;                 // the complete state of this step
    std::optional<LessonState> answerState;  // state + the task's answer
    SourceLocation where;
};

struct Lesson {
    std::string id;                    // file stem: "intro"
    std::string file;                  // as named in messages: "lessons/intro.md"
    std::string title;
    std::string introduction;          // Markdown before the first step
    std::vector<int> introductionLines;
    LessonState start;
    std::vector<LessonStep> steps;
};

// "intro" -> <root>/lessons/intro.md (named "lessons/intro.md" in messages); a name with a '/' or
// ending in ".md" is a path. Parses and validates every step (computing its state): any error is an
// InputError "file:line: ..." naming what was expected.
Lesson loadLesson(const std::string& nameOrPath);
Lesson parseLesson(const std::string& text, const std::string& file, const std::string& id);
// Lesson ids in <root>/lessons/ (every *.md but README.md), sorted.
std::vector<std::string> listLessons();

// Applies one command to a state (the validator and the player share it). InputError on bad input.
void applyLessonCommand(LessonState& state, const LessonCommand& command);

}  // namespace shadowlab
