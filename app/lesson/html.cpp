#include "lesson/html.h"

#include <sstream>

namespace shadowlab {

std::string htmlEscape(const std::string& text) {
    std::string out;
    for (char c : text) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            default: out += c;
        }
    }
    return out;
}

namespace {

// Inline Markdown: `code`, **bold**, *emphasis*, [text](url); everything else escaped.
std::string inlineHtml(const std::string& s) {
    std::string out;
    size_t i = 0;
    while (i < s.size()) {
        if (s[i] == '`') {
            size_t e = s.find('`', i + 1);
            if (e != std::string::npos) {
                out += "<code>" + htmlEscape(s.substr(i + 1, e - i - 1)) + "</code>";
                i = e + 1;
                continue;
            }
        }
        if (s.compare(i, 2, "**") == 0) {
            size_t e = s.find("**", i + 2);
            if (e != std::string::npos) {
                out += "<strong>" + inlineHtml(s.substr(i + 2, e - i - 2)) + "</strong>";
                i = e + 2;
                continue;
            }
        }
        if (s[i] == '*' && i + 1 < s.size() && s[i + 1] != ' ') {
            size_t e = s.find('*', i + 1);
            if (e != std::string::npos) {
                out += "<em>" + inlineHtml(s.substr(i + 1, e - i - 1)) + "</em>";
                i = e + 1;
                continue;
            }
        }
        if (s[i] == '[') {
            size_t close = s.find("](", i);
            size_t end = close == std::string::npos ? close : s.find(')', close);
            if (end != std::string::npos) {
                out += "<a href=\"" + htmlEscape(s.substr(close + 2, end - close - 2)) + "\">" +
                       inlineHtml(s.substr(i + 1, close - i - 1)) + "</a>";
                i = end + 1;
                continue;
            }
        }
        out += htmlEscape(std::string(1, s[i]));
        ++i;
    }
    return out;
}

}  // namespace

std::string markdownToHtml(const std::string& markdown) {
    std::istringstream in(markdown);
    std::string line, out, paragraph, list;
    bool inCode = false;
    auto flush = [&] {
        if (!paragraph.empty()) out += "<p>" + inlineHtml(paragraph) + "</p>\n";
        paragraph.clear();
        if (!list.empty()) out += "</" + list + ">\n";
        list.clear();
    };
    while (std::getline(in, line)) {
        if (line.rfind("```", 0) == 0) {
            if (!inCode) flush();
            out += inCode ? "</pre>\n" : "<pre>";
            inCode = !inCode;
            continue;
        }
        if (inCode) {
            out += htmlEscape(line) + "\n";
            continue;
        }
        if (line.find_first_not_of(" \t") == std::string::npos) {
            flush();
            continue;
        }
        if (line.rfind("### ", 0) == 0) {
            flush();
            out += "<h3>" + inlineHtml(line.substr(4)) + "</h3>\n";
            continue;
        }
        bool bullet = line.rfind("- ", 0) == 0;
        size_t dot = line.find(". ");
        bool numbered = dot != std::string::npos && dot > 0 && dot < 4 &&
                        line.find_first_not_of("0123456789") == dot;
        if (bullet || numbered) {
            std::string kind = bullet ? "ul" : "ol";
            if (!paragraph.empty() || list != kind) flush();
            if (list.empty()) out += "<" + kind + ">\n";
            list = kind;
            out += "<li>" + inlineHtml(line.substr(bullet ? 2 : dot + 2)) + "</li>\n";
            continue;
        }
        if (!list.empty() && (line[0] == ' ' || line[0] == '\t')) {  // continuation of a list item
            out.insert(out.size() - 6, " " + inlineHtml(line.substr(line.find_first_not_of(" \t"))));
            continue;
        }
        if (!list.empty()) flush();
        paragraph += (paragraph.empty() ? "" : " ") + line;
    }
    if (inCode) out += "</pre>\n";
    flush();
    return out;
}

std::string lessonHandoutHtml(const Lesson& lesson, const std::vector<HandoutStep>& steps, int width, int height) {
    std::ostringstream h;
    // Width only: the error view carries its colour bar below the image.
    (void)height;
    std::string size = "width=\"" + std::to_string(width) + "\"";
    h << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" << htmlEscape(lesson.title)
      << "</title>\n<style>\n"
         "body{font-family:sans-serif;max-width:60em;margin:2em auto;padding:0 1em;font-size:18px;line-height:1.5;color:#222}\n"
         "figure{display:inline-block;margin:0 1em 1em 0;vertical-align:top}figcaption{font-size:14px;color:#555}\n"
         "img{image-rendering:pixelated;border:1px solid #ccc}code,pre{background:#f4f4f4;padding:0 .2em}\n"
         ".task{border-left:4px solid #c80;padding:.2em 1em;background:#fff8ee}.step{border-top:1px solid #ddd;margin-top:2em}\n"
         "</style>\n</head>\n<body>\n";
    h << "<h1>" << htmlEscape(lesson.title) << "</h1>\n<p><em>shadowlab lesson <code>" << htmlEscape(lesson.id)
      << "</code> (" << htmlEscape(lesson.file) << "), " << steps.size()
      << " steps, rendered by <code>shadowlab lesson " << htmlEscape(lesson.id)
      << " --headless</code>; every picture is the program's own output.</em></p>\n";
    h << markdownToHtml(lesson.introduction);
    for (size_t k = 0; k < steps.size(); ++k) {
        const HandoutStep& s = steps[k];
        h << "<section class=\"step\" id=\"step-" << k + 1 << "\">\n<h2>" << k + 1 << ". " << htmlEscape(s.title) << "</h2>\n";
        h << "<figure><img src=\"" << s.image << "\" " << size << " alt=\"" << htmlEscape(s.caption) << "\"><figcaption>"
          << htmlEscape(s.caption) << "</figcaption></figure>\n";
        for (const auto& [view, file] : s.views)
            h << "<figure><img src=\"" << file << "\" alt=\"" << view << "\"><figcaption>" << view
              << "</figcaption></figure>\n";
        h << markdownToHtml(s.narration);
        for (const std::string& n : s.notes) h << "<p><code>" << htmlEscape(n) << "</code></p>\n";
        if (!s.animation.empty()) {
            h << "<p>Animated:</p>\n";
            for (const auto& [label, file] : s.animation)
                h << "<figure><img src=\"" << file << "\" " << size << " alt=\"" << htmlEscape(label) << "\"><figcaption>"
                  << htmlEscape(label) << "</figcaption></figure>\n";
        }
        if (!s.task.empty()) {
            h << "<div class=\"task\">\n<p><strong>Try this:</strong> " << inlineHtml(s.task) << "</p>\n"
              << "<p>The program checks <code>" << htmlEscape(s.check) << "</code>. In this step's state: <code>"
              << htmlEscape(s.ownOutcome) << "</code></p>\n<details><summary>Show me</summary>\n<pre>"
              << htmlEscape(s.answerCommands) << "</pre>\n<figure><img src=\"" << s.answerImage << "\" " << size
              << " alt=\"answer\"><figcaption>the answer's state</figcaption></figure>\n<p><code>"
              << htmlEscape(s.answerOutcome) << "</code></p>\n</details>\n</div>\n";
        }
        h << "</section>\n";
    }
    h << "</body>\n</html>\n";
    return h.str();
}

}  // namespace shadowlab
