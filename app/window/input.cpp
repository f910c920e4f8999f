// The window's input: keys (F1 lists them: helpText below is the single list), the mouse (orbit,
// pan, zoom, drag the light, drag the split, pick a pixel) and --script, whose steps call the same
// functions as the keys, the mouse and the panel.
#include "gl/loader.h"
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "error.h"
#include "scene/input_file.h"
#include "views.h"
#include "window/camera_control.h"
#include "lesson/player.h"
#include "window/window.h"

namespace shadowlab {

const char* Window::helpText() {
    return "Keys\n"
           "  F1            this list;  F5: presentation mode (large text, one-line bars, wide narration)\n"
           "  T / Shift+T   next / previous technique\n"
           "  S / Shift+S   next / previous scene\n"
           "  1 .. 9        technique by its place in the list\n"
           "  D             reset the technique's parameters to the paper's defaults\n"
           "  C             split view: off -> reference -> second technique -> off\n"
           "  E             error view |technique - reference| (heat map)\n"
           "  B             background reference on / off\n"
           "  F             light frustum on / off\n"
           "  L             light outline on / off;  Shift+L: reset the light\n"
           "  [ / ]         light smaller / larger\n"
           "  G             light shape: square <-> disk\n"
           "  N             next light (the one the controls edit)\n"
           "  R             reset the camera\n"
           "  Arrows        orbit the camera;  PageUp / PageDown: zoom\n"
           "  Space         play / pause animated scenes\n"
           "  X             reduced resolution while dragging on / off\n"
           "  + / -         UI scale (projectors)\n"
           "  Tab           panel on / off;  H: HUD on / off;  V: views panel\n"
           "  A             accuracy-time chart of the settings tried (against the complete reference)\n"
           "  P or F12      screenshot (shadowlab-<n>.png in the working folder)\n"
           "  With a lesson open (window --lesson L): Right / Left or PageDown / PageUp step,\n"
           "                R restores the step, C checks the task, M shows the answer, Space plays\n"
           "  Esc or Q      quit\n"
           "Mouse (in the view)\n"
           "  left drag     orbit the camera\n"
           "  left drag on the light, or Shift + left drag: move the light in its plane\n"
           "  left drag on the split line: move the split\n"
           "  right or middle drag: pan;  wheel: zoom\n"
           "  Ctrl + click  pick a pixel (views and HUD show it)\n";
}

void Window::key(int key, int mods) {
    if (lessonKey(key)) return;  // an open lesson's panel reads it (app/lesson/panel.cpp)
    bool shift = (mods & GLFW_MOD_SHIFT) != 0;
    int step = shift ? -1 : 1;
    Light light = state_.lights.empty() ? Light{} : state_.lights[size_t(state_.lightIndex)];
    switch (key) {
    case GLFW_KEY_ESCAPE:
    case GLFW_KEY_Q: glfwSetWindowShouldClose(window_, GLFW_TRUE); break;
    case GLFW_KEY_F1: state_.showHelp = !state_.showHelp; break;
    case GLFW_KEY_F5: setPresentation(!state_.presentation); break;
    case GLFW_KEY_T: cycleTechnique(step); break;
    case GLFW_KEY_S: cycleScene(step); break;
    case GLFW_KEY_D: resetAllParams(); break;
    case GLFW_KEY_C:
        if (state_.compare == WindowState::Compare::None) setCompare(WindowState::Compare::Reference);
        else if (state_.compare == WindowState::Compare::Reference) setCompare(WindowState::Compare::Technique);
        else setCompare(WindowState::Compare::None);
        break;
    case GLFW_KEY_E: setErrorView(!state_.errorView); break;
    case GLFW_KEY_B: state_.backgroundReference = !state_.backgroundReference; break;
    case GLFW_KEY_F: state_.showFrustum = !state_.showFrustum; break;
    case GLFW_KEY_L:
        if (shift) resetLight();
        else state_.showLight = !state_.showLight;
        break;
    case GLFW_KEY_LEFT_BRACKET:
    case GLFW_KEY_RIGHT_BRACKET:
        if (!state_.lights.empty()) {
            light.size = std::max(0.0f, light.size * (key == GLFW_KEY_RIGHT_BRACKET ? 1.25f : 0.8f));
            if (light.size < 0.01f && key == GLFW_KEY_RIGHT_BRACKET) light.size = 0.05f;
            setLight(state_.lightIndex, light);
        }
        break;
    case GLFW_KEY_G:
        if (!state_.lights.empty()) {
            light.shape = light.shape == LightShape::Square ? LightShape::Disk : LightShape::Square;
            // the same area: a square of width w and a disk of radius w / sqrt(pi)
            light.size = light.shape == LightShape::Disk ? light.size / 1.7724539f : light.size * 1.7724539f;
            setLight(state_.lightIndex, light);
        }
        break;
    case GLFW_KEY_N:
        if (!state_.lights.empty()) state_.lightIndex = (state_.lightIndex + 1) % int(state_.lights.size());
        break;
    case GLFW_KEY_R: resetCamera(); break;
    case GLFW_KEY_LEFT: noteInput(); setCamera(orbitCamera(state_.camera, -0.1f, 0.0f)); break;
    case GLFW_KEY_RIGHT: noteInput(); setCamera(orbitCamera(state_.camera, 0.1f, 0.0f)); break;
    case GLFW_KEY_UP: noteInput(); setCamera(orbitCamera(state_.camera, 0.0f, 0.1f)); break;
    case GLFW_KEY_DOWN: noteInput(); setCamera(orbitCamera(state_.camera, 0.0f, -0.1f)); break;
    case GLFW_KEY_PAGE_UP: noteInput(); setCamera(zoomCamera(state_.camera, 0.9f)); break;
    case GLFW_KEY_PAGE_DOWN: noteInput(); setCamera(zoomCamera(state_.camera, 1.0f / 0.9f)); break;
    case GLFW_KEY_SPACE: state_.playing = !state_.playing; break;
    case GLFW_KEY_X: state_.reduceWhileDragging = !state_.reduceWhileDragging; break;
    case GLFW_KEY_EQUAL:
    case GLFW_KEY_KP_ADD: setUiScale(state_.uiScale + 0.25f); break;
    case GLFW_KEY_MINUS:
    case GLFW_KEY_KP_SUBTRACT: setUiScale(state_.uiScale - 0.25f); break;
    case GLFW_KEY_TAB: state_.showPanel = !state_.showPanel; break;
    case GLFW_KEY_H: state_.showHud = !state_.showHud; break;
    case GLFW_KEY_V: state_.showViews = !state_.showViews; break;
    case GLFW_KEY_A: state_.showAccuracy = !state_.showAccuracy; break;
    case GLFW_KEY_P:
    case GLFW_KEY_F12: {
        std::string name;
        do name = "shadowlab-" + std::to_string(++shotCounter_) + ".png";
        while (std::filesystem::exists(name));
        screenshot(name);
        break;
    }
    default:
        if (key >= GLFW_KEY_1 && key <= GLFW_KEY_9) {
            size_t i = size_t(key - GLFW_KEY_1);
            if (i < techniques_.size()) selectTechnique(techniques_[i]);
        }
        break;
    }
}

// Mouse positions arrive in window units; the technique view's actions work in its own region
// (window/layout.h): a press outside it starts nothing.
void Window::mouseButton(int button, bool press, int mods, glm::vec2 windowAt) {
    mouse_ = windowAt;
    if (!press) {
        if (drag_ != Drag::None) touch();
        drag_ = Drag::None;
        return;
    }
    // A script's drag-light starts on the light's centre wherever it is drawn, even off the view
    // (plant's light, above its default camera's view): the one press allowed outside.
    if (!layout_.technique.contains(windowAt) && !pressOnLight_) return;
    const glm::vec2 at = toView(windowAt);
    glm::vec2 size(layout_.technique.w, layout_.technique.h);
    dragStart_ = dragLast_ = at;
    if (button == GLFW_MOUSE_BUTTON_RIGHT || button == GLFW_MOUSE_BUTTON_MIDDLE) {
        drag_ = Drag::Pan;
        return;
    }
    if (button != GLFW_MOUSE_BUTTON_LEFT) return;
    if (mods & GLFW_MOD_CONTROL) {
        glm::ivec2 fb = renderSize();
        pickPixel(glm::ivec2(at * glm::vec2(fb) / size));
        return;
    }
    if (state_.compare != WindowState::Compare::None && !state_.errorView &&
        std::abs(at.x - state_.split * size.x) < 8.0f * state_.uiScale) {
        drag_ = Drag::Split;
        return;
    }
    // On the light (its centre or inside its outline) or with Shift: move the light.
    bool onLight = false;
    if (!state_.lights.empty() && state_.showLight) {
        const Light& l = state_.lights[size_t(state_.lightIndex)];
        auto centre = projectToWindow(state_.camera, aspect(), l.position, size);
        if (centre && glm::length(*centre - at) < 14.0f * state_.uiScale) onLight = true;
        std::vector<glm::vec3> outline = lightOutline(l);
        std::vector<glm::vec2> poly;
        for (const glm::vec3& p : outline)
            if (auto q = projectToWindow(state_.camera, aspect(), p, size)) poly.push_back(*q);
        if (poly.size() == outline.size() && poly.size() >= 3) {  // point in polygon (even-odd)
            bool inside = false;
            for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++)
                if ((poly[i].y > at.y) != (poly[j].y > at.y) &&
                    at.x < (poly[j].x - poly[i].x) * (at.y - poly[i].y) / (poly[j].y - poly[i].y) + poly[i].x)
                    inside = !inside;
            onLight = onLight || inside;
        }
    }
    if (!state_.lights.empty() && (onLight || (mods & GLFW_MOD_SHIFT))) {
        const Light& l = state_.lights[size_t(state_.lightIndex)];
        Ray ray = cameraRay(state_.camera, aspect(), at, size);
        auto hit = intersectPlane(ray, l.position, l.direction);
        if (hit) {
            drag_ = Drag::Light;
            dragLightStart_ = l.position;
            dragHitStart_ = *hit;
            return;
        }
    }
    drag_ = Drag::Orbit;
}

