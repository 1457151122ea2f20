// Inline SVG for the report: line plots with axes, ticks and a legend, and the colour bar of
// the depth-residual map. Plain SVG 1.1 text, no script, meant to sit inside an HTML page.
#pragma once

#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace mcpose::report {

// `text` with &, <, >, " and ' replaced by entities: safe as element text and as a quoted
// attribute value in HTML and SVG.
std::string EscapeXml(std::string_view text);

// Tick values covering [lo, hi] at a step of 1, 2 or 5 times a power of ten, at most about
// `max_ticks` of them, each a multiple of the step. Empty when the range is empty or not finite.
std::vector<double> NiceTicks(double lo, double hi, int max_ticks);

struct PlotSeries {
  std::string name;    // in the legend and as the line's tooltip
  std::string colour;  // CSS colour, e.g. "#1f77b4"
  std::vector<std::array<double, 2>> points;  // (x, y) in data units, drawn in this order
  double width_px = 1.5;
  bool dashed = false;
  bool in_legend = true;
};

struct LinePlot {
  std::string id;  // names the plot's clip path: unique in the page
  int width_px = 360, height_px = 220;
  std::string title, x_label, y_label;
  double x_min = 0, x_max = 1, y_min = 0, y_max = 1;  // the axes' ranges; points outside are clipped
  std::vector<PlotSeries> series;
  // Horizontal reference lines (e.g. a stopping threshold): y value and label.
  std::vector<std::pair<double, std::string>> y_rules;
  bool x_integer = false;             // x ticks at whole numbers only (iterations)
  bool legend_bottom_right = false;  // else top left, inside the frame
};

// The plot as one <svg> element: frame, ticks from NiceTicks, grid lines, axis labels, the
// series as polylines, the legend in a corner inside the frame.
std::string LinePlotSvg(const LinePlot& plot);

// A horizontal colour bar for a map of values in [-limit, +limit]: `stops` are the map's
// colours from -limit to +limit (CSS colours, evenly spaced), labelled with ticks in `unit`.
// `id` names the gradient; it must be unique in the page.
std::string ColourBarSvg(const std::string& id, const std::vector<std::string>& stops, double limit,
                         const std::string& unit, int width_px);

}  // namespace mcpose::report
