#include "report/svg.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace mcpose::report {
namespace {

// Margins of the plot frame inside the SVG, pixels: room for tick labels and axis titles.
constexpr double kLeft = 46, kRight = 10, kTop = 22, kBottom = 36;

std::string Num(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.1f", v);
  return buffer;
}

// A tick label: short, and -0 printed as 0.
std::string TickLabel(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%g", std::fabs(v) < 1e-12 ? 0.0 : v);
  return buffer;
}

}  // namespace

std::string EscapeXml(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

std::vector<double> NiceTicks(double lo, double hi, int max_ticks) {
  if (!(std::isfinite(lo) && std::isfinite(hi) && hi > lo && max_ticks >= 2)) return {};
  // The smallest step of 1, 2 or 5 times a power of ten that keeps the count within max_ticks.
  const double raw = (hi - lo) / (max_ticks - 1);
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  double step = 10 * power;
  for (double m : {1.0, 2.0, 5.0}) {
    if (m * power >= raw) {
      step = m * power;
      break;
    }
  }
  std::vector<double> ticks;
  for (double k = std::ceil(lo / step - 1e-9); k * step <= hi + 1e-9 * step; k += 1) ticks.push_back(k * step);
  return ticks;
}

std::string LinePlotSvg(const LinePlot& p) {
  const double w = p.width_px, h = p.height_px;
  const double fw = w - kLeft - kRight, fh = h - kTop - kBottom;
  const auto sx = [&](double x) { return kLeft + (x - p.x_min) / (p.x_max - p.x_min) * fw; };
  const auto sy = [&](double y) { return kTop + (p.y_max - y) / (p.y_max - p.y_min) * fh; };
  std::string s = "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"plot\" width=\"" + std::to_string(p.width_px) +
                  "\" height=\"" + std::to_string(p.height_px) + "\" viewBox=\"0 0 " + std::to_string(p.width_px) +
                  " " + std::to_string(p.height_px) + "\" font-family=\"sans-serif\" font-size=\"10\">";
  s += "<title>" + EscapeXml(p.title) + "</title>";
  s += "<text x=\"" + Num(kLeft) + "\" y=\"14\" font-size=\"12\" font-weight=\"bold\">" + EscapeXml(p.title) + "</text>";
  // Grid and ticks.
  for (double x : NiceTicks(p.x_min, p.x_max, p.x_integer ? 11 : 6)) {
    if (p.x_integer && x != std::round(x)) continue;
    s += "<line x1=\"" + Num(sx(x)) + "\" y1=\"" + Num(kTop) + "\" x2=\"" + Num(sx(x)) + "\" y2=\"" +
         Num(kTop + fh) + "\" stroke=\"#e4e4e4\"/>";
    s += "<text x=\"" + Num(sx(x)) + "\" y=\"" + Num(kTop + fh + 12) + "\" text-anchor=\"middle\">" + TickLabel(x) +
         "</text>";
  }
  for (double y : NiceTicks(p.y_min, p.y_max, 6)) {
    s += "<line x1=\"" + Num(kLeft) + "\" y1=\"" + Num(sy(y)) + "\" x2=\"" + Num(kLeft + fw) + "\" y2=\"" +
         Num(sy(y)) + "\" stroke=\"#e4e4e4\"/>";
    s += "<text x=\"" + Num(kLeft - 4) + "\" y=\"" + Num(sy(y) + 3) + "\" text-anchor=\"end\">" + TickLabel(y) +
         "</text>";
  }
  s += "<rect x=\"" + Num(kLeft) + "\" y=\"" + Num(kTop) + "\" width=\"" + Num(fw) + "\" height=\"" + Num(fh) +
       "\" fill=\"none\" stroke=\"#888\"/>";
  s += "<text x=\"" + Num(kLeft + fw / 2) + "\" y=\"" + Num(h - 6) + "\" text-anchor=\"middle\">" +
       EscapeXml(p.x_label) + "</text>";
  s += "<text transform=\"translate(11 " + Num(kTop + fh / 2) + ") rotate(-90)\" text-anchor=\"middle\">" +
       EscapeXml(p.y_label) + "</text>";
  // Data, clipped to the frame.
  const std::string clip = EscapeXml(p.id) + "-clip";
  s += "<clipPath id=\"" + clip + "\"><rect x=\"" + Num(kLeft) + "\" y=\"" + Num(kTop) + "\" width=\"" + Num(fw) +
       "\" height=\"" + Num(fh) + "\"/></clipPath><g clip-path=\"url(#" + clip + ")\">";
  for (const auto& [y, label] : p.y_rules) {
    s += "<line x1=\"" + Num(kLeft) + "\" y1=\"" + Num(sy(y)) + "\" x2=\"" + Num(kLeft + fw) + "\" y2=\"" +
         Num(sy(y)) + "\" stroke=\"#666\" stroke-dasharray=\"2 3\"><title>" + EscapeXml(label) + "</title></line>";
    s += "<text x=\"" + Num(kLeft + fw - 3) + "\" y=\"" + Num(sy(y) - 3) + "\" text-anchor=\"end\" fill=\"#666\">" +
         EscapeXml(label) + "</text>";
  }
  for (const PlotSeries& series : p.series) {
    if (series.points.empty()) continue;
    s += "<polyline fill=\"none\" stroke=\"" + EscapeXml(series.colour) + "\" stroke-width=\"" + Num(series.width_px) +
         "\"" + (series.dashed ? " stroke-dasharray=\"5 3\"" : "") + " points=\"";
    for (size_t i = 0; i < series.points.size(); ++i) {
      if (i) s += ' ';
      s += Num(sx(series.points[i][0])) + "," + Num(sy(series.points[i][1]));
    }
    s += "\"><title>" + EscapeXml(series.name) + "</title></polyline>";
  }
  s += "</g>";
  // Legend.
  const auto in_legend = std::count_if(p.series.begin(), p.series.end(), [](const PlotSeries& x) { return x.in_legend; });
  // Bottom right: the text ends at the frame's right edge, the rows end above its bottom.
  double ly = p.legend_bottom_right ? kTop + fh - 6 - 12.0 * (static_cast<double>(in_legend) - 1) : kTop + 12;
  const double lx = p.legend_bottom_right ? kLeft + fw - 6 : kLeft + 6;
  const char* anchor = p.legend_bottom_right ? "end" : "start";
  for (const PlotSeries& series : p.series) {
    if (!series.in_legend) continue;
    // The line sample sits before the text (top left) or after it (bottom right).
    const double x0 = p.legend_bottom_right ? lx - 18 : lx, tx = p.legend_bottom_right ? lx - 22 : lx + 22;
    s += "<line x1=\"" + Num(x0) + "\" y1=\"" + Num(ly - 3) + "\" x2=\"" + Num(x0 + 18) + "\" y2=\"" +
         Num(ly - 3) + "\" stroke=\"" + EscapeXml(series.colour) + "\" stroke-width=\"" + Num(series.width_px) +
         "\"" + (series.dashed ? " stroke-dasharray=\"5 3\"" : "") + "/>";
    s += "<text x=\"" + Num(tx) + "\" y=\"" + Num(ly) + "\" text-anchor=\"" + anchor + "\">" +
         EscapeXml(series.name) + "</text>";
    ly += 12;
  }
  s += "</svg>";
  return s;
}

std::string ColourBarSvg(const std::string& id, const std::vector<std::string>& stops, double limit,
                         const std::string& unit, int width_px) {
  constexpr double kMargin = 14, kBarHeight = 10;
  const double bw = width_px - 2 * kMargin - 12;
  std::string s = "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"colourbar\" width=\"" + std::to_string(width_px) +
                  "\" height=\"34\" viewBox=\"0 0 " + std::to_string(width_px) +
                  " 34\" font-family=\"sans-serif\" font-size=\"10\"><defs><linearGradient id=\"" + EscapeXml(id) +
                  "\">";
  for (size_t i = 0; i < stops.size(); ++i) {
    const double offset = stops.size() > 1 ? 100.0 * static_cast<double>(i) / static_cast<double>(stops.size() - 1) : 0;
    s += "<stop offset=\"" + Num(offset) + "%\" stop-color=\"" + EscapeXml(stops[i]) + "\"/>";
  }
  s += "</linearGradient></defs><rect x=\"" + Num(kMargin) + "\" y=\"2\" width=\"" + Num(bw) + "\" height=\"" +
       Num(kBarHeight) + "\" fill=\"url(#" + EscapeXml(id) + ")\" stroke=\"#888\"/>";
  const std::vector<double> ticks = NiceTicks(-limit, limit, 5);
  for (size_t i = 0; i < ticks.size(); ++i) {
    const double x = kMargin + (ticks[i] + limit) / (2 * limit) * bw;
    s += "<line x1=\"" + Num(x) + "\" y1=\"" + Num(2 + kBarHeight) + "\" x2=\"" + Num(x) + "\" y2=\"" +
         Num(5 + kBarHeight) + "\" stroke=\"#444\"/>";
    // The unit follows the last label.
    s += "<text x=\"" + Num(x) + "\" y=\"" + Num(16 + kBarHeight) + "\" text-anchor=\"middle\">" +
         TickLabel(ticks[i]) + (i + 1 == ticks.size() ? " " + EscapeXml(unit) : "") + "</text>";
  }
  s += "</svg>";
  return s;
}

}  // namespace mcpose::report