void Window::mouseMove(glm::vec2 windowAt) {
    mouse_ = windowAt;
    if (drag_ == Drag::None) return;
    const glm::vec2 at = toView(windowAt);
    glm::vec2 size(layout_.technique.w, layout_.technique.h);
    glm::vec2 delta = at - dragLast_;
    dragLast_ = at;
    noteInput();
    switch (drag_) {
    case Drag::Orbit: setCamera(orbitCamera(state_.camera, delta.x * 0.008f, delta.y * 0.008f)); break;
    case Drag::Pan: setCamera(panCamera(state_.camera, delta.x / size.y, delta.y / size.y)); break;
    case Drag::Split: setSplit(at.x / size.x); break;
    case Drag::Light: {
        Light l = state_.lights[size_t(state_.lightIndex)];
        Ray ray = cameraRay(state_.camera, aspect(), at, size);
        if (auto hit = intersectPlane(ray, dragLightStart_, l.direction)) {
            glm::vec3 offset = *hit - dragHitStart_;
            if (glm::length(offset) > 50.0f) offset *= 50.0f / glm::length(offset);  // near the horizon
            l.position = dragLightStart_ + offset;
            setLight(state_.lightIndex, l);
        }
        break;
    }
    case Drag::None: break;
    }
}

void Window::scroll(double dy) {
    if (dy == 0.0) return;
    noteInput();
    setCamera(zoomCamera(state_.camera, float(std::pow(0.9, dy))));
}

