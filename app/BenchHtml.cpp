// The HTML bench report: one self-contained page (inline CSS, SVG and base64 PNGs) that opens
// anywhere, including a farm's artefact browser with no network.
#include "app/BenchResult.h"
#include "metrics/Heatmap.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace fp::app {

namespace {

std::string escape(const std::string& s) {
    std::string out;
    for (char c : s) {
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

std::string ms(double seconds) { return fmt::format("{:.2f}", seconds * 1e3); }

std::string unitRate(double perSecond, const std::string& unit) {
    const char* prefix = "";
    double v = perSecond;
    if (v >= 1e9) v /= 1e9, prefix = "G";
    else if (v >= 1e6) v /= 1e6, prefix = "M";
    else if (v >= 1e3) v /= 1e3, prefix = "k";
    return fmt::format("{:.2f} {}{}/s", v, prefix, unit);
}

// The heat map's scale beside it: the colour map as a CSS gradient from 0 to the heat scale.
std::string heatScaleBar(double scale) {
    std::string stops;
    for (const auto& c : heatColorStops())
        stops += fmt::format(", rgb({},{},{})", int(std::lround(c[0] * 255)),
                             int(std::lround(c[1] * 255)), int(std::lround(c[2] * 255)));
    return fmt::format(
        R"~(<div class="scale" data-heat-scale="{:.6g}"><span>0</span>)~"
        R"~(<span class="bar" style="background:linear-gradient(to right{})"></span>)~"
        R"~(<span>{:.4g}</span> |error|</div>)~",
        scale, stops, scale);
}

// "Nice" tick spacing for an axis covering [lo, hi].
double tickStep(double lo, double hi) {
    const double span = std::max(hi - lo, 1e-12);
    const double raw = span / 5.0, mag = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 5.0, 10.0})
        if (raw <= m * mag) return m * mag;
    return 10.0 * mag;
}

// A sequence: the first error's RMSE on each frame (x: frame, y: RMSE), a line per setting, so
// the denoiser's temporal accumulation shows as a falling line.
std::string sequencePlot(const BenchResult& r) {
    double lo = 1e300, hi = -1e300;
    std::size_t n = 0;
    int lines = 0;
    for (const auto& s : r.settings)
        if (!s.errors.empty() && s.errors.front().rmseByFrame.size() >= 2) {
            ++lines;
            for (double v : s.errors.front().rmseByFrame)
                lo = std::min(lo, v), hi = std::max(hi, v);
            n = std::max(n, s.errors.front().rmseByFrame.size());
        }
    if (n < 2)
        return {};
    // The legend goes under the axes, a line per setting (labels are long).
    const double W = 640, L = 70, R = 20, T = 20, B = 45, plotH = 240;
    const double H = T + plotH + B + 16.0 * lines;
    const double step = tickStep(lo, hi);
    lo = std::floor(lo / step) * step;
    hi = std::max(std::ceil(hi / step) * step, lo + step);
    auto X = [&](std::size_t i) { return L + (W - L - R) * double(i) / double(n - 1); };
    auto Y = [&](double v) { return T + plotH - plotH * (v - lo) / (hi - lo); };
    std::ostringstream svg;
    svg << fmt::format(R"(<svg id="sequence" width="{}" height="{}" viewBox="0 0 {} {}" )"
                       R"(xmlns="http://www.w3.org/2000/svg" font-family="sans-serif">)",
                       W, H, W, H);
    const int ticks = int(std::lround((hi - lo) / step));
    for (int k = 0; k <= ticks; ++k) {
        const double v = lo + k * step;
        svg << fmt::format(R"(<line x1="{}" x2="{}" y1="{:.1f}" y2="{:.1f}" stroke="#ddd"/>)"
                           R"(<text x="{}" y="{:.1f}" font-size="11" text-anchor="end">{:.4g}</text>)",
                           L, W - R, Y(v), Y(v), L - 6, Y(v) + 4, v);
    }
    for (std::size_t i = 0; i < n; ++i)
        svg << fmt::format(R"(<text x="{:.1f}" y="{}" font-size="11" text-anchor="middle">{}</text>)",
                           X(i), T + plotH + 16, i < r.frames.size() ? r.frames[i] : int(i));
    svg << fmt::format(R"(<text x="{}" y="{}" font-size="12" text-anchor="middle">frame</text>)"
                       R"~(<text x="14" y="{}" font-size="12" transform="rotate(-90 14 {})" )~"
                       R"~(text-anchor="middle">RMSE</text>)~",
                       (L + W - R) / 2, T + plotH + 34, T + plotH / 2, T + plotH / 2);
    static const char* kColours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728",
                                     "#9467bd", "#8c564b", "#e377c2", "#7f7f7f"};
    int line = 0;
    for (const auto& s : r.settings) {
        if (s.errors.empty() || s.errors.front().rmseByFrame.size() < 2)
            continue;
        const char* colour = kColours[line % 8];
        std::string points;
        const auto& v = s.errors.front().rmseByFrame;
        for (std::size_t i = 0; i < v.size(); ++i)
            points += fmt::format("{:.1f},{:.1f} ", X(i), Y(v[i]));
        svg << fmt::format(R"(<polyline fill="none" stroke="{}" stroke-width="2" points="{}"/>)"
                           R"(<text x="{}" y="{}" font-size="11" fill="{}">{} ({:.4g} → {:.4g})</text>)",
                           colour, points, L, T + plotH + B + 16 * line + 10, colour,
                           escape(s.label), v.front(), v.back());
        ++line;
    }
    svg << "</svg>";
    return svg.str();
}

