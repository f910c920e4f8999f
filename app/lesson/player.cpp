#include "lesson/player.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "error.h"

namespace shadowlab {

namespace {

// The nearest value the parameter's table accepts (animations sweep through valid values only).
double snapParam(const ParamDesc& p, double v) {
    v = std::clamp(v, p.minValue, p.maxValue);
    if (p.type == ParamDesc::Type::Float) return v;
    double step = p.step > 1.0 ? p.step : 1.0;
    v = p.minValue + std::round((v - p.minValue) / step) * step;
    if (p.constraint == ParamDesc::Constraint::Odd && std::fmod(std::fabs(v), 2.0) != 1.0)
        v = v + 1.0 <= p.maxValue ? v + 1.0 : v - 1.0;
    if (p.constraint == ParamDesc::Constraint::PowerOfTwo) v = std::exp2(std::round(std::log2(std::max(v, 1.0))));
    return std::clamp(v, p.minValue, p.maxValue);
}

std::string number(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

}  // namespace

std::string animatedValueText(const LessonStep& step, double fraction) {
    const LessonAnimation& a = *step.animate;
    double v = a.from + (a.to - a.from) * std::clamp(fraction, 0.0, 1.0);
    if (a.target.rfind("light.", 0) == 0) return number(v);
    const ParamDesc* p = findTechnique(step.state.technique)->findParam(a.target);
    return number(snapParam(*p, v));
}

LessonState animatedState(const LessonStep& step, double fraction) {
    LessonState s = step.state;
    if (!step.animate) return s;
    const LessonAnimation& a = *step.animate;
    std::string text = animatedValueText(step, fraction);
    if (a.target.rfind("light.", 0) == 0) {
        double v = std::stod(text);
        Light& l = s.lights.at(0);
        if (a.target == "light.size") {
            l.size = float(v);
            if (v > 0.0 && l.shape == LightShape::Point) l.shape = LightShape::Square;
        } else {
            l.position[a.target == "light.x" ? 0 : a.target == "light.y" ? 1 : 2] = float(v);
        }
    } else {
        s.params.set(*findTechnique(s.technique), a.target, text, a.where.str());
    }
    return s;
}

LessonPlayer::LessonPlayer(Lesson lesson, LessonHost& host) : lesson_(std::move(lesson)), host_(host) {
    if (lesson_.steps.empty()) throw InputError(lesson_.file + ": the lesson has no step");
    feedback_.resize(lesson_.steps.size());
    for (size_t i = 0; i < lesson_.steps.size(); ++i)
        feedback_[i].status = lesson_.steps[i].task ? TaskStatus::NotChecked : TaskStatus::NoTask;
    goTo(0);
}

void LessonPlayer::apply(const LessonState& state) {
    // A pending check was of the state before: dropped (the student checks again).
    for (Feedback& f : feedback_)
        if (f.pending) {
            f.pending = false;
            f.message.clear();
        }
    applyLessonState(host_, state);
}

void LessonPlayer::goTo(size_t step) {
    if (step >= lesson_.steps.size())
        throw InputError(lesson_.file + ": step " + std::to_string(step + 1) + " does not exist (the lesson has " +
                         std::to_string(lesson_.steps.size()) + ")");
    step_ = step;
    animationTime_ = 0.0;
    playing_ = hasAnimation();
    apply(lesson_.steps[step_].state);
    expectResults_.clear();
    expectWaiting_.clear();
    expectStatus_ = lesson_.steps[step_].expects.empty() ? ExpectStatus::None : ExpectStatus::Pending;
    expectVersion_ = host_.shownVersion();
}

TaskCondition::Outcome evaluateOnHost(const TaskCondition& condition, LessonHost& host) {
    TaskBuffers own = host.readTaskBuffers(condition.reads());
    std::vector<TaskBuffers> variants;
    for (const TaskVariant& v : condition.variants()) variants.push_back(host.readVariantBuffers(v.state, v.reads));
    return condition.evaluate(own, variants);
}

bool LessonPlayer::checkExpects() {
    if (expectStatus_ != ExpectStatus::Pending) return true;
    if (host_.shownVersion() != expectVersion_) {
        expectStatus_ = ExpectStatus::Changed;
        return true;
    }
    const std::vector<LessonExpect>& expects = step().expects;
    bool reference = false;
    for (const LessonExpect& e : expects) reference = reference || e.condition.reads().reference;
    if (!host_.taskBuffersReady(reference, expectWaiting_)) return false;
    expectWaiting_.clear();
    expectResults_.clear();
    for (const LessonExpect& e : expects) {
        ExpectResult r;
        try {
            r.outcome = evaluateOnHost(e.condition, host_);
            r.passed = r.outcome.passed;
            r.message = r.outcome.message;
            r.failure = r.passed ? "" : e.condition.failures(r.outcome);
        } catch (const InputError& error) {  // what the buffers cannot answer: reported as the claim's failure
            r.passed = false;
            r.message = r.failure = error.what();
        }
        expectResults_.push_back(r);
    }
    expectStatus_ = ExpectStatus::Checked;
    return true;
}

bool LessonPlayer::next() {
    if (atLast()) return false;
    goTo(step_ + 1);
    return true;
}

bool LessonPlayer::previous() {
    if (atFirst()) return false;
    goTo(step_ - 1);
    return true;
}

void LessonPlayer::restore() { goTo(step_); }

const LessonPlayer::Feedback& LessonPlayer::checkTask() {
    Feedback& f = feedback_[step_];
    const LessonStep& s = step();
    if (!s.task) {
        f = {TaskStatus::NoTask, "this step has no task"};
        return f;
    }
    std::string waiting;
    if (!host_.taskBuffersReady(s.task->check.readsReference(), waiting)) {
        f.pending = true;
        f.message = "checking: waiting for " + waiting;
        return f;
    }
    f.pending = false;
    TaskCondition::Outcome outcome;
    try {
        outcome = evaluateOnHost(s.task->check, host_);
    } catch (const InputError& error) {  // the student's state cannot answer it (another technique's internal)
        outcome.message = error.what();
    }
    if (f.status == TaskStatus::ShownAnswer && outcome.passed) {
        f.message = outcome.message;  // solved by show me: stays marked as shown
        return f;
    }
    f.status = outcome.passed ? TaskStatus::Passed : TaskStatus::NotYet;
    f.message = outcome.message;
    return f;
}

bool LessonPlayer::finishCheck() {
    Feedback& f = feedback_[step_];
    if (!f.pending || !step().task) return false;
    checkTask();
    return !f.pending;
}

void LessonPlayer::showMe() {
    const LessonStep& s = step();
    if (!s.answerState) return;
    playing_ = false;
    apply(*s.answerState);
    if (feedback_[step_].status != TaskStatus::Passed) feedback_[step_].status = TaskStatus::ShownAnswer;
}

size_t LessonPlayer::tasksSolved() const {
    size_t n = 0;
    for (const Feedback& f : feedback_) n += f.status == TaskStatus::Passed;
    return n;
}

size_t LessonPlayer::taskCount() const {
    size_t n = 0;
    for (const LessonStep& s : lesson_.steps) n += s.task.has_value();
    return n;
}

void LessonPlayer::update(double seconds) {
    if (!playing_ || !hasAnimation() || expectsPending()) return;  // the claims are of the step's own state
    const LessonAnimation& a = *step().animate;
    animationTime_ += seconds;
    // Back and forth: from -> to in `seconds`, then back.
    double phase = std::fmod(animationTime_ / a.seconds, 2.0);
    double fraction = phase <= 1.0 ? phase : 2.0 - phase;
    std::string text = animatedValueText(step(), fraction);
    if (a.target.rfind("light.", 0) == 0) {
        LessonState s = animatedState(step(), fraction);
        host_.setLight(0, s.lights[0]);
    } else {
        host_.setParam(a.target, text);
    }
}

}  // namespace shadowlab