// ---- --script -------------------------------------------------------------------------------------------
// One step per line ('#' starts a comment):
//   key NAME [shift|ctrl]      a key as if pressed (NAME: a letter, digit, F1, F12, space, tab, left,
//                              right, up, down, pageup, pagedown, [, ], +, -, esc)
//   technique ID | scene NAME|PATH | param KEY VALUE | reset-params
//                              the panel's actions
//   drag BUTTON MODS x0 y0 x1 y1 FRAMES
//                              a mouse drag in window coordinates over FRAMES frames
//                              (BUTTON left|right|middle, MODS none|shift|ctrl)
//   view NAME | close-view NAME  a VTK view in the views panel (scene3d, shadow-map, internal, error)
//   enlarge-view NAME | off      that view (opened if it is not) over the technique view's region; off: back
//   drag-light DX DY FRAMES    a left drag from the selected light's centre, by (DX, DY) pixels
//   scroll DY | pick X Y | split off|reference|TECHNIQUE | split-at F | error on|off
//   frustum on|off | ui-scale F | help on|off | panel on|off | views on|off | background on|off
//   resize W H                 the window's size (waits 3 frames for the window system)
//   wait N                     N frames
//   wait-reference [MAX]       until the reference (and the progressive reference the view shows)
//                              is complete (at most MAX frames, default 100000)
//   screenshot FILE            the whole window, UI included, one frame later (.png, or .pfm for tests)
//   reference-samples N        N of the progressive reference
//   reference reference|raytraced   which progressive reference the split, error view and metrics use
//   reference-rays M           M of the progressive ray tracer (rays per pixel)
//   save-reference FILE.pfm    the complete reference's visibility (fails when it is not complete)
//   save-visibility FILE.pfm   the technique's visibility of the last frame (reference, raytraced:
//                              the complete progressive one)
namespace {

int keyCode(const std::string& name) {
    static const std::map<std::string, int> named = {
        {"f1", GLFW_KEY_F1},       {"f12", GLFW_KEY_F12},         {"space", GLFW_KEY_SPACE},
        {"tab", GLFW_KEY_TAB},     {"left", GLFW_KEY_LEFT},       {"right", GLFW_KEY_RIGHT},
        {"up", GLFW_KEY_UP},       {"down", GLFW_KEY_DOWN},       {"pageup", GLFW_KEY_PAGE_UP},
        {"pagedown", GLFW_KEY_PAGE_DOWN}, {"[", GLFW_KEY_LEFT_BRACKET}, {"]", GLFW_KEY_RIGHT_BRACKET},
        {"+", GLFW_KEY_EQUAL},     {"-", GLFW_KEY_MINUS},         {"esc", GLFW_KEY_ESCAPE}};
    std::string lower = name;
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
    if (auto it = named.find(lower); it != named.end()) return it->second;
    if (lower.size() == 1 && lower[0] >= 'a' && lower[0] <= 'z') return GLFW_KEY_A + (lower[0] - 'a');
    if (lower.size() == 1 && lower[0] >= '0' && lower[0] <= '9') return GLFW_KEY_0 + (lower[0] - '0');
    return -1;
}

int modsCode(const std::string& name) {
    if (name == "none") return 0;
    if (name == "shift") return GLFW_MOD_SHIFT;
    if (name == "ctrl") return GLFW_MOD_CONTROL;
    return -1;
}

int buttonCode(const std::string& name) {
    if (name == "left") return GLFW_MOUSE_BUTTON_LEFT;
    if (name == "right") return GLFW_MOUSE_BUTTON_RIGHT;
    if (name == "middle") return GLFW_MOUSE_BUTTON_MIDDLE;
    return -1;
}

}  // namespace

