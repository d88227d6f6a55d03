// Bar charts drawn with Cairo, as PNG bytes, for report.html. Internal to validate/.
#pragma once

#include <string>
#include <vector>

namespace mbest::validate {

struct ChartSeries {
  std::string name;
  std::vector<double> percent;  // one per category, in [0, 100]; NaN = no data
  std::vector<int> counts;      // one per category: how many items the value is over
};

// A grouped bar chart: one group per category, one bar per series, each bar labelled with
// its value and count. The y axis runs from a multiple of 5 below the lowest value to 100.
std::string bar_chart_png(const std::string& title, const std::string& x_title,
                          const std::vector<std::string>& categories,
                          const std::vector<ChartSeries>& series);

std::string base64(const std::string& bytes);

}  // namespace mbest::validate
