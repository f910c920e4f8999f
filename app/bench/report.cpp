// The bench's outputs as text: CSV rows, the Markdown report with the paper's numbers beside ours,
// and a LaTeX table (bench.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>

#include "bench/bench.h"
#include "graph/technique.h"
#include "scene/json_reader.h"

namespace shadowlab {

namespace {

std::string num(double v, const char* format = "%.9g") {
    if (std::isnan(v)) return "nan";
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    char text[64];
    std::snprintf(text, sizeof text, format, v);
    return text;
}

// Times are measurements, not results: 4 decimals (0.1 microsecond) is below their noise.
std::string ms(double v) { return num(v, "%.4f"); }

std::string paramsText(const nlohmann::json& parameters) {
    std::string out;
    for (const auto& [k, v] : parameters.items())
        out += (out.empty() ? "" : " ") + k + "=" + (v.is_string() ? v.get<std::string>() : v.is_number() ? num(v.get<double>()) : v.dump());
    return out;
}

std::string csvField(const std::string& s) {
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string out = "\"";
    for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
    return out + "\"";
}

std::string bytesText(size_t b) {
    char text[32];
    if (b >= (1u << 20)) std::snprintf(text, sizeof text, "%.1f MiB", double(b) / double(1 << 20));
    else std::snprintf(text, sizeof text, "%.1f KiB", double(b) / 1024.0);
    return text;
}

std::string label(const Measurement& m) {
    return m.setting.technique + (m.setting.sets.empty() ? "" : " " + m.setting.describe());
}

}  // namespace

const std::vector<std::string>& fixedCsvColumns() {
    static const std::vector<std::string> columns = {
        "scene", "light_size", "technique", "setting", "technique_ran", "params", "width", "height", "frames", "warmup",
        "clock", "shadow_ms", "fixed_ms", "total_ms", "rmse", "max_abs", "psnr", "ssim", "pixels", "penumbra_rmse",
        "penumbra_max_abs", "penumbra_psnr", "penumbra_ssim", "penumbra_pixels", "technique_memory_bytes",
        "memory_bytes", "kernel_clamped_fraction", "reference", "reference_key"};
    return columns;
}

std::vector<std::string> csvColumns(const std::vector<Measurement>& rows) {
    std::vector<std::string> columns = fixedCsvColumns();
    // Pass columns: the frame's fixed passes first, then each technique's passes in the order seen.
    std::vector<std::string> passes;
    for (const char* fixed : {"gbuffer", "shade"})
        for (const Measurement& m : rows)
            if (m.passMs.count(fixed) && std::find(passes.begin(), passes.end(), fixed) == passes.end()) passes.push_back(fixed);
    for (const Measurement& m : rows)
        for (const auto& [name, v] : m.passMs)
            if (std::find(passes.begin(), passes.end(), name) == passes.end()) passes.push_back(name);
    for (const std::string& p : passes) columns.push_back("ms." + p);
    // Counter columns: light 0's counters, in the order seen (empty where a row has none).
    std::vector<std::string> counters;
    for (const Measurement& m : rows)
        for (const auto& [name, v] : m.counters)
            if (std::find(counters.begin(), counters.end(), name) == counters.end()) counters.push_back(name);
    for (const std::string& c : counters) columns.push_back("counter." + c);
    return columns;
}

std::optional<double> numericValue(const Measurement& m, const std::string& c) {
    if (c == "light_size") return m.lightSize;
    if (c == "width") return m.width;
    if (c == "height") return m.height;
    if (c == "frames") return m.frames;
    if (c == "warmup") return m.warmup;
    if (c == "shadow_ms") return m.shadowMs;
    if (c == "fixed_ms") return m.fixedMs;
    if (c == "total_ms") return m.totalMs;
    if (c == "fps") return m.totalMs > 0 ? 1000.0 / m.totalMs : NAN;
    if (c == "rmse") return m.all.rmse;
    if (c == "max_abs") return m.all.maxAbs;
    if (c == "psnr") return m.all.psnr;
    if (c == "ssim") return m.all.ssim;
    if (c == "pixels") return double(m.all.pixels);
    if (c == "penumbra_rmse") return m.penumbra.rmse;
    if (c == "penumbra_max_abs") return m.penumbra.maxAbs;
    if (c == "penumbra_psnr") return m.penumbra.psnr;
    if (c == "penumbra_ssim") return m.penumbra.ssim;
    if (c == "penumbra_pixels") return double(m.penumbra.pixels);
    if (c == "technique_memory_bytes") return double(m.techniqueBytes);
    if (c == "memory_bytes") return double(m.memoryBytes);
    if (c == "kernel_clamped_fraction") {
        if (std::isnan(m.kernelClampedFraction)) return std::nullopt;
        return m.kernelClampedFraction;
    }
    if (c.rfind("ms.", 0) == 0) {
        auto it = m.passMs.find(c.substr(3));
        if (it != m.passMs.end()) return it->second;
    }
    if (c.rfind("counter.", 0) == 0) {
        auto it = m.counters.find(c.substr(8));
        if (it != m.counters.end()) return it->second;
    }
    return std::nullopt;
}

std::string csvValue(const Measurement& m, const std::string& c) {
    if (c == "scene") return m.scene;
    if (c == "technique") return m.setting.technique;
    if (c == "setting") return m.setting.describe();
    if (c == "technique_ran") return m.techniqueRan;
    if (c == "params") return paramsText(m.parameters);
    if (c == "clock") return m.clock;
    if (c == "reference") return m.referenceDesc;
    if (c == "reference_key") return m.referenceKey;
    if (c == "width" || c == "height" || c == "frames" || c == "warmup" || c == "pixels" || c == "penumbra_pixels" ||
        c == "technique_memory_bytes" || c == "memory_bytes")
        return num(*numericValue(m, c), "%.0f");
    if (c.find("_ms") != std::string::npos || c.rfind("ms.", 0) == 0) {
        std::optional<double> v = numericValue(m, c);
        return v ? ms(*v) : "";
    }
    std::optional<double> v = numericValue(m, c);
    return v ? num(*v) : "";
}

std::string toCsv(const std::vector<Measurement>& rows) {
    const std::vector<std::string> columns = csvColumns(rows);
    std::string out;
    for (size_t i = 0; i < columns.size(); ++i) out += (i ? "," : "") + columns[i];
    out += "\n";
    for (const Measurement& m : rows) {
        for (size_t i = 0; i < columns.size(); ++i) out += (i ? "," : "") + csvField(csvValue(m, columns[i]));
        out += "\n";
    }
    return out;
}

double errorOf(const Measurement& m, const std::string& metric) {
    return metric == "1-ssim" ? 1.0 - m.all.ssim : m.all.rmse;
}

std::string benchReportMarkdown(const BenchSpec& spec, const std::vector<Measurement>& rows, const RunInfo& info,
                                const std::string& chartPath) {
    std::ostringstream o;
    o << "# " << spec.title << "\n\n";
    if (!spec.reproduces.empty()) o << spec.reproduces << "\n\n";
    o << "Made by `" ;
    for (size_t i = 0; i < info.commandLine.size(); ++i) o << (i ? " " : "") << info.commandLine[i];
    o << "` on " << info.date << ".\n\n";
    o << "| | |\n|---|---|\n";
    o << "| program | shadowlab " << info.version << " |\n";
    o << "| GL renderer | " << info.glRenderer << " |\n";
    o << "| CPU | " << info.cpu << " |\n";
    o << "| LP_NUM_THREADS | " << info.lpNumThreads << " |\n";
    if (!info.loadAverage.empty())
        o << "| load average at the start (1, 5, 15 min) | " << info.loadAverage
          << " (other processes on the cores make times vary; errors do not) |\n";
    if (!rows.empty()) {
        o << "| size | " << rows[0].width << "x" << rows[0].height << " |\n";
        o << "| frames | " << rows[0].warmup << " warm-up, then the median of " << rows[0].frames
          << " timed frames, every pass run every frame |\n";
        o << "| clock | " << rows[0].clock << " |\n";
        o << "| reference | " << rows[0].referenceDesc << " (cached by scene, size, light and settings) |\n";
    }
    o << "| run time | " << num(info.seconds, "%.1f") << " s |\n\n";
    if (!chartPath.empty())
        o << "![" << (spec.errorMetric == "1-ssim" ? "1 - SSIM" : "RMSE") << " against shadow time](" << chartPath
          << ")\n\n";
    o << "`shadow_ms` is the technique's passes (what speed claims compare); `fixed_ms` the G-buffer and shading, "
         "the same for every technique. Errors are on the visibility buffer against the reference; the penumbra "
         "columns only count pixels where the reference is strictly between 0 and 1.\n\n";

    std::vector<std::string> scenes;
    for (const Measurement& m : rows)
        if (std::find(scenes.begin(), scenes.end(), m.scene) == scenes.end()) scenes.push_back(m.scene);
    for (const std::string& scene : scenes) {
        o << "## " << scene << "\n\n";
        o << "| light size | technique | setting | shadow ms | fixed ms | RMSE | max abs | PSNR dB | SSIM | penumbra RMSE | "
             "penumbra SSIM | memory |\n";
        o << "|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
        for (const Measurement& m : rows) {
            if (m.scene != scene) continue;
            o << "| " << num(m.lightSize, "%g") << " | " << m.setting.technique
              << (m.techniqueRan != m.setting.technique && !m.techniqueRan.empty() ? " (ran " + m.techniqueRan + ")" : "")
              << " | " << m.setting.describe() << " | " << num(m.shadowMs, "%.2f") << " | " << num(m.fixedMs, "%.2f")
              << " | " << num(m.all.rmse, "%.4f") << " | " << num(m.all.maxAbs, "%.3f") << " | "
              << num(m.all.psnr, "%.2f") << " | " << num(m.all.ssim, "%.4f") << " | " << num(m.penumbra.rmse, "%.4f")
              << " | " << num(m.penumbra.ssim, "%.4f") << " | " << bytesText(m.techniqueBytes) << " |\n";
        }
        o << "\n";
    }

    if (spec.paper.present) {
        const PaperSpec& p = spec.paper;
        o << "## The paper's numbers and ours\n\n";
        o << "**" << p.citation << "**" << (p.what.empty() ? "" : ": " + p.what) << "\n\n";
        if (!p.machine.empty()) o << "The paper's machine: " << p.machine << ". Ours: " << info.glRenderer << ", " << info.cpu << ".\n\n";
        if (!p.note.empty()) o << p.note << "\n\n";
        // Each paper row against each of our rows it names (one per scene and light size that matches).
        auto ours = [&](const PaperRow& row) {
            std::vector<const Measurement*> out;
            for (const Measurement& m : rows)
                if (paperRowMatches(row, m.scene, m.lightSize, m.setting.technique, m.parameters)) out.push_back(&m);
            return out;
        };
        const PaperRow* base = nullptr;
        for (const PaperRow& row : p.rows)
            if (row.label == p.baseline) base = &row;
        if (p.compare == "ratio")
            o << "The machines differ, so each value is given as a ratio to the row \"" << p.baseline
              << "\" of the same source (paper to paper, ours to ours, on the same scene and light size).\n\n";
        o << "| row | column | maps to | scene | paper | ours |" << (p.compare == "ratio" ? " paper ratio | our ratio |" : " ours / paper |") << "\n";
        o << "|---|---|---|---|---:|---:|" << (p.compare == "ratio" ? "---:|---:|" : "---:|") << "\n";
        for (const PaperRow& row : p.rows) {
            std::vector<const Measurement*> matches = ours(row);
            for (const auto& [column, paperValue] : row.values) {
                std::string csvColumn;
                for (const auto& [c, target] : p.columns)
                    if (c == column) csvColumn = target;
                double paperBase = NAN;
                if (base)
                    for (const auto& [c, v] : base->values)
                        if (c == column) paperBase = v;
                if (matches.empty()) {
                    o << "| " << row.label << " | " << column << " | `" << csvColumn << "` | " << (row.scene.empty() ? "-" : row.scene)
                      << " | " << num(paperValue, "%g") << " | not run ("
                      << (isPlannedTechnique(row.technique) && !findTechnique(row.technique) ? row.technique + " has not landed yet" : "no matching setting")
                      << ") |" << (p.compare == "ratio" ? " | |" : " |") << "\n";
                    continue;
                }
                for (const Measurement* m : matches) {
                    std::optional<double> v = numericValue(*m, csvColumn);
                    o << "| " << row.label << " | " << column << " | `" << csvColumn << "` | " << m->scene << " | "
                      << num(paperValue, "%g") << " | " << (v ? num(*v, "%.4g") : "-") << " |";
                    if (p.compare == "ratio") {
                        double ourBase = NAN;
                        if (base)
                            for (const Measurement& bm : rows)
                                if (bm.scene == m->scene && bm.lightSize == m->lightSize &&
                                    paperRowMatches(*base, bm.scene, bm.lightSize, bm.setting.technique, bm.parameters))
                                    if (auto bv = numericValue(bm, csvColumn)) ourBase = *bv;
                        o << " " << num(paperValue / paperBase, "%.3f") << " | " << (v ? num(*v / ourBase, "%.3f") : "-") << " |";
                    } else {
                        o << " " << (v ? num(*v / paperValue, "%.3f") : "-") << " |";
                    }
                    o << "\n";
                }
            }
        }
        o << "\n";
    }
    return o.str();
}

std::string benchLatexTable(const BenchSpec& spec, const std::vector<Measurement>& rows) {
    auto esc = [](const std::string& s) {
        std::string out;
        for (char c : s) {
            if (c == '_' || c == '%' || c == '&' || c == '#') out += '\\';
            out += c;
        }
        return out;
    };
    std::ostringstream o;
    o << "% " << esc(spec.title) << " (shadowlab bench)\n";
    o << "\\begin{tabular}{llrrrrr}\n\\hline\n";
    o << "Scene & Technique (setting) & Shadow ms & RMSE & PSNR (dB) & SSIM & Penumbra RMSE \\\\\n\\hline\n";
    for (const Measurement& m : rows)
        o << esc(m.scene) << " & " << esc(label(m)) << " & " << num(m.shadowMs, "%.2f") << " & " << num(m.all.rmse, "%.4f")
          << " & " << num(m.all.psnr, "%.2f") << " & " << num(m.all.ssim, "%.4f") << " & " << num(m.penumbra.rmse, "%.4f")
          << " \\\\\n";
    o << "\\hline\n\\end{tabular}\n";
    return o.str();
}

}  // namespace shadowlab
