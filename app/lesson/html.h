// The HTML handout of a lesson (`shadowlab lesson L --headless`): narration converted from
// Markdown, each step's pictures, the task with what the program measured both ways.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "lesson/lesson.h"

namespace shadowlab {

// A picture of the handout: its file, caption, and size in pixels (the <img>'s width and height:
// pictures are shown at their native size, never scaled).
struct HandoutPicture {
    std::string file, label;
    int width = 0, height = 0;
};

// An expectation of a step as measured (`expect`): its condition, what was found, and whether it held.
struct HandoutExpect {
    std::string condition, measured;
    bool passed = false;
};

struct HandoutStep {
    std::string title, narration;
    HandoutPicture picture;                   // the technique view
    std::vector<HandoutPicture> views;        // the views the step shows
    std::vector<HandoutPicture> animation;    // first, middle and last frame
    std::vector<std::string> notes;           // picked pixel values
    std::vector<HandoutExpect> expects;
    std::string task, check, ownOutcome, answerOutcome, answerCommands;
    HandoutPicture answer;
};

// Why a link target is refused, "" when it is allowed: a handout links to relative paths, #anchors
// and http: / https: URLs; every other scheme (javascript:, data:, vbscript:, file:, mailto:, ...),
// a protocol-relative '//host', a backslash, a space or a control character is refused.
std::string linkRefusal(const std::string& url);
// The Markdown subset lessons use: paragraphs, '###' headings, '- ' and '1. ' lists, **bold**,
// *emphasis*, `code`, [links](url), fenced code blocks, and '$...$' kept as text. A refused link
// is its text without the link.
std::string markdownToHtml(const std::string& markdown);
// The same, with the source line of each line of `markdown` in `file`: a refused link is an
// InputError "file:line: link 'javascript:...' refused: ...".
std::string markdownToHtml(const std::string& markdown, const std::string& file, const std::vector<int>& lines);
// Inline Markdown of one line (a task's prompt): a refused link is an InputError naming `where`.
void checkInlineLinks(const std::string& text, const SourceLocation& where);
std::string htmlEscape(const std::string& text);
// The handout: per step its pictures at their native size with the measured expectations under
// them, the narration beside them (two columns that wrap on a narrow screen), and a print
// stylesheet that starts every step on a new page.
std::string lessonHandoutHtml(const Lesson& lesson, const std::vector<HandoutStep>& steps);

}  // namespace shadowlab