namespace {
constexpr double kMaxScriptFrames = 10000000;  // ~3.9 days at 30 fps: a script's longest wait or drag
constexpr double kMaxScriptPixels = 100000;    // a drag's window coordinates and offsets
}  // namespace

std::deque<ScriptCommand> parseScript(const std::string& path) {
    // Through the input gate (a folder read as an empty script, exit 0 having done nothing; a FIFO
    // or /dev/zero blocked or grew without bound).
    std::istringstream in(readInputFile(path, "window script", kMaxTextInputBytes));
    std::deque<ScriptCommand> script;
    std::string text;
    static const std::map<std::string, std::pair<size_t, size_t>> arity = {
        {"key", {1, 2}},      {"technique", {1, 1}}, {"scene", {1, 1}},      {"param", {2, 2}},
        {"reset-params", {0, 0}}, {"drag", {7, 7}},  {"scroll", {1, 1}},     {"pick", {2, 2}},
        {"split", {1, 1}},    {"split-at", {1, 1}},  {"error", {1, 1}},      {"frustum", {1, 1}},
        {"ui-scale", {1, 1}}, {"help", {1, 1}},      {"present", {1, 1}},    {"panel", {1, 1}},      {"views", {1, 1}}, {"accuracy", {1, 1}}, {"save-accuracy", {1, 1}},
        {"background", {1, 1}}, {"resize", {2, 2}},  {"wait", {1, 1}},       {"wait-reference", {0, 1}},
        {"screenshot", {1, 1}}, {"reference-samples", {1, 1}}, {"save-reference", {1, 1}},
        {"reference", {1, 1}}, {"reference-rays", {1, 1}},
        {"save-visibility", {1, 1}}, {"drag-light", {3, 3}}, {"view", {1, 1}}, {"close-view", {1, 1}}, {"enlarge-view", {1, 1}},
        {"lesson", {1, 1}}};
    for (int line = 1; std::getline(in, text); ++line) {
        if (auto hash = text.find('#'); hash != std::string::npos) text.resize(hash);
        std::istringstream words(text);
        ScriptCommand c;
        c.line = line;
        if (!(words >> c.verb)) continue;
        for (std::string w; words >> w;) c.args.push_back(w);
        std::string where = path + ":" + std::to_string(line) + ": ";
        auto it = arity.find(c.verb);
        if (it == arity.end()) throw InputError(where + "unknown step '" + c.verb + "' (see app/window/input.cpp)");
        if (c.args.size() < it->second.first || c.args.size() > it->second.second)
            throw InputError(where + "'" + c.verb + "' takes " + std::to_string(it->second.first) +
                             (it->second.first == it->second.second ? "" : "-" + std::to_string(it->second.second)) +
                             " argument(s), got " + std::to_string(c.args.size()));
        // A number with its range checked in the type the window stores it in (whole numbers for
        // frames, pixels and counts: the runner reads them with stoi): never NaN, never a value
        // the runner cannot hold ("wait 99999999999" was an uncaught out_of_range, "ui-scale nan"
        // an ImGui assertion).
        // The argument is then rewritten in the form the runner reads back exactly (stoi of "1e3"
        // was 1 and of "0x10" 0 where stod had checked 1000 and 16; stof of "1e-50" threw
        // out_of_range): what was checked is what runs.
        auto number = [&](std::string& s, double lo = -1e6, double hi = 1e6, bool whole = false,
                          const char* what = "a number") {
            double v = std::nan("");
            try {
                size_t used = 0;
                v = std::stod(s, &used);
                if (used != s.size()) v = std::nan("");
            } catch (const std::exception&) {
            }
            if (!std::isfinite(v) || v < lo || v > hi || (whole && v != std::floor(v))) {
                char range[96];
                std::snprintf(range, sizeof range, "%s%s in [%g, %g]", whole ? "a whole number of " : "", what, lo, hi);
                throw InputError(where + c.verb + ": expected " + range + ", got '" + s + "'");
            }
            if (whole) {
                s = std::to_string(static_cast<long long>(v));
            } else {
                const float f = std::abs(v) < 1e-30 ? 0.0f : float(v);
                char text[32];
                std::snprintf(text, sizeof text, "%.9g", double(f));
                s = text;
            }
            return v;
        };
        auto onOff = [&](const std::string& s) {
            if (s != "on" && s != "off") throw InputError(where + "expected on or off, got '" + s + "'");
        };
        if (c.verb == "lesson") {
            static const std::set<std::string> actions = {"next", "previous", "restore", "check", "show-me"};
            if (!actions.count(c.args[0]))
                throw InputError(where + "lesson: expected next, previous, restore, check or show-me, got '" + c.args[0] + "'");
        } else if (c.verb == "key") {
            if (keyCode(c.args[0]) < 0) throw InputError(where + "unknown key '" + c.args[0] + "'");
            if (c.args.size() > 1 && modsCode(c.args[1]) < 0)
                throw InputError(where + "expected shift or ctrl, got '" + c.args[1] + "'");
        } else if (c.verb == "technique") {
            if (!findTechnique(c.args[0])) throw InputError(where + "unknown technique '" + c.args[0] + "'");
        } else if (c.verb == "scene") {
            std::string s = c.args[0];
            if (!(s.size() > 5 && (s.ends_with(".gltf") || s.ends_with(".glb"))) && !isRandomSceneName(s)) {
                try {
                    resolveScenePath(s);
                } catch (const InputError& e) {
                    throw InputError(where + e.what());
                }
            }
        } else if (c.verb == "drag") {
            if (buttonCode(c.args[0]) < 0) throw InputError(where + "expected left, right or middle, got '" + c.args[0] + "'");
            if (modsCode(c.args[1]) < 0) throw InputError(where + "expected none, shift or ctrl, got '" + c.args[1] + "'");
            for (size_t i = 2; i < 6; ++i) number(c.args[i], -kMaxScriptPixels, kMaxScriptPixels, false, "window units");
            number(c.args[6], 1, kMaxScriptFrames, true, "frames");
        } else if (c.verb == "drag-light") {
            for (size_t i = 0; i < 2; ++i) number(c.args[i], -kMaxScriptPixels, kMaxScriptPixels, false, "window units");
            number(c.args[2], 1, kMaxScriptFrames, true, "frames");
        } else if (c.verb == "reference") {
            if (c.args[0] != "reference" && c.args[0] != "raytraced")
                throw InputError(where + "reference: expected reference or raytraced, got '" + c.args[0] + "'");
        } else if (c.verb == "reference-rays") {
            number(c.args[0], 1, 65536, true, "rays");
        } else if (c.verb == "reference-samples") {
            number(c.args[0], 1, 65536, true, "samples");
        } else if (c.verb == "scroll") {
            number(c.args[0], -1000, 1000, false, "wheel steps");
        } else if (c.verb == "split-at") {
            number(c.args[0], 0, 1, false, "a fraction of the view's width");
        } else if (c.verb == "ui-scale") {
            number(c.args[0], 0.5, 4, false, "a UI scale");
        } else if (c.verb == "wait") {
            number(c.args[0], 0, kMaxScriptFrames, true, "frames");
        } else if (c.verb == "wait-reference") {
            if (!c.args.empty()) number(c.args[0], 1, kMaxScriptFrames, true, "frames");
        } else if (c.verb == "pick") {
            number(c.args[0], 0, 8191, true, "a pixel column");
            number(c.args[1], 0, 8191, true, "a pixel row");
        } else if (c.verb == "resize") {
            number(c.args[0], 64, 8192, true, "a window width");
            number(c.args[1], 64, 8192, true, "a window height");
        } else if (c.verb == "split") {
            if (c.args[0] != "off" && c.args[0] != "reference" && !findTechnique(c.args[0]))
                throw InputError(where + "split: expected off, reference or a technique, got '" + c.args[0] + "'");
        } else if (c.verb == "enlarge-view") {
            const std::vector<ViewInfo> views = listViews();
            if (c.args[0] != "off" && std::none_of(views.begin(), views.end(), [&](const ViewInfo& v) { return v.name == c.args[0]; })) {
                std::string names;
                for (const ViewInfo& v : views) names += ", " + v.name;
                throw InputError(where + "enlarge-view: expected off or a view (" + names.substr(2) + "), got '" + c.args[0] + "'");
            }
        } else if (c.verb == "error" || c.verb == "frustum" || c.verb == "help" || c.verb == "panel" || c.verb == "present" ||
                   c.verb == "views" || c.verb == "background" || c.verb == "accuracy") {
            onOff(c.args[0]);
        } else if (c.verb == "screenshot" || c.verb == "save-reference" || c.verb == "save-visibility" ||
                   c.verb == "save-accuracy") {
            checkPathName(where + c.verb, c.args[0]);
            std::filesystem::path parent = std::filesystem::path(c.args[0]).parent_path();
            std::error_code ec;
            if (!parent.empty() && !std::filesystem::is_directory(parent, ec))
                throw InputError(where + "screenshot: folder '" + parent.string() + "' does not exist");
        }
        script.push_back(c);
    }
    return script;
}

