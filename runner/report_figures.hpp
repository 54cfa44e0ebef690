// The `[[figures]]` tables of a study file: what `runner report` draws and tabulates. Each figure
// names its x (a parameter, or an HDF5 dataset for series), its y (metrics or datasets), the
// parameters that split the data into curves, a filter, log axes, an optional fit (power law or
// straight line) and reference series (a CSV file with its citation, or an analytic expression).
// Parsed and validated with the rest of the study file (file:line diagnostics); see docs/report.md.
#pragma once

#include "cases/case.hpp"
#include "expr.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace sph::runner {

struct ReferenceSeries {
  std::string label;
  std::string citation;
  // Either an analytic expression in x (and numeric parameters of the case) ...
  std::optional<Expr> expr;
  // ... or a CSV file (resolved against the study file's directory) and two of its columns.
  std::filesystem::path csv;
  std::string csv_x, csv_y;
  std::string style; // "line" or "points" (default: line for expr, points for csv)
  int line = 0;
};

struct FilterValue {
  std::string param;
  std::vector<ParamValue> values; // a job matches when its value is one of these
};

struct FigureSpec {
  std::string name; // file stem of the image and data files
  std::string title;
  std::string kind = "metric"; // "metric": one point per job; "series": one curve per job (HDF5)
                               // ("convergence" in the file: a metric figure, see below)
  std::string x;               // metric: a parameter or "scheme"; series: a dataset name
  std::vector<std::string> y;  // metric: metric names; series: dataset names
  std::string file;            // series: HDF5 file in the job's output directory
  std::vector<std::string> group;
  std::vector<FilterValue> where;
  std::string agg = "mean"; // mean, median, min, max over jobs sharing x and group (seeds)
  bool spread = true;       // draw min..max bars where several jobs share a point
  bool log_x = false, log_y = false;
  std::string x_label, y_label;
  std::string fit = "none"; // none, power (y = C x^p), linear (y = a + b x)
  std::optional<std::pair<double, double>> fit_range; // x interval of the points fitted
  std::vector<std::string> mark = {"diverged"};       // job states drawn as markers
  bool x_is_string = false;                           // x is a string parameter (categories)
  std::vector<ReferenceSeries> references;
  // kind = "convergence" (stored as a metric figure with these set): the table of `runner
  // converge` beneath the figure: "self" (the metric converges to a value) or "error" (it tends
  // to 0), how x is a resolution (auto, spacing, count), a formal order for two resolutions, and
  // parameters that do not split the groups.
  std::optional<std::string> convergence;
  std::string resolution = "auto";
  std::optional<double> formal_order;
  std::vector<std::string> ignore;
  int line = 0;
};

// A reference CSV: '#' lines are comments (put the citation there), the first other line names
// the columns, every further line holds numbers.
struct CsvTable {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
};
CsvTable read_reference_csv(const std::filesystem::path& path); // throws std::runtime_error

// Reads the [[figures]] of a study file (already valid: load_study() checked them). Throws
// StudyError with file:line diagnostics otherwise.
std::vector<FigureSpec> load_figures(const std::filesystem::path& study_file,
                                     const std::vector<ParamSpec>& specs);
std::vector<FigureSpec> parse_figures_text(const std::string& text, const std::string& file,
                                           const std::vector<ParamSpec>& specs);

} // namespace sph::runner