// Time (x) against error (y), Pareto front joined; or frame time bars when nothing has an error.
std::string plot(const BenchResult& r) {
    const double W = 640, H = 360, L = 70, R = 20, T = 20, B = 50;
    std::ostringstream svg;
    svg << fmt::format(R"(<svg id="plot" xmlns="http://www.w3.org/2000/svg" width="{}" height="{}" )"
                       R"(viewBox="0 0 {} {}" role="img">)",
                       W, H, W, H);
    std::vector<const BenchSetting*> pts;
    for (const auto& s : r.settings)
        if (s.hasError()) pts.push_back(&s);
    if (pts.empty()) {
        // Bars: frame median per setting.
        double top = 0;
        for (const auto& s : r.settings) top = std::max(top, s.frame.max);
        top = top > 0 ? top : 1;
        const double bh = std::min(40.0, (H - T - B) / std::max<std::size_t>(1, r.settings.size()));
        for (std::size_t i = 0; i < r.settings.size(); ++i) {
            const auto& s = r.settings[i];
            const double y = T + i * bh;
            const double w = (W - L - R - 160) * s.frame.median / top;
            svg << fmt::format(R"(<rect x="{}" y="{}" width="{:.1f}" height="{:.1f}" fill="#4a7fb0"/>)",
                               L + 150, y + 4, w, bh - 8);
            svg << fmt::format(R"(<text x="{}" y="{:.1f}" font-size="12" text-anchor="end">{}</text>)",
                               L + 140, y + bh / 2 + 4, escape(s.label));
            svg << fmt::format(R"(<text x="{:.1f}" y="{:.1f}" font-size="12">{} ms</text>)",
                               L + 156 + w, y + bh / 2 + 4, ms(s.frame.median));
        }
        svg << "</svg>";
        return svg.str();
    }
    double x0 = 1e300, x1 = -1e300, y0 = 0, y1 = -1e300;
    for (const auto* s : pts) {
        x0 = std::min(x0, s->frame.median * 1e3);
        x1 = std::max(x1, s->frame.median * 1e3);
        y1 = std::max(y1, s->error());
    }
    const double pad = std::max((x1 - x0) * 0.1, 0.05 * std::max(x1, 1e-3));
    x0 = std::max(0.0, x0 - pad);
    x1 += pad;
    y1 = y1 > 0 ? y1 * 1.15 : 1.0;
    auto X = [&](double v) { return L + (v - x0) / (x1 - x0) * (W - L - R); };
    auto Y = [&](double v) { return H - B - (v - y0) / (y1 - y0) * (H - T - B); };
    svg << fmt::format(R"(<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="#333"/>)", L, H - B, W - R, H - B);
    svg << fmt::format(R"(<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="#333"/>)", L, T, L, H - B);
    const double xStep = tickStep(x0, x1), yStep = tickStep(y0, y1);
    for (double t = std::ceil(x0 / xStep) * xStep; t <= x1; t += xStep)
        svg << fmt::format(R"(<text x="{:.1f}" y="{}" font-size="11" text-anchor="middle">{:g}</text>)",
                           X(t), H - B + 16, t);
    for (double t = 0; t <= y1; t += yStep)
        svg << fmt::format(R"(<text x="{}" y="{:.1f}" font-size="11" text-anchor="end">{:.3g}</text>)"
                           R"(<line x1="{}" x2="{}" y1="{:.1f}" y2="{:.1f}" stroke="#ddd"/>)",
                           L - 6, Y(t) + 4, t, L, W - R, Y(t), Y(t));
    svg << fmt::format(R"(<text x="{}" y="{}" font-size="12" text-anchor="middle">frame time, ms )"
                       R"((median of {} runs)</text>)",
                       (L + W - R) / 2, H - 12, r.runs);
    svg << fmt::format(R"~(<text x="16" y="{}" font-size="12" text-anchor="middle" )~"
                       R"~(transform="rotate(-90 16 {})">RMSE against truth</text>)~",
                       (T + H - B) / 2, (T + H - B) / 2);
    std::vector<const BenchSetting*> front;
    for (const auto* s : pts)
        if (s->pareto) front.push_back(s);
    std::sort(front.begin(), front.end(),
              [](auto* a, auto* b) { return a->frame.median < b->frame.median; });
    std::string line;
    for (const auto* s : front) line += fmt::format("{:.1f},{:.1f} ", X(s->frame.median * 1e3), Y(s->error()));
    if (front.size() > 1)
        svg << R"(<polyline fill="none" stroke="#d0702a" stroke-width="2" points=")" << line << "\"/>";
    for (const auto* s : pts) {
        const double px = X(s->frame.median * 1e3), py = Y(s->error());
        const std::size_t index = std::size_t(s - r.settings.data()) + 1;
        svg << fmt::format(R"(<circle cx="{:.1f}" cy="{:.1f}" r="5" fill="{}"><title>{}: {} ms, )"
                           R"(RMSE {:.4g}</title></circle>)",
                           px, py, s->pareto ? "#d0702a" : "#4a7fb0", escape(s->label),
                           ms(s->frame.median), s->error());
        svg << fmt::format(R"(<text x="{:.1f}" y="{:.1f}" font-size="11">{}</text>)", px + 7, py - 7,
                           index);
    }
    svg << "</svg>";
    return svg.str();
}

// Each error measure's method (the passes its source depends on) as one point per setting: the
// method's time (x) against its RMSE (y), a colour per measure; on the GPU, Lumen's budgets for
// GI and reflections at 1080p on current consoles, 4 ms ("High") and 8 ms ("Epic"), as lines.
std::string methodsPlot(const BenchResult& r) {
    struct Point {
        const BenchSetting* setting;
        const ErrorNodeResult* error;
    };
    std::vector<Point> pts;
    std::vector<std::string> measures;
    for (const auto& s : r.settings)
        for (const auto& e : s.errors)
            if (!e.methodPasses.empty() && e.metrics.count("rmse")) {
                pts.push_back({&s, &e});
                if (std::find(measures.begin(), measures.end(), e.name) == measures.end())
                    measures.push_back(e.name);
            }
    if (pts.empty()) return "";
    const bool gpu = r.device == "cuda";
    const double W = 640, L = 70, R = 20, T = 20, B = 50, plotH = 290;
    const double H = T + plotH + B + 16.0 * double(measures.size());
    double x1 = gpu ? 9.0 : 0.0, y1 = 0;
    for (const auto& p : pts) {
        x1 = std::max(x1, p.error->methodSeconds * 1e3);
        y1 = std::max(y1, p.error->metrics.at("rmse"));
    }
    x1 = x1 > 0 ? x1 * 1.1 : 1.0;
    y1 = y1 > 0 ? y1 * 1.15 : 1.0;
    auto X = [&](double v) { return L + v / x1 * (W - L - R); };
    auto Y = [&](double v) { return T + plotH - v / y1 * plotH; };
    std::ostringstream svg;
    svg << fmt::format(R"(<svg id="methods" xmlns="http://www.w3.org/2000/svg" width="{}" height="{}" )"
                       R"(viewBox="0 0 {} {}" role="img" font-family="sans-serif">)",
                       W, H, W, H);
    svg << fmt::format(R"(<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="#333"/>)", L, T + plotH, W - R, T + plotH);
    svg << fmt::format(R"(<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="#333"/>)", L, T, L, T + plotH);
    const double xStep = tickStep(0, x1), yStep = tickStep(0, y1);
    for (double t = 0; t <= x1; t += xStep)
        svg << fmt::format(R"(<text x="{:.1f}" y="{}" font-size="11" text-anchor="middle">{:g}</text>)",
                           X(t), T + plotH + 16, t);
    for (double t = 0; t <= y1; t += yStep)
        svg << fmt::format(R"(<text x="{}" y="{:.1f}" font-size="11" text-anchor="end">{:.3g}</text>)"
                           R"(<line x1="{}" x2="{}" y1="{:.1f}" y2="{:.1f}" stroke="#ddd"/>)",
                           L - 6, Y(t) + 4, t, L, W - R, Y(t), Y(t));
    if (gpu)
        for (const auto& [budget, name] : {std::pair{4.0, "Lumen High, 4 ms"}, std::pair{8.0, "Lumen Epic, 8 ms"}})
            svg << fmt::format(R"(<line class="budget" x1="{0:.1f}" x2="{0:.1f}" y1="{1}" y2="{2}" )"
                               R"(stroke="#b03a3a" stroke-dasharray="5 4"/>)"
                               R"(<text x="{3:.1f}" y="{4}" font-size="11" fill="#b03a3a">{5}</text>)",
                               X(budget), T, T + plotH, X(budget) + 4, T + 12, name);
    svg << fmt::format(R"(<text x="{}" y="{}" font-size="12" text-anchor="middle">the method's )"
                       R"(passes, ms{} (median of {} runs)</text>)",
                       (L + W - R) / 2, T + plotH + 34, gpu ? " on the GPU" : "", r.runs);
    svg << fmt::format(R"~(<text x="16" y="{}" font-size="12" text-anchor="middle" )~"
                       R"~(transform="rotate(-90 16 {})">RMSE against truth</text>)~",
                       T + plotH / 2, T + plotH / 2);
    static const char* kColors[] = {"#4a7fb0", "#d0702a", "#6aa84f", "#8e63b5", "#b03a3a", "#555"};
    for (const auto& p : pts) {
        const std::size_t m = std::size_t(std::find(measures.begin(), measures.end(), p.error->name) -
                                          measures.begin());
        const double px = X(p.error->methodSeconds * 1e3), py = Y(p.error->metrics.at("rmse"));
        svg << fmt::format(R"(<circle class="method" cx="{:.1f}" cy="{:.1f}" r="5" fill="{}"><title>{} )"
                           R"(at {}: {} ms ({}), RMSE {:.4g}</title></circle>)",
                           px, py, kColors[m % 6], escape(p.error->name), escape(p.setting->label),
                           ms(p.error->methodSeconds), escape(fmt::format("{}", fmt::join(p.error->methodPasses, ", "))),
                           p.error->metrics.at("rmse"));
        svg << fmt::format(R"(<text x="{:.1f}" y="{:.1f}" font-size="11">{}</text>)", px + 7, py - 7,
                           std::size_t(p.setting - r.settings.data()) + 1);
    }
    for (std::size_t m = 0; m < measures.size(); ++m)
        svg << fmt::format(R"(<circle cx="{}" cy="{}" r="5" fill="{}"/><text x="{}" y="{}" font-size="12">{}</text>)",
                           L + 6, T + plotH + B + 16 * m + 4, kColors[m % 6], L + 16,
                           T + plotH + B + 16 * m + 8, escape(measures[m]));
    svg << "</svg>";
    return svg.str();
}

// One error_measure taken apart, setting by setting: a diverging stacked bar of the steps'
// shares of the squared error (a negative share, a step that cancels others, left of 0), then
// the table of step RMSE, bias and share and the sentence.
std::string decompositionSection(const BenchResult& r, const std::string& errorName) {
    static const char* kColors[] = {"#4a7fb0", "#d0702a", "#6aa84f", "#8e63b5"};
    std::vector<std::pair<const BenchSetting*, const ErrorDecompositionResult*>> rows;
    for (const auto& s : r.settings)
        for (const auto& e : s.errors)
            if (e.name == errorName && e.decomposition)
                rows.push_back({&s, &*e.decomposition});
    if (rows.empty())
        return "";
    double lo = 0, hi = 1;
    for (const auto& [s, d] : rows) {
        double neg = 0, pos = 0;
        for (const auto& step : d->steps)
            (step.share < 0 ? neg : pos) += step.share;
        lo = std::min(lo, neg);
        hi = std::max(hi, pos);
    }
    const double W = 760, L = 220, R = 20, T = 28, rowH = 28, B = 36;
    const double H = T + rowH * double(rows.size()) + B;
    auto X = [&](double v) { return L + (v - lo) / (hi - lo) * (W - L - R); };
    std::ostringstream h;
    h << "<h3>" << escape(errorName) << "</h3>\n";
    h << fmt::format(R"(<svg class="decomposition" xmlns="http://www.w3.org/2000/svg" width="{}" )"
                     R"(height="{}" viewBox="0 0 {} {}" role="img">)",
                     W, H, W, H);
    // Legend.
    double lx = L;
    for (std::size_t k = 0; k < rows.front().second->steps.size() && k < 4; ++k) {
        const std::string& name = rows.front().second->steps[k].name;
        h << fmt::format(R"(<rect x="{:.1f}" y="6" width="12" height="12" fill="{}"/>)"
                         R"(<text x="{:.1f}" y="16" font-size="12">{}</text>)",
                         lx, kColors[k], lx + 16, escape(name));
        lx += 28 + 7.0 * double(name.size());
    }
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const auto& [s, d] = rows[i];
        const double y = T + rowH * double(i);
        h << fmt::format(R"(<text x="{}" y="{:.1f}" font-size="12" text-anchor="end">{}</text>)",
                         L - 8, y + rowH / 2 + 4, escape(s->label));
        double pos = 0, neg = 0;
        for (std::size_t k = 0; k < d->steps.size() && k < 4; ++k) {
            const auto& step = d->steps[k];
            double& at = step.share < 0 ? neg : pos;
            const double a = X(at), b = X(at + step.share);
            at += step.share;
            h << fmt::format(R"(<rect x="{:.1f}" y="{:.1f}" width="{:.1f}" height="{:.1f}" )"
                             R"(fill="{}"><title>{}: {:.1f} % of the squared error, RMSE {:.4g}, )"
                             R"(bias {:+.4g}</title></rect>)",
                             std::min(a, b), y + 4, std::abs(b - a), rowH - 8, kColors[k],
                             escape(step.name), 100.0 * step.share, step.rmse, step.bias);
        }
    }
    const double axisY = T + rowH * double(rows.size());
    h << fmt::format(R"(<line x1="{:.1f}" x2="{:.1f}" y1="{}" y2="{}" stroke="#333"/>)", X(0),
                     X(0), T, axisY);
    const double step = tickStep(lo, hi);
    for (double t = std::ceil(lo / step) * step; t <= hi + 1e-9; t += step)
        h << fmt::format(R"(<text x="{:.1f}" y="{:.1f}" font-size="11" text-anchor="middle">)"
                         R"({:.0f} %</text>)",
                         X(t), axisY + 16, std::abs(t) < 1e-9 ? 0.0 : 100.0 * t);
    h << fmt::format(R"(<text x="{:.1f}" y="{:.1f}" font-size="12" text-anchor="middle">share )"
                     R"(of the squared error against {}</text>)",
                     (L + W - R) / 2, H - 4, escape(rows.front().second->steps.back().to));
    h << "</svg>\n";
    h << "<table><tr><th class=\"l\">setting</th><th class=\"l\">step</th><th>RMSE</th>"
         "<th>bias</th><th>share</th><th class=\"l\">from → to</th></tr>\n";
    for (const auto& [s, d] : rows) {
        double biases = 0;
        for (const auto& step : d->steps) {
            h << "<tr><td class=\"l\">" << escape(s->label) << "</td><td class=\"l\">"
              << escape(step.name) << "</td>"
              << fmt::format("<td>{:.4g}</td><td>{:+.4g}</td><td>{:.1f} %</td>", step.rmse,
                             step.bias, 100.0 * step.share)
              << "<td class=\"l\">" << escape(step.from) << " → " << escape(step.to)
              << "</td></tr>\n";
            biases += step.bias;
        }
        h << "<tr><td class=\"l\">" << escape(s->label) << "</td><td class=\"l\"><b>total</b></td>"
          << fmt::format("<td>{:.4g}</td><td>{:+.4g} (steps: {:+.4g})</td><td>100 %</td>", d->rmse,
                         d->bias, biases)
          << "<td class=\"l\">" << escape(d->sentence) << "</td></tr>\n";
    }
    h << "</table>\n";
    return h.str();
}

// What the plan said about the error measures (a truth of another definition than the judged
// pass's, app/TruthDefinitions.h), once per measure and message, with the settings it holds for
// when not all of them.
std::string measureWarnings(const BenchResult& r) {
    std::vector<std::pair<std::string, std::string>> order;  // (measure, message)
    std::map<std::pair<std::string, std::string>, std::vector<std::string>> settings;
    for (const auto& s : r.settings)
        for (const auto& e : s.errors)
            for (const auto& w : e.warnings) {
                auto& labels = settings[{e.name, w}];
                if (labels.empty()) order.push_back({e.name, w});
                labels.push_back(s.label);
            }
    if (order.empty()) return "";
    std::ostringstream h;
    h << "<div class=\"warnings\"><p class=\"meta\"><b>Warnings</b> about the error measures "
         "(also said on the command line):</p><ul>\n";
    for (const auto& key : order) {
        const auto& labels = settings[key];
        h << "<li class=\"warning\"><b>" << escape(key.first) << "</b>: " << escape(key.second);
        if (labels.size() < r.settings.size())
            h << " <span class=\"meta\">(" << escape(fmt::format("{}", fmt::join(labels, "; ")))
              << ")</span>";
        h << "</li>\n";
    }
    h << "</ul></div>\n";
    return h.str();
}

}  // namespace

std::string benchHtml(const BenchResult& r) {
    std::ostringstream h;
    h << R"(<!DOCTYPE html><html lang="en"><head><meta charset="utf-8"><title>framepass bench</title>
<style>
body{font-family:system-ui,sans-serif;margin:24px;color:#222;max-width:1200px}
table{border-collapse:collapse;margin:12px 0;font-size:13px}td,th{border:1px solid #ccc;padding:4px 8px;text-align:right}
th{background:#f2f2f2}td.l,th.l{text-align:left}tr.front td{background:#fff4ea}
figure{display:inline-block;margin:0 12px 12px 0}figcaption{font-size:12px;color:#555}
img{image-rendering:pixelated;border:1px solid #ccc;max-width:380px}
.meta{color:#555;font-size:13px}
.warnings li{color:#8a4b00;font-size:13px;margin:2px 0}
.scale{font-size:12px;color:#555;display:flex;align-items:center;gap:4px;margin-top:2px}
.scale .bar{display:inline-block;width:160px;height:10px;border:1px solid #ccc}
</style></head><body>
)";
    h << "<h1>framepass bench</h1>\n";
    const std::string frames =
        r.frames.size() > 1
            ? fmt::format("frames {} in order with history (times per frame, errors on frame {})",
                          fmt::join(r.frames, ","), r.frame)
            : fmt::format("frame {}", r.frame);
    h << fmt::format("<p class=\"meta\">config <code>{}</code> · capture <code>{}</code> · {} "
                     "· {}×{} · median of {} runs after {} warm-up · {} threads</p>\n",
                     escape(r.config), escape(r.capture), frames, r.extent.width, r.extent.height,
                     r.runs, r.warmup, r.threads);

    // The table: one row per setting.
    std::vector<std::string> passNames;
    for (const auto& s : r.settings)
        for (const auto& p : s.passes)
            if (std::find(passNames.begin(), passNames.end(), p.name) == passNames.end())
                passNames.push_back(p.name);
    const bool anyError = std::any_of(r.settings.begin(), r.settings.end(),
                                      [](const BenchSetting& s) { return s.hasError(); });
    // FLIP where the error measure takes it (its flip parameter).
    const bool anyFlip = std::any_of(r.settings.begin(), r.settings.end(), [](const BenchSetting& s) {
        return s.hasError() && s.errors.front().metrics.count("flip");
    });
    h << "<h2>Speed against error</h2>\n<table id=\"table\"><tr><th>#</th><th class=\"l\">setting</th>"
         "<th>frame ms (min–max)</th>";
    for (const auto& n : passNames) h << "<th>" << escape(n) << " ms</th>";
    if (anyError)
        h << "<th>RMSE</th><th>relMSE</th><th>SMAPE</th>" << (anyFlip ? "<th>FLIP</th>" : "")
          << "<th>reference noise</th><th>Pareto</th>";
    h << "</tr>\n";
    for (const auto& s : r.settings) {
        h << (s.pareto ? "<tr class=\"front\">" : "<tr>") << "<td>" << (&s - r.settings.data()) + 1
          << "</td><td class=\"l\">" << escape(s.label)
          << "</td>"
          << fmt::format("<td>{} ({}–{})</td>", ms(s.frame.median), ms(s.frame.min), ms(s.frame.max));
        for (const auto& n : passNames) {
            auto it = std::find_if(s.passes.begin(), s.passes.end(),
                                   [&](const PassTiming& p) { return p.name == n; });
            h << "<td>" << (it == s.passes.end() ? "culled" : ms(it->seconds.median)) << "</td>";
        }
        if (anyError) {
            if (s.hasError()) {
                const auto& m = s.errors.front().metrics;
                auto get = [&](const char* k) {
                    auto it = m.find(k);
                    return it == m.end() ? std::string("—") : fmt::format("{:.4g}", it->second);
                };
                h << "<td>" << get("rmse") << "</td><td>" << get("relMse") << "</td><td>"
                  << get("smape") << "</td>" << (anyFlip ? "<td>" + get("flip") + "</td>" : "")
                  << "<td>" << get("referenceNoiseRmse") << "</td><td>" << (s.pareto ? "✓" : "")
                  << "</td>";
            } else {
                h << "<td colspan=\"" << (anyFlip ? 6 : 5) << "\">no error measured</td>";
            }
        }
        h << "</tr>\n";
    }
    h << "</table>\n";
    if (anyError)
        h << "<p class=\"meta\">Error: the first error_measure pass of the chain ("
          << escape(r.settings.front().errors.empty() ? "" : r.settings.front().errors.front().name)
          << "). Pareto: no other setting is both faster and more accurate.</p>\n";
    h << measureWarnings(r);
    h << plot(r) << "\n";
    if (const std::string methods = methodsPlot(r); !methods.empty())
        h << "<h2>Methods: time against error</h2>\n<p class=\"meta\">Each error measure's "
             "method, the passes its source depends on (not the whole chain, not the measure), "
             "timed per setting"
          << (r.device == "cuda" ? "; the dashed lines are Lumen's budgets for GI and "
                                   "reflections at 1080p on current consoles"
                                 : "")
          << ".</p>\n"
          << methods << "\n";
    if (const std::string seq = sequencePlot(r); !seq.empty())
        h << "<h2>Error over the sequence</h2>\n<p class=\"meta\">The first error_measure's RMSE "
             "on each frame of the last run, each frame with the history of those before it.</p>\n"
          << seq << "\n";

    // Why the error is what it is, per error_measure that was taken apart.
    std::vector<std::string> decomposed;
    for (const auto& s : r.settings)
        for (const auto& e : s.errors)
            if (e.decomposition &&
                std::find(decomposed.begin(), decomposed.end(), e.name) == decomposed.end())
                decomposed.push_back(e.name);
    if (!decomposed.empty()) {
        h << "<h2>Why the error is what it is</h2>\n<p class=\"meta\">Each error taken apart "
             "along a ladder of images from the result to its reference: the same chain "
             "converged (noise), framepass's screen-space oracle (Unreal's approximation), the "
             "one-bounce truth (the screen-space limit), the full truth (multi-bounce); for "
             "ray-traced GI, converged (noise), every bounce (the bounces not traced), the full "
             "truth (the light the pass leaves out). A step's "
             "share is Σ d·e / Σ e² (d: the step's difference, e: the total's), so the shares "
             "add up to 100 % and the biases to the total bias; a negative share is a step that "
             "cancels part of the others.</p>\n";
        for (const auto& name : decomposed)
            h << decompositionSection(r, name);
    }

    h << "<h2>Passes</h2>\n";
    for (const auto& s : r.settings) {
        h << "<details" << (&s == &r.settings.front() ? " open" : "") << "><summary>"
          << escape(s.label) << "</summary><table><tr><th class=\"l\">pass</th><th class=\"l\">"
                                 "type</th><th>median ms</th><th>min ms</th><th>max ms</th>"
                                 "<th>throughput</th><th title=\"its rays' bare Embree loops "
                                 "one ray at a time, over its own time\">Embree's speed</th>"
                                 "</tr>\n";
        for (const auto& p : s.passes)
            h << "<tr><td class=\"l\">" << escape(p.name) << "</td><td class=\"l\">" << escape(p.type)
              << "</td><td>" << ms(p.seconds.median) << "</td><td>" << ms(p.seconds.min)
              << "</td><td>" << ms(p.seconds.max) << "</td><td>"
              << (p.work ? unitRate(p.throughput(), p.unit) : std::string("—")) << "</td><td>"
              << (p.bareSeconds ? fmt::format("{:.0f} %", p.bareRatio() * 100) : std::string("—"))
              << "</td></tr>\n";
        h << "</table></details>\n";
    }

    // Images of the settings on the Pareto front (of every setting when none has an error).
    bool imagesHeader = false;
    for (const auto& s : r.settings)
        for (const auto& e : s.errors) {
            if (anyError && !s.pareto) continue;
            if (e.images.result.empty() && e.images.truth.empty() && e.images.heat.empty()) continue;
            if (!imagesHeader) h << "<h2>Images</h2>\n";
            imagesHeader = true;
            h << "<h3>" << escape(s.label) << " · " << escape(e.name) << "</h3><div>";
            auto fig = [&](const std::string& png, const std::string& caption,
                           const std::string& extra = "") {
                if (png.empty())
                    return;
                h << "<figure><img alt=\"" << escape(caption) << "\" src=\"data:image/png;base64,"
                  << png << "\"><figcaption>" << escape(caption) << extra
                  << "</figcaption></figure>";
            };
            fig(e.images.result, "result: " + e.source);
            fig(e.images.truth, "truth: " + e.reference);
            const auto scale = e.metrics.find("heatScale");
            fig(e.images.heat, "|error| heat map (viridis, grey = sky)",
                scale == e.metrics.end() ? std::string() : heatScaleBar(scale->second));
            h << "</div>\n";
        }

    // Lets a headless browser (and the test) confirm the page really rendered.
    h << R"(<script>
window.addEventListener('load', () => {
  const imgs = [...document.images];
  const ok = imgs.every(i => i.complete && i.naturalWidth > 0) && document.getElementById('plot');
  document.body.setAttribute('data-rendered', ok ? 'ok' : 'broken');
  document.body.setAttribute('data-images', String(imgs.length));
});
</script></body></html>
)";
    return h.str();
}

}  // namespace fp::app
