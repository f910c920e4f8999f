// The HTML handout of a lesson (`shadowlab lesson L --headless`): narration converted from
// Markdown, each step's pictures, the task with what the program measured both ways.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "lesson/lesson.h"

namespace shadowlab {

struct HandoutStep {
    std::string title, narration;
    std::string image, caption;                                  // the technique view
    std::vector<std::pair<std::string, std::string>> views;      // (view, file)
    std::vector<std::pair<std::string, std::string>> animation;  // (label, file)
    std::vector<std::string> notes;                              // picked pixel values
    std::string task, check, ownOutcome, answerOutcome, answerImage, answerCommands;
};

// The Markdown subset lessons use: paragraphs, '###' headings, '- ' and '1. ' lists, **bold**,
// *emphasis*, `code`, [links](url), fenced code blocks, and '$...$' kept as text.
std::string markdownToHtml(const std::string& markdown);
std::string htmlEscape(const std::string& text);
std::string lessonHandoutHtml(const Lesson& lesson, const std::vector<HandoutStep>& steps, int width, int height);

}  // namespace shadowlab
