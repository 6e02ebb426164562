// tools/quadcast/plot.hpp -- log-log scatter plots drawn into an RGBA image (benchmark figures)
#pragma once

// A tiny rasteriser for benchmark figures, no plotting library: axes with decade ticks, one
// marker shape and colour per series, a polyline through each series' points, a label per
// point, a legend, a title and axis labels in a built-in 5x7 bitmap font (upper case, digits,
// common punctuation; lower case is drawn as upper case). Save with render::write_png.

#include <string>
#include <vector>

#include "quadcast/render/types.hpp"

namespace quadcast::cli {

struct PlotSeries {
    std::string name;
    std::vector<double> x, y;          ///< points (non-positive or non-finite points are skipped)
    std::vector<std::string> labels;   ///< optional text next to each point
};

struct LogLogPlot {
    std::string title, x_label, y_label;
    std::vector<PlotSeries> series;
};

/// Draws the plot into a width x height RGBA image (white background). The axis ranges are the
/// data's bounding box widened to whole decades. Throws std::invalid_argument for an image
/// smaller than 200 x 150.
render::Image draw_loglog(const LogLogPlot& plot, int width, int height);

}  // namespace quadcast::cli
