#include "lesson/html.h"

#include <cctype>
#include <sstream>

#include "error.h"

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

std::string linkRefusal(const std::string& url) {
    if (url.empty()) return "an empty link target";
    for (unsigned char c : url)
        if (c <= 0x20 || c == 0x7f)
            return "a link target with a space or a control character (a browser drops them, 'java\\tscript:' is 'javascript:')";
    if (url.find('\\') != std::string::npos) return "a link target with a backslash (a browser reads it as '/')";
    if (url.rfind("//", 0) == 0) return "a protocol-relative link target ('//host'); write https://host";
    // A scheme: letters, digits, + - . before the first ':' that comes before any / ? #.
    size_t colon = url.find(':');
    size_t stop = url.find_first_of("/?#");
    if (colon == std::string::npos || (stop != std::string::npos && stop < colon)) return "";  // relative
    std::string scheme;
    for (size_t i = 0; i < colon; ++i) scheme += char(std::tolower(static_cast<unsigned char>(url[i])));
    if (scheme == "http" || scheme == "https") return "";
    return "the link scheme '" + scheme + ":' (a handout links to relative paths, #anchors, http: and https: only)";
}

namespace {

// Where a refused link is reported: the file, and the source line of each offset of the text.
struct LinkCheck {
    const std::string* file = nullptr;
    std::vector<std::pair<size_t, int>> lineAt;  // (offset where a source line starts, its line number)
    int line(size_t offset) const {
        int l = lineAt.empty() ? 0 : lineAt.front().second;
        for (const auto& [start, number] : lineAt)
            if (start <= offset) l = number;
        return l;
    }
};

// Inline Markdown: `code`, **bold**, *emphasis*, [text](url); everything else escaped. A link whose
// target linkRefusal() refuses is an InputError naming its line when `check` says where the text
// came from, else its text without the link.
std::string inlineHtml(const std::string& s, const LinkCheck* check = nullptr, size_t base = 0) {
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
                out += "<strong>" + inlineHtml(s.substr(i + 2, e - i - 2), check, base + i + 2) + "</strong>";
                i = e + 2;
                continue;
            }
        }
        if (s[i] == '*' && i + 1 < s.size() && s[i + 1] != ' ') {
            size_t e = s.find('*', i + 1);
            if (e != std::string::npos) {
                out += "<em>" + inlineHtml(s.substr(i + 1, e - i - 1), check, base + i + 1) + "</em>";
                i = e + 1;
                continue;
            }
        }
        if (s[i] == '[') {
            size_t close = s.find("](", i);
            size_t end = close == std::string::npos ? close : s.find(')', close);
            if (end != std::string::npos) {
                const std::string url = s.substr(close + 2, end - close - 2);
                const std::string text = inlineHtml(s.substr(i + 1, close - i - 1), check, base + i + 1);
                const std::string refused = linkRefusal(url);
                if (!refused.empty() && check)
                    throw InputError(*check->file + ":" + std::to_string(check->line(base + close + 2)) + ": link '" + url +
                                     "' refused: " + refused);
                out += refused.empty() ? "<a href=\"" + htmlEscape(url) + "\">" + text + "</a>" : text;
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

void checkInlineLinks(const std::string& text, const SourceLocation& where) {
    LinkCheck check;
    check.file = &where.file;
    check.lineAt = {{0, where.line}};
    inlineHtml(text, &check);
}

std::string markdownToHtml(const std::string& markdown) { return markdownToHtml(markdown, "", {}); }

std::string markdownToHtml(const std::string& markdown, const std::string& file, const std::vector<int>& lines) {
    std::istringstream in(markdown);
    std::string line, out, paragraph, list;
    bool inCode = false;
    const bool checked = !file.empty();
    LinkCheck check;
    check.file = &file;
    size_t lineIndex = 0;
    auto source = [&] { return lineIndex < lines.size() ? lines[lineIndex] : 0; };
    // One piece of inline text from the current source line (a list item, a heading).
    auto inlineLine = [&](const std::string& text) {
        LinkCheck one;
        one.file = &file;
        one.lineAt = {{0, source()}};
        return inlineHtml(text, checked ? &one : nullptr);
    };
    auto flush = [&] {
        if (!paragraph.empty()) out += "<p>" + inlineHtml(paragraph, checked ? &check : nullptr) + "</p>\n";
        paragraph.clear();
        check.lineAt.clear();
        if (!list.empty()) out += "</" + list + ">\n";
        list.clear();
    };
    for (; std::getline(in, line); ++lineIndex) {
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
            out += "<h3>" + inlineLine(line.substr(4)) + "</h3>\n";
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
            out += "<li>" + inlineLine(line.substr(bullet ? 2 : dot + 2)) + "</li>\n";
            continue;
        }
        if (!list.empty() && (line[0] == ' ' || line[0] == '\t')) {  // continuation of a list item
            out.insert(out.size() - 6, " " + inlineLine(line.substr(line.find_first_not_of(" \t"))));
            continue;
        }
        if (!list.empty()) flush();
        if (!paragraph.empty()) paragraph += " ";
        check.lineAt.push_back({paragraph.size(), source()});
        paragraph += line;
    }
    if (inCode) out += "</pre>\n";
    flush();
    return out;
}

namespace {

std::string figureHtml(const HandoutPicture& p) {
    return "<figure><img src=\"" + htmlEscape(p.file) + "\" width=\"" + std::to_string(p.width) + "\" height=\"" +
           std::to_string(p.height) + "\" alt=\"" + htmlEscape(p.label) + "\"><figcaption>" + htmlEscape(p.label) +
           "</figcaption></figure>\n";
}

}  // namespace

std::string lessonHandoutHtml(const Lesson& lesson, const std::vector<HandoutStep>& steps) {
    std::ostringstream h;
    h << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
         "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>"
      << htmlEscape(lesson.title)
      << "</title>\n<style>\n"
         // Pictures at their native size (width and height attributes, never scaled by CSS) in a
         // column as wide as the widest of them; the narration beside them, below them when the
         // screen is too narrow for both.
         "body{font-family:sans-serif;margin:2em;font-size:18px;line-height:1.5;color:#222}\n"
         ".intro{max-width:42em}\n"
         ".columns{display:flex;flex-wrap:wrap;gap:1.5em;align-items:flex-start}\n"
         ".pictures{flex:0 0 auto;width:min-content}\n"
         ".narration{flex:1 1 22em;max-width:42em}\n"
         "figure{display:inline-block;margin:0 0 1em 0;vertical-align:top}figcaption{font-size:14px;color:#555}\n"
         "img{image-rendering:pixelated;border:1px solid #ccc;max-width:none}code,pre{background:#f4f4f4;padding:0 .2em}\n"
         "pre{white-space:pre-wrap}\n"
         ".expects{list-style:none;padding:0;margin:0 0 1em 0;font-size:14px;overflow-wrap:anywhere}\n"
         ".expects li{margin:.2em 0;padding-left:.5em;border-left:4px solid #2a2}.expects li.fails{border-color:#c22}\n"
         ".notes{font-size:14px;overflow-wrap:anywhere}\n"
         ".task{border-left:4px solid #c80;padding:.2em 1em;background:#fff8ee}.step{border-top:1px solid #ddd;margin-top:2em}\n"
         // Print or project: one step per page, links written out.
         "@media print{\n"
         "body{margin:0;font-size:11pt}\n"
         ".step{page-break-before:always;break-before:page;border-top:none;margin-top:0}\n"
         "figure,.task,.expects li{page-break-inside:avoid;break-inside:avoid}\n"
         "a[href^=\"http\"]::after{content:\" (\" attr(href) \")\";font-size:90%}\n"
         "}\n"
         "</style>\n</head>\n<body>\n";
    h << "<div class=\"intro\">\n<h1>" << htmlEscape(lesson.title) << "</h1>\n<p><em>shadowlab lesson <code>"
      << htmlEscape(lesson.id) << "</code> (" << htmlEscape(lesson.file) << "), " << steps.size()
      << " steps, rendered by <code>shadowlab lesson " << htmlEscape(lesson.id)
      << " --headless</code>; every picture is the program's own output, every claim marked below a picture is "
         "measured on it.</em></p>\n";
    h << markdownToHtml(lesson.introduction) << "</div>\n";
    for (size_t k = 0; k < steps.size(); ++k) {
        const HandoutStep& s = steps[k];
        h << "<section class=\"step\" id=\"step-" << k + 1 << "\">\n<h2>" << k + 1 << ". " << htmlEscape(s.title) << "</h2>\n";
        h << "<div class=\"columns\">\n<div class=\"pictures\">\n" << figureHtml(s.picture);
        for (const HandoutPicture& v : s.views) h << figureHtml(v);
        if (!s.animation.empty()) {
            h << "<p>Animated:</p>\n";
            for (const HandoutPicture& a : s.animation) h << figureHtml(a);
        }
        if (!s.expects.empty()) {
            h << "<ul class=\"expects\">\n";
            for (const HandoutExpect& e : s.expects)
                h << "<li class=\"" << (e.passed ? "holds" : "fails") << "\">" << (e.passed ? "holds" : "FAILS")
                  << ": <code>expect " << htmlEscape(e.condition) << "</code><br>measured: <code>" << htmlEscape(e.measured)
                  << "</code></li>\n";
            h << "</ul>\n";
        }
        for (const std::string& n : s.notes) h << "<p class=\"notes\"><code>" << htmlEscape(n) << "</code></p>\n";
        h << "</div>\n<div class=\"narration\">\n" << markdownToHtml(s.narration);
        if (!s.task.empty()) {
            h << "<div class=\"task\">\n<p><strong>Try this:</strong> " << inlineHtml(s.task) << "</p>\n"
              << "<p>The program checks <code>" << htmlEscape(s.check) << "</code>. In this step's state: <code>"
              << htmlEscape(s.ownOutcome) << "</code></p>\n<details><summary>Show me</summary>\n<pre>"
              << htmlEscape(s.answerCommands) << "</pre>\n"
              << figureHtml(s.answer) << "<p><code>" << htmlEscape(s.answerOutcome) << "</code></p>\n</details>\n</div>\n";
        }
        h << "</div>\n</div>\n</section>\n";
    }
    h << "</body>\n</html>\n";
    return h.str();
}

}  // namespace shadowlab
