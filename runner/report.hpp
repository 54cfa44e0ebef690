// `runner report`: a static HTML page with a study's figures and tables, regenerated from the
// database (and the jobs' HDF5 outputs for series figures). Figures are drawn by gnuplot, run as a
// separate process on a generated script; a figure is redrawn only when the hash of its script
// (which holds all its data) changed. Without gnuplot the page still has every table and says why
// the figures are missing. See docs/report.md.
#pragma once

#include "report_figures.hpp"

#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace sph::runner {

struct ReportOptions {
  std::string study;                // a study file, or the name of a study in the database
  std::filesystem::path db;         // database
  std::filesystem::path out_dir;    // empty: <db dir>/report/<study>/
  std::string tier;                 // only jobs of this tier (empty: every job of the study)
  std::string image_format = "svg"; // svg or png
};

// Writes <out_dir>/index.html and the figures; prints a one-line summary. Returns 0, or throws
// (StudyError for an invalid study file, std::runtime_error otherwise).
int cmd_report(const ReportOptions& options, std::ostream& out);

// ---- exposed for tests -----------------------------------------------------------------------

// Least-squares fit. power: y = C x^p on (log x, log y) (slope p, intercept log C);
// linear: y = a + b x (slope b, intercept a). Points with x <= 0 or y <= 0 are skipped for power.
struct LineFit {
  std::string kind; // power or linear
  double slope = 0, intercept = 0, r2 = 0;
  std::size_t n = 0;
  double x_min = 0, x_max = 0;
  double eval(double x) const; // the fitted y at x
};
std::optional<LineFit> fit_points(const std::string& kind, const std::vector<double>& x,
                                  const std::vector<double>& y);

// One curve of a figure: a series of (x, y) with the spread of the jobs aggregated in each point.
struct CurvePoint {
  double x = 0;          // the value, or the category index for string x
  double y = 0;          // aggregated
  double lo = 0, hi = 0; // min and max over the jobs aggregated
  std::size_t n = 0;     // jobs with a value
};
struct Curve {
  std::string label;
  std::string y;         // metric or dataset
  std::size_t group = 0; // index of the group (colour)
  std::size_t y_index = 0;
  std::vector<CurvePoint> points;
  std::optional<LineFit> fit;
};
struct Marker {
  double x = 0;
  std::size_t group = 0;
  std::string state;
};
struct RefCurve {
  std::string label, style;
  std::vector<std::pair<double, double>> points;
};
struct FigureData {
  const FigureSpec* spec = nullptr;
  std::vector<std::string> x_categories; // string x: the category names (x = index)
  std::vector<Curve> curves;
  std::vector<Marker> markers;
  std::vector<RefCurve> references;
};

// The gnuplot script that draws `d` into `image` (a file name relative to the script's directory,
// written under a temporary name and renamed by the caller). Holds all the data inline.
std::string gnuplot_script(const FigureData& d, const std::string& image,
                           const std::string& format);

// gnuplot's version line, or nullopt when it cannot be run. SPH_GNUPLOT overrides the program
// (a path or a name looked up in PATH).
std::optional<std::string> gnuplot_version(std::string* program = nullptr);

struct DrawOutcome {
  bool drawn = false;     // gnuplot ran and produced the image
  bool unchanged = false; // the image was up to date (same script hash), not redrawn
  std::string error;
};
// Draws figure `name` in out_dir: writes <name>.gp, runs gnuplot when <name>.<format>'s stored
// hash (<name>.sha256) differs from the script's, renames the image into place.
DrawOutcome draw_figure(const std::string& program, const std::string& version,
                        const std::filesystem::path& out_dir, const std::string& name,
                        const std::string& script, const std::string& format);

} // namespace sph::runner
