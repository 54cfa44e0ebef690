// The read-only commands: query (SQL to CSV), status, cases, table (pivot), export and publish.
// Each returns a process exit code and writes to the given streams.
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace sph::runner {

// Runs one SQL statement on a read-only connection and prints CSV with a header row.
// timeout_s: the query is stopped with an error after this many seconds (0: no limit).
int cmd_query(const std::filesystem::path& db, const std::string& sql, std::ostream& out,
              double timeout_s = 0);

// Counts by state per study (and tier), running jobs with heartbeat age, the last errors.
int cmd_status(const std::filesystem::path& db, const std::string& study, std::ostream& out);

// The registered cases with their parameters.
// `runner cases [CASE]`: every case and scheme with its parameters; one case with the scheme
// parameters that apply, its metrics and its HDF5 datasets.
int cmd_cases(std::ostream& out, const std::string& name = "");

struct TableOptions {
  std::string study;
  std::string rows, cols; // parameter names (or "scheme")
  std::string metric;
  std::string agg = "mean";    // mean, min, max, count
  std::string format = "text"; // text, csv or markdown
  // KEY=VALUE filters on the jobs' parameters (all must hold), e.g. "lattice=uniform".
  std::vector<std::string> where;
};
int cmd_table(const std::filesystem::path& db, const TableOptions& t, std::ostream& out);

// Grid-convergence verification of a metric over a resolution parameter (convergence.hpp): per
// group of the other parameters, the observed order, the Richardson-extrapolated value and the
// GCI of the finest resolution.
struct ConvergeOptions {
  std::string study;
  std::string param; // the resolution: a spacing (dx) or a count (n_side, D_over_dx)
  std::string metric;
  std::string kind = "self";          // self: the metric converges to a value; error: it tends to 0
  std::string resolution = "auto";    // auto, spacing or count (count: h = 1 / value)
  std::optional<double> formal_order; // stands in for p where only two resolutions exist
  std::string format = "text";        // text, csv or markdown
  std::vector<std::string> where;
  std::vector<std::string> ignore; // parameters that do not split groups (e.g. t_end)
  std::string published; // read a published record (docs/results/STUDY.csv) instead of the db
};
int cmd_converge(const std::filesystem::path& db, const ConvergeOptions& c, std::ostream& out);

// One job's value of the metric at its resolution x, with its parameters (name -> value as JSON
// text), as `runner converge` and the report's convergence figures read them.
struct ConvergeRow {
  double x = 0;
  double f = 0;
  std::map<std::string, std::string> params;
};
// The table `runner converge` prints: one row per group of the other varying parameters (those
// that are a function of the resolution do not split groups), columns as `header`.
struct ConvergeTable {
  bool count = false; // the resolution is a count (spacing h = 1 / x)
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
};
ConvergeTable converge_table(const std::vector<ConvergeRow>& rows, const ConvergeOptions& c);

// One row (csv) or object (json) per job of a study: key, state, scheme, parameters, metrics.
int cmd_export(const std::filesystem::path& db, const std::string& study, const std::string& format,
               std::ostream& out);

// The committed record of a study's runs (docs/results/<study>.csv, issue 15): one row per job and
// metric, header `study,job,tier,code_version,params,metric,value`, of every done or diverged job
// of the study in the database. Rows of jobs the file already holds and the database does not
// (runs recorded from another database) are kept; a job in both is replaced. Prints a summary.
int cmd_publish(const std::filesystem::path& db, const std::string& study,
                const std::filesystem::path& out_file, std::ostream& log);

// RFC 4180 field quoting, and its inverse: one line (no embedded line breaks) into its fields.
std::string csv_field(const std::string& s);
std::vector<std::string> csv_split(const std::string& line);

} // namespace sph::runner
