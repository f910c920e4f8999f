// The lesson player (DESIGN.md section 8): next and previous step, each step restoring its own
// complete state through a LessonHost whatever the user changed, "try this" tasks checked on the
// host's rendered buffers with feedback, "show me" applying the answer, an animated value, and
// progress. The window draws it with drawLessonPanel(); tests drive it through a fake host.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "lesson/host.h"
#include "lesson/lesson.h"

namespace shadowlab {

class LessonPlayer {
public:
    enum class TaskStatus { NoTask, NotChecked, Passed, NotYet, ShownAnswer };
    struct Feedback {
        TaskStatus status = TaskStatus::NoTask;
        std::string message;  // what the condition measured, one line per term
        bool pending = false;  // checked while what it reads was still being computed (the message says what)
    };

    // Applies step 0 to the host.
    LessonPlayer(Lesson lesson, LessonHost& host);

    const Lesson& lesson() const { return lesson_; }
    size_t stepIndex() const { return step_; }
    size_t stepCount() const { return lesson_.steps.size(); }
    const LessonStep& step() const { return lesson_.steps[step_]; }
    bool atFirst() const { return step_ == 0; }
    bool atLast() const { return step_ + 1 == lesson_.steps.size(); }

    // Moves and applies the step's complete state (false at either end: nothing changes).
    bool next();
    bool previous();
    void goTo(size_t step);
    // Re-applies the current step's state (undo whatever the user changed).
    void restore();

    // Renders and checks the current step's task; the feedback says what was measured. When the
    // host is not ready (LessonHost::taskBuffersReady) the check is pending: its status unchanged,
    // its message what it waits for, until finishCheck() runs it.
    const Feedback& checkTask();
    // A pending check, run once the host is ready (true: it ran; the feedback has its result).
    bool finishCheck();
    bool checkPending() const { return feedback_[step_].pending; }
    // The step's expectations (`expect`, the narration's claims), checked on what the host shows
    // when the step is entered, once the host is ready (LessonHost::taskBuffersReady: the window's
    // progressive reference complete); while they wait, the step's animation holds still. A failing
    // expectation is reported (expectResults), never fatal.
    enum class ExpectStatus { None, Pending, Checked, Changed };
    struct ExpectResult {
        bool passed = false;
        std::string message;   // every term: its value and what it needs
        std::string failure;   // the failing terms and their values ("" when passed)
        TaskCondition::Outcome outcome;
    };
    ExpectStatus expectStatus() const { return expectStatus_; }
    bool expectsPending() const { return expectStatus_ == ExpectStatus::Pending; }
    // Runs the pending expectations if the host is ready (true: they ran, or none was pending).
    // Changed: what the host shows is no longer the step (the user changed it first); R restores.
    bool checkExpects();
    const std::vector<ExpectResult>& expectResults() const { return expectResults_; }
    const std::string& expectWaiting() const { return expectWaiting_; }  // Pending: what they wait for

    // Applies the step's answer state (the task's "show me").
    void showMe();
    const Feedback& feedback() const { return feedback_[step_]; }
    TaskStatus status(size_t step) const { return feedback_.at(step).status; }
    // Tasks solved by the student (not by show me), and tasks in the lesson.
    size_t tasksSolved() const;
    size_t taskCount() const;
    // Fraction of the lesson reached: (step + 1) / steps.
    float progress() const { return float(step_ + 1) / float(lesson_.steps.size()); }

    // The step's animation: play/pause, and advance by `seconds` (applies the new value to the host).
    bool hasAnimation() const { return step().animate.has_value(); }
    bool playing() const { return playing_; }
    void setPlaying(bool playing) { playing_ = playing && hasAnimation(); }
    void update(double seconds);
    double animationTime() const { return animationTime_; }

private:
    void apply(const LessonState& state);
    Lesson lesson_;
    LessonHost& host_;
    size_t step_ = 0;
    std::vector<Feedback> feedback_;
    bool playing_ = false;
    double animationTime_ = 0.0;
    ExpectStatus expectStatus_ = ExpectStatus::None;
    std::vector<ExpectResult> expectResults_;
    std::string expectWaiting_;
    unsigned long long expectVersion_ = 0;  // the host's shownVersion() when the step was applied
};

// Renders what `condition` reads on `host` (what it shows, and each variant aside) and evaluates it.
TaskCondition::Outcome evaluateOnHost(const TaskCondition& condition, LessonHost& host);

// The animated step's state at `fraction` in [0, 1] of its animation (the value snapped to what
// the parameter's table accepts: whole, odd, power of two).
LessonState animatedState(const LessonStep& step, double fraction);
// The animated value at `fraction` as the host receives it (a parameter's text or the light size).
std::string animatedValueText(const LessonStep& step, double fraction);

// The ImGui panel (app/lesson/panel.cpp): title, progress, narration wrapped at `fontScale`, the
// task with its feedback, and buttons; keys: Right/PageDown next, Left/PageUp previous, R restore,
// C check, M show me, Space play/pause. Call between ImGui::NewFrame() and ImGui::Render().
// Where the panel put its step buttons, in screen pixels: the window's --report gives them, and a
// test checks the buttons stay inside the panel however long the step's text below the narration is.
struct LessonPanelRects {
    float panel[4] = {0, 0, 0, 0};  // x, y, width, height of the panel
    float next[4] = {0, 0, 0, 0};   // x, y, width, height of "Next >"
};
LessonPanelRects drawLessonPanel(LessonPlayer& player, float fontScale = 1.5f);

}  // namespace shadowlab