void Window::setScript(std::deque<ScriptCommand> script, const std::string& path) {
    script_ = std::move(script);
    scriptPath_ = path;
    scriptDone_ = false;
}

void Window::runScriptStep() {
    if (scriptDone_) return;
    if (scriptDrag_) {
        ScriptDrag& d = *scriptDrag_;
        ++d.step;
        glm::vec2 at = glm::mix(d.from, d.to, float(d.step) / float(d.frames));
        mouseMove(at);
        if (d.step >= d.frames) {
            mouseButton(d.button, false, d.mods, at);
            scriptDrag_.reset();
        }
        return;
    }
    if (scriptWait_ > 0) {
        --scriptWait_;
        return;
    }
    if (scriptWaitReference_ > 0) {
        --scriptWaitReference_;
        const bool refDone = !referenceNeeded() || ref().complete();
        const bool shownDone = !shownSource() || shownSource()->complete();
        if (!refDone || !shownDone || referenceVersion_ != version_ || interacting() || reduced_ || !imageComplete_) return;
        scriptWaitReference_ = 0;
    }
    // A `lesson check` waiting for the reference it reads (Window::finishPendingCheck): the next
    // command once it has run.
    if (lesson_ && (lesson_->checkPending() || lesson_->expectsPending())) return;
    while (!script_.empty()) {
        // save-visibility saves a complete frame: while the frame budget has it refined in slices
        // (or reduced), the script waits for it.
        if (script_.front().verb == "save-visibility" && (!imageComplete_ || reduced_)) return;
        ScriptCommand c = script_.front();
        script_.pop_front();
        const auto& a = c.args;
        auto on = [&](size_t i) { return a[i] == "on"; };
        if (c.verb == "key") key(keyCode(a[0]), a.size() > 1 ? modsCode(a[1]) : 0);
        else if (c.verb == "lesson") {
            lessonAction(a[0]);
            // The next command once the check (and the step's expectations) have run.
            if (lesson_ && (lesson_->checkPending() || lesson_->expectsPending())) return;
        }
        else if (c.verb == "technique") selectTechnique(a[0]);
        else if (c.verb == "scene") selectScene(a[0]);
        else if (c.verb == "param") setParam(a[0], a[1]);
        else if (c.verb == "reset-params") resetAllParams();
        else if (c.verb == "scroll") scroll(std::stod(a[0]));
        else if (c.verb == "pick") pickPixel(glm::ivec2(std::stoi(a[0]), std::stoi(a[1])));
        else if (c.verb == "split") {
            if (a[0] == "off") setCompare(WindowState::Compare::None);
            else if (a[0] == "reference") setCompare(WindowState::Compare::Reference);
            else setCompare(WindowState::Compare::Technique, a[0]);
        } else if (c.verb == "split-at") setSplit(std::stof(a[0]));
        else if (c.verb == "error") setErrorView(on(0));
        else if (c.verb == "frustum") state_.showFrustum = on(0);
        else if (c.verb == "ui-scale") setUiScale(std::stof(a[0]));
        else if (c.verb == "help") state_.showHelp = on(0);
        else if (c.verb == "present") setPresentation(on(0));
        else if (c.verb == "panel") state_.showPanel = on(0);
        else if (c.verb == "views") state_.showViews = on(0);
        else if (c.verb == "accuracy") state_.showAccuracy = on(0);
        else if (c.verb == "save-accuracy") saveAccuracyPoints(a[0]);
        else if (c.verb == "background") state_.backgroundReference = on(0);
        else if (c.verb == "view") openView(a[0]);
        else if (c.verb == "close-view") closeView(a[0]);
        else if (c.verb == "enlarge-view") enlargeView(a[0]);
        else if (c.verb == "reference-samples") setReferenceSamples(std::stoi(a[0]));
        else if (c.verb == "reference") setReferenceTechnique(a[0]);
        else if (c.verb == "reference-rays") setReferenceRays(std::stoi(a[0]));
        else if (c.verb == "save-reference" || c.verb == "save-visibility") {
            // The technique view showing a progressive reference saves that one (complete).
            const ProgressiveSource* source = c.verb == "save-reference" ? &ref() : shownSource();
            if (source && !(source->complete() && referenceVersion_ == version_)) {
                setStatus(scriptPath_ + ":" + std::to_string(c.line) + ": " + c.verb + ": the " +
                              (c.verb == "save-reference" ? state_.referenceTechnique : state_.technique) + " is not complete",
                          true);
                scriptFailed_ = true;
            } else {
                OutputSet outputs;
                writePFM(outputs.stage(a[0]), source ? source->visibility() : renderer_->visibility());
                outputs.commit();
            }
        }
        else if (c.verb == "resize") {
            glfwSetWindowSize(window_, std::stoi(a[0]), std::stoi(a[1]));
            scriptWait_ = 3;
            return;
        } else if (c.verb == "wait") {
            scriptWait_ = std::max(0, std::stoi(a[0]) - 1);
            return;
        } else if (c.verb == "wait-reference") {
            scriptWaitReference_ = a.empty() ? 100000 : std::max(1, std::stoi(a[0]));
            return;
        } else if (c.verb == "screenshot") {
            // One frame first, so panels that auto-resize have their size, then the shot.
            if (!shotArmed_) {
                shotArmed_ = true;
                script_.push_front(c);
            } else {
                shotArmed_ = false;
                screenshot(a[0]);
            }
            return;
        } else if (c.verb == "drag-light") {
            // A left drag that starts on the selected light's centre (where the window draws it).
            if (state_.lights.empty()) continue;
            auto centre = projectToWindow(state_.camera, aspect(), state_.lights[size_t(state_.lightIndex)].position,
                                          glm::vec2(layout_.technique.w, layout_.technique.h));
            if (centre) *centre += glm::vec2(layout_.technique.x, layout_.technique.y);  // window units
            if (!centre) {
                setStatus(scriptPath_ + ":" + std::to_string(c.line) + ": drag-light: the light is behind the camera", true);
                scriptFailed_ = true;
                continue;
            }
            ScriptDrag d;
            d.button = GLFW_MOUSE_BUTTON_LEFT;
            d.from = *centre;
            d.to = *centre + glm::vec2(std::stof(a[0]), std::stof(a[1]));
            d.frames = std::max(1, std::stoi(a[2]));
            pressOnLight_ = true;
            mouseButton(d.button, true, 0, d.from);
            pressOnLight_ = false;
            scriptDrag_ = d;
            return;
        } else if (c.verb == "drag") {
            ScriptDrag d;
            d.button = buttonCode(a[0]);
            d.mods = modsCode(a[1]);
            d.from = {std::stof(a[2]), std::stof(a[3])};
            d.to = {std::stof(a[4]), std::stof(a[5])};
            d.frames = std::max(1, std::stoi(a[6]));
            mouseButton(d.button, true, d.mods, d.from);
            scriptDrag_ = d;
            return;
        }
    }
    scriptDone_ = true;
}

}  // namespace shadowlab
