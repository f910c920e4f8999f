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

// ---- task conditions ------------------------------------------------------------------------------
// What a task's condition reads: the technique's visibility, the reference's, and the object ids
// (-1 on background), all of one size.
struct TaskBuffers {
    Image visibility;
    Image reference;
    Image ids;
};

// A condition over the buffers (grammar in lessons/README.md), e.g.
//   min(reference) >= 0.01
//   fraction(visibility < 0.5 in lit & object:0) < 0.01
class TaskCondition {
public:
    TaskCondition() = default;
    // Throws InputError naming `where` when the text does not parse.
    TaskCondition(const std::string& text, const SourceLocation& where);
    struct Outcome {
        bool passed = false;
        std::string message;           // one line per term: its value and what it needs
        std::vector<double> values;    // each term's value (NaN when its mask is empty)
    };
    Outcome evaluate(const TaskBuffers& buffers) const;
    const std::string& text() const { return text_; }
    bool readsReference() const;

private:
    struct Term {
        std::string stat;              // min, max, mean, fraction
        std::string buffer;            // visibility, reference, error
        std::string compare;           // fraction only: < <= > >=
        double threshold = 0.0;
        std::vector<std::string> masks;  // all, lit, umbra, penumbra, object:N
        std::string op;                // < <= > >=
        double value = 0.0;
        std::string text;
    };
    std::string text_;
    std::vector<Term> terms_;
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
    std::vector<LessonCommand> commands;
    std::optional<LessonAnimation> animate;
    std::optional<LessonTask> task;
    LessonState state;                 // the complete state of this step
    std::optional<LessonState> answerState;  // state + the task's answer
    SourceLocation where;
};

struct Lesson {
    std::string id;                    // file stem: "intro"
    std::string file;                  // as named in messages: "lessons/intro.md"
    std::string title;
    std::string introduction;          // Markdown before the first step
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
