// The lesson player's ImGui panel (Dear ImGui 1.86): what the window draws beside the views.
#include <imgui.h>

#include <algorithm>
#include <cctype>
#include <initializer_list>
#include <cstdio>
#include <sstream>
#include <string>

#include "lesson/player.h"

namespace shadowlab {

namespace {

bool keyPressed(ImGuiKey key) {
    int index = ImGui::GetKeyIndex(key);
    return index >= 0 && ImGui::IsKeyPressed(index, false);
}

bool letterPressed(char upper) {
    // Letters are read from the character queue (layout-independent in 1.86).
    const ImGuiIO& io = ImGui::GetIO();
    for (int i = 0; i < io.InputQueueCharacters.Size; ++i)
        if (io.InputQueueCharacters[i] == ImWchar(upper) || io.InputQueueCharacters[i] == ImWchar(upper - 'A' + 'a'))
            return true;
    return false;
}

// Markdown narration as the panel shows it: the source's hard line breaks joined within a paragraph
// (ImGui wraps at the panel's width), list items and blank lines kept, ** emphasis markers dropped.
std::string reflowNarration(const std::string& markdown) {
    std::string out, line;
    std::istringstream in(markdown);
    bool paragraphOpen = false;
    while (std::getline(in, line)) {
        size_t first = line.find_first_not_of(" \t");
        if (first == std::string::npos) {
            if (!out.empty() && out.back() != '\n') out += "\n";
            if (!out.empty()) out += "\n";
            paragraphOpen = false;
            continue;
        }
        std::string text = line.substr(first);
        bool item = text.rfind("- ", 0) == 0 || text.rfind("* ", 0) == 0 ||
                    (std::isdigit(static_cast<unsigned char>(text[0])) && text.find(". ") != std::string::npos &&
                     text.find(". ") < 4);
        if (paragraphOpen && !item) out += " ";
        else if (paragraphOpen) out += "\n";
        out += text;
        paragraphOpen = true;
    }
    std::string clean;
    for (size_t i = 0; i < out.size(); ++i) {
        if (out.compare(i, 2, "**") == 0) {
            ++i;
            continue;
        }
        clean += out[i];
    }
    return clean;
}

const char* statusText(LessonPlayer::TaskStatus s) {
    switch (s) {
        case LessonPlayer::TaskStatus::NoTask: return "";
        case LessonPlayer::TaskStatus::NotChecked: return "not checked yet";
        case LessonPlayer::TaskStatus::Passed: return "solved!";
        case LessonPlayer::TaskStatus::NotYet: return "not yet";
        case LessonPlayer::TaskStatus::ShownAnswer: return "answer shown";
    }
    return "";
}

ImVec4 statusColour(LessonPlayer::TaskStatus s) {
    switch (s) {
        case LessonPlayer::TaskStatus::Passed: return ImVec4(0.3f, 0.9f, 0.3f, 1.0f);
        case LessonPlayer::TaskStatus::NotYet: return ImVec4(1.0f, 0.6f, 0.2f, 1.0f);
        case LessonPlayer::TaskStatus::ShownAnswer: return ImVec4(0.6f, 0.7f, 1.0f, 1.0f);
        default: return ImVec4(0.8f, 0.8f, 0.8f, 1.0f);
    }
}

}  // namespace

LessonPanelRects drawLessonPanel(LessonPlayer& player, float fontScale) {
    LessonPanelRects rects;
    const Lesson& lesson = player.lesson();
    ImGui::Begin("Lesson", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
    ImGui::SetWindowFontScale(fontScale);
    // Keys work while no text field has the keyboard.
    if (!ImGui::GetIO().WantTextInput) {
        if (keyPressed(ImGuiKey_RightArrow) || keyPressed(ImGuiKey_PageDown)) player.next();
        if (keyPressed(ImGuiKey_LeftArrow) || keyPressed(ImGuiKey_PageUp)) player.previous();
        if (keyPressed(ImGuiKey_Space)) player.setPlaying(!player.playing());
        if (letterPressed('R')) player.restore();
        if (letterPressed('C') && player.step().task) player.checkTask();
        if (letterPressed('M') && player.step().task) player.showMe();
    }
    const LessonStep& step = player.step();
    ImGui::TextWrapped("%s", lesson.title.c_str());
    char progress[64];
    std::snprintf(progress, sizeof progress, "step %zu of %zu", player.stepIndex() + 1, player.stepCount());
    ImGui::ProgressBar(player.progress(), ImVec2(-1.0f, 0.0f), progress);
    if (player.taskCount() > 0) ImGui::Text("tasks solved: %zu of %zu", player.tasksSolved(), player.taskCount());
    ImGui::Separator();
    ImGui::TextWrapped("%s", step.title.c_str());
    ImGui::Spacing();
    // A button on the line of the one before when it fits in the column, else on the next line.
    auto flowButton = [](const char* label, bool first) {
        const ImGuiStyle& style = ImGui::GetStyle();
        const float w = ImGui::CalcTextSize(label).x + 2.0f * style.FramePadding.x;
        if (!first && ImGui::GetItemRectMax().x + style.ItemSpacing.x + w <=
                          ImGui::GetWindowPos().x + ImGui::GetWindowContentRegionMax().x)
            ImGui::SameLine();
        return ImGui::Button(label);
    };
    // What the step's claims came to: one line under the narration.
    const bool claims = !step.expects.empty();
    char claimsLine[256] = "";
    bool claimsBad = false;
    if (claims) {
        size_t held = 0;
        for (const LessonPlayer::ExpectResult& r : player.expectResults()) held += r.passed;
        switch (player.expectStatus()) {
            case LessonPlayer::ExpectStatus::Pending:
                std::snprintf(claimsLine, sizeof claimsLine, "checking the step's claims: %s",
                              player.expectWaiting().empty() ? "..." : player.expectWaiting().c_str());
                break;
            case LessonPlayer::ExpectStatus::Changed:
                std::snprintf(claimsLine, sizeof claimsLine, "claims not checked: the step was changed first (R restores it)");
                break;
            default:
                std::snprintf(claimsLine, sizeof claimsLine, "claims: %zu of %zu hold (measured here, listed under the narration)",
                              held, player.expectResults().size());
        }
        claimsBad = player.expectStatus() == LessonPlayer::ExpectStatus::Checked && held < player.expectResults().size();
    }
    const LessonPlayer::Feedback& feedback = player.feedback();
    const std::string taskPrompt = step.task ? "Try this: " + step.task->prompt : "";
    const char* taskStatus = feedback.pending ? "checking ..." : statusText(feedback.status);
    const char* playLabel = player.playing() ? "Pause (Space)" : "Play (Space)";
    // The narration scrolls; everything under it (the claims line, the task with its buttons,
    // status and message, the step buttons) keeps the height it takes at the panel's width, so the
    // step buttons stay on screen: a fixed guess of rows cut "Next >" off at 1024x768 under a task
    // whose prompt wraps to five lines.
    {
        const ImGuiStyle& style = ImGui::GetStyle();
        const float width = ImGui::GetContentRegionAvail().x;
        const auto text = [&](const char* t) { return ImGui::CalcTextSize(t, nullptr, false, width).y + style.ItemSpacing.y; };
        const auto buttons = [&](std::initializer_list<const char*> labels) {  // rows as flowButton lays them out
            float x = 0.0f;
            int rows = 1;
            for (const char* label : labels) {
                const float w = ImGui::CalcTextSize(label).x + 2.0f * style.FramePadding.x;
                if (x > 0.0f && x + style.ItemSpacing.x + w > width) {
                    ++rows;
                    x = w;
                } else {
                    x += (x > 0.0f ? style.ItemSpacing.x : 0.0f) + w;
                }
            }
            return float(rows) * ImGui::GetFrameHeightWithSpacing();
        };
        const float separator = 1.0f + style.ItemSpacing.y;
        float below = separator + (player.hasAnimation() ? buttons({"< Previous", "Restore step (R)", playLabel, "Next >"})
                                                         : buttons({"< Previous", "Restore step (R)", "Next >"}));
        if (claims) below += text(claimsLine);
        if (step.task) {
            below += separator + text(taskPrompt.c_str()) + buttons({"Check (C)", "Show me (M)"}) + text(taskStatus);
            if (!feedback.message.empty()) below += text(feedback.message.c_str());
        }
        // At least three lines of narration whatever the rest takes (it scrolls).
        const float least = 3.0f * ImGui::GetTextLineHeightWithSpacing();
        below = std::min(below + style.ItemSpacing.y, std::max(0.0f, ImGui::GetContentRegionAvail().y - least));
        ImGui::BeginChild("narration", ImVec2(0, -below), false);
    }
    ImGui::PushTextWrapPos(0.0f);
    ImGui::TextUnformatted(reflowNarration(step.narration).c_str());
    // The step's claims as measured (lessons/README.md, expect), each with its value.
    if (player.expectStatus() == LessonPlayer::ExpectStatus::Checked) {
        ImGui::Spacing();
        for (size_t k = 0; k < player.expectResults().size(); ++k) {
            const LessonPlayer::ExpectResult& r = player.expectResults()[k];
            ImGui::PushStyleColor(ImGuiCol_Text, r.passed ? ImVec4(0.5f, 0.85f, 0.5f, 1.0f) : ImVec4(1.0f, 0.45f, 0.35f, 1.0f));
            ImGui::TextWrapped("%s expect %s: %s", r.passed ? "holds:" : "FAILS:", step.expects[k].condition.text().c_str(),
                               r.passed ? r.message.c_str() : r.failure.c_str());
            ImGui::PopStyleColor();
        }
    }
    ImGui::PopTextWrapPos();
    ImGui::EndChild();
    if (claims) {
        ImGui::PushStyleColor(ImGuiCol_Text, claimsBad ? ImVec4(1.0f, 0.45f, 0.35f, 1.0f) : ImVec4(0.8f, 0.8f, 0.8f, 1.0f));
        ImGui::TextWrapped("%s", claimsLine);
        ImGui::PopStyleColor();
    }
    if (step.task) {
        ImGui::Separator();
        ImGui::TextWrapped("%s", taskPrompt.c_str());
        if (flowButton("Check (C)", true)) player.checkTask();
        if (flowButton("Show me (M)", false)) player.showMe();
        ImGui::PushStyleColor(ImGuiCol_Text, feedback.pending ? ImVec4(0.8f, 0.8f, 0.8f, 1.0f) : statusColour(feedback.status));
        ImGui::TextWrapped("%s", taskStatus);
        ImGui::PopStyleColor();
        if (!feedback.message.empty()) ImGui::TextWrapped("%s", feedback.message.c_str());
    }
    ImGui::Separator();
    ImGui::BeginDisabled(player.atFirst());
    if (flowButton("< Previous", true)) player.previous();
    ImGui::EndDisabled();
    if (flowButton("Restore step (R)", false)) player.restore();
    if (player.hasAnimation())
        if (flowButton(playLabel, false)) player.setPlaying(!player.playing());
    ImGui::BeginDisabled(player.atLast());
    if (flowButton("Next >", false)) player.next();
    ImGui::EndDisabled();
    const ImVec2 nextMin = ImGui::GetItemRectMin(), nextMax = ImGui::GetItemRectMax();
    const ImVec2 at = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
    rects = {{at.x, at.y, size.x, size.y}, {nextMin.x, nextMin.y, nextMax.x - nextMin.x, nextMax.y - nextMin.y}};
    ImGui::End();
    return rects;
}

}  // namespace shadowlab
