// Errors found in a study file, reported compiler-style as "file:line:col: message", and the
// did-you-mean suggestions that go with them.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace sph::runner {

struct Diagnostic {
  std::string file;
  int line = 0; // 1-based; 0: no position
  int column = 0;
  std::string message;
};

std::string format_diagnostic(const Diagnostic& d);

// A study that cannot be run: one or more diagnostics, all reported together.
class StudyError : public std::runtime_error {
public:
  explicit StudyError(std::vector<Diagnostic> diagnostics);
  const std::vector<Diagnostic>& diagnostics() const { return diagnostics_; }

private:
  std::vector<Diagnostic> diagnostics_;
};

// Collects diagnostics for one file; throws them together.
class Diagnostics {
public:
  explicit Diagnostics(std::string file) : file_(std::move(file)) {}
  void error(int line, std::string message, int column = 0);
  bool empty() const { return items_.empty(); }
  std::size_t size() const { return items_.size(); }
  const std::string& file() const { return file_; }
  // Throws StudyError when any error was recorded.
  void throw_if_any() const;

private:
  std::string file_;
  std::vector<Diagnostic> items_;
};

std::size_t edit_distance(const std::string& a, const std::string& b);

// " (did you mean 'x'?)" for the closest candidate within a small edit distance, else "".
std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates);

// "'a', 'b', 'c'"
std::string quoted_list(const std::vector<std::string>& items);

} // namespace sph::runner
